//! The values of every `task.json` a merge reads, checked before any is used (issue 41 §2).
//!
//! [`super::merge`] refuses a task of another design or folder; this checks
//! what the task says. A hand-edited or corrupt task once merged silently: a
//! legible time above what the scenario can give (0.5 → 6.7 s), −50 s, 1e308
//! (a mean of `null` in `design.json`), no units, two tasks with the same unit
//! numbers (one silently dropped by the per-cell table), a candidate twice, a
//! `kind` holding a newline (a forged `design.csv` row), and tasks run before
//! and after a model file was replaced. Each is refused here, naming the task
//! file and the field.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use ufcsr::{format::CandidateValue, format::DesignTask, format::ScenarioSource, format::UnitValues};

use super::plan::Plan;
use super::run::{TASK_FILE, task_dir};
use crate::error::{CaptureError, Result};

/// The candidate kinds a task writes.
pub(crate) const CANDIDATE_KINDS: [&str; 2] = ["part", "patch"];
/// The whole sphere in square degrees: no candidate subtends more, per eye.
const SPHERE_DEG2: f64 =
    4.0 * std::f64::consts::PI * (180.0 / std::f64::consts::PI) * (180.0 / std::f64::consts::PI);
/// Room for rounding in the bounds (seconds are sums of frame times).
const SLACK: f64 = 1e-6;
/// The tallest eye the populations draw, metres (with room).
const MAX_EYE_HEIGHT_M: f64 = 3.0;
/// The most tasks named in one message.
const NAMED_TASKS: usize = 8;

/// Checks every task's values against its cell's `limits` (seconds), its units against the other
/// tasks of its cell, and the files the tasks read against each other.
pub(crate) fn check_tasks(
    plan: &Plan,
    out: &Path,
    tasks: &[DesignTask],
    limits: &super::checks::CellLimits,
) -> Result<()> {
    for task in tasks {
        let path = task_dir(out, task.task).join(TASK_FILE);
        let limit = limits.get(&task.cell).copied().unwrap_or(f64::INFINITY);
        check_task(task, limit).map_err(|message| CaptureError::bad_file(&path, message))?;
    }
    check_units_unique(out, tasks)?;
    check_inputs_agree(plan, out, tasks)
}

/// One task's values: finite, within `[0, limit]` seconds, units there and unique, candidates
/// unique, named without control characters and of a known kind.
pub fn check_task(task: &DesignTask, limit: f64) -> std::result::Result<(), String> {
    if !(task.seconds.is_finite() && task.seconds >= 0.0) {
        return Err(format!("seconds {}: must be a finite time, 0 or more", task.seconds));
    }
    if task.units.is_empty() {
        return Err("units: empty (every task measures at least one observer)".into());
    }
    let mut numbers = std::collections::BTreeSet::new();
    for (u, unit) in task.units.iter().enumerate() {
        if !numbers.insert(unit.unit) {
            return Err(format!("units[{u}].unit {}: twice in the task", unit.unit));
        }
        check_unit(unit, limit).map_err(|e| format!("units[{u}] (unit {}){e}", unit.unit))?;
    }
    Ok(())
}

fn check_unit(unit: &UnitValues, limit: f64) -> std::result::Result<(), String> {
    if !(unit.eye_height_m.is_finite() && unit.eye_height_m > 0.0 && unit.eye_height_m <= MAX_EYE_HEIGHT_M) {
        return Err(format!(
            ".eye_height_m {}: must be more than 0 and at most {MAX_EYE_HEIGHT_M} m",
            unit.eye_height_m
        ));
    }
    if unit.position.iter().any(|p| !(p.is_finite() && p.abs() <= ufcsr::files::MAX_COORDINATE_M)) {
        return Err(format!(".position {:?}: must be finite coordinates", unit.position));
    }
    let mut names = std::collections::BTreeSet::new();
    for (c, candidate) in unit.candidates.iter().enumerate() {
        let at = format!(".candidates[{c}] {:?}", candidate.name);
        if !names.insert(candidate.name.as_str()) {
            return Err(format!("{at}: twice in the unit"));
        }
        check_candidate(candidate, limit).map_err(|e| format!("{at}: {e}"))?;
    }
    Ok(())
}

fn check_candidate(c: &CandidateValue, limit: f64) -> std::result::Result<(), String> {
    if c.name.is_empty() || c.name.chars().any(char::is_control) {
        return Err("name: empty or with a control character".into());
    }
    if !CANDIDATE_KINDS.contains(&c.kind.as_str()) {
        return Err(format!("kind {:?}: must be one of {}", c.kind, CANDIDATE_KINDS.join(", ")));
    }
    let within =
        |value: f64, most: f64| value.is_finite() && value >= 0.0 && value <= most * (1.0 + SLACK) + SLACK;
    if !within(c.legible_s, limit) {
        return Err(format!(
            "legible_s {}: must be 0 to {limit:.3} s, the cell's measured frames times the seconds each stands for",
            c.legible_s
        ));
    }
    if !within(c.decision_window_legible_s, c.legible_s) {
        return Err(format!(
            "decision_window_legible_s {}: must be 0 to the legible time, {} s",
            c.decision_window_legible_s, c.legible_s
        ));
    }
    if !within(c.angular_area_deg2_s, SPHERE_DEG2 * limit) {
        return Err(format!(
            "angular_area_deg2_s {}: must be 0 to the whole sphere over the cell's {limit:.3} s",
            c.angular_area_deg2_s
        ));
    }
    Ok(())
}

/// `tasks` as `task-0001, task-0004, …` (at most [`NAMED_TASKS`]).
fn named(tasks: &[u32]) -> String {
    let mut names: Vec<String> = tasks.iter().take(NAMED_TASKS).map(|t| format!("task {t}")).collect();
    if tasks.len() > NAMED_TASKS {
        names.push(format!("and {} more", tasks.len() - NAMED_TASKS));
    }
    names.join(", ")
}

/// Two tasks of one cell with the same unit number: the per-cell table would keep one.
fn check_units_unique(out: &Path, tasks: &[DesignTask]) -> Result<()> {
    let mut owner: BTreeMap<(&ufcsr::format::CellLevels, u32), u32> = BTreeMap::new();
    for task in tasks {
        for unit in &task.units {
            if let Some(first) = owner.insert((&task.cell, unit.unit), task.task) {
                return Err(CaptureError::bad_file(
                    task_dir(out, task.task).join(TASK_FILE),
                    format!(
                        "unit {} of cell {} is also in task {first}: one of the two would be dropped; run both \
                         tasks again",
                        unit.unit, task.cell
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// Whether a task of `cell` reads a file (a model other than the demo, or a scene file).
fn reads_files(plan: &Plan, cell: &ufcsr::format::CellLevels) -> bool {
    let design = &plan.design;
    let model = design
        .vehicles
        .iter()
        .any(|v| v.name == cell.vehicle && v.model.as_deref().is_some_and(|m| m != "demo"));
    let scene = design
        .scenarios
        .iter()
        .any(|s| s.name == cell.scenario && matches!(s.source, ScenarioSource::Scene { .. }));
    model || scene
}

/// The files the tasks read, one version each: tasks run before and after a model was replaced
/// are refused, naming both groups of tasks.
fn check_inputs_agree(plan: &Plan, out: &Path, tasks: &[DesignTask]) -> Result<()> {
    let tasks_dir: PathBuf = out.join("tasks");
    let unrecorded: Vec<u32> =
        tasks.iter().filter(|t| t.inputs.is_empty() && reads_files(plan, &t.cell)).map(|t| t.task).collect();
    if !unrecorded.is_empty() {
        return Err(CaptureError::bad_file(
            &tasks_dir,
            format!(
                "{} record no fingerprint of the model or scene files they read (written by an older ufcsr), \
                 so a file replaced between tasks could not be told: run them again",
                named(&unrecorded)
            ),
        ));
    }
    let mut versions: BTreeMap<&str, BTreeMap<&str, Vec<u32>>> = BTreeMap::new();
    for task in tasks {
        for (file, hash) in &task.inputs {
            versions.entry(file).or_default().entry(hash).or_default().push(task.task);
        }
    }
    for (file, by_hash) in versions {
        if by_hash.len() > 1 {
            let groups: Vec<String> =
                by_hash.iter().map(|(hash, tasks)| format!("{} read version {hash}", named(tasks))).collect();
            return Err(CaptureError::bad_file(
                &tasks_dir,
                format!(
                    "{file} changed between tasks: {}; run the tasks of the old version again, so every task \
                     measured the same file",
                    groups.join("; ")
                ),
            ));
        }
    }
    Ok(())
}
