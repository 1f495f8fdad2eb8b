//! `ufcsr COMMAND ...` runs the toolkit's programs with the same arguments.

use std::path::Path;
use std::process::Command;

fn ufcsr() -> Command {
    Command::new(env!("CARGO_BIN_EXE_ufcsr"))
}

#[test]
fn ufcsr_batch_plan_is_ufcsr_capture_batch_plan() {
    let batch = Path::new(env!("CARGO_MANIFEST_DIR")).join("../fixtures/batches/demo-study.json");
    let capture = env!("CARGO_BIN_EXE_ufcsr-capture");
    let via_umbrella =
        ufcsr().args(["batch", "plan"]).arg(&batch).args(["--program", capture]).output().unwrap();
    let direct = Command::new(capture)
        .args(["batch", "plan"])
        .arg(&batch)
        .args(["--program", capture])
        .output()
        .unwrap();
    assert!(via_umbrella.status.success(), "{}", String::from_utf8_lossy(&via_umbrella.stderr));
    assert!(!via_umbrella.stdout.is_empty());
    assert_eq!(via_umbrella.stdout, direct.stdout);
}

#[test]
fn ufcsr_analyze_runs_the_analyzer_and_passes_its_exit_code() {
    let analyzer = Path::new(env!("CARGO_BIN_EXE_ufcsr")).with_file_name("ufcsr-analyze");
    if !analyzer.is_file() {
        assert!(std::env::var_os("CI").is_none(), "CI: ufcsr-analyze is not built beside ufcsr");
        eprintln!("SKIPPED: ufcsr-analyze is not built (cargo test --workspace builds it)");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let example = Path::new(env!("CARGO_MANIFEST_DIR")).join("../fixtures/example");
    let out = dir.path().join("out");
    let status = ufcsr().arg("analyze").arg(&example).arg("--out").arg(&out).arg("--quiet").status().unwrap();
    assert!(status.success());
    assert!(out.join("result.json").is_file());
    // Subcommands of either program route the same way.
    let compared = dir.path().join("compared");
    let status = ufcsr().arg("report").arg(&out).arg(&out).arg("--out").arg(&compared).status().unwrap();
    assert!(status.success());
    assert!(compared.join("report.html").is_file());
    let gpu_views = dir.path().join("gpu-views");
    let views = ufcsr().arg("views").arg(&out).arg("--out").arg(&gpu_views).output().unwrap();
    assert!(views.status.success(), "{}", String::from_utf8_lossy(&views.stderr));
    assert!(gpu_views.join("views.png").is_file());
    // The analyzer's own failure comes through (exit 2: nothing could be analysed).
    let missing = ufcsr().arg("analyze").arg(dir.path().join("missing")).output().unwrap();
    assert!(!missing.status.success());
    assert!(String::from_utf8_lossy(&missing.stderr).contains("missing"));
}

#[test]
fn an_unknown_command_is_a_usage_error() {
    let output = ufcsr().arg("capturee").output().unwrap();
    assert_eq!(output.status.code(), Some(2));
    let message = String::from_utf8_lossy(&output.stderr);
    assert!(message.contains("unknown command") && message.contains("usage: ufcsr"), "{message}");
    assert!(ufcsr().arg("--help").output().unwrap().status.success());
}
