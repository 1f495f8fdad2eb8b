//! Running tasks: one cell and replicate measured from each drawn observer
//! by the exact measure with candidate placements (what `ufcsr capture …
//! --measure unobstructed --placement` does), each candidate scored with the
//! placement rules (legible seconds, `docs/placement.md`) and its angular
//! area summed, written as `tasks/task-NNNN/task.json` last, atomically: a
//! task whose `task.json` is there and of this design is complete, and a
//! re-run skips it; anything else (absent, partial, failed, another design)
//! is measured again.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

use ufcsr::{
    format::CandidateValue, format::DESIGN_TASK_SCHEMA, format::DesignTask, format::ObserverSampling,
    format::UnitValues, placement::Thresholds,
};

use super::build::cell_scene;
use super::plan::{Plan, PlannedTask};
use crate::error::{CaptureError, Result};
use crate::exact::measure::measure_unobstructed;
use crate::exact::types::{DEG2_PER_SR, MeasureOptions, PlacementCandidates};
use crate::job::{CaptureOptions, FrameSelection};
use crate::scene::Scene;
use crate::scene::track::ValueOrTrack;
use crate::study::observers::population::sample_observers;

/// The task file's name inside its folder.
pub const TASK_FILE: &str = "task.json";

/// The folder of task `index` under `out`.
pub fn task_dir(out: &Path, index: u32) -> PathBuf {
    out.join(task_relative(index))
}

/// [`task_dir`] relative to the output folder.
pub(crate) fn task_relative(index: u32) -> PathBuf {
    Path::new("tasks").join(format!("task-{index:04}"))
}

/// True when `tasks/`, the task's folder or its `task.json` is a link: nothing of the task is
/// read or written through one (a link planted there points outside the output folder).
pub(crate) fn task_behind_link(out: &Path, index: u32) -> bool {
    let file = task_relative(index).join(TASK_FILE);
    ufcsr::files::crosses_link(out, &file)
        || std::fs::symlink_metadata(out.join(&file)).is_ok_and(|m| m.file_type().is_symlink())
}

/// A seed derived from the design's, for one purpose and numbers (SplitMix64 steps).
pub fn derived_seed(seed: u64, purpose: u64, numbers: &[u64]) -> u64 {
    let mut z = seed ^ purpose.wrapping_mul(0x9E37_79B9_7F4A_7C15);
    for &n in numbers {
        z = z.wrapping_add(n.wrapping_add(1).wrapping_mul(0xBF58_476D_1CE4_E5B9));
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
    }
    z
}

/// The task already complete in `out`, when its file is there, reads and is of this design.
pub(crate) fn completed(plan: &Plan, out: &Path, index: u32) -> Option<DesignTask> {
    if task_behind_link(out, index) {
        return None;
    }
    let path = task_dir(out, index).join(TASK_FILE);
    let bytes = ufcsr::files::read_limited(&path, ufcsr::files::SMALL_INPUT_LIMIT).ok()?;
    let task: DesignTask = ufcsr::format::parse_json(&path, &bytes, "design task").ok()?;
    (task.schema == DESIGN_TASK_SCHEMA && task.design_hash == plan.hash && task.task == index).then_some(task)
}

/// One drawn observer: where, how tall, and the texel sample's seed.
pub(super) struct Unit {
    position: Option<[f64; 3]>,
    eye_height_m: f64,
    seed: u64,
}

/// The task's observers: drawn from the design's population, or the scene's own pedestrian.
pub(super) fn units(plan: &Plan, task: &PlannedTask, scene: &Scene) -> Result<Vec<Unit>> {
    let design = &plan.design;
    let seed = |unit: u32| derived_seed(design.seed, 2, &[u64::from(task.replicate), u64::from(unit)]);
    let Some(population) = &design.population else {
        return Ok(vec![Unit { position: None, eye_height_m: scene.rig.eye_height_m, seed: seed(0) }]);
    };
    let sampling = ObserverSampling::Random {
        observers: population.observers,
        seed: derived_seed(design.seed, 1, &[u64::from(task.replicate)]),
    };
    let rig_place = population.population.place == ufcsr::format::ObserverPlace::Rig;
    let drawn = sample_observers(&population.population, &sampling, scene.rig.anchor().to_array())?;
    Ok(drawn
        .iter()
        .zip(0..)
        .map(|(o, i)| Unit {
            position: (!rig_place).then_some(o.position),
            eye_height_m: o.eye_height_m,
            seed: seed(i),
        })
        .collect())
}

/// Per candidate: legible seconds under the default rules, in all and inside the decision window,
/// and angular area, deg²·s per eye. The seconds are the placement's own, from the same code
/// (`ufcsr::placement::timelines` and `ArchiveTimelines::exposure`, which `ufcsr placement` reports
/// as `legible_s` and `decision_window_legible_s`): the dwell applies, and the window ends at the
/// frame of the smallest vehicle–pedestrian distance.
pub fn candidate_values(table: ufcsr::placement::PlacementTable) -> Vec<CandidateValue> {
    let table = Arc::new(table);
    let eyes = table.eyes.len().max(1) as f64;
    let scored = ufcsr::placement::timelines(table.clone(), &Thresholds::default());
    scored
        .timelines
        .iter()
        .map(|t| {
            let rows = &table.candidates[&t.name];
            let sr: f64 = rows.sightings.values().map(|s| s.solid_angle_sr).sum();
            let exposure = scored.exposure(t);
            CandidateValue {
                name: t.name.clone(),
                kind: t.kind.name().to_string(),
                legible_s: exposure.legible_s,
                decision_window_legible_s: exposure.decision_window_legible_s,
                angular_area_deg2_s: sr * DEG2_PER_SR * table.frame_s / eyes,
            }
        })
        .collect()
}

/// Measures one unit into `out` and scores its candidates.
fn measure_unit(
    (device, queue): (&wgpu::Device, &wgpu::Queue),
    plan: &Plan,
    scene: &Scene,
    (unit, display_m): (&Unit, Option<[f64; 2]>),
    out: &Path,
) -> Result<Vec<CandidateValue>> {
    let measure = &plan.design.measure;
    let mut scene = scene.clone();
    if let Some(p) = unit.position {
        scene.rig.pedestrian = ValueOrTrack::Fixed(p);
    }
    scene.rig.eye_height_m = unit.eye_height_m;
    let scenario = scene.scenarios[0].clone();
    let options = CaptureOptions {
        out: out.to_path_buf(),
        palette: [measure.palette, measure.palette],
        frames: FrameSelection::every(measure.frame_step),
        views_scale: 1,
        ..CaptureOptions::default()
    };
    let candidates = PlacementCandidates {
        display_m,
        spacing_m: measure.patch_spacing_m.unwrap_or(crate::exact::types::DEFAULT_PATCH_SPACING_M),
    };
    let measure_options = MeasureOptions {
        sample: measure.sample,
        seed: unit.seed,
        placement: Some(candidates),
        ..MeasureOptions::default()
    };
    let measured = measure_unobstructed(device, queue, &scene, &scenario, &options, &measure_options)?;
    let written = measured.placement.ok_or_else(|| CaptureError::BadOptions("no placement table".into()))?;
    let mut values = candidate_values(ufcsr::placement::read_table(&written.csv)?);
    let laid_out = ufcsr::placement::read_footprints(&written.csv)?;
    add_unseen_patches(&mut values, laid_out.keys());
    Ok(values)
}

/// Adds a zero for every display patch of the layout (`placement-patches.csv`) that the table
/// lacks: the table has rows only for patches some eye saw, but the layout is the vehicle's alone
/// (not the unit's texel sample), so a patch this unit never saw is there with 0 s, and every unit
/// of a vehicle names the same patches.
pub(crate) fn add_unseen_patches<'a>(
    values: &mut Vec<CandidateValue>,
    laid_out: impl Iterator<Item = &'a String>,
) {
    let seen: std::collections::BTreeSet<String> = values.iter().map(|v| v.name.clone()).collect();
    for name in laid_out.filter(|name| !seen.contains(*name)) {
        values.push(CandidateValue {
            name: name.clone(),
            kind: "patch".into(),
            legible_s: 0.0,
            decision_window_legible_s: 0.0,
            angular_area_deg2_s: 0.0,
        });
    }
}

/// Runs task `task` of `plan` into `out` and writes its `task.json`.
pub fn run_task(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    plan: &Plan,
    task: &PlannedTask,
    out: &Path,
) -> Result<DesignTask> {
    let start = Instant::now();
    let design = &plan.design;
    let traffic_seed = derived_seed(design.seed, 3, &[u64::from(task.replicate)]);
    let scene = cell_scene(design, plan.base(), &task.cell, traffic_seed)?;
    let inputs = super::plan::input_hashes(plan.base(), &scene.input_files)?;
    let level = design.vehicles.iter().find(|v| v.name == task.cell.vehicle);
    let display_m = level.and_then(|v| v.display_m);
    // Real folders, never links: a link planted at `tasks` or `task-NNNN` is replaced.
    ufcsr::files::create_output_dir(out)?;
    let dir = ufcsr::files::output_sub_dir(out, &task_relative(task.index))?;
    let drawn = units(plan, task, &scene)?;
    let per_task = drawn.len() as u32;
    let mut values = Vec::with_capacity(drawn.len());
    for (i, unit) in drawn.iter().enumerate() {
        let unit_dir = ufcsr::files::output_sub_dir(&dir, Path::new(&format!("unit-{i:03}")))?;
        let candidates = measure_unit((device, queue), plan, &scene, (unit, display_m), &unit_dir)?;
        values.push(UnitValues {
            unit: task.replicate * per_task + i as u32,
            eye_height_m: unit.eye_height_m,
            position: unit.position.unwrap_or_else(|| scene.rig.anchor().to_array()),
            seed: unit.seed,
            candidates,
        });
    }
    let result = DesignTask {
        schema: DESIGN_TASK_SCHEMA.into(),
        design_hash: plan.hash.clone(),
        task: task.index,
        cell: task.cell.clone(),
        replicate: task.replicate,
        units: values,
        seconds: start.elapsed().as_secs_f64(),
        inputs,
    };
    write_task(&result, &dir)?;
    Ok(result)
}

/// Writes `task.json` into `dir`, atomically (a link at `dir` is replaced by a real folder;
/// [`run_task`] has made the folders above real).
pub fn write_task(task: &DesignTask, dir: &Path) -> Result<PathBuf> {
    ufcsr::files::real_dir(dir)?;
    let path = dir.join(TASK_FILE);
    let json = serde_json::to_vec_pretty(task).map_err(|e| CaptureError::bad_file(&path, e.to_string()))?;
    ufcsr::files::write_bytes_atomically(&path, &json)?;
    Ok(path)
}
