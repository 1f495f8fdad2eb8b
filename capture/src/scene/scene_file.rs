//! The JSON scene file: vehicle, occluders, rig and scenarios.
//!
//! Paths are relative to the scene file. See `capture/README.md` for the
//! reference; `fixtures/scenes/` has examples. A loaded scene is the same
//! whether it came from a file, from the built-in demo or from a Unity export.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use glam::{DMat4, DVec3};
use serde::{Deserialize, Serialize};
use serde_json::json;

use crate::error::{CaptureError, Result};
use crate::scene::demo;
use crate::scene::mesh::{Axes, Mesh, Occluders, PartSource, load_model};
use crate::scene::rig::Rig;
use crate::scene::scenario::Scenario;
use crate::scene::track::{Motion, Pose};
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

/// Something that hides the vehicle but is never counted.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum OccluderSpec {
    /// An axis-aligned box in world coordinates.
    Box { min: [f64; 3], max: [f64; 3] },
    /// An environment mesh, placed by position and yaw.
    Mesh {
        path: PathBuf,
        #[serde(default)]
        axes: Axes,
        #[serde(default)]
        position: [f64; 3],
        #[serde(default)]
        yaw_deg: f64,
    },
    /// Another copy of the vehicle, parked.
    Vehicle { position: [f64; 3], yaw_deg: f64 },
    /// The demo's ground and corner buildings.
    DemoIntersection,
    /// A ground plane at height `z` (hides the underside of the vehicle).
    Ground { z: f64 },
}

impl OccluderSpec {
    /// The occluder's node name in `scene.glb`: its kind and number in the
    /// scene file; `None` for the demo intersection, which names its own.
    fn name(&self, number: usize) -> Option<String> {
        let name = match self {
            OccluderSpec::Box { .. } => format!("box #{number}"),
            OccluderSpec::Mesh { path, .. } => format!("mesh #{number} {}", path.display()),
            OccluderSpec::Vehicle { .. } => format!("vehicle #{number}"),
            OccluderSpec::Ground { .. } => format!("ground #{number}"),
            OccluderSpec::DemoIntersection => return None,
        };
        Some(name)
    }

    /// Positions and yaw within the tracks' street scale (as the rig's).
    fn check(&self) -> std::result::Result<(), String> {
        let limit = crate::scene::track::MAX_TRACK_MAGNITUDE;
        let values: Vec<f64> = match self {
            OccluderSpec::Box { min, max } => min.iter().chain(max).copied().collect(),
            OccluderSpec::Mesh { position, yaw_deg, .. } | OccluderSpec::Vehicle { position, yaw_deg } => {
                position.iter().copied().chain([*yaw_deg]).collect()
            }
            OccluderSpec::Ground { z } => vec![*z],
            OccluderSpec::DemoIntersection => Vec::new(),
        };
        match values.iter().find(|v| !(v.is_finite() && v.abs() <= limit)) {
            Some(value) => Err(format!("{value:e} is beyond ±{limit:e}: not a street scene")),
            None => Ok(()),
        }
    }
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
    pub info: serde_json::Value,
    /// Doubts about the vehicle (size, axes, origin, part rules) to show the user.
    pub warnings: Vec<String>,
    /// Every file the scene was read from (scene file, meshes and the files
    /// they name, Unity export): a capture refuses to write over any of them.
    pub input_files: Vec<PathBuf>,
}

impl Scene {
    /// The built-in demo: truck, intersection, scenarios A–D.
    pub fn demo() -> Scene {
        let scenarios = demo::SCENARIOS.iter().filter_map(|(name, _, _)| demo::scenario(name)).collect();
        let vehicle = demo::truck();
        Scene {
            name: "demo".into(),
            info: json!({
                "name": "demo",
                "vehicle": "built-in pickup truck (5.9 × 2.0 × 1.9 m)",
                "environment": "four-way intersection with corner buildings; pedestrian at the south-west corner",
                "scenarios": demo::SCENARIOS.iter().map(|(n, _, d)| json!({"name": n, "arrives": d})).collect::<Vec<_>>(),
            }),
            vehicle,
            occluders: demo::intersection(),
            rig: demo::rig(),
            scenarios,
            warnings: Vec::new(),
            input_files: Vec::new(),
        }
    }

    /// The Unity scenarios and rig replayed with the demo truck; the MCity
    /// environment is not available, so only a ground plane occludes.
    pub fn unity(path: &Path) -> Result<Scene> {
        let (rig, scenarios) = unity::load(path)?;
        let mut occluders = Occluders::default();
        occluders.begin_named("ground");
        add_ground(&mut occluders, rig.pedestrian[2], DVec3::from(rig.pedestrian));
        Ok(Scene {
            name: "unity".into(),
            info: json!({
                "name": "unity",
                "source": path.display().to_string(),
                "vehicle": "built-in pickup truck standing in for the Unity F-150",
                "environment": "ground plane only (MCity not available)",
            }),
            vehicle: demo::truck(),
            occluders,
            rig,
            scenarios,
            warnings: Vec::new(),
            input_files: vec![path.to_path_buf()],
        })
    }

    /// Loads a scene file.
    pub fn load(path: &Path) -> Result<Scene> {
        let bytes = ufcsr::read_limited(path, ufcsr::SMALL_INPUT_LIMIT)?;
        Scene::parse(path, &bytes)
    }

    /// A scene from the bytes of the scene file `path` (which names it in
    /// messages; meshes and the `unity` file are read relative to its folder).
    pub fn parse(path: &Path, bytes: &[u8]) -> Result<Scene> {
        let file: SceneFile = serde_json::from_slice(bytes)
            .map_err(|e| CaptureError::bad_input(path, format!("invalid scene file: {e}")))?;
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
        rig.check().map_err(|e| CaptureError::bad_input(path, format!("rig: {e}")))?;
        if !file.scenarios.is_empty() {
            scenarios = own_scenarios(path, &file)?;
        }
        if scenarios.is_empty() {
            return Err(CaptureError::bad_input(
                path,
                "the scene has no scenarios (give \"scenarios\" or \"unity\")",
            ));
        }
        let (occluders, occluder_files) = build_occluders(&file, base, path, &vehicle, &rig)?;
        input_files.extend(occluder_files);
        let name = file.name.clone().unwrap_or_else(|| {
            path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_else(|| "scene".into())
        });
        Ok(Scene {
            info: json!({
                "name": name,
                "file": path.display().to_string(),
                "vehicle": file.vehicle.mesh,
                "occluder_objects": occluders.objects.len(),
            }),
            name,
            vehicle,
            occluders,
            rig,
            scenarios,
            warnings,
            input_files,
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
        motion.check().map_err(|e| CaptureError::bad_input(path, format!("scenario {name}: {e}")))?;
        crate::scene::scenario::check_duration(spec.duration_s)
            .map_err(|message| CaptureError::bad_input(path, format!("scenario {name}: {message}")))?;
        scenarios.push(Scenario { name: name.clone(), duration_s: spec.duration_s, motion });
    }
    Ok(scenarios)
}

/// The scene file's occluders, with the mesh files they read.
fn build_occluders(
    file: &SceneFile,
    base: &Path,
    path: &Path,
    vehicle: &Mesh,
    rig: &Rig,
) -> Result<(Occluders, Vec<PathBuf>)> {
    let mut occluders = Occluders::default();
    let mut files = Vec::new();
    for (number, spec) in file.occluders.iter().enumerate() {
        spec.check().map_err(|message| CaptureError::bad_input(path, format!("occluder: {message}")))?;
        if let Some(name) = spec.name(number) {
            occluders.begin_named(name);
        }
        match spec {
            OccluderSpec::Box { min, max } => occluders.add_box(DVec3::from(*min), DVec3::from(*max)),
            OccluderSpec::Mesh { path: mesh_path, axes, position, yaw_deg } => {
                let (mesh, mesh_files) = load_model(&base.join(mesh_path), PartSource::Node, axes)?;
                files.extend(mesh_files);
                let pose = Pose { position: DVec3::from(*position), yaw_deg: *yaw_deg };
                occluders.add_mesh_chunked(
                    &mesh,
                    crate::scene::rig::vehicle_to_world(&pose),
                    ENVIRONMENT_CELL_M,
                );
            }
            OccluderSpec::Vehicle { position, yaw_deg } => {
                let pose = Pose { position: DVec3::from(*position), yaw_deg: *yaw_deg };
                occluders.add_mesh(vehicle, crate::scene::rig::vehicle_to_world(&pose));
            }
            OccluderSpec::DemoIntersection => occluders.append(&demo::intersection()),
            OccluderSpec::Ground { z } => add_ground(&mut occluders, *z, DVec3::from(rig.pedestrian)),
        }
    }
    Ok((occluders, files))
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
