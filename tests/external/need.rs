//! What a test of this binary needs from outside the repository, and the one
//! rule for when it is missing: the test is reported *ignored* with the
//! reason (`test slurm::… ... ignored (needs Slurm …)`), so the summary line
//! counts it as skipped, never as passed; and where `CI` is set (`.ci/run`
//! sets `CI=1`) the same test fails instead, so a missing install step
//! cannot hide behind a skip.

use std::path::PathBuf;
use std::process::Command;

use libtest_mimic::{Completion, Failed, Trial};

/// What a test body returns: passed, ignored (with the reason) or failed.
pub type Outcome = Result<Completion, Failed>;

/// True where a missing tool must fail the test: `CI` set to anything but
/// empty, `0` or `false`.
pub fn strict() -> bool {
    std::env::var("CI").is_ok_and(|value| !matches!(value.trim(), "" | "0" | "false"))
}

/// The outcome of a test whose `what` is missing: ignored, or failed under CI.
pub fn missing(what: &str) -> Outcome {
    if strict() {
        Err(Failed::from(format!("CI is set, so this is a failure, not a skip: needs {what}")))
    } else {
        Ok(Completion::ignored_with(format!("needs {what}")))
    }
}

/// A trial named like the former `#[test]` (`module::function`).
pub fn trial(name: &str, body: fn() -> Outcome) -> Trial {
    Trial::ignorable_test(name, body)
}

/// The `shared/` folder beside the checkout (reference data), or the folder
/// named by `UFCSR_SHARED` (the skip tests point it at an empty folder).
/// The same from either crate (this file is also the capture's rule).
pub fn shared_dir() -> PathBuf {
    match std::env::var_os("UFCSR_SHARED") {
        Some(dir) => PathBuf::from(dir),
        None => repository().join("../shared"),
    }
}

/// The repository's root: the folder above this crate that holds `Cargo.lock`.
pub fn repository() -> PathBuf {
    let crate_dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let root = crate_dir.ancestors().find(|dir| dir.join("Cargo.lock").is_file());
    root.unwrap_or(crate_dir).to_path_buf()
}

/// True when `program --version` runs and succeeds.
pub fn runs(program: &str) -> bool {
    Command::new(program).arg("--version").output().is_ok_and(|output| output.status.success())
}
