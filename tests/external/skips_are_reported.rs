//! The skip rule of this binary, checked on itself: run with `UFCSR_SHARED`
//! pointing at an empty folder, the reference-data test shows as ignored in
//! the summary line (`0 passed; 0 failed; 1 ignored`) with its reason; with
//! `CI=1` the same run fails and names what is missing.

use std::process::{Command, Output};

use crate::need::Outcome;
use libtest_mimic::Completion;

const TEST: &str = "reference_pidt::f150_part_texel_counts_match_an_independent_count";

/// This binary, running only [`TEST`], with the reference data hidden.
fn run_hidden(ci: Option<&str>) -> Output {
    let empty = tempfile::tempdir().unwrap();
    let mut command = Command::new(std::env::current_exe().unwrap());
    command
        .args(["--exact", TEST, "--test-threads", "1", "--color", "never"])
        .env("UFCSR_SHARED", empty.path())
        .env_remove("CI");
    if let Some(value) = ci {
        command.env("CI", value);
    }
    command.output().unwrap()
}

pub fn a_missing_input_is_counted_ignored_and_fails_under_ci() -> Outcome {
    let skipped = run_hidden(None);
    let stdout = String::from_utf8_lossy(&skipped.stdout);
    assert!(skipped.status.success(), "{stdout}");
    let line = stdout.lines().find(|line| line.contains(TEST)).unwrap_or_default();
    assert!(line.contains("... ignored (needs "), "{stdout}");
    assert!(stdout.contains("0 passed; 0 failed; 1 ignored"), "{stdout}");
    assert!(stdout.contains("ref/f150"), "the reason names the missing folder: {stdout}");

    let strict = run_hidden(Some("1"));
    let stdout = String::from_utf8_lossy(&strict.stdout);
    assert!(!strict.status.success(), "{stdout}");
    assert!(stdout.contains("0 passed; 1 failed; 0 ignored"), "{stdout}");
    assert!(stdout.contains("CI is set"), "{stdout}");
    Ok(Completion::Completed)
}
