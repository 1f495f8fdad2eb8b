//! Tests of issue 41 §2 without a GPU: a vast crossing is counted, never
//! listed; unknown level fields and control characters are refused; the
//! files a design's tasks will read are checked when planning; every value a
//! merge reads is checked, naming the task file and field; tasks that read
//! two versions of a model are refused; nothing is read through a link; and
//! the result set is written whole or not at all.

use std::path::{Path, PathBuf};

use ufcsr::format::DesignTask;

use super::checks::check_inputs;
use super::merge::merge_design;
use super::output::write_result_set;
use super::plan::{LISTED_CELLS, Plan, cell_count, plan_checked, plan_design};
use super::run::{task_dir, write_task};

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../fixtures/designs").join(name)
}

fn tiny_value() -> serde_json::Value {
    serde_json::from_slice(&std::fs::read(fixture("tiny-2x2.json")).unwrap()).unwrap()
}

/// `value` written as `d.json` in `dir`, planned from the file.
fn plan_file(dir: &Path, value: &serde_json::Value) -> crate::error::Result<Plan> {
    let path = dir.join("d.json");
    std::fs::write(&path, serde_json::to_vec(value).unwrap()).unwrap();
    plan_design(&path)
}

#[test]
fn a_vast_crossing_is_counted_and_refused_before_any_cell_is_listed() {
    let mut value = tiny_value();
    value["vehicles"] =
        (0..1000).map(|i| serde_json::json!({"name": format!("v{i}"), "body": "van"})).collect();
    value["scenarios"] = (0..1000)
        .map(|i| serde_json::json!({"name": format!("s{i}"), "kind": "demo", "scenario": "A"}))
        .collect();
    let design: ufcsr::format::Design = serde_json::from_value(value).unwrap();
    assert_eq!(cell_count(&design), 1_000_000);
    LISTED_CELLS.with(|n| n.set(0));
    let refused = plan_checked(design, Path::new("big.json")).unwrap_err().to_string();
    assert!(refused.contains("1000000 cells × 2 replicates = 2000000 tasks"), "{refused}");
    assert_eq!(LISTED_CELLS.with(std::cell::Cell::get), 0, "the cells were listed before the count");
    // The count is the listing's, for every shipped design (kinds that do not go together left out).
    for name in ["tiny-2x2.json", "intersection.json", "street.json", "street-quick.json"] {
        let plan = plan_design(&fixture(name)).unwrap();
        assert_eq!(cell_count(&plan.design), plan.cells.len() as u128, "{name}");
    }
}

#[test]
fn unknown_level_fields_and_control_characters_are_refused_by_name() {
    let dir = tempfile::tempdir().unwrap();
    let mut value = tiny_value();
    value["scenarios"][1] =
        serde_json::json!({"name": "street-2", "kind": "street", "position": 2, "speed": 8});
    let speed = plan_file(dir.path(), &value).unwrap_err().to_string();
    assert!(
        speed.contains("d.json") && speed.contains("scenarios: [1]") && speed.contains("\"speed\""),
        "{speed}"
    );
    assert!(speed.contains("speed_mps"), "the message lists the fields the level has: {speed}");
    let mut value = tiny_value();
    value["traffic"] = serde_json::json!([{"name": "none", "kind": "none", "vehicles": 3}]);
    let traffic = plan_file(dir.path(), &value).unwrap_err().to_string();
    assert!(traffic.contains("traffic: [0]") && traffic.contains("\"vehicles\""), "{traffic}");
    // The fixtures still read, and their hash is unchanged by the stricter reader.
    assert!(plan_design(&fixture("street.json")).is_ok());
    let mut value = tiny_value();
    value["vehicles"][1]["name"] = "van\u{1b}[2J\nforged".into();
    let name = plan_file(dir.path(), &value).unwrap_err().to_string();
    assert!(name.contains("vehicles[1]") && name.contains("control character"), "{name}");
}

/// The tiny design after `edit`, planned from `dir`, checked as `plan` does.
fn inputs_refusal(dir: &Path, edit: impl Fn(&mut serde_json::Value)) -> String {
    let mut value = tiny_value();
    edit(&mut value);
    let plan = plan_file(dir, &value).unwrap();
    check_inputs(&plan).unwrap_err().to_string()
}

#[cfg(unix)]
#[test]
fn what_every_task_would_fail_on_is_refused_when_planning() {
    let dir = tempfile::tempdir().unwrap();
    let model = |model: &'static str| {
        move |v: &mut serde_json::Value| v["vehicles"][1] = serde_json::json!({"name": "m", "model": model})
    };
    let missing = inputs_refusal(dir.path(), model("absent.glb"));
    assert!(missing.contains("vehicles[1] \"m\"") && missing.contains("absent.glb"), "{missing}");
    std::fs::create_dir(dir.path().join("folder.glb")).unwrap();
    let folder = inputs_refusal(dir.path(), model("folder.glb"));
    assert!(folder.contains("vehicles[1]") && folder.contains("folder.glb"), "{folder}");
    assert!(
        std::process::Command::new("mkfifo").arg(dir.path().join("fifo.obj")).status().unwrap().success()
    );
    let fifo = inputs_refusal(dir.path(), model("fifo.obj"));
    assert!(fifo.contains("vehicles[1]") && fifo.contains("fifo.obj"), "{fifo}");
    std::os::unix::fs::symlink("/dev/zero", dir.path().join("zero.glb")).unwrap();
    let zero = inputs_refusal(dir.path(), model("zero.glb"));
    assert!(zero.contains("vehicles[1]") && zero.contains("zero.glb"), "{zero}");
    let dims = inputs_refusal(dir.path(), |v| {
        v["vehicles"][1]["dims"] = serde_json::json!({"height_m": 1.0, "bonnet_height_m": 0.9})
    });
    assert!(dims.contains("vehicles[1] \"van\"") && dims.contains("bonnet_height_m"), "{dims}");
    let palette = inputs_refusal(dir.path(), |v| v["measure"]["palette"] = 16.into());
    assert!(
        palette.contains("vehicles[0] \"pickup\"") && palette.contains("measure.palette 16"),
        "{palette}"
    );
    let scene = |file: &str, scenario: &str| {
        let (file, scenario) = (file.to_string(), scenario.to_string());
        move |v: &mut serde_json::Value| {
            v["scenarios"] =
                serde_json::json!([{"name": "s", "kind": "scene", "file": file, "scenario": scenario}]);
        }
    };
    let no_file = inputs_refusal(dir.path(), scene("absent-scene.json", "A"));
    assert!(no_file.contains("scenario=s") && no_file.contains("absent-scene.json"), "{no_file}");
    let demo_scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../fixtures/scenes/demo.json");
    std::fs::copy(&demo_scene, dir.path().join("scene.json")).unwrap();
    let no_scenario = inputs_refusal(dir.path(), scene("scene.json", "Z"));
    assert!(no_scenario.contains("scenario=s") && no_scenario.contains("\"Z\""), "{no_scenario}");
    // A step that keeps one frame of a scenario would make its totals one frame's (1/fps).
    let lone = inputs_refusal(dir.path(), |v| v["measure"]["frame_step"] = 100.into());
    assert!(
        lone.contains("d.json")
            && lone.contains("measure.frame_step 100 keeps one frame")
            && lone.contains("at most"),
        "{lone}"
    );
    // The step it offers keeps two frames of that cell's scenario, one more keeps one.
    let offered: u32 = lone.rsplit("at most ").next().and_then(|n| n.trim().parse().ok()).expect("a step");
    let frames =
        [181, 121].into_iter().find(|&n| lone.contains(&format!("scenario's {n} "))).expect("frames");
    let kept = |step: u32| crate::job::FrameSelection::every(step).frames(frames).len();
    assert!(kept(offered) == 2 && kept(offered + 1) == 1, "{lone}");
    // The shipped design plans: every cell builds and its bound is the measured frames' time,
    // every 30th frame of demo A's 3 s and street-2's 2 s at 60 fps: the scenarios' durations
    // (keeping their last frames too read 3.5 and 2.5 s).
    let plan = plan_design(&fixture("tiny-2x2.json")).unwrap();
    let limits = check_inputs(&plan).unwrap();
    assert_eq!(limits.len(), 4);
    for (cell, seconds) in &limits {
        let want = if cell.scenario == "A" { 3.0 } else { 2.0 };
        assert!((seconds - want).abs() < 1e-12, "{cell}: {seconds} s");
    }
}

/// The tiny design's 8 tasks written into `dir` (every value within its cell's bound), then `edit`
/// applied to task 3; returns the merge's refusal.
fn merge_refusal(edit: impl Fn(&mut Vec<DesignTask>)) -> String {
    let plan = plan_design(&fixture("tiny-2x2.json")).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let mut tasks: Vec<DesignTask> = (0..8).map(|i| super::tests::synthetic(&plan, i, 0.5, 0.25)).collect();
    assert!(merge_tasks(&plan, dir.path(), &tasks).is_ok());
    edit(&mut tasks);
    merge_tasks(&plan, dir.path(), &tasks).unwrap_err()
}

fn merge_tasks(plan: &Plan, dir: &Path, tasks: &[DesignTask]) -> Result<(), String> {
    for task in tasks {
        write_task(task, &task_dir(dir, task.task)).unwrap();
    }
    merge_design(plan, dir).map(|_| ()).map_err(|e| e.to_string())
}

#[test]
fn every_value_a_merge_reads_is_checked_naming_the_task_file_and_field() {
    let value = |field: &str, v: f64| {
        let field = field.to_string();
        move |tasks: &mut Vec<DesignTask>| {
            let c = &mut tasks[3].units[0].candidates[0];
            match field.as_str() {
                "legible_s" => c.legible_s = v,
                "decision_window_legible_s" => c.decision_window_legible_s = v,
                _ => c.angular_area_deg2_s = v,
            }
        }
    };
    for (field, v) in
        [("legible_s", 6.7), ("legible_s", -50.0), ("legible_s", 1e308), ("angular_area_deg2_s", 1e308)]
    {
        let refused = merge_refusal(value(field, v));
        assert!(refused.contains("task-0003/task.json") && refused.contains(field), "{field} {v}: {refused}");
    }
    let window = merge_refusal(value("decision_window_legible_s", 0.9));
    assert!(window.contains("decision_window_legible_s 0.9"), "{window}");
    let empty = merge_refusal(|t| t[3].units.clear());
    assert!(empty.contains("task-0003") && empty.contains("units: empty"), "{empty}");
    // Task 2 and 3 are the pickup's street-2 replicates 0 and 1: one unit number in both.
    let twice = merge_refusal(|t| t[3].units[0].unit = t[2].units[0].unit);
    assert!(twice.contains("task-0003") && twice.contains("also in task 2"), "{twice}");
    let duplicate = merge_refusal(|t| {
        let again = t[3].units[0].candidates[0].clone();
        t[3].units[0].candidates.push(again);
    });
    assert!(duplicate.contains("candidates[2] \"a\"") && duplicate.contains("twice"), "{duplicate}");
    let kind = merge_refusal(|t| t[3].units[0].candidates[0].kind = "part\nall,forged,part,99".into());
    assert!(kind.contains("task-0003") && kind.contains("kind"), "{kind}");
    let name = merge_refusal(|t| t[3].units[0].candidates[0].name = "a\u{1b}]0;x\u{7}".into());
    assert!(name.contains("control character"), "{name}");
}

#[test]
fn tasks_that_read_two_versions_of_a_model_are_refused_naming_them() {
    let plan = plan_design(&fixture("tiny-2x2.json")).unwrap();
    let mut tasks: Vec<DesignTask> = (0..8).map(|i| super::tests::synthetic(&plan, i, 0.5, 0.25)).collect();
    for task in &mut tasks {
        let hash = if task.task < 2 { "1111111111111111" } else { "2222222222222222" };
        task.inputs.insert("models/car.glb".into(), hash.into());
    }
    let dir = tempfile::tempdir().unwrap();
    let refused = merge_tasks(&plan, dir.path(), &tasks).unwrap_err();
    assert!(refused.contains("models/car.glb changed between tasks"), "{refused}");
    assert!(refused.contains("task 0, task 1 read version 1111111111111111"), "{refused}");
    for task in &mut tasks {
        task.inputs.insert("models/car.glb".into(), "1111111111111111".into());
    }
    assert!(merge_tasks(&plan, dir.path(), &tasks).is_ok());
}

#[cfg(unix)]
#[test]
fn no_task_is_read_through_a_link() {
    let plan = plan_design(&fixture("tiny-2x2.json")).unwrap();
    let (dir, elsewhere) = (tempfile::tempdir().unwrap(), tempfile::tempdir().unwrap());
    for i in 0..8 {
        write_task(&super::tests::synthetic(&plan, i, 0.5, 0.25), &task_dir(elsewhere.path(), i)).unwrap();
    }
    std::os::unix::fs::symlink(elsewhere.path().join("tasks"), dir.path().join("tasks")).unwrap();
    assert!(super::run::completed(&plan, dir.path(), 0).is_none(), "a task behind a link is not complete");
    let refused = merge_design(&plan, dir.path()).unwrap_err().to_string();
    assert!(refused.contains("task-0000") && refused.contains("behind a link"), "{refused}");
}

#[cfg(unix)]
#[test]
fn the_result_set_is_written_whole_or_not_at_all() {
    let plan = plan_design(&fixture("tiny-2x2.json")).unwrap();
    let dir = tempfile::tempdir().unwrap();
    for i in 0..8 {
        write_task(&super::tests::synthetic(&plan, i, 0.5, 0.25), &task_dir(dir.path(), i)).unwrap();
    }
    let result = merge_design(&plan, dir.path()).unwrap();
    std::fs::create_dir(dir.path().join("design.html")).unwrap();
    let refused = write_result_set(&result, dir.path(), &[]).unwrap_err().to_string();
    assert!(refused.contains("design.html"), "{refused}");
    assert!(!dir.path().join("design.json").exists() && !dir.path().join("design.csv").exists());
    std::fs::remove_dir(dir.path().join("design.html")).unwrap();
    let written = write_result_set(&result, dir.path(), &[]).unwrap();
    assert!(written.iter().all(|f| f.is_file()), "{written:?}");
    let leftovers: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .flatten()
        .filter(|e| e.file_name().to_string_lossy().starts_with(".ufcsr"))
        .collect();
    assert!(leftovers.is_empty(), "{leftovers:?}");
}

#[test]
fn a_task_records_a_fingerprint_of_every_file_it_read() {
    let dir = tempfile::tempdir().unwrap();
    let scenes = Path::new(env!("CARGO_MANIFEST_DIR")).join("../fixtures/scenes");
    for file in ["box-truck.obj", "box-truck.mtl"] {
        std::fs::copy(scenes.join(file), dir.path().join(file)).unwrap();
    }
    let mut value = tiny_value();
    value["vehicles"][1] = serde_json::json!({"name": "box", "model": "box-truck.obj"});
    let plan = plan_file(dir.path(), &value).unwrap();
    let cell = plan.tasks.iter().find(|t| t.cell.vehicle == "box").unwrap().cell.clone();
    let scene = super::build::cell_scene(&plan.design, plan.base(), &cell, 1).unwrap();
    let hashes = super::plan::input_hashes(plan.base(), &scene.input_files).unwrap();
    let names: Vec<&str> = hashes.keys().map(String::as_str).collect();
    assert_eq!(names, ["box-truck.mtl", "box-truck.obj"]);
    // A replaced model is another version.
    let mut obj = std::fs::read(dir.path().join("box-truck.obj")).unwrap();
    obj.extend_from_slice(b"\n# edited\n");
    std::fs::write(dir.path().join("box-truck.obj"), obj).unwrap();
    let again = super::plan::input_hashes(plan.base(), &scene.input_files).unwrap();
    assert_ne!(again["box-truck.obj"], hashes["box-truck.obj"]);
    assert_eq!(again["box-truck.mtl"], hashes["box-truck.mtl"]);
}
