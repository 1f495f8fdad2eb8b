//! The design folder's tests without a GPU: planning refuses bad designs by
//! factor and level and counts the shipped designs' tasks; merging refuses a
//! task of another design and names a missing cell; a re-run knows a
//! complete task from a partial one; the intervals cover a known mean.

use std::path::{Path, PathBuf};

use ufcsr::{
    format::CandidateValue, format::DESIGN_TASK_SCHEMA, format::Design, format::DesignTask,
    format::UnitValues,
};

use super::merge::{display_effects, merge_design};
use super::plan::{Plan, plan_checked, plan_design};
use super::run::{add_unseen_patches, candidate_values, completed, task_dir, write_task};
use super::stats::{cell_data, group_summary, main_effects, p_best};

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../fixtures/designs").join(name)
}

fn tiny() -> Design {
    let bytes = std::fs::read(fixture("tiny-2x2.json")).unwrap();
    serde_json::from_slice(&bytes).unwrap()
}

fn refusal(edit: impl Fn(&mut serde_json::Value)) -> String {
    let mut value = serde_json::to_value(tiny()).unwrap();
    edit(&mut value);
    let design: Design = serde_json::from_value(value).unwrap();
    plan_checked(design, Path::new("bad.json")).unwrap_err().to_string()
}

#[test]
fn the_shipped_designs_plan_into_their_tasks() {
    let count = |name: &str| plan_design(&fixture(name)).unwrap();
    let tiny = count("tiny-2x2.json");
    assert_eq!((tiny.cells.len(), tiny.tasks.len()), (4, 8));
    assert_eq!(tiny.tasks[3].replicate, 1);
    assert_eq!(count("intersection.json").tasks.len(), 4 * 3 * 2);
    // 5 bodies × 14 street scenarios × 3 traffic levels (generated traffic goes with street scenarios).
    assert_eq!(count("street.json").cells.len(), 5 * 14 * 3);
    // The hash is the design's: the same file plans alike, an edit changes it.
    assert_eq!(tiny.hash, count("tiny-2x2.json").hash);
    let mut other = tiny.design.clone();
    other.seed += 1;
    assert_ne!(plan_checked(other, Path::new("x.json")).unwrap().hash, tiny.hash);
}

#[test]
fn invalid_designs_are_refused_naming_the_factor_and_level() {
    let body = refusal(|v| v["vehicles"][1]["body"] = "buss".into());
    assert!(
        body.contains("vehicles[1] \"van\"") && body.contains("buss") && body.contains("sedan"),
        "{body}"
    );
    let both = refusal(|v| v["vehicles"][0]["body"] = "van".into());
    assert!(both.contains("vehicles[0] \"pickup\"") && both.contains("exactly one"), "{both}");
    let demo = refusal(|v| v["scenarios"][0]["scenario"] = "E".into());
    assert!(demo.contains("scenarios[0] \"A\"") && demo.contains("\"E\""), "{demo}");
    let position = refusal(|v| v["scenarios"][1]["position"] = 9.into());
    assert!(position.contains("scenarios[1] \"street-2\"") && position.contains("1 to 8"), "{position}");
    let twice = refusal(|v| v["vehicles"][1]["name"] = "pickup".into());
    assert!(twice.contains("vehicles[1] \"pickup\""), "{twice}");
    let cell = refusal(|v| {
        v["crossing"] = serde_json::json!({"cells": [{"vehicle": "van", "scenario": "A", "traffic": "rush"}]})
    });
    assert!(cell.contains("cells[0]") && cell.contains("traffic level \"rush\""), "{cell}");
    let misfit = refusal(|v| {
        v["traffic"] = serde_json::json!([{"name": "lead", "kind": "lead-car"}]);
        v["crossing"] =
            serde_json::json!({"cells": [{"vehicle": "van", "scenario": "street-2", "traffic": "lead"}]});
    });
    assert!(misfit.contains("\"lead\" does not fit scenario level \"street-2\""), "{misfit}");
    let crowd = refusal(|v| {
        v["scenarios"][1]["speed_mps"] = 8.0.into();
        v["traffic"] = serde_json::json!([{"name": "six", "kind": "generated", "vehicles": 6}]);
    });
    assert!(crowd.contains("traffic=six") && crowd.contains("6 other vehicles"), "{crowd}");
    assert!(refusal(|v| v["measure"]["sample"] = 0.0.into()).contains("measure.sample"));
    assert!(refusal(|v| v["measure"]["rendered_ppd"] = 8.0.into()).contains("measure.rendered_ppd"));
}

/// A synthetic task of `plan`: every unit sees candidates "a" and "b" with the given legible times.
pub(super) fn synthetic(plan: &Plan, index: u32, a: f64, b: f64) -> DesignTask {
    let planned = &plan.tasks[index as usize];
    let value = |name: &str, s: f64| CandidateValue {
        name: name.into(),
        kind: "part".into(),
        legible_s: s,
        decision_window_legible_s: 0.5 * s,
        angular_area_deg2_s: 10.0 * s,
    };
    DesignTask {
        schema: DESIGN_TASK_SCHEMA.into(),
        design_hash: plan.hash.clone(),
        task: index,
        cell: planned.cell.clone(),
        replicate: planned.replicate,
        units: vec![UnitValues {
            unit: planned.replicate,
            eye_height_m: 1.6,
            position: [0.0; 3],
            seed: 1,
            candidates: vec![value("a", a), value("b", b)],
        }],
        seconds: 0.0,
        inputs: Default::default(),
    }
}

#[test]
fn merge_refuses_a_task_of_another_design_and_names_a_missing_cell() {
    let plan = plan_design(&fixture("tiny-2x2.json")).unwrap();
    let dir = tempfile::tempdir().unwrap();
    for i in 0..plan.tasks.len() as u32 {
        // Within every cell's bound (its measured time: 2 s on the street, 3 s in A).
        write_task(&synthetic(&plan, i, 0.2 + 0.25 * f64::from(i), 0.8), &task_dir(dir.path(), i)).unwrap();
    }
    let merged = merge_design(&plan, dir.path()).unwrap();
    assert_eq!(merged.tasks, 8);
    assert_eq!(merged.overall.best[0].name, "a");
    assert!(merged.answer.iter().any(|l| l.starts_with("across all: best part a")), "{:?}", merged.answer);
    // The pickup has a display size but no patch in these tasks: said, not dropped silently.
    assert!(
        merged.answer.iter().any(|l| l.starts_with("displays: not compared for pickup")),
        "{:?}",
        merged.answer
    );
    // Candidate a's vehicle effect: pickup tasks 0–3 (mean 0.575), van tasks 4–7 (mean 1.575).
    let effect = merged.main_effects.iter().find(|e| e.factor == "vehicle" && e.candidate == "a").unwrap();
    assert!((effect.range_s.mean - 1.0).abs() < 1e-12, "{effect:?}");
    assert_eq!((effect.highest.as_str(), effect.lowest.as_str()), ("van", "pickup"));
    // The effects are in design.csv with the groups, under one header.
    let csv = super::report::csv(&merged);
    let fields = |line: &str| line.split(',').count();
    assert!(csv.lines().all(|line| fields(line) == 13), "{csv}");
    assert!(csv.contains("vehicle: van - pickup,a,range,1.000000,"), "{csv}");
    assert!(csv.contains("vehicle=van,a,level-effect,0.500000,"), "{csv}");
    // A task of another design.
    let mut foreign = synthetic(&plan, 5, 1.0, 1.0);
    foreign.design_hash = "0123456789abcdef".into();
    write_task(&foreign, &task_dir(dir.path(), 5)).unwrap();
    let refused = merge_design(&plan, dir.path()).unwrap_err().to_string();
    assert!(refused.contains("task-0005") && refused.contains("another design"), "{refused}");
    // A missing task names its cell.
    std::fs::remove_file(task_dir(dir.path(), 5).join("task.json")).unwrap();
    let missing = merge_design(&plan, dir.path()).unwrap_err().to_string();
    let cell = &plan.tasks[5].cell;
    assert!(
        missing.contains("1 missing") && missing.contains(&format!("cell {cell}, replicate 1")),
        "{missing}"
    );
}

#[test]
fn a_rerun_skips_complete_tasks_and_redoes_partial_or_foreign_ones() {
    let plan = plan_design(&fixture("tiny-2x2.json")).unwrap();
    let dir = tempfile::tempdir().unwrap();
    assert!(completed(&plan, dir.path(), 0).is_none());
    write_task(&synthetic(&plan, 0, 1.0, 1.0), &task_dir(dir.path(), 0)).unwrap();
    assert!(completed(&plan, dir.path(), 0).is_some());
    // A partial task: its folder and an archive, no task.json.
    std::fs::create_dir_all(task_dir(dir.path(), 1).join("unit-000")).unwrap();
    assert!(completed(&plan, dir.path(), 1).is_none());
    // A truncated task.json (a run killed while writing would leave none, but a copy may).
    std::fs::write(task_dir(dir.path(), 1).join("task.json"), b"{\"schema\": ").unwrap();
    assert!(completed(&plan, dir.path(), 1).is_none());
    let mut foreign = synthetic(&plan, 2, 1.0, 1.0);
    foreign.design_hash = "ffffffffffffffff".into();
    write_task(&foreign, &task_dir(dir.path(), 2)).unwrap();
    assert!(completed(&plan, dir.path(), 2).is_none());
}

/// Box–Muller on the analyzer's seeded generator: normal draws for the coverage test.
struct Normal(ufcsr::SplitMix64);

impl Normal {
    fn draw(&mut self) -> f64 {
        let (u, v) = (self.0.unit().max(1e-300), self.0.unit());
        (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
    }
}

#[test]
fn the_interval_of_a_vehicle_and_of_all_covers_the_known_mean_about_95_percent_of_the_time() {
    // Two vehicles × two scenarios, 8 units: cell means 2, 3, 4, 5 s; each
    // unit has an effect shared by its cells (an observer's height) plus
    // cell noise. Truth: vehicle "v0" 2.5 s, all 3.5 s.
    let plan = plan_design(&fixture("tiny-2x2.json")).unwrap();
    let (trials, units) = (400, 8u32);
    let mut normal = Normal(ufcsr::SplitMix64(11));
    let (mut covered_vehicle, mut covered_all) = (0, 0);
    for trial in 0..trials {
        let shared: Vec<f64> = (0..units).map(|_| 0.8 * normal.draw()).collect();
        let mut tasks = Vec::new();
        for (c, cell) in plan.cells.iter().enumerate() {
            let mut task = synthetic(&plan, 0, 0.0, 0.0);
            task.cell = cell.clone();
            task.units = (0..units)
                .map(|u| {
                    let value = 2.0 + c as f64 + shared[u as usize] + 0.5 * normal.draw();
                    let mut unit = synthetic(&plan, 0, value, 0.0).units.remove(0);
                    unit.unit = u;
                    unit
                })
                .collect();
            tasks.push(task);
        }
        let data = cell_data(&plan.cells, &tasks);
        let vehicle: Vec<_> = data.iter().filter(|d| d.cell.vehicle == plan.cells[0].vehicle).collect();
        let all: Vec<_> = data.iter().collect();
        let inside = |group: ufcsr::format::GroupSummary, truth: f64| {
            let a = group.candidates.iter().find(|c| c.name == "a").unwrap();
            let [lo, hi] = a.legible_s.ci95.unwrap();
            lo <= truth && truth <= hi
        };
        covered_vehicle += usize::from(inside(group_summary("v".into(), &vehicle, trial), 2.5));
        covered_all += usize::from(inside(group_summary("all".into(), &all, trial), 3.5));
    }
    let rate = |n: usize| n as f64 / trials as f64;
    eprintln!("coverage: vehicle {:.3}, all {:.3}", rate(covered_vehicle), rate(covered_all));
    assert!((0.90..=0.99).contains(&rate(covered_vehicle)), "{}", rate(covered_vehicle));
    assert!((0.90..=0.99).contains(&rate(covered_all)), "{}", rate(covered_all));
}

/// One trial's tasks: every cell of `plan` with `units` units, candidate "a" valued `value(cell, unit)`.
fn tasks_of(plan: &Plan, units: u32, mut value: impl FnMut(usize, u32) -> f64) -> Vec<DesignTask> {
    plan.cells
        .iter()
        .enumerate()
        .map(|(c, cell)| {
            let mut task = synthetic(plan, 0, 0.0, 0.0);
            task.cell = cell.clone();
            task.units = (0..units)
                .map(|u| {
                    let mut unit = synthetic(plan, 0, value(c, u), 0.0).units.remove(0);
                    unit.unit = u;
                    unit
                })
                .collect();
            task
        })
        .collect()
}

#[test]
fn the_main_effects_intervals_cover_a_known_effect_about_95_percent_of_the_time() {
    // Two vehicles × two scenarios, 8 units. Candidate a: 2 s, +1.5 s on the
    // second vehicle, no scenario effect; per unit an effect shared by its
    // cells (an observer's height), a unit × vehicle effect (how a body suits
    // that observer) and cell noise. Truth: the vehicle range 1.5 s (second
    // vehicle highest), its levels' effects −0.75 and +0.75 s, the scenario
    // levels' effects 0.
    let plan = plan_design(&fixture("tiny-2x2.json")).unwrap();
    let vehicles: Vec<String> = plan.design.vehicles.iter().map(|v| v.name.clone()).collect();
    let (trials, units) = (400, 8u32);
    let mut normal = Normal(ufcsr::SplitMix64(29));
    let mut covered = [0usize; 4];
    for _ in 0..trials {
        let shared: Vec<f64> = (0..units).map(|_| 0.8 * normal.draw()).collect();
        let suits: Vec<[f64; 2]> = (0..units).map(|_| [0.4 * normal.draw(), 0.4 * normal.draw()]).collect();
        let tasks = tasks_of(&plan, units, |c, u| {
            let second = usize::from(plan.cells[c].vehicle == vehicles[1]);
            2.0 + 1.5 * second as f64 + shared[u as usize] + suits[u as usize][second] + 0.5 * normal.draw()
        });
        let data = cell_data(&plan.cells, &tasks);
        let effects = main_effects(&data.iter().collect::<Vec<_>>(), &["a".to_string()]);
        let of = |factor: &str| effects.iter().find(|e| e.factor == factor).unwrap();
        let inside = |v: &ufcsr::format::MeanInterval, truth: f64| {
            v.ci95.is_some_and(|[lo, hi]| lo <= truth && truth <= hi)
        };
        let vehicle = of("vehicle");
        covered[0] += usize::from(vehicle.highest == vehicles[1] && inside(&vehicle.range_s, 1.5));
        let level = |name: &str| vehicle.levels.iter().find(|l| l.level == name).unwrap();
        covered[1] += usize::from(inside(&level(&vehicles[0]).effect_s, -0.75));
        covered[2] += usize::from(inside(&level(&vehicles[1]).mean_s, 2.0 + 1.5));
        covered[3] += usize::from(of("scenario").levels.iter().all(|l| inside(&l.effect_s, 0.0)));
    }
    let rates = covered.map(|n| n as f64 / trials as f64);
    eprintln!("coverage: vehicle range, level effect, level mean, scenario effects {rates:?}");
    for rate in rates {
        assert!((0.90..=0.99).contains(&rate), "{rates:?}");
    }
}

#[test]
fn the_effects_figure_draws_each_levels_effect_with_its_interval() {
    let plan = plan_design(&fixture("tiny-2x2.json")).unwrap();
    let mut normal = Normal(ufcsr::SplitMix64(7));
    let tasks = tasks_of(&plan, 6, |_, _| 2.0 + normal.draw());
    let data = cell_data(&plan.cells, &tasks);
    let effects = main_effects(&data.iter().collect::<Vec<_>>(), &["windshield_rail_left".to_string()]);
    let figure = super::output::effects_figure("tiny", &effects);
    let levels: Vec<&ufcsr::format::LevelEffect> = effects.iter().flat_map(|e| &e.levels).collect();
    assert_eq!(figure.rows.len(), levels.len());
    for (row, level) in figure.rows.iter().zip(levels) {
        assert_eq!((row.value, row.interval), (level.effect_s.mean, level.effect_s.ci95));
        assert!(row.interval.is_some(), "six units give an interval");
        assert!(
            row.label.starts_with("windshield rail, left: ") && row.label.ends_with(&level.level),
            "{}",
            row.label
        );
    }
}

#[test]
fn p_best_is_one_for_a_candidate_larger_in_every_unit() {
    let rows: Vec<Vec<f64>> =
        (0..10).map(|i| vec![5.0 + f64::from(i % 2), 1.0, 1.0 + f64::from(i % 2)]).collect();
    let p = p_best(&rows, &[0, 1], 3);
    assert_eq!(p.p_best, vec![1.0, 0.0]);
    let tie = p_best(&rows, &[1, 2], 3);
    assert!(tie.p_best[1] > 0.9, "{tie:?}");
}

/// Issue 42 §3: exact ties share P(best), 1/t each whatever their order; a weaker candidate gets 0.
#[test]
fn an_exact_tie_of_k_candidates_gives_each_one_over_k() {
    for t in [2usize, 3, 7] {
        // Per unit: t candidates with the same seconds (varying over units), one a second less.
        let rows: Vec<Vec<f64>> = (0..8)
            .map(|u| {
                let mut row = vec![2.0 + f64::from(u % 3); t];
                row.push(1.0 + f64::from(u % 3));
                row
            })
            .collect();
        let among: Vec<usize> = (0..=t).collect();
        let shares = p_best(&rows, &among, 5);
        for c in 0..t {
            assert!((shares.p_best[c] - 1.0 / t as f64).abs() < 1e-12, "{t}: {:?}", shares.p_best);
            assert_eq!(shares.p_within_epsilon[c], 1.0);
        }
        assert_eq!(shares.p_best[t], 0.0);
    }
}

/// No P(best) with one unit ("n/a: one unit") or when every candidate is legible 0 s ("no
/// candidate legible"), and the answer says so instead of naming a best of nothing.
#[test]
fn one_unit_or_nothing_legible_gives_no_p_best_and_ties_are_named() {
    let plan = plan_design(&fixture("tiny-2x2.json")).unwrap();
    let one = cell_data(&plan.cells, &tasks_of(&plan, 1, |_, _| 2.0));
    let summary = group_summary("one".into(), &[&one[0]], 1);
    assert!(
        summary
            .best
            .iter()
            .all(|b| b.p_best.is_none() && b.p_best_note.as_deref() == Some(ufcsr::placement::ONE_UNIT))
    );
    // Candidates a and b both 0 s in every unit.
    let zero = cell_data(&plan.cells, &tasks_of(&plan, 4, |_, _| 0.0));
    let summary = group_summary("zero".into(), &[&zero[0]], 1);
    assert!(
        summary.best.iter().all(|b| b.p_best.is_none()
            && b.p_best_note.as_deref() == Some(ufcsr::placement::NO_CANDIDATE_LEGIBLE)),
        "{:?}",
        summary.best
    );
    // a and b tie exactly (b is 0 in tasks_of; make it equal to a): each names the other, 1/2 each.
    let mut tied = tasks_of(&plan, 4, |_, u| 1.0 + f64::from(u));
    for task in &mut tied {
        for unit in &mut task.units {
            unit.candidates[1].legible_s = unit.candidates[0].legible_s;
        }
    }
    let tied = cell_data(&plan.cells, &tied);
    let summary = group_summary("tied".into(), &[&tied[0]], 1);
    assert_eq!(summary.best[0].tied_with, vec!["b".to_string()]);
    assert_eq!((summary.best[0].p_best, summary.best[1].p_best), (Some(0.5), Some(0.5)));
}

/// Issue 42 §2: the design's merge uses the placement's one mountability rule: the most legible
/// surface, a windshield, is never the best part; the record lists it with the reason.
#[test]
fn design_merge_never_picks_a_not_mountable_part_and_lists_it_with_the_reason() {
    let plan = plan_design(&fixture("tiny-2x2.json")).unwrap();
    let dir = tempfile::tempdir().unwrap();
    for i in 0..plan.tasks.len() as u32 {
        // Within every cell's measured time (2 s on the street, 3 s in A): merge checks every value.
        let mut task = synthetic(&plan, i, 0.5 + 0.15 * f64::from(i), 0.2);
        let mut glass = task.units[0].candidates[0].clone();
        (glass.name, glass.legible_s) = ("windshield".into(), 1.6 + 0.05 * f64::from(i));
        glass.decision_window_legible_s = 0.5 * glass.legible_s;
        glass.angular_area_deg2_s = 10.0 * glass.legible_s;
        task.units[0].candidates.push(glass);
        write_task(&task, &task_dir(dir.path(), i)).unwrap();
    }
    let merged = merge_design(&plan, dir.path()).unwrap();
    for group in merged.vehicles.iter().chain([&merged.overall]) {
        assert!(group.best.iter().all(|b| b.name != "windshield"), "{:?}", group.best);
        let excluded = group.excluded.iter().find(|e| e.candidate == "windshield").expect("listed");
        assert_eq!(excluded.reason, ufcsr::format::ExclusionReason::NotMountable);
    }
    assert_eq!(merged.overall.best[0].name, "a");
    assert!(
        merged.answer.iter().any(|l| l.contains("not mountable") && l.contains("windshield")),
        "{:?}",
        merged.answer
    );
    assert!(super::report::page(&merged).contains("not mountable (wheels, glass): windshield"));
}

#[test]
fn a_tasks_legible_seconds_are_the_placement_commands_for_the_same_table() {
    // 100 frames of 0.1 s; the vehicle is closest at frame 80 (8.0 s), so the
    // 6 s decision window holds frames 21–80. Part a is legible in frames
    // 0–49, 60–63 (0.4 s, under the 1 s dwell: not counted) and 70–99; part
    // b in 10–40. Known answer: a 8.0 s, 4.0 s of it in the window; b 3.1 s
    // and 2.0 s.
    let dir = tempfile::tempdir().unwrap();
    let mut text = String::from(
        "frame,time_s,eye,distance_m,candidate,kind,solid_angle_sr,visible_fraction,view_angle_deg,\
         angular_height_deg,frame_s\n",
    );
    let legible = |name: &str, f: u32| match name {
        "a" => f < 50 || (60..64).contains(&f) || f >= 70,
        _ => (10..=40).contains(&f),
    };
    for frame in 0..100u32 {
        let distance = 5.0 + (f64::from(frame) - 80.0).abs();
        for name in ["a", "b"] {
            let (sr, fraction) = if legible(name, frame) { (1e-3, 1.0) } else { (0.0, 0.0) };
            let time = f64::from(frame) / 10.0;
            text += &format!("{frame},{time},left,{distance},{name},part,{sr},{fraction},10,2,0.1\n");
        }
    }
    let path = dir.path().join("placement-frames.csv");
    std::fs::write(&path, text).unwrap();
    let ours = candidate_values(ufcsr::placement::read_table(&path).unwrap());
    let theirs = ufcsr::placement(&ufcsr::PlacementOptions::new(vec![path])).unwrap().document.candidates;
    for (name, legible_s, window_s) in [("a", 8.0, 4.0), ("b", 3.1, 2.0)] {
        let task = ours.iter().find(|c| c.name == name).unwrap();
        let placement = theirs.iter().find(|c| c.name == name).unwrap();
        assert_eq!(
            (task.legible_s, task.decision_window_legible_s),
            (placement.legible_s, placement.decision_window_legible_s),
            "{name}"
        );
        assert!((task.legible_s - legible_s).abs() < 1e-9, "{name}: {}", task.legible_s);
        assert!(
            (task.decision_window_legible_s - window_s).abs() < 1e-9,
            "{name}: {}",
            task.decision_window_legible_s
        );
    }
}

#[test]
fn displays_are_compared_within_a_vehicle_and_said_where_not_measured() {
    // Pickup (with a display size): two patches laid out, "p@front" seen by
    // every unit, "p@side" by none (the table has no rows for it; the layout
    // names it, so it is there with 0 s). Van: no display size, no patches.
    let plan = plan_design(&fixture("tiny-2x2.json")).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let layout = ["p@front".to_string(), "p@side".to_string()];
    for i in 0..plan.tasks.len() as u32 {
        let mut task = synthetic(&plan, i, 2.0, 1.0);
        if task.cell.vehicle == "pickup" {
            let values = &mut task.units[0].candidates;
            let mut front = values[0].clone();
            (front.name, front.kind, front.legible_s) =
                ("p@front".into(), "patch".into(), 0.5 + 0.5 * f64::from(i));
            front.decision_window_legible_s = 0.5 * front.legible_s;
            values.push(front);
            add_unseen_patches(values, layout.iter());
            assert_eq!(values.len(), 4, "{values:?}");
        }
        write_task(&task, &task_dir(dir.path(), i)).unwrap();
    }
    let merged = merge_design(&plan, dir.path()).unwrap();
    let pickup = merged.vehicles.iter().find(|v| v.group == "vehicle pickup").unwrap();
    let displays: Vec<_> = pickup.best.iter().filter(|b| b.kind == "patch").collect();
    assert_eq!(displays.len(), 2, "{:?}", pickup.best);
    assert_eq!((displays[0].name.as_str(), displays[0].p_best), ("p@front", Some(1.0)));
    assert_eq!(displays[1].legible_s.mean, 0.0);
    // Tasks 0–3 are the pickup's: p@front 0.5, 1, 1.5, 2 s, mean 1.25 s over its two units.
    assert!((displays[0].legible_s.mean - 1.25).abs() < 1e-12, "{:?}", displays[0]);
    assert!(merged.answer[0].contains("best display p@front 1.25 s"), "{:?}", merged.answer);
    let none = merged.answer.iter().find(|l| l.starts_with("displays: none measured for van")).unwrap();
    assert!(none.contains("across all"), "{none}");
    assert!(!merged.answer.iter().any(|l| l.contains("not compared")), "{:?}", merged.answer);
    assert!(!merged.overall.candidates.iter().any(|c| c.kind == "patch"));
}

/// The tiny design with two demo scenarios and two traffic levels (none, lead car), one replicate.
fn traffic_plan() -> Plan {
    let mut value = serde_json::to_value(tiny()).unwrap();
    value["scenarios"] = serde_json::json!([
        {"name": "A", "kind": "demo", "scenario": "A"},
        {"name": "B", "kind": "demo", "scenario": "B"}
    ]);
    value["traffic"] =
        serde_json::json!([{"name": "none", "kind": "none"}, {"name": "lead", "kind": "lead-car"}]);
    value["replicates"] = 1.into();
    plan_checked(serde_json::from_value(value).unwrap(), Path::new("traffic.json")).unwrap()
}

/// One trial's tasks of [`traffic_plan`], `units` units each: parts "a" and "b" everywhere; on the
/// pickup the display "p@front" (2.1 s, 1.2 s less behind the lead car; a unit effect shared by its
/// cells and cell noise) and "p@side" (1 s, no traffic effect, cell noise).
fn traffic_tasks(plan: &Plan, units: u32, normal: &mut Normal) -> Vec<DesignTask> {
    let shared: Vec<f64> = (0..units).map(|_| 0.8 * normal.draw()).collect();
    let mut tasks = tasks_of(plan, units, |_, u| 2.0 + shared[u as usize]);
    for (i, task) in tasks.iter_mut().enumerate() {
        task.task = i as u32;
        if task.cell.vehicle != "pickup" {
            continue;
        }
        let lead = if task.cell.traffic == "lead" { 1.2 } else { 0.0 };
        for unit in &mut task.units {
            let mut patch = unit.candidates[0].clone();
            patch.kind = "patch".into();
            (patch.name, patch.legible_s) =
                ("p@front".into(), 2.1 - lead + shared[unit.unit as usize] + 0.4 * normal.draw());
            patch.decision_window_legible_s = 0.5 * patch.legible_s;
            unit.candidates.push(patch.clone());
            (patch.name, patch.legible_s) = ("p@side".into(), 1.0 + 0.4 * normal.draw());
            patch.decision_window_legible_s = 0.5 * patch.legible_s;
            unit.candidates.push(patch);
        }
    }
    tasks
}

#[test]
fn a_displays_main_effects_are_within_its_vehicle_and_cover_a_known_traffic_effect() {
    // Truth for the pickup's p@front: traffic range 1.2 s (none highest), level effects +0.6 and
    // −0.6 s, scenario effects 0; no vehicle effect (a display is compared within one body).
    let plan = traffic_plan();
    assert_eq!(plan.cells.len(), 8);
    let mut normal = Normal(ufcsr::SplitMix64(41));
    // Through the files: design.json's display effects, the CSV rows and the page's label.
    let dir = tempfile::tempdir().unwrap();
    // The normal model's draws clamped to what a cell can give (merge refuses the rest).
    let limits = super::checks::check_inputs(&plan).unwrap();
    for mut task in traffic_tasks(&plan, 8, &mut normal) {
        for c in task.units.iter_mut().flat_map(|u| u.candidates.iter_mut()) {
            c.legible_s = c.legible_s.clamp(0.0, limits[&task.cell]);
            c.decision_window_legible_s = 0.5 * c.legible_s;
        }
        write_task(&task, &task_dir(dir.path(), task.task)).unwrap();
    }
    let merged = merge_design(&plan, dir.path()).unwrap();
    let effects = &merged.display_main_effects;
    assert!(effects.iter().all(|e| e.within_vehicle.as_deref() == Some("pickup") && e.factor != "vehicle"));
    let traffic = effects.iter().find(|e| e.factor == "traffic" && e.candidate == "p@front").unwrap();
    assert_eq!((traffic.highest.as_str(), traffic.lowest.as_str()), ("none", "lead"));
    // Clamped to the cells' 3 s the draws have no closed-form truth, so the files must carry a
    // detected effect; the coverage of the unclamped truth is measured over 400 trials below.
    let range = &traffic.range_s;
    assert!(
        range.ci95.is_some_and(|[lo, hi]| 0.0 < lo && lo <= range.mean && range.mean <= hi),
        "{traffic:?}"
    );
    assert!(effects.iter().any(|e| e.factor == "scenario" && e.candidate == "p@side"), "{effects:?}");
    assert!(merged.main_effects.iter().all(|e| e.within_vehicle.is_none()));
    let csv = super::report::csv(&merged);
    assert!(csv.contains("within vehicle pickup: traffic: none - lead,p@front,range,"), "{csv}");
    assert!(csv.contains("within vehicle pickup: traffic=lead,p@front,level-effect,"), "{csv}");
    assert!(csv.lines().all(|line| line.split(',').count() == 13), "{csv}");
    assert!(super::report::page(&merged).contains("Displays, within one body"));
    // Coverage over 400 trials, by the merge's own arithmetic.
    let mut covered = [0usize; 3];
    let trials = 400;
    for _ in 0..trials {
        let data = cell_data(&plan.cells, &traffic_tasks(&plan, 8, &mut normal));
        let of: Vec<_> = data.iter().filter(|c| c.cell.vehicle == "pickup").collect();
        let vehicles = [group_summary("vehicle pickup".into(), &of, 1)];
        let effects = display_effects(&data, &vehicles);
        let front =
            |factor: &str| effects.iter().find(|e| e.factor == factor && e.candidate == "p@front").unwrap();
        let inside = |v: &ufcsr::format::MeanInterval, truth: f64| {
            v.ci95.is_some_and(|[lo, hi]| lo <= truth && truth <= hi)
        };
        let traffic = front("traffic");
        covered[0] += usize::from(traffic.highest == "none" && inside(&traffic.range_s, 1.2));
        covered[1] +=
            usize::from(traffic.levels.iter().any(|l| l.level == "lead" && inside(&l.effect_s, -0.6)));
        covered[2] += usize::from(front("scenario").levels.iter().all(|l| inside(&l.effect_s, 0.0)));
    }
    let rates = covered.map(|n| n as f64 / f64::from(trials));
    eprintln!("coverage: traffic range, lead effect, scenario effects {rates:?}");
    for rate in rates {
        assert!((0.90..=0.99).contains(&rate), "{rates:?}");
    }
}
