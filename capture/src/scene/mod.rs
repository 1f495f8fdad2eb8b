//! What is captured: the scene file ([`scene_file`]: vehicle, occluders, rig,
//! scenarios), the meshes and their loaders ([`mesh`], with [`model_files`]
//! reading OBJ/MTL safely), the occluders ([`occluders`] still and
//! [`moving`] traffic and other pedestrians), the vehicle's spec and checks ([`vehicle`]),
//! several measured vehicles in one scene, one pass each ([`fleet`] their
//! names, [`fleet_pass`] the pass of one),
//! parts from a part map painted over the model's own UVs ([`part_map`]) and
//! parts by region ([`regions`], cutting triangles along their boundaries:
//! [`cut`]), the pedestrian's eyes and tiles ([`rig`]),
//! the scene at one frame ([`frame_state`]: everything that moves, once),
//! the vehicle's motion ([`track`] keyframes, [`scenario`] a timed motion,
//! [`unity`] Unity exports), the one ray–triangle test ([`ray_triangle`],
//! shared by the exact measure and the scene checks), surfaces lying on one
//! another ([`coincident`], found for the scene checks and the exact
//! measure), and the built-in scenes
//! ([`demo`] the truck and intersection, [`street`] the raycasting study's
//! street, [`family`] the parametric sedan, SUV, van, pickup and bus, with
//! [`shapes`] the building blocks they share, [`degenerate_mesh`] a vehicle of
//! bad triangles), and the rules the fuzz entries (`crate::fuzz_entry`) exercise. Nothing here
//! renders or writes an archive.

pub(crate) mod coincident;
pub(crate) mod cut;
pub(crate) mod degenerate_mesh;
pub(crate) mod demo;
pub(crate) mod family;
pub(crate) mod fleet;
pub(crate) mod fleet_pass;
pub(crate) mod frame_state;
pub(crate) mod mesh;
pub(crate) mod model_files;
pub(crate) mod moving;
pub(crate) mod occluders;
pub(crate) mod part_map;
pub(crate) mod ray_triangle;
pub(crate) mod region_pieces;
pub(crate) mod regions;
pub(crate) mod rig;
pub(crate) mod scenario;
pub(crate) mod scene_file;
pub(crate) mod shapes;
pub(crate) mod street;
pub(crate) mod track;
pub(crate) mod unity;
pub(crate) mod vehicle;

pub use family::{BodyDims, BodyType, body_mesh};

pub use degenerate_mesh::degenerate_vehicle;
pub use demo::{ADJACENT_LANE_AHEAD_M, ADJACENT_LANE_M, DemoTraffic, LEAD_CAR_AHEAD_M};
pub use fleet::{DEFAULT_VEHICLE_NAME, FleetVehicle};
pub use frame_state::FrameState;
pub use mesh::{Axes, Mesh, PartSource, load_vehicle, triangle_area};
pub use moving::{FollowOffset, MovingOccluder, OccluderPath, PEDESTRIAN_BODY_M, pedestrian_body};
pub use occluders::{OccluderObject, Occluders};
pub use part_map::{PartMapReport, PartMapSpec, UNMAPPED_PART};
pub use regions::{PartRule, RegionReport};
pub use rig::{
    Eye, EyeCamera, Rig, TileId, box_corners, box_outside, look_to, reversed_z_perspective, vehicle_to_world,
};
pub use scenario::Scenario;
pub use scene_file::{Scene, SceneFile};
pub use street::{StreetOptions, street_scene};
pub use track::{Key, Motion, Pose, Track, ValueOrTrack};
pub use vehicle::{PartsFrom, VehicleSpec};
