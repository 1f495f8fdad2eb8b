//! Studies, not runs (issue 36): one design file for vehicles × scenarios ×
//! traffic × pedestrians, planned into independent tasks, run locally or as
//! a Slurm array, merged into one placement answer per body type.
//!
//! The folder: [`plan`] reads and checks the design (every refusal names
//! the factor and level) and lists its tasks (cell × replicate) under the
//! design's hash; [`build`] makes one cell's scene (the demo intersection
//! with its traffic, the street generator, a scene file; the level's
//! vehicle from a model or the parametric family); [`run`] measures a task
//! from each drawn observer with the exact measure and candidate placements
//! and scores them with the placement rules, writing `task.json` last, so a
//! re-run skips complete tasks; [`stats`] the merge's arithmetic (intervals
//! over the random units, P(best), main effects); [`merge`] reads every task,
//! refusing another design's and naming missing cells; [`report`] writes
//! `design.json`, `design.csv` and `design.html`. [`checks`] loads what the
//! tasks will read before any runs (and gives merge each cell's bounds),
//! [`task_checks`] checks every value a merge reads, [`output`] writes the
//! result files as one set. `docs/design.md` is the user's page.

pub(crate) mod build;
pub(crate) mod checks;
#[cfg(test)]
mod checks_tests;
pub(crate) mod merge;
pub(crate) mod output;
pub(crate) mod plan;
pub(crate) mod report;
pub(crate) mod run;
pub(crate) mod stats;
pub(crate) mod task_checks;
#[cfg(test)]
mod tests;

pub use checks::check_inputs as check_design_inputs;
pub use merge::{merge_design, read_tasks};
pub use output::write_result_set as write_design_result_set;
pub use plan::{MAX_TASKS, Plan, PlannedTask, plan_checked, plan_design};
pub use report::write_result as write_design_result;
pub use run::{TASK_FILE, candidate_values, derived_seed, run_task, task_dir, write_task};
pub use stats::{
    CellData, INTERVAL_METHOD, Pair, cell_data, group_summary, main_effects, mean_interval, p_best,
};
pub use task_checks::check_task as check_design_task;

use std::path::Path;

use ufcsr::format::DesignTask;

use crate::error::Result;

/// What [`run_design`] did with each task.
#[derive(Debug, Clone, PartialEq)]
pub enum TaskOutcome {
    /// Already complete in the output folder: skipped.
    Skipped(u32),
    /// Measured now.
    Ran(DesignTask),
}

/// Runs `only` one task, or every task of `plan`, into `out`, skipping the
/// complete ones (resumable); `report` hears of each as it finishes.
pub fn run_design(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    plan: &Plan,
    only: Option<u32>,
    out: &Path,
    mut report: impl FnMut(&TaskOutcome),
) -> Result<Vec<TaskOutcome>> {
    if let Some(index) = only
        && index as usize >= plan.tasks.len()
    {
        return Err(crate::error::CaptureError::BadOptions(format!(
            "--task {index}: the design has tasks 0 to {}",
            plan.tasks.len().saturating_sub(1)
        )));
    }
    let mut outcomes = Vec::new();
    for task in plan.tasks.iter().filter(|t| only.is_none_or(|i| i == t.index)) {
        let outcome = match run::completed(plan, out, task.index) {
            Some(_) => TaskOutcome::Skipped(task.index),
            None => TaskOutcome::Ran(run::run_task(device, queue, plan, task, out)?),
        };
        report(&outcome);
        outcomes.push(outcome);
    }
    Ok(outcomes)
}
