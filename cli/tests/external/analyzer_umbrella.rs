//! `ufcsr analyze …` runs the analyzer's binary, which only a workspace
//! build puts beside `ufcsr` (`cargo test -p ufcsr-capture` alone does not):
//! ignored with the reason when it is absent; a failure under `CI`.

use std::path::Path;
use std::process::Command;

use libtest_mimic::Completion;

use crate::need::{Outcome, missing};

fn ufcsr() -> Command {
    Command::new(env!("CARGO_BIN_EXE_ufcsr"))
}

pub fn ufcsr_analyze_runs_the_analyzer_and_passes_its_exit_code() -> Outcome {
    let analyzer = Path::new(env!("CARGO_BIN_EXE_ufcsr")).with_file_name("ufcsr-analyze");
    if !analyzer.is_file() {
        return missing(&format!("{} (cargo test --workspace builds it)", analyzer.display()));
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
    Ok(Completion::Completed)
}
