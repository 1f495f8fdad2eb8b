//! One cell's scene: the level's vehicle in the level's scenario with the
//! level's traffic, built the way a capture builds it (the demo's
//! intersection and traffic, the street generator, a scene file), so a task
//! measures exactly what `ufcsr capture … --measure unobstructed` would.

use std::path::{Path, PathBuf};

use ufcsr::{
    format::CellLevels, format::Design, format::ScenarioSource, format::TrafficKind, format::VehicleLevel,
};

use crate::error::{CaptureError, Result};
use crate::scene::Scene;
use crate::scene::demo::{self, DemoTraffic};
use crate::scene::family::{BodyDims, BodyType, body_mesh};
use crate::scene::mesh::{Axes, Mesh, PartSource, load_model};
use crate::scene::street::{StreetOptions, street_scene};

/// The vehicle of a level (a model file, the demo pickup, or a family body), with every file it read (the model and its buffers or MTL files; none for
/// the demo pickup and a family body).
pub(crate) fn vehicle_model(level: &VehicleLevel, base: &Path) -> Result<(Mesh, Vec<PathBuf>)> {
    if let Some(model) = &level.model {
        if model == "demo" {
            return Ok((demo::truck(), Vec::new()));
        }
        return load_model(&base.join(model), PartSource::default(), &Axes::default());
    }
    let name = level.body.as_deref().unwrap_or_default();
    let body = BodyType::parse(name).ok_or_else(|| {
        CaptureError::BadOptions(format!("vehicle {:?}: unknown body {name:?}", level.name))
    })?;
    let dims = BodyDims::typical(body).with(&level.dims.unwrap_or_default());
    Ok((body_mesh(body, &dims)?, Vec::new()))
}

/// The scene of `cell`; `traffic_seed` places generated traffic.
pub(crate) fn cell_scene(
    design: &Design,
    base: &Path,
    cell: &CellLevels,
    traffic_seed: u64,
) -> Result<Scene> {
    let vehicle = design.vehicles.iter().find(|v| v.name == cell.vehicle);
    let vehicle =
        vehicle.ok_or_else(|| CaptureError::BadOptions(format!("no vehicle level {:?}", cell.vehicle)))?;
    cell_scene_with(design, base, cell, traffic_seed, vehicle_model(vehicle, base)?)
}

/// [`cell_scene`] with the level's vehicle already loaded ([`vehicle_model`]): the scene's
/// `input_files` are every file the cell read (the model's and a scene file's).
pub(crate) fn cell_scene_with(
    design: &Design,
    base: &Path,
    cell: &CellLevels,
    traffic_seed: u64,
    (mesh, model_files): (Mesh, Vec<PathBuf>),
) -> Result<Scene> {
    let missing = |factor: &str, name: &str| CaptureError::BadOptions(format!("no {factor} level {name:?}"));
    let vehicle = design.vehicles.iter().find(|v| v.name == cell.vehicle);
    let vehicle = vehicle.ok_or_else(|| missing("vehicle", &cell.vehicle))?;
    let scenario = design.scenarios.iter().find(|s| s.name == cell.scenario);
    let scenario = scenario.ok_or_else(|| missing("scenario", &cell.scenario))?;
    let traffic = design.traffic.iter().find(|t| t.name == cell.traffic);
    let traffic = traffic.ok_or_else(|| missing("traffic", &cell.traffic))?;
    let mut scene = match (&scenario.source, &traffic.kind) {
        (ScenarioSource::Demo { scenario }, kind) => demo_scene(scenario, kind, &mesh)?,
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
            scene.refuse_fleet("a design cell (its level names the vehicle)")?;
            let chosen = scene.scenario(scenario)?.clone();
            scene.scenarios = vec![chosen];
            scene
        }
    };
    // A design's answer is about people: where the scene kept the paper's eyes, a median adult's
    // (a design's population, when it has one, draws each observer's own; issue 42 §6).
    crate::study::observers::people_by_default(&mut scene.rig);
    scene.vehicle = mesh;
    scene.input_files.extend(model_files);
    scene.name = format!("{} / {} / {}", cell.vehicle, cell.scenario, cell.traffic);
    scene.info.name = scene.name.clone();
    scene.info.vehicle = Some(vehicle.body.clone().or(vehicle.model.clone()).unwrap_or_default());
    Ok(scene)
}

/// The demo intersection's `scenario` with the level's `kind` of traffic: the twin is `mesh`.
fn demo_scene(scenario: &str, kind: &TrafficKind, mesh: &Mesh) -> Result<Scene> {
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
    Ok(scene)
}

/// The street generator's parts as a scene.
fn street_as_scene(mesh: &Mesh, options: &StreetOptions) -> Result<Scene> {
    let (occluders, rig, scenario) = street_scene(mesh, options)?;
    Ok(Scene {
        name: scenario.name.clone(),
        vehicle: mesh.clone(),
        info: ufcsr::format::SceneRecord {
            name: scenario.name.clone(),
            environment: Some(
                "the raycasting study's street (two-way two-lane, walkways, alleyways; docs/design.md)"
                    .into(),
            ),
            ..ufcsr::format::SceneRecord::default()
        },
        occluders,
        rig,
        scenarios: vec![scenario],
        warnings: Vec::new(),
        input_files: Vec::new(),
        fleet: Vec::new(),
        vehicle_path: None,
    })
}
