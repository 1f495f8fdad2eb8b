//! One cell's scene: the level's vehicle in the level's scenario with the
//! level's traffic, built the way a capture builds it (the demo's
//! intersection and traffic, the street generator, a scene file), so a task
//! measures exactly what `ufcsr capture … --measure unobstructed` would.

use std::path::Path;

use ufcsr::{CellLevels, Design, ScenarioSource, TrafficKind, VehicleLevel};

use crate::error::{CaptureError, Result};
use crate::scene::Scene;
use crate::scene::demo::{self, DemoTraffic};
use crate::scene::family::{BodyDims, BodyType, body_mesh};
use crate::scene::mesh::{Axes, Mesh, PartSource, load_vehicle};
use crate::scene::street::{StreetOptions, street_scene};

/// The vehicle of a level: a model file, the demo pickup, or a family body.
pub fn vehicle_mesh(level: &VehicleLevel, base: &Path) -> Result<Mesh> {
    if let Some(model) = &level.model {
        if model == "demo" {
            return Ok(demo::truck());
        }
        return load_vehicle(&base.join(model), PartSource::default(), &Axes::default());
    }
    let name = level.body.as_deref().unwrap_or_default();
    let body = BodyType::parse(name).ok_or_else(|| {
        CaptureError::BadOptions(format!("vehicle {:?}: unknown body {name:?}", level.name))
    })?;
    let dims = BodyDims::typical(body).with(&level.dims.unwrap_or_default());
    body_mesh(body, &dims)
}

/// The scene of `cell`; `traffic_seed` places generated traffic.
pub fn cell_scene(design: &Design, base: &Path, cell: &CellLevels, traffic_seed: u64) -> Result<Scene> {
    let missing = |factor: &str, name: &str| CaptureError::BadOptions(format!("no {factor} level {name:?}"));
    let vehicle = design.vehicles.iter().find(|v| v.name == cell.vehicle);
    let vehicle = vehicle.ok_or_else(|| missing("vehicle", &cell.vehicle))?;
    let scenario = design.scenarios.iter().find(|s| s.name == cell.scenario);
    let scenario = scenario.ok_or_else(|| missing("scenario", &cell.scenario))?;
    let traffic = design.traffic.iter().find(|t| t.name == cell.traffic);
    let traffic = traffic.ok_or_else(|| missing("traffic", &cell.traffic))?;
    let mesh = vehicle_mesh(vehicle, base)?;
    let mut scene = match (&scenario.source, &traffic.kind) {
        (ScenarioSource::Demo { scenario }, kind) => {
            let demo_traffic = match kind {
                TrafficKind::AdjacentLane => Some(DemoTraffic::AdjacentLane),
                TrafficKind::LeadCar => Some(DemoTraffic::LeadCar),
                _ => None,
            };
            let mut scene = match demo_traffic {
                Some(t) => Scene::demo_with_traffic(t, scenario)?,
                None => {
                    let mut scene = Scene::demo();
                    let chosen = scene.scenario(scenario)?.clone();
                    scene.scenarios = vec![chosen];
                    scene
                }
            };
            // The demo's traffic is the subject's twin: the level's vehicle.
            scene.occluders.moving.iter_mut().for_each(|m| m.mesh = mesh.clone());
            scene
        }
        (ScenarioSource::Street(street), kind) => {
            let others = if let TrafficKind::Generated { vehicles } = kind { *vehicles } else { 0 };
            let options = StreetOptions {
                position: street.position,
                pedestrian: street.pedestrian,
                speed_mps: street.speed_mps,
                others,
                seed: traffic_seed,
            };
            street_as_scene(&mesh, &options)?
        }
        (ScenarioSource::Scene { file, scenario }, _) => {
            let mut scene = Scene::load(&base.join(file))?;
            let chosen = scene.scenario(scenario)?.clone();
            scene.scenarios = vec![chosen];
            scene
        }
    };
    // A design's answer is about people: where the scene kept the paper's eyes, a median adult's
    // (a design's population, when it has one, draws each observer's own; issue 42 §6).
    crate::scene::people_by_default(&mut scene.rig);
    scene.vehicle = mesh;
    scene.name = format!("{} / {} / {}", cell.vehicle, cell.scenario, cell.traffic);
    scene.info.name = scene.name.clone();
    scene.info.vehicle = Some(vehicle.body.clone().or(vehicle.model.clone()).unwrap_or_default());
    Ok(scene)
}

/// The street generator's parts as a scene.
fn street_as_scene(mesh: &Mesh, options: &StreetOptions) -> Result<Scene> {
    let (occluders, rig, scenario) = street_scene(mesh, options)?;
    Ok(Scene {
        name: scenario.name.clone(),
        vehicle: mesh.clone(),
        info: ufcsr::SceneRecord {
            name: scenario.name.clone(),
            environment: Some(
                "the raycasting study's street (two-way two-lane, walkways, alleyways; docs/design.md)"
                    .into(),
            ),
            ..ufcsr::SceneRecord::default()
        },
        occluders,
        rig,
        scenarios: vec![scenario],
        warnings: Vec::new(),
        input_files: Vec::new(),
    })
}
