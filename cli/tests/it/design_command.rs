//! `ufcsr design plan|run|merge` end to end on a 2 × 2 design (one
//! replicate, the exact measure at 1/256 of a 256² palette): the plan's
//! lines are the tasks, a re-run skips complete tasks and redoes a removed
//! one, merge writes the result set with the answer first (the pickup's
//! displays compared across its cells) and names a missing cell. (Refusals
//! by factor and level, another design's task and the intervals' coverage
//! are the library's tests, `design::tests`.)

use std::path::Path;
use std::process::{Command, Output};

fn ufcsr(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_ufcsr")).args(args).env("XDG_RUNTIME_DIR", dir).output().unwrap()
}

fn text(output: &Output) -> String {
    format!("{}\n{}", String::from_utf8_lossy(&output.stdout), String::from_utf8_lossy(&output.stderr))
}

#[test]
fn a_design_plans_runs_resumes_and_merges() {
    let dir = tempfile::tempdir().unwrap();
    let fixture = Path::new(env!("CARGO_MANIFEST_DIR")).join("../fixtures/designs/tiny-2x2.json");
    let mut design: serde_json::Value = serde_json::from_slice(&std::fs::read(fixture).unwrap()).unwrap();
    design["replicates"] = 1.into();
    let file = dir.path().join("design.json");
    std::fs::write(&file, serde_json::to_vec(&design).unwrap()).unwrap();
    let (file, out) = (file.to_str().unwrap(), dir.path().join("out"));
    let out = out.to_str().unwrap();
    let plan = ufcsr(dir.path(), &["design", "plan", file, "--out", out, "--program", "ufcsr"]);
    let lines: Vec<String> = String::from_utf8_lossy(&plan.stdout).lines().map(str::to_string).collect();
    assert_eq!(lines.len(), 4, "{}", text(&plan));
    assert!(lines[3].starts_with("ufcsr design run") && lines[3].contains("--task 3"), "{}", lines[3]);
    // Merging before running names the missing cells.
    let early = ufcsr(dir.path(), &["design", "merge", file, "--out", out]);
    assert_ne!(early.status.code(), Some(0));
    assert!(text(&early).contains("4 missing") && text(&early).contains("vehicle=van scenario=street-2"));
    let run = ufcsr(dir.path(), &["design", "run", file, "--out", out, "--json"]);
    assert!(run.status.success(), "{}", text(&run));
    let summary: serde_json::Value = serde_json::from_slice(&run.stdout).unwrap();
    assert_eq!((summary["ran"].as_u64(), summary["skipped"].as_u64()), (Some(4), Some(0)), "{summary}");
    // --json's written: exactly the files the run left in --out (every task's folder).
    let mut written: Vec<String> =
        summary["written"].as_array().unwrap().iter().map(|p| p.as_str().unwrap().to_string()).collect();
    let mut there = Vec::new();
    let mut folders = vec![std::path::PathBuf::from(out)];
    while let Some(folder) = folders.pop() {
        for entry in std::fs::read_dir(folder).unwrap().map(Result::unwrap) {
            if entry.file_type().unwrap().is_dir() {
                folders.push(entry.path());
            } else {
                there.push(entry.path().display().to_string());
            }
        }
    }
    written.sort();
    there.sort();
    assert!(there.len() > 4 && written == there, "written {written:?}\nthere {there:?}");
    // Resumable: complete tasks are skipped, a removed one is measured again.
    std::fs::remove_file(Path::new(out).join("tasks/task-0002/task.json")).unwrap();
    let again = ufcsr(dir.path(), &["design", "run", file, "--out", out]);
    assert!(text(&again).contains("1 task(s) run, 3 skipped"), "{}", text(&again));
    let merge = ufcsr(dir.path(), &["design", "merge", file, "--out", out]);
    assert!(merge.status.success(), "{}", text(&merge));
    assert!(text(&merge).contains("for a pickup: ") && text(&merge).contains("across all:"));
    let result: ufcsr::format::DesignResult =
        serde_json::from_slice(&std::fs::read(Path::new(out).join("design.json")).unwrap()).unwrap();
    assert_eq!((result.tasks, result.cells.len(), result.vehicles.len()), (4, 4, 2));
    // The pickup's display patches are laid out from its mesh alone, so its cells name the same ones
    // and its displays are compared (best 1–3 with P(best)); the van has no display size: said.
    let pickup = result.vehicles.iter().find(|v| v.group == "vehicle pickup").unwrap();
    let displays: Vec<_> = pickup.best.iter().filter(|b| b.kind == "patch").collect();
    assert!(!displays.is_empty() && displays[0].rank == 1, "{:?}", pickup.best);
    assert!(text(&merge).contains("for a pickup: ") && text(&merge).contains("display"));
    follows_the_answer_rules(&result);
    assert!(
        result.answer.iter().any(|l| l.starts_with("displays: none measured for van")),
        "{:?}",
        result.answer
    );
    assert!(!result.answer.iter().any(|l| l.contains("not compared")), "{:?}", result.answer);
    let page = std::fs::read_to_string(Path::new(out).join("design.html")).unwrap();
    assert!(page.find("Answer").unwrap() < page.find("Main effects").unwrap());
    // The pickup's displays' main effects: its two scenarios, within its own cells only.
    let effects = &result.display_main_effects;
    assert!(!effects.is_empty(), "{result:?}");
    assert!(effects.iter().all(|e| e.within_vehicle.as_deref() == Some("pickup") && e.factor == "scenario"));
    assert!(effects.iter().all(|e| displays.iter().any(|d| d.name == e.candidate)), "{effects:?}");
    assert!(page.contains("Displays, within one body"));
    let csv = std::fs::read_to_string(Path::new(out).join("design.csv")).unwrap();
    assert!(csv.contains("within vehicle pickup: scenario="), "{csv}");
}

/// Issue 42 §2–§3: no group's best is glass or a wheel (the placement's one rule), what was left
/// out is said, and a best of 0 s is no best.
fn follows_the_answer_rules(result: &ufcsr::format::DesignResult) {
    for group in result.vehicles.iter().chain([&result.overall]) {
        for best in &group.best {
            assert!(
                ufcsr::placement::exclusions(
                    [(best.name.as_str(), ufcsr::placement::CandidateKind::Part)].into_iter(),
                    &Default::default(),
                    &ufcsr::placement::default_not_mountable()
                )
                .is_empty(),
                "{best:?}"
            );
        }
    }
    assert!(
        !result.answer.iter().any(|l| l.contains("best part windshield") || l.contains(" 0.00 s [")),
        "{:?}",
        result.answer
    );
    assert!(
        result.answer.iter().any(|l| l.starts_with("left out of the answers: not mountable")),
        "{:?}",
        result.answer
    );
}
