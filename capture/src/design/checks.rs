//! What a design's tasks will read, checked once before any task runs (issue 41 §2).
//!
//! [`super::plan`] checks the design file alone; a design whose every task
//! then failed (a missing, FIFO, `/dev/zero` or folder `model`, a missing
//! scene file or scenario, dims the body family cannot build, a palette the
//! body does not fit) still planned with exit 0, and a Slurm array started on
//! it. [`check_inputs`] does here what `run` will do, without measuring: it
//! loads each vehicle level once through the file layer, unwraps it into the
//! design's palette, builds every cell's scene and draws its observers. The
//! same pass gives `merge` each cell's longest possible legible time
//! ([`CellLimits`]), against which a task's values are checked, and
//! [`input_hashes`](super::plan::input_hashes) fingerprints the files a task read, so a merge can refuse
//! tasks run before and after a model was replaced.

use std::collections::BTreeMap;
use std::path::PathBuf;

use ufcsr::format::CellLevels;

use super::build::{cell_scene_with, vehicle_model};
use super::plan::Plan;
use super::run::derived_seed;
use crate::error::{CaptureError, Result};
use crate::scene::mesh::Mesh;

/// Per cell, the most seconds one candidate can be legible: the measured frames (every
/// `frame_step`-th of the scenario's) times the seconds each stands for.
pub(crate) type CellLimits = BTreeMap<CellLevels, f64>;

/// Loads every vehicle level, unwraps it into the palette and builds every cell's scene with its
/// observers, as `run` will: an error names the design file, the level or cell, and the cause.
/// Returns each cell's [`CellLimits`].
pub fn check_inputs(plan: &Plan) -> Result<CellLimits> {
    let design = &plan.design;
    let bad = |message: String| CaptureError::bad_file(&plan.path, message);
    let palette = design.measure.palette;
    let mut models: BTreeMap<&str, (Mesh, Vec<PathBuf>)> = BTreeMap::new();
    for (i, level) in design.vehicles.iter().enumerate() {
        let at = format!("vehicles[{i}] {:?}", level.name);
        let (mesh, files) = vehicle_model(level, plan.base()).map_err(|e| bad(format!("{at}: {e}")))?;
        crate::texture::uv_islands::unwrap_islands(&mesh, [palette, palette])
            .map_err(|e| bad(format!("{at} in measure.palette {palette}: {e}")))?;
        models.insert(level.name.as_str(), (mesh, files));
    }
    let mut limits = CellLimits::new();
    for task in &plan.tasks {
        if limits.contains_key(&task.cell) {
            continue;
        }
        let cell = &task.cell;
        let model = models
            .get(cell.vehicle.as_str())
            .cloned()
            .ok_or_else(|| bad(format!("cell {cell}: no vehicle")))?;
        let seed = derived_seed(design.seed, 3, &[u64::from(task.replicate)]);
        let scene = cell_scene_with(design, plan.base(), cell, seed, model)
            .map_err(|e| bad(format!("cell {cell}: {e}")))?;
        super::run::units(plan, task, &scene).map_err(|e| bad(format!("cell {cell}: population: {e}")))?;
        let scenario = scene.scenarios.first().ok_or_else(|| bad(format!("cell {cell}: no scenario")))?;
        let frames = scene.rig.frame_count(scenario.duration_s).max(1);
        let step = design.measure.frame_step.max(1);
        let measured = crate::job::FrameSelection::every(step).frames(frames).len();
        if frames > 1 && measured < 2 {
            // A lone frame stands for one frame's 1/fps, not for the scenario.
            return Err(bad(format!(
                "cell {cell}: measure.frame_step {step} keeps one frame of the scenario's {frames} ({} s at {} \
                 fps), which would stand for 1/{} s; use at most {}",
                scenario.duration_s,
                scene.rig.fps,
                scene.rig.fps,
                crate::job::longest_step_keeping_two(frames).unwrap_or(1)
            )));
        }
        limits.insert(cell.clone(), measured as f64 * f64::from(step) / scene.rig.fps);
    }
    Ok(limits)
}
