//! The documented way to run a design's tasks side by side (docs/design.md)
//! cannot run shell code hidden in a path, and a task writes through no link
//! planted in the output folder (issue 41 §2). Once, `plan` printed commands
//! quoted for `sh` and the docs piped them through `xargs -I{} sh -c '{}'`:
//! xargs strips the quotes, so a design in `x$(touch PWNED)/` ran `touch`.
//! Now the pipeline passes task numbers, and `plan`'s commands go to `sh`
//! one line at a time. A one-task design (a van, the static street-2, 1/256
//! of a 256² palette) keeps the real run short.

use std::path::Path;
use std::process::{Command, Output};

fn text(output: &Output) -> String {
    format!("{}\n{}", String::from_utf8_lossy(&output.stdout), String::from_utf8_lossy(&output.stderr))
}

/// `sh -c SCRIPT sh ARGS…` in `dir`, with the built `ufcsr` first on the PATH.
fn sh(dir: &Path, script: &str, args: &[&Path]) -> Output {
    let bin = Path::new(env!("CARGO_BIN_EXE_ufcsr")).parent().unwrap();
    let path = format!("{}:{}", bin.display(), std::env::var("PATH").unwrap_or_default());
    Command::new("sh")
        .args(["-c", script, "sh"])
        .args(args)
        .current_dir(dir)
        .env("PATH", path)
        .env("XDG_RUNTIME_DIR", dir)
        .output()
        .unwrap()
}

#[cfg(unix)]
#[test]
fn the_documented_pipeline_runs_no_code_hidden_in_a_path_and_writes_through_no_link() {
    let dir = tempfile::tempdir().unwrap();
    let hostile = dir.path().join("x$(touch PWNED)");
    std::fs::create_dir(&hostile).unwrap();
    let design = hostile.join("d.json");
    let value = serde_json::json!({
        "schema": "ufcsr-design/1",
        "name": "one task",
        "vehicles": [{"name": "van", "body": "van"}],
        "scenarios": [{"name": "street-2", "kind": "street", "position": 2}],
        "measure": {"sample": 0.00390625, "palette": 256, "frame_step": 30, "patch_spacing_m": 0.3}
    });
    std::fs::write(&design, serde_json::to_vec(&value).unwrap()).unwrap();
    let out = dir.path().join("out");
    let elsewhere = dir.path().join("elsewhere");
    std::fs::create_dir_all(&out).unwrap();
    std::fs::create_dir_all(&elsewhere).unwrap();
    std::os::unix::fs::symlink(&elsewhere, out.join("tasks")).unwrap();
    // docs/design.md's line, with the user's shell quoting the paths.
    let pipeline = r#"ufcsr design plan "$1" --out "$2" --indices | xargs -P 2 -I{} ufcsr design run "$1" --out "$2" --task {}"#;
    let run = sh(dir.path(), pipeline, &[&design, &out]);
    assert!(run.status.success(), "{}", text(&run));
    assert!(!dir.path().join("PWNED").exists(), "the path's $(…) ran");
    assert!(String::from_utf8_lossy(&run.stderr).contains("task 1 of 1 ["), "{}", text(&run));
    let tasks = std::fs::symlink_metadata(out.join("tasks")).unwrap();
    assert!(tasks.is_dir() && !tasks.file_type().is_symlink(), "the planted link is still there");
    assert!(out.join("tasks/task-0000/task.json").is_file());
    assert_eq!(std::fs::read_dir(&elsewhere).unwrap().count(), 0, "written through the link");
    // plan's commands, one line at a time through sh (`xargs -d '\n'` keeps the quotes), echoed.
    let lines = r#"ufcsr design plan "$1" --out "$2" --program echo | xargs -d '\n' -I{} sh -c '{}'"#;
    let echoed = sh(dir.path(), lines, &[&design, &out]);
    assert!(echoed.status.success(), "{}", text(&echoed));
    let expected = format!("design run {} --task 0 --out {}\n", design.display(), out.display());
    assert_eq!(String::from_utf8_lossy(&echoed.stdout), expected);
    assert!(!dir.path().join("PWNED").exists(), "the path's $(…) ran");
}

/// `batch plan`'s documented pipeline (docs/scale-out.md: `xargs -d '\n' -I{} sh -c '{}'`)
/// keeps `plan`'s quotes: an output folder `x$(touch PWNED)` in the batch file reaches the
/// command as text (echoed here) and never runs.
#[cfg(unix)]
#[test]
fn the_documented_batch_pipeline_runs_no_code_hidden_in_a_path() {
    let dir = tempfile::tempdir().unwrap();
    let batch = dir.path().join("batch.json");
    let value = serde_json::json!({
        "out": "x$(touch PWNED)",
        "scenes": ["demo"],
        "scenarios": ["A"],
        "ppd": [10],
        "frame_step": [30]
    });
    std::fs::write(&batch, serde_json::to_vec(&value).unwrap()).unwrap();
    let lines = r#"ufcsr batch plan "$1" --program echo | xargs -d '\n' -I{} sh -c '{}'"#;
    let echoed = sh(dir.path(), lines, &[&batch]);
    assert!(echoed.status.success(), "{}", text(&echoed));
    let stdout = String::from_utf8_lossy(&echoed.stdout);
    assert!(stdout.contains("x$(touch PWNED)"), "the path reached the command as text: {stdout}");
    assert!(!dir.path().join("PWNED").exists(), "the path's $(…) ran: {stdout}");
}
