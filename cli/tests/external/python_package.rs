//! The Python package (`python/`, pure Python) installed and tested with
//! its pytest suite, so that the README's one test command covers it.
//!
//! It is installed the way a user without Rust does: a venv under the target
//! folder, `pip install ./python` with a `PATH` that holds no `cargo` or
//! `rustc` (checked), then pytest, with this build's `ufcsr-analyze` as the
//! program `ufcsr.analyze()` runs and the reference the suite compares
//! against. The venv and its tools (numpy, pandas, pytest, the flit_core
//! build backend) are kept between runs.
//!
//! Without python3, a working venv/pip or PyPI it is reported ignored with
//! the reason — and fails instead when `CI` is set.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::time::Instant;

use crate::need::{Outcome, missing, strict};
use libtest_mimic::Completion;

/// Python packages the build and the suite need beside `./python`'s own.
const TOOLS: [&str; 4] = ["flit_core>=3.9,<4", "numpy", "pandas", "pytest"];

/// Writes a timing line to stderr (this harness does not capture it).
fn say(line: &str) {
    let _ = writeln!(std::io::stderr(), "python_package: {line}");
}

/// A missing tool or registry: ignored with the reason, or a failure under CI
/// (with the tool's own error).
fn unavailable(what: &str, output: Option<&Output>) -> Outcome {
    // The tool's own error only where it fails the run: a skip's reason stays one line.
    let detail =
        output.map(|output| String::from_utf8_lossy(&output.stderr).into_owned()).unwrap_or_default();
    if strict() && !detail.trim().is_empty() {
        missing(&format!("{what}\n{}", detail.trim()))
    } else {
        missing(what)
    }
}

/// Runs `command`, `None` when it could not start at all.
fn run(command: &mut Command) -> Option<Output> {
    command.output().ok()
}

fn succeeded(output: &Option<Output>) -> bool {
    output.as_ref().is_some_and(|output| output.status.success())
}

/// Both streams of `output`, for a failure message.
fn both_streams(output: &Output) -> String {
    format!("{}\n{}", String::from_utf8_lossy(&output.stdout), String::from_utf8_lossy(&output.stderr))
}

/// The venv's interpreter, creating the venv (and its tools) on first use;
/// `Err` with the outcome that reports what is unavailable.
fn prepared_venv(venv: &Path) -> Result<PathBuf, Outcome> {
    let python = venv.join("bin").join("python");
    if !python.exists() {
        let python3 = std::env::var("UFCSR_PYTHON").unwrap_or_else(|_| "python3".to_string());
        if !succeeded(&run(Command::new(&python3).arg("--version"))) {
            return Err(unavailable(&format!("{python3} (not installed)"), None));
        }
        let created = run(Command::new(&python3).args(["-m", "venv"]).arg(venv));
        if !succeeded(&created) {
            let _ = std::fs::remove_dir_all(venv);
            return Err(unavailable("python3 -m venv (install python3-venv)", created.as_ref()));
        }
    }
    let imports = "import flit_core, numpy, pandas, pytest";
    if !succeeded(&run(Command::new(&python).args(["-c", imports]))) {
        let installed = run(Command::new(&python)
            .args(["-m", "pip", "install", "--quiet", "--retries", "1", "--timeout", "60"])
            .args(TOOLS));
        if !succeeded(&installed) {
            return Err(unavailable(
                "pip to install flit_core, numpy, pandas, pytest (no pip or no PyPI)",
                installed.as_ref(),
            ));
        }
    }
    Ok(python)
}

/// `PATH` with the venv's `bin` first, as an activated venv has it, and
/// without any folder that holds `cargo` or `rustc`: the install must not
/// need (or find) a Rust toolchain.
fn venv_path_without_rust(python: &Path) -> std::ffi::OsString {
    let bin = python.parent().expect("the venv's bin folder").to_path_buf();
    let rest = std::env::var_os("PATH").unwrap_or_default();
    let rust_free = std::env::split_paths(&rest).filter(|dir| !holds_rust(dir));
    std::env::join_paths(std::iter::once(bin).chain(rust_free)).expect("a valid PATH")
}

fn holds_rust(dir: &Path) -> bool {
    ["cargo", "rustc"].iter().any(|tool| dir.join(tool).exists())
}

pub fn python_package_builds_installs_and_passes_its_pytest_suite() -> Outcome {
    let repository = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/.."));
    let work = Path::new(env!("CARGO_TARGET_TMPDIR")).join("python-package");
    let python = match prepared_venv(&work.join("venv")) {
        Ok(python) => python,
        Err(outcome) => return outcome,
    };

    let path = venv_path_without_rust(&python);
    assert!(
        !std::env::split_paths(&path).any(|dir| holds_rust(&dir)),
        "the install's PATH still holds a Rust toolchain"
    );
    let started = Instant::now();
    let installed = Command::new(&python)
        .args(["-m", "pip", "install", "--quiet", "--no-build-isolation", "--no-deps", "--force-reinstall"])
        .arg(repository.join("python"))
        .env("PATH", &path)
        .env_remove("CARGO")
        .env_remove("RUSTC")
        .current_dir(repository)
        .output()
        .expect("run pip");
    assert!(installed.status.success(), "pip install ./python failed:\n{}", both_streams(&installed));
    let built = started.elapsed().as_secs_f64();

    let started = Instant::now();
    let tested = Command::new(&python)
        .args(["-m", "pytest", "-q", "-W", "error", "-p", "no:cacheprovider", "python/tests"])
        .env("UFCSR_ANALYZE_BIN", env!("CARGO_BIN_EXE_ufcsr-analyze"))
        .current_dir(repository)
        .output()
        .expect("run pytest");
    let report = both_streams(&tested);
    assert!(tested.status.success(), "pytest python/tests failed:\n{report}");
    let summary = report.lines().rev().find(|line| line.contains("passed")).unwrap_or("no summary line");
    say(&format!(
        "pip install ./python {built:.1} s (wall clock, no Rust on PATH), pytest {:.1} s: {}",
        started.elapsed().as_secs_f64(),
        summary.trim()
    ));
    Ok(Completion::Completed)
}
