//! What is captured: the scene file ([`scene_file`]: vehicle, occluders, rig,
//! scenarios), the meshes and their loaders ([`mesh`], with [`model_files`]
//! reading OBJ/MTL safely), the vehicle's checks ([`vehicle`]) and parts by
//! region ([`regions`]), the pedestrian's eyes and tiles ([`rig`]), the
//! vehicle's motion ([`track`] keyframes, [`scenario`] a timed motion,
//! [`unity`] Unity exports), and the built-in scenes ([`demo`] the truck and
//! intersection, [`degenerate_mesh`] a vehicle of bad triangles). Nothing
//! here renders or writes an archive.

pub mod degenerate_mesh;
pub mod demo;
pub mod mesh;
pub mod model_files;
pub mod regions;
pub mod rig;
pub mod scenario;
pub mod scene_file;
pub mod track;
pub mod unity;
pub mod vehicle;

pub use scene_file::*;
