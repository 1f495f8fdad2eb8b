//! `ufcsr COMMAND ...` is the same command as the program's own (`ufcsr
//! batch plan` is `ufcsr batch plan`), and refuses what is none.

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
fn an_unknown_command_is_a_usage_error() {
    let output = ufcsr().arg("capturee").output().unwrap();
    assert_eq!(output.status.code(), Some(2));
    let message = String::from_utf8_lossy(&output.stderr);
    // clap's usage error (the router's "unknown command" before the one command tree).
    assert!(message.contains("unrecognized subcommand") && message.contains("Usage: ufcsr"), "{message}");
    assert!(ufcsr().arg("--help").output().unwrap().status.success());
}

#[test]
fn every_capture_command_in_the_usage_routes_to_its_help() {
    // The analyzer's commands need its binary beside this one (tests/external covers them).
    for command in ["capture", "assemble", "batch", "study", "observers", "verify", "inspect", "views"] {
        let output = ufcsr().args([command, "--help"]).output().unwrap();
        assert!(
            output.status.success(),
            "ufcsr {command} --help: {}",
            String::from_utf8_lossy(&output.stderr)
        );
        let usage = String::from_utf8_lossy(&output.stdout);
        assert!(usage.contains(&format!("Usage: ufcsr {command}")), "ufcsr {command} --help: {usage}");
    }
}
