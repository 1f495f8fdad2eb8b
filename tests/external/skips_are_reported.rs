//! The skip rule, checked on the binary itself: run with `UFCSR_SHARED`
//! pointing at an empty folder, a reference-data test shows as ignored in
//! the summary line (`0 passed; 0 failed; 1 ignored`) with its reason; with
//! `CI=1` the same run fails and names what is missing. Both crates' external
//! binaries include this file (the capture's by path) and check one of their
//! own reference-data tests with it.

use std::process::{Command, Output};

use crate::need::Outcome;
use libtest_mimic::Completion;

/// This binary, running only `test`, with the reference data hidden.
fn run_hidden(test: &str, ci: Option<&str>) -> Output {
    let empty = tempfile::tempdir().unwrap();
    let mut command = Command::new(std::env::current_exe().unwrap());
    command
        .args(["--exact", test, "--test-threads", "1", "--color", "never"])
        .env("UFCSR_SHARED", empty.path())
        .env_remove("CI");
    if let Some(value) = ci {
        command.env("CI", value);
    }
    command.output().unwrap()
}

/// `test`, with `../shared` hidden, is ignored with a reason naming
/// `missing_path`, and fails under `CI=1`.
pub fn a_hidden_reference_is_ignored_and_fails_under_ci(test: &str, missing_path: &str) -> Outcome {
    let skipped = run_hidden(test, None);
    let stdout = String::from_utf8_lossy(&skipped.stdout);
    assert!(skipped.status.success(), "{stdout}");
    let line = stdout.lines().find(|line| line.contains(test)).unwrap_or_default();
    assert!(line.contains("... ignored (needs "), "{stdout}");
    assert!(stdout.contains("0 passed; 0 failed; 1 ignored"), "{stdout}");
    assert!(stdout.contains(missing_path), "the reason names the missing file: {stdout}");

    let strict = run_hidden(test, Some("1"));
    let stdout = String::from_utf8_lossy(&strict.stdout);
    assert!(!strict.status.success(), "{stdout}");
    assert!(stdout.contains("0 passed; 1 failed; 0 ignored"), "{stdout}");
    assert!(stdout.contains("CI is set"), "{stdout}");
    Ok(Completion::Completed)
}
