//! An interrupted capture leaves no temporary files (the analyzer's half of
//! the atomic-results promise is in `tests/it/atomic_results.rs`). Needs the
//! `ufcsr-capture` binary beside `ufcsr-analyze`, which `cargo test
//! --workspace` builds and `cargo test -p ufcsr` does not.

use std::path::{Path, PathBuf};

use crate::need::{Outcome, missing};
use libtest_mimic::Completion;

/// Every file under `dir` whose name marks it temporary.
fn leftovers(dir: &Path) -> Vec<PathBuf> {
    let mut found = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(folder) = stack.pop() {
        for entry in std::fs::read_dir(&folder).into_iter().flatten().flatten() {
            let name = entry.file_name().to_string_lossy().into_owned();
            if name.contains(".tmp-") || name.starts_with(".ufcsr-staging-") {
                found.push(entry.path());
            }
            if entry.path().is_dir() {
                stack.push(entry.path());
            }
        }
    }
    found
}

pub fn an_interrupted_capture_leaves_no_temporary_files() -> Outcome {
    let capture = Path::new(env!("CARGO_BIN_EXE_ufcsr-analyze")).with_file_name("ufcsr-capture");
    if !capture.is_file() {
        return missing("ufcsr-capture built beside ufcsr-analyze (cargo test --workspace builds it)");
    }
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("archive");
    let mut child = std::process::Command::new(&capture)
        .args(["demo", "--scenario", "B", "--ppd", "30", "--palette-size", "1024", "-q", "--out"])
        .arg(&out)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    // Interrupt once tiles are being written.
    let started = std::time::Instant::now();
    while started.elapsed() < std::time::Duration::from_secs(60) {
        let tiles = std::fs::read_dir(out.join("tiles")).map(|d| d.count()).unwrap_or(0);
        if tiles > 5 || child.try_wait().unwrap().is_some() {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    let pid = child.id().to_string();
    let _ = std::process::Command::new("kill").args(["-INT", &pid]).status();
    let output = child.wait_with_output().unwrap();
    if output.status.code() == Some(0) {
        // A machine too fast to catch it mid-way: nothing was checked, so say so.
        return Ok(Completion::ignored_with("the capture finished before it could be interrupted"));
    }
    assert_eq!(output.status.code(), Some(130), "{}", String::from_utf8_lossy(&output.stderr));
    assert!(String::from_utf8_lossy(&output.stderr).contains("interrupted"));
    assert!(leftovers(&out).is_empty(), "left behind: {:?}", leftovers(&out));
    assert!(!out.join("manifest.json").exists(), "an interrupted capture wrote a manifest");
    Ok(Completion::Completed)
}
