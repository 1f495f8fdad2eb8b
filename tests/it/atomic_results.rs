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
