//! A result set is written whole or not at all: a failure while writing it
//! (here a vehicle model that turns out to be corrupt) leaves the previous
//! result set byte for byte and no staging folder or temporary file.

use crate::common;

use std::path::{Path, PathBuf};

/// Every file under `dir` whose name marks it temporary.
fn leftovers(dir: &Path) -> Vec<PathBuf> {
    let mut found = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(folder) = stack.pop() {
        for entry in std::fs::read_dir(&folder).unwrap().flatten() {
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

#[test]
fn a_failure_while_writing_leaves_the_previous_result_set_whole() {
    let dir = tempfile::tempdir().unwrap();
    let example = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("fixtures/example");
    let out = dir.path().join("out");
    let status = common::analyzer().arg(&example).arg("--out").arg(&out).arg("-q").status().unwrap();
    assert!(status.success());
    let before: Vec<(PathBuf, Vec<u8>)> =
        ["result.json", "parts.csv", "heatmap.png", "heatmap.glb", "report.html"]
            .iter()
            .map(|name| (out.join(name), std::fs::read(out.join(name)).unwrap()))
            .collect();

    // A second run, with a --scale that changes every output, whose
    // vehicle model is garbage: it fails only after counting, while writing.
    let bad_mesh = dir.path().join("bad.glb");
    std::fs::write(&bad_mesh, b"glTF but not really").unwrap();
    let output = common::analyzer()
        .arg(&example)
        .arg("--out")
        .arg(&out)
        .args(["-q", "--scale", "log", "--mesh"])
        .arg(&bad_mesh)
        .output()
        .unwrap();
    assert!(!output.status.success());
    assert!(String::from_utf8_lossy(&output.stderr).contains("bad.glb"));
    for (path, bytes) in &before {
        assert!(&std::fs::read(path).unwrap() == bytes, "{} changed although the run failed", path.display());
    }
    assert!(leftovers(&out).is_empty(), "left behind: {:?}", leftovers(&out));
}

#[test]
fn an_interrupted_capture_leaves_no_temporary_files() {
    let capture = Path::new(env!("CARGO_BIN_EXE_ufcsr-analyze")).with_file_name("ufcsr-capture");
    if !capture.is_file() {
        assert!(std::env::var_os("CI").is_none(), "CI: ufcsr-capture is not built beside ufcsr-analyze");
        eprintln!("SKIPPED: ufcsr-capture is not built (cargo test --workspace builds it)");
        return;
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
        eprintln!("SKIPPED: the capture finished before it could be interrupted");
        return;
    }
    assert_eq!(output.status.code(), Some(130), "{}", String::from_utf8_lossy(&output.stderr));
    assert!(String::from_utf8_lossy(&output.stderr).contains("interrupted"));
    assert!(leftovers(&out).is_empty(), "left behind: {:?}", leftovers(&out));
    assert!(!out.join("manifest.json").exists(), "an interrupted capture wrote a manifest");
}

#[test]
fn a_smaller_result_set_takes_away_stale_files_and_keeps_the_users_own() {
    let dir = tempfile::tempdir().unwrap();
    let example = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("fixtures/example");
    let out = dir.path().join("out");
    let run = |extra: &[&str]| {
        let status = common::analyzer().arg(&example).arg("--out").arg(&out).arg("-q").args(extra).status();
        assert!(status.unwrap().success());
    };
    run(&[]);
    assert!(out.join("frames.csv").is_file());
    // A note of the user's inside views/, and a file of theirs beside the results.
    std::fs::write(out.join("views/my-notes.txt"), b"mine").unwrap();
    std::fs::write(out.join("paper-draft.txt"), b"mine too").unwrap();
    run(&["--frames-csv", "off"]);
    assert!(!out.join("frames.csv").exists(), "a stale frames.csv of the earlier run is left");
    assert_eq!(std::fs::read(out.join("views/my-notes.txt")).unwrap(), b"mine");
    assert_eq!(std::fs::read(out.join("paper-draft.txt")).unwrap(), b"mine too");
    assert!(out.join("views/front.png").is_file() && out.join("result.json").is_file());
    assert!(leftovers(&out).is_empty(), "left behind: {:?}", leftovers(&out));
}
