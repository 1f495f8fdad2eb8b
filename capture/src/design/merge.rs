//! Merging: every planned task's `task.json`, exact or refused.
//!
//! A task of another design (its hash differs), a task file in the wrong
//! folder, a task outside the plan, or any missing task is refused, naming
//! the task and the cell, so a result set is always the whole design. The
//! arithmetic is in [`super::stats`]; the files written in [`super::report`].

use std::path::Path;

use ufcsr::{
    format::DESIGN_RESULT_SCHEMA, format::DESIGN_TASK_SCHEMA, format::DesignResult, format::DesignTask,
    format::GroupSummary, format::MainEffect,
};

use super::plan::Plan;
use super::run::{TASK_FILE, task_dir};
use super::stats::{CellData, INTERVAL_METHOD, cell_data, group_summary, main_effects};
use crate::error::{CaptureError, Result};

/// The most missing cells named in one message.
const NAMED_MISSING: usize = 20;

/// Reads one task file, refusing one of another design or place.
fn read_task(plan: &Plan, out: &Path, index: u32) -> Result<Option<DesignTask>> {
    let path = task_dir(out, index).join(TASK_FILE);
    if super::run::task_behind_link(out, index) {
        return Err(CaptureError::bad_file(
            &path,
            "lies behind a link (tasks/, its folder or the file): not read",
        ));
    }
    if !path.exists() {
        return Ok(None);
    }
    let bytes = ufcsr::files::read_limited(&path, ufcsr::files::SMALL_INPUT_LIMIT)?;
    let task: DesignTask = ufcsr::format::parse_json(&path, &bytes, "design task")?;
    ufcsr::format::check_version(&path, &task.schema, DESIGN_TASK_SCHEMA)?;
    if task.design_hash != plan.hash {
        return Err(CaptureError::bad_file(
            &path,
            format!(
                "task {} is of another design (hash {}), not of {:?} (hash {}): refused; run it again for this \
                 design or merge it with its own",
                task.task, task.design_hash, plan.design.name, plan.hash
            ),
        ));
    }
    let planned = &plan.tasks[index as usize];
    if task.task != index || task.cell != planned.cell || task.replicate != planned.replicate {
        return Err(CaptureError::bad_file(
            &path,
            format!(
                "holds task {} ({}), but this folder is task {index} ({})",
                task.task, task.cell, planned.cell
            ),
        ));
    }
    Ok(Some(task))
}

/// Task folders beyond the plan (left by a larger design in the same folder).
fn refuse_unplanned(plan: &Plan, out: &Path) -> Result<()> {
    let dir = out.join("tasks");
    let Ok(entries) = std::fs::read_dir(&dir) else { return Ok(()) };
    for entry in entries.flatten() {
        let name = entry.file_name().to_string_lossy().into_owned();
        let index = name.strip_prefix("task-").and_then(|n| n.parse::<usize>().ok());
        if let Some(index) = index
            && index >= plan.tasks.len()
            && entry.path().join(TASK_FILE).exists()
        {
            return Err(CaptureError::bad_file(
                entry.path(),
                format!("task {index} is not in this design's plan of {} tasks: refused", plan.tasks.len()),
            ));
        }
    }
    Ok(())
}

/// Every task of `plan` in `out`, or an error naming the missing cells.
pub fn read_tasks(plan: &Plan, out: &Path) -> Result<Vec<DesignTask>> {
    refuse_unplanned(plan, out)?;
    let mut tasks = Vec::with_capacity(plan.tasks.len());
    let mut missing = Vec::new();
    for planned in &plan.tasks {
        match read_task(plan, out, planned.index)? {
            Some(task) => tasks.push(task),
            None => missing.push(format!(
                "task {} (cell {}, replicate {})",
                planned.index, planned.cell, planned.replicate
            )),
        }
    }
    if !missing.is_empty() {
        let more = missing.len().saturating_sub(NAMED_MISSING);
        missing.truncate(NAMED_MISSING);
        let tail = if more > 0 { format!("; and {more} more") } else { String::new() };
        return Err(CaptureError::BadOptions(format!(
            "{}: {} missing, not merged: {}{tail} (run them: `ufcsr design run DESIGN --task I`)",
            out.display(),
            missing.len() + more,
            missing.join("; ")
        )));
    }
    Ok(tasks)
}

/// The best of `kind` in a group, as a phrase: `None` when none is legible (a best of 0 s is
/// no best); a tie names the tied set; no P(best) with one unit.
fn best_phrase(group: &GroupSummary, kind: &str) -> Option<String> {
    let best = group.best.iter().find(|b| b.kind == kind && b.rank == 1)?;
    if best.legible_s.mean <= 0.0 {
        return None;
    }
    let interval = best.legible_s.ci95.map_or_else(
        || format!(" (n = {}, no interval)", best.legible_s.n),
        |[lo, hi]| format!(" [{lo:.2}–{hi:.2}]"),
    );
    let p = match (best.p_best, best.p_within_epsilon, &best.p_best_note) {
        (Some(p), Some(w), _) => {
            format!("P(best) {p:.2}, P(within {:.2} s) {w:.2}", best.epsilon_s.unwrap_or(0.0))
        }
        (Some(p), None, _) => format!("P(best) {p:.2}"),
        (None, _, Some(note)) => format!("P(best) {note}"),
        (None, _, None) => "P(best) n/a".into(),
    };
    let name = if best.tied_with.is_empty() {
        best.name.clone()
    } else {
        format!("{} (tied: {}, {})", best.name, best.name, best.tied_with.join(", "))
    };
    Some(format!("{name} {:.2} s{interval}, {p}", best.legible_s.mean))
}

/// The answer, first: per vehicle and across all, the best part and display.
fn answer(vehicles: &[GroupSummary], overall: &GroupSummary) -> Vec<String> {
    let line = |who: &str, group: &GroupSummary| {
        let parts = best_phrase(group, "part")
            .map_or_else(|| "no part legible (no candidate legible)".into(), |p| format!("best part {p}"));
        let has_display = group.best.iter().any(|b| b.kind == "patch");
        let display = match best_phrase(group, "patch") {
            Some(d) => format!("; best display {d}"),
            None if has_display => "; no display legible".into(),
            None => String::new(),
        };
        format!("{who}: {parts}{display}")
    };
    let mut lines: Vec<String> = vehicles
        .iter()
        .map(|v| line(&format!("for a {}", v.group.trim_start_matches("vehicle ")), v))
        .collect();
    lines.push(line("across all", overall));
    let left_out = super::stats::left_out_line(vehicles.iter().chain([overall]));
    if !left_out.is_empty() {
        lines.push(left_out);
    }
    lines
}

/// [`answer`], plus what the answer says of displays where it names none. Display patches are
/// laid out from the vehicle's mesh and display size alone, so every unit and cell of one vehicle
/// names the same patches (a patch a unit never saw is there with 0 s) and a vehicle's displays are
/// compared; a patch's name carries its place on the body, so across bodies only patches at the
/// same place on every body are common, and a group with none is answered for whole parts (said,
/// not a silent omission). A vehicle without a display size has no patches (said, when another
/// has one).
fn answer_with_displays(plan: &Plan, vehicles: &[GroupSummary], overall: &GroupSummary) -> Vec<String> {
    let mut lines = answer(vehicles, overall);
    let sized = |name: &str| plan.design.vehicles.iter().any(|v| v.name == name && v.display_m.is_some());
    let name_of = |v: &GroupSummary| v.group.trim_start_matches("vehicle ").to_string();
    let has_patch = |group: &GroupSummary| group.candidates.iter().any(|c| c.kind == "patch");
    let without_size: Vec<String> = vehicles.iter().map(name_of).filter(|v| !sized(v)).collect();
    if without_size.len() == vehicles.len() {
        return lines;
    }
    let mut uncommon: Vec<String> =
        vehicles.iter().filter(|v| sized(&name_of(v)) && !has_patch(v)).map(name_of).collect();
    if without_size.is_empty() && !has_patch(overall) {
        uncommon.push("across all".into());
    }
    if !uncommon.is_empty() {
        lines.push(format!(
            "displays: not compared for {} (no patch of the display size lies at the same place on every body \
             and in every unit of the group, or none fits on the body: a patch's name carries its place), whole \
             parts only",
            uncommon.join(", ")
        ));
    }
    if !without_size.is_empty() {
        lines.push(format!(
            "displays: none measured for {} (no display size, `display_m`, in the design), so for {} and across \
             all whole parts only",
            without_size.join(", "),
            if without_size.len() == 1 { "it" } else { "them" }
        ));
    }
    lines
}

/// Per vehicle, its best 1–3 displays (its `best` patches): the main effect of every factor
/// with two or more levels among that vehicle's cells (so never the vehicle), by the same
/// arithmetic as the parts' ([`main_effects`]) over that vehicle's cells only, since a patch's
/// name carries its place on that body and means nothing on another.
pub(super) fn display_effects(data: &[CellData], vehicles: &[GroupSummary]) -> Vec<MainEffect> {
    let mut effects = Vec::new();
    for group in vehicles {
        let vehicle = group.group.trim_start_matches("vehicle ");
        let names: Vec<String> =
            group.best.iter().filter(|b| b.kind == "patch").map(|b| b.name.clone()).collect();
        let of: Vec<&CellData> = data.iter().filter(|c| c.cell.vehicle == vehicle).collect();
        if names.is_empty() || of.is_empty() {
            continue;
        }
        effects.extend(main_effects(&of, &names).into_iter().map(|mut e| {
            e.within_vehicle = Some(vehicle.to_string());
            e
        }));
    }
    effects
}

/// Merges every task of `plan` in `out` into one result.
pub fn merge_design(plan: &Plan, out: &Path) -> Result<DesignResult> {
    let tasks = read_tasks(plan, out)?;
    let limits = super::checks::check_inputs(plan)?;
    super::task_checks::check_tasks(plan, out, &tasks, &limits)?;
    let data = cell_data(&plan.cells, &tasks);
    let seed = plan.design.seed;
    let cells = data.iter().map(|c| group_summary(format!("cell {}", c.cell), &[c], seed)).collect();
    let vehicles: Vec<GroupSummary> = plan
        .design
        .vehicles
        .iter()
        .filter_map(|v| {
            let of: Vec<_> = data.iter().filter(|c| c.cell.vehicle == v.name).collect();
            (!of.is_empty()).then(|| group_summary(format!("vehicle {}", v.name), &of, seed))
        })
        .collect();
    let all: Vec<_> = data.iter().collect();
    let overall = group_summary("all".into(), &all, seed);
    let mut named: Vec<String> = overall.best.iter().map(|b| b.name.clone()).collect();
    named.extend(overall.candidates.iter().filter(|c| c.kind == "part").take(5).map(|c| c.name.clone()));
    named.dedup();
    named.sort();
    named.dedup();
    Ok(DesignResult {
        schema: DESIGN_RESULT_SCHEMA.into(),
        design: plan.design.name.clone(),
        design_hash: plan.hash.clone(),
        tasks: tasks.len() as u32,
        interval: INTERVAL_METHOD.into(),
        answer: answer_with_displays(plan, &vehicles, &overall),
        main_effects: main_effects(&all, &named),
        display_main_effects: display_effects(&data, &vehicles),
        cells,
        vehicles,
        overall,
    })
}
