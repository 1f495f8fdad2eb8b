//! The JSON scene file: vehicle, occluders, rig and scenarios.
//!
//! Paths are relative to the scene file. See `capture/README.md` for the
//! reference; `fixtures/scenes/` has examples. A loaded scene is the same
//! whether it came from a file, from the built-in demo or from a Unity export.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use glam::{DMat4, DVec3};
use serde::{Deserialize, Serialize};

use crate::error::{CaptureError, Result};
use crate::scene::demo;
use crate::scene::family::{BodyDims, BodyType, body_mesh};
use crate::scene::fleet::FleetVehicle;
use crate::scene::mesh::{Axes, Mesh, PartSource, load_model};
use crate::scene::moving::{FollowOffset, MovingOccluder, OccluderPath, PEDESTRIAN_BODY_M};
use crate::scene::occluders::Occluders;
use crate::scene::rig::Rig;
use crate::scene::scenario::Scenario;
use crate::scene::track::{Motion, Pose, ValueOrTrack};
use crate::scene::unity;
use crate::scene::vehicle::VehicleSpec;

/// A scene file.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneFile {
    /// Name recorded in the manifest.
    #[serde(default)]
    pub name: Option<String>,
    pub vehicle: VehicleSpec,
    #[serde(default)]
    pub occluders: Vec<OccluderSpec>,
    /// Rig settings; missing fields take the paper's defaults.
    #[serde(default)]
    pub rig: Option<Rig>,
    /// Scenarios by name.
    #[serde(default)]
    pub scenarios: BTreeMap<String, ScenarioSpec>,
    /// A Unity export (`unity-intersection.json`) whose rig and scenarios are
    /// used when the file gives none of its own.
    #[serde(default)]
    pub unity: Option<PathBuf>,
}

/// Something that hides the vehicle but is never counted: its shape, and
/// for a `box`, `mesh`, `vehicle` or `pedestrian` where it stands or how it
/// moves (the `position`, `yaw_deg` and `follow` keys of the same object).
#[derive(Debug, Clone)]
pub struct OccluderSpec {
    pub shape: OccluderShape,
    pub placement: PlacementSpec,
}

/// What an occluder is.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum OccluderShape {
    /// An axis-aligned box: world coordinates, or, once placed by
    /// `position`, `yaw_deg` or `follow`, its own frame.
    Box { min: [f64; 3], max: [f64; 3] },
    /// A mesh (an environment, or a car of your own), in its own frame.
    Mesh {
        path: PathBuf,
        #[serde(default)]
        axes: Axes,
    },
    /// Another copy of the vehicle, or with `model` a vehicle of its own
    /// (a vehicle spec: mesh or body, parts, axes); with `measure`, a
    /// vehicle measured too, under that name (an archive of its own:
    /// [`crate::scene::fleet`]).
    Vehicle {
        #[serde(default, skip_serializing_if = "Option::is_none")]
        measure: Option<String>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        model: Option<Box<VehicleSpec>>,
    },
    /// Another pedestrian: a body-sized box ([`PEDESTRIAN_BODY_M`], or
    /// `size_m`: length, width, height).
    Pedestrian {
        #[serde(default = "default_body")]
        size_m: [f64; 3],
    },
    /// The demo's ground and corner buildings.
    DemoIntersection,
    /// A ground plane at height `z` (hides the underside of the vehicle).
    Ground { z: f64 },
}

fn default_body() -> [f64; 3] {
    PEDESTRIAN_BODY_M
}

/// Where an occluder stands or how it moves. It moves when its `position`
/// or `yaw_deg` is a list of track keys, or with a `follow` offset; it
/// stands still otherwise.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlacementSpec {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub position: Option<ValueOrTrack<3>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub yaw_deg: Option<ValueOrTrack<1>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub follow: Option<FollowOffset>,
}

/// The keys of a [`PlacementSpec`], and the kinds that take them.
const PLACEMENT_KEYS: [&str; 3] = ["position", "yaw_deg", "follow"];
const PLACED_KINDS: [&str; 4] = ["box", "mesh", "vehicle", "pedestrian"];

impl<'de> Deserialize<'de> for OccluderSpec {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        use serde::de::Error;
        let mut value = serde_json::Value::deserialize(d)?;
        let mut placement = serde_json::Map::new();
        if let Some(outer) = value.as_object_mut()
            && outer.len() == 1
            && let Some((kind, serde_json::Value::Object(inner))) = outer.iter_mut().next()
            && PLACED_KINDS.contains(&kind.as_str())
        {
            for key in PLACEMENT_KEYS {
                if let Some(v) = inner.remove(key) {
                    placement.insert(key.into(), v);
                }
            }
        }
        let shape = OccluderShape::deserialize(value).map_err(D::Error::custom)?;
        let placement =
            PlacementSpec::deserialize(serde_json::Value::Object(placement)).map_err(D::Error::custom)?;
        Ok(OccluderSpec { shape, placement })
    }
}

impl Serialize for OccluderSpec {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        use serde::ser::Error;
        let mut value = serde_json::to_value(&self.shape).map_err(S::Error::custom)?;
        let placement = serde_json::to_value(&self.placement).map_err(S::Error::custom)?;
        if let (Some(outer), serde_json::Value::Object(placement)) = (value.as_object_mut(), placement)
            && let Some(serde_json::Value::Object(inner)) = outer.values_mut().next()
        {
            inner.extend(placement);
        }
        value.serialize(s)
    }
}

impl PlacementSpec {
    /// Checks the values (the vehicle's track bounds), naming the key.
    fn check(&self) -> std::result::Result<(), String> {
        if self.follow.is_some() && (self.position.is_some() || self.yaw_deg.is_some()) {
            return Err("give either follow or position/yaw_deg, not both".into());
        }
        if let Some(follow) = &self.follow {
            follow.check()?;
        }
        if let Some(position) = &self.position {
            position.check().map_err(|e| format!("position: {e}"))?;
        }
        if let Some(yaw) = &self.yaw_deg {
            yaw.check().map_err(|e| format!("yaw_deg: {e}"))?;
        }
        Ok(())
    }

    /// True when nothing places the occluder (a box in world coordinates).
    fn is_empty(&self) -> bool {
        self.position.is_none() && self.yaw_deg.is_none() && self.follow.is_none()
    }

    /// How it moves, or `None` when it stands still.
    fn path(&self) -> Option<OccluderPath> {
        if let Some(follow) = self.follow {
            return Some(OccluderPath::Follow(follow));
        }
        let keyed = self.position.as_ref().is_some_and(|p| p.keys().is_some())
            || self.yaw_deg.as_ref().is_some_and(|y| y.keys().is_some());
        keyed.then(|| OccluderPath::Tracks {
            position: self.position.clone().unwrap_or(ValueOrTrack::Fixed([0.0; 3])),
            yaw_deg: self.yaw_deg.clone().unwrap_or(ValueOrTrack::Fixed([0.0])),
        })
    }

    /// A still occluder as one that moves on fixed tracks (a measured
    /// vehicle is always a moving occluder: its passes swap it with the
    /// scene's own vehicle).
    fn fixed_path(&self) -> OccluderPath {
        OccluderPath::Tracks {
            position: self.position.clone().unwrap_or(ValueOrTrack::Fixed([0.0; 3])),
            yaw_deg: self.yaw_deg.clone().unwrap_or(ValueOrTrack::Fixed([0.0])),
        }
    }

    /// Where a still occluder stands (its fixed values).
    fn fixed_pose(&self) -> Pose {
        Pose {
            position: DVec3::from(self.position.as_ref().map_or([0.0; 3], |p| p.eval(0.0))),
            yaw_deg: self.yaw_deg.as_ref().map_or(0.0, |y| y.eval(0.0)[0]),
        }
    }
}

impl OccluderSpec {
    /// The occluder's node name in `scene.glb` and the manifest: its kind
    /// and number in the scene file; `None` for the demo intersection, which
    /// names its own.
    fn name(&self, number: usize) -> Option<String> {
        let name = match &self.shape {
            OccluderShape::Box { .. } => format!("box #{number}"),
            OccluderShape::Mesh { path, .. } => format!("mesh #{number} {}", path.display()),
            OccluderShape::Vehicle { .. } => format!("vehicle #{number}"),
            OccluderShape::Pedestrian { .. } => format!("pedestrian #{number}"),
            OccluderShape::Ground { .. } => format!("ground #{number}"),
            OccluderShape::DemoIntersection => return None,
        };
        Some(name)
    }

    /// Positions, yaw, tracks and offsets within the tracks' street scale
    /// (as the rig's and the vehicle's).
    fn check(&self) -> std::result::Result<(), String> {
        let limit = crate::scene::track::MAX_TRACK_MAGNITUDE;
        let values: Vec<f64> = match &self.shape {
            OccluderShape::Box { min, max } => min.iter().chain(max).copied().collect(),
            OccluderShape::Pedestrian { size_m } => {
                if !size_m.iter().all(|v| v.is_finite() && *v > 0.0 && *v <= 100.0) {
                    return Err(format!("size_m {size_m:?} must be three lengths in (0, 100] m"));
                }
                Vec::new()
            }
            OccluderShape::Ground { z } => vec![*z],
            OccluderShape::Mesh { .. } | OccluderShape::Vehicle { .. } | OccluderShape::DemoIntersection => {
                Vec::new()
            }
        };
        if let Some(value) = values.iter().find(|v| !(v.is_finite() && v.abs() <= limit)) {
            return Err(format!("{value:e} is beyond ±{limit:e}: not a street scene"));
        }
        if let OccluderShape::Box { min, max } = &self.shape {
            check_box(min, max)?;
        }
        if matches!(self.shape, OccluderShape::Vehicle { .. }) && self.placement.is_empty() {
            return Err("a vehicle needs a position (fixed or a track) or a follow offset".into());
        }
        if let OccluderShape::Vehicle { model: Some(model), .. } = &self.shape
            && model.measure.is_some()
        {
            return Err("model.measure: give measure beside model, not inside it".into());
        }
        self.placement.check()
    }
}

/// A box's corners: `min` at most `max` on every axis (issue 41: a box
/// with `min` above `max` was accepted, an inside-out box).
fn check_box(min: &[f64; 3], max: &[f64; 3]) -> std::result::Result<(), String> {
    for (axis, (low, high)) in min.iter().zip(max).enumerate() {
        if low > high {
            return Err(format!(
                "box.min[{axis}] {low} is above box.max[{axis}] {high}: min must be the low corner, max the high one"
            ));
        }
    }
    Ok(())
}

/// A scenario in a scene file.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ScenarioSpec {
    pub duration_s: f64,
    /// Vehicle position keys (world metres, Z up).
    pub position: crate::scene::track::Track<3>,
    /// Vehicle yaw keys (degrees, counter-clockwise from +X).
    pub yaw_deg: crate::scene::track::Track<1>,
}

/// A scene ready to capture.
#[derive(Debug, Clone)]
pub struct Scene {
    pub name: String,
    pub vehicle: Mesh,
    pub occluders: Occluders,
    pub rig: Rig,
    pub scenarios: Vec<Scenario>,
    /// What the manifest records about the scene.
    pub info: ufcsr::format::SceneRecord,
    /// Doubts about the vehicle (size, axes, origin, part rules) to show the user.
    pub warnings: Vec<String>,
    /// Every file the scene was read from (scene file, meshes and the files
    /// they name, Unity export): a capture refuses to write over any of them.
    pub input_files: Vec<PathBuf>,
    /// The vehicles a scene file measures, its own `vehicle` first, when it
    /// measures more than that one (`vehicle` occluders with `measure`);
    /// empty otherwise. [`Scene::measuring`] makes each one's pass.
    pub fleet: Vec<FleetVehicle>,
    /// How the measured vehicle moves: `None` along the scenario's motion;
    /// `Some` in the pass of a fleet vehicle other than the scene's own, as
    /// that vehicle moved as an occluder (following the scenario's motion,
    /// or on its own tracks).
    pub vehicle_path: Option<OccluderPath>,
}

impl Scene {
    /// The built-in demo: truck, intersection, scenarios A–D.
    pub fn demo() -> Scene {
        let scenarios = demo::SCENARIOS.iter().filter_map(|(name, _, _)| demo::scenario(name)).collect();
        let vehicle = demo::truck();
        Scene {
            name: "demo".into(),
            info: ufcsr::format::SceneRecord {
                name: "demo".into(),
                vehicle: Some("built-in pickup truck (5.9 × 2.0 × 1.9 m)".into()),
                environment: Some(
                    "four-way intersection with corner buildings; pedestrian at the south-west corner".into(),
                ),
                scenarios: Some(
                    demo::SCENARIOS
                        .iter()
                        .map(|(n, _, d)| ufcsr::format::DemoScenario {
                            name: (*n).into(),
                            arrives: (*d).into(),
                        })
                        .collect(),
                ),
                ..ufcsr::format::SceneRecord::default()
            },
            vehicle,
            occluders: demo::intersection(),
            rig: demo::rig(),
            scenarios,
            warnings: Vec::new(),
            input_files: Vec::new(),
            fleet: Vec::new(),
            vehicle_path: None,
        }
    }

    /// The demo with a body of the family ([`crate::scene::family`]) in
    /// place of the truck: the scenarios stop it with its front bumper at
    /// the stop line, as they stop the truck, and the head turns to its
    /// middle. Dimensions no such body can have are refused naming the field.
    pub fn demo_with_body(body: BodyType, dims: &BodyDims) -> Result<Scene> {
        let vehicle = body_mesh(body, dims)?;
        let mut scene = Scene::demo();
        scene.scenarios = demo::SCENARIOS
            .iter()
            .filter_map(|(name, _, _)| demo::scenario_for_length(name, dims.length_m))
            .collect();
        scene.rig.look_at_vehicle = [0.0, 0.0, dims.height_m / 2.0];
        scene.vehicle = vehicle;
        scene.name = format!("demo, {}", body.name());
        scene.info.vehicle = Some(format!(
            "built-in {} ({} × {} × {} m; docs/vehicles.md)",
            body.name(),
            dims.length_m,
            dims.width_m,
            dims.height_m
        ));
        Ok(scene)
    }

    /// The demo with traffic, for one scenario (the adjacent lane's side
    /// depends on it): the demo scene holding only `scenario`, with the
    /// truck's twin following it ([`demo::DemoTraffic`]).
    pub fn demo_with_traffic(traffic: demo::DemoTraffic, scenario: &str) -> Result<Scene> {
        let mut scene = Scene::demo();
        let chosen = scene.scenario(scenario)?.clone();
        scene.occluders.moving.push(traffic.occluder(&chosen));
        scene.name = format!("demo, {}", traffic.name());
        let offset = traffic.offset(&chosen);
        scene.info.traffic = Some(ufcsr::format::TrafficRecord {
            name: traffic.name().into(),
            follow: ufcsr::format::FollowRecord {
                ahead_m: offset.ahead_m,
                left_m: offset.left_m,
                yaw_deg: offset.yaw_deg,
            },
        });
        scene.scenarios = vec![chosen];
        Ok(scene)
    }

    /// The Unity scenarios and rig replayed with the demo truck; the MCity
    /// environment is not available, so only a ground plane occludes.
    pub fn unity(path: &Path) -> Result<Scene> {
        let (rig, scenarios) = unity::load(path)?;
        let mut occluders = Occluders::default();
        occluders.begin_named("ground");
        add_ground(&mut occluders, rig.anchor().z, rig.anchor());
        Ok(Scene {
            name: "unity".into(),
            info: ufcsr::format::SceneRecord {
                name: "unity".into(),
                source: Some(path.display().to_string()),
                vehicle: Some("built-in pickup truck standing in for the Unity F-150".into()),
                environment: Some("ground plane only (MCity not available)".into()),
                ..ufcsr::format::SceneRecord::default()
            },
            vehicle: demo::truck(),
            occluders,
            rig,
            scenarios,
            warnings: Vec::new(),
            input_files: vec![path.to_path_buf()],
            fleet: Vec::new(),
            vehicle_path: None,
        })
    }

    /// Loads a scene file.
    pub fn load(path: &Path) -> Result<Scene> {
        let bytes = ufcsr::files::read_limited(path, ufcsr::files::SMALL_INPUT_LIMIT)?;
        Scene::parse(path, &bytes)
    }

    /// A scene from the bytes of the scene file `path` (which names it in
    /// messages; meshes and the `unity` file are read relative to its folder).
    pub fn parse(path: &Path, bytes: &[u8]) -> Result<Scene> {
        let file: SceneFile = serde_json::from_slice(bytes)
            .map_err(|e| CaptureError::bad_file(path, format!("invalid scene file: {e}")))?;
        let base = path.parent().unwrap_or(Path::new("."));
        let crate::scene::vehicle::Vehicle { mesh: vehicle, warnings, files, .. } =
            crate::scene::vehicle::build(&file.vehicle, base, path)?;
        let mut input_files = vec![path.to_path_buf()];
        input_files.extend(files);
        let (mut rig, mut scenarios) = match &file.unity {
            Some(unity_path) => {
                input_files.push(base.join(unity_path));
                unity::load(&base.join(unity_path))?
            }
            None => (Rig::default(), Vec::new()),
        };
        if let Some(own) = &file.rig {
            rig = own.clone();
        }
        rig.check().map_err(|e| CaptureError::bad_file(path, format!("rig: {e}")))?;
        if !file.scenarios.is_empty() {
            scenarios = own_scenarios(path, &file)?;
        }
        if scenarios.is_empty() {
            return Err(CaptureError::bad_file(
                path,
                "the scene has no scenarios (give \"scenarios\" or \"unity\")",
            ));
        }
        for scenario in &scenarios {
            crate::scene::scenario::check_frame_time(scenario, rig.fps, "rig.fps")
                .map_err(|message| CaptureError::bad_file(path, message))?;
        }

        let built = build_occluders(&file.occluders, path, &vehicle, &rig)?;
        let (occluders, mut warnings) = (built.occluders, warnings);
        input_files.extend(built.files);
        warnings.extend(built.warnings);
        let described = describe_vehicle(&file.vehicle);
        let fleet = crate::scene::fleet::fleet(path, &file.vehicle, &described, built.measured)?;
        let name = file.name.clone().unwrap_or_else(|| {
            path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_else(|| "scene".into())
        });
        Ok(Scene {
            info: ufcsr::format::SceneRecord {
                name: name.clone(),
                file: Some(path.display().to_string()),
                vehicle: Some(described),
                occluder_objects: Some(occluders.objects.len() as u64),
                moving_occluders: Some(occluders.moving.iter().map(|m| m.name.clone()).collect()),
                ..ufcsr::format::SceneRecord::default()
            },
            name,
            vehicle,
            occluders,
            rig,
            scenarios,
            warnings,
            input_files,
            fleet,
            vehicle_path: None,
        })
    }

    /// The scenario called `name` (case-insensitive).
    pub fn scenario(&self, name: &str) -> Result<&Scenario> {
        self.scenarios.iter().find(|s| s.name.eq_ignore_ascii_case(name)).ok_or_else(|| {
            let names: Vec<&str> = self.scenarios.iter().map(|s| s.name.as_str()).collect();
            CaptureError::BadOptions(format!("no scenario {name:?}; the scene has {}", names.join(", ")))
        })
    }
}

/// The scenarios a scene file gives itself, checked.
fn own_scenarios(path: &Path, file: &SceneFile) -> Result<Vec<Scenario>> {
    let mut scenarios = Vec::new();
    for (name, spec) in &file.scenarios {
        let motion = Motion { position: spec.position.clone(), yaw_deg: spec.yaw_deg.clone() };
        motion.check().map_err(|e| CaptureError::bad_file(path, format!("scenario {name}: {e}")))?;
        crate::scene::scenario::check_duration(spec.duration_s)
            .map_err(|message| CaptureError::bad_file(path, format!("scenario {name}: {message}")))?;
        scenarios.push(Scenario { name: name.clone(), duration_s: spec.duration_s, motion });
    }
    Ok(scenarios)
}

/// A vehicle in words, for the manifest: its mesh file, or the family body.
fn describe_vehicle(spec: &VehicleSpec) -> String {
    match &spec.body {
        Some(body) => format!("built-in {body} (docs/vehicles.md)"),
        None => spec.mesh.clone(),
    }
}

/// What a scene file's occluders became.
struct BuiltOccluders {
    occluders: Occluders,
    /// The files they read (meshes, and the files a `model` names).
    files: Vec<PathBuf>,
    /// The vehicles among them that are measured too (always moving
    /// occluders, a parked one on fixed tracks).
    measured: Vec<FleetVehicle>,
    /// Doubts about a `vehicle` occluder's own `model`, naming it.
    warnings: Vec<String>,
}

/// The scene file's occluders (the still ones in world coordinates, the
/// moving ones in their own frames, see [`crate::scene::moving`]).
fn build_occluders(specs: &[OccluderSpec], path: &Path, vehicle: &Mesh, rig: &Rig) -> Result<BuiltOccluders> {
    let base = path.parent().unwrap_or(Path::new("."));
    let mut occluders = Occluders::default();
    let mut files = Vec::new();
    let mut measured = Vec::new();
    let mut warnings = Vec::new();
    for (number, spec) in specs.iter().enumerate() {
        let name = spec.name(number);
        spec.check().map_err(|message| {
            let which = name.clone().unwrap_or_else(|| format!("#{number}"));
            CaptureError::bad_file(path, format!("occluders[{number}] ({which}): {message}"))
        })?;
        let own: Mesh = match &spec.shape {
            OccluderShape::Box { min, max } => {
                let mut mesh = Mesh::default();
                let (min, max) = (DVec3::from(*min).as_vec3(), DVec3::from(*max).as_vec3());
                mesh.add_box(min, max, [Some("box"); 6]);
                mesh
            }
            OccluderShape::Mesh { path: mesh_path, axes } => {
                let (mesh, mesh_files) = load_model(&base.join(mesh_path), PartSource::Node, axes)?;
                files.extend(mesh_files);
                mesh
            }
            OccluderShape::Vehicle { model: None, .. } => vehicle.clone(),
            OccluderShape::Vehicle { model: Some(model), .. } => {
                let which = format!("occluders[{number}] (vehicle #{number}) model");
                let built = crate::scene::vehicle::build(model, base, path).map_err(|error| match error {
                    CaptureError::BadFile { path, message } => {
                        CaptureError::bad_file(path, format!("{which}: {message}"))
                    }
                    other => other,
                })?;
                files.extend(built.files);
                warnings.extend(built.warnings.iter().map(|warning| format!("{which}: {warning}")));
                built.mesh
            }
            OccluderShape::Pedestrian { size_m } => crate::scene::moving::pedestrian_body(*size_m),
            OccluderShape::DemoIntersection => {
                occluders.append(&demo::intersection());
                continue;
            }
            OccluderShape::Ground { z } => {
                occluders.begin_named(name.unwrap_or_default());
                add_ground(&mut occluders, *z, rig.anchor());
                continue;
            }
        };
        let name = name.unwrap_or_default();
        let measure = match &spec.shape {
            OccluderShape::Vehicle { measure: Some(measure), model } => Some((measure, model)),
            _ => None,
        };
        if let Some((measure, model)) = measure {
            measured.push(FleetVehicle {
                name: measure.clone(),
                source: format!("occluders[{number}]"),
                moving: Some(occluders.moving.len()),
                described: model.as_deref().map(describe_vehicle),
            });
        }
        match spec.placement.path().or_else(|| measure.map(|_| spec.placement.fixed_path())) {
            Some(path) => occluders.moving.push(MovingOccluder { name, mesh: own, path }),
            None => {
                occluders.begin_named(name);
                let to_world = crate::scene::rig::vehicle_to_world(&spec.placement.fixed_pose());
                match spec.shape {
                    OccluderShape::Mesh { .. } => {
                        occluders.add_mesh_chunked(&own, to_world, ENVIRONMENT_CELL_M)
                    }
                    _ => occluders.add_mesh(&own, to_world),
                }
            }
        }
    }
    Ok(BuiltOccluders { occluders, files, measured, warnings })
}

/// Environment meshes are split into squares of this size for culling.
const ENVIRONMENT_CELL_M: f64 = 20.0;

/// A 400 m square ground plane at height `z` around `centre`.
fn add_ground(occluders: &mut Occluders, z: f64, centre: DVec3) {
    let mut ground = Mesh::default();
    let g = 200.0_f32;
    let (cx, cy, z) = (centre.x as f32, centre.y as f32, z as f32);
    let v = glam::vec3;
    ground.add_quad(
        "ground",
        v(cx - g, cy - g, z),
        v(cx + g, cy - g, z),
        v(cx + g, cy + g, z),
        v(cx - g, cy + g, z),
    );
    occluders.add_mesh(&ground, DMat4::IDENTITY);
}
