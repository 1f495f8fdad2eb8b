//! Issue 41, left from the last campaign: `ufcsr placement` refused a bad
//! `--mesh` only after writing its tables (half a result), and a table that
//! is a FIFO was reported as "no placement-frames.csv here".

use std::path::Path;
use std::process::{Command, Output, Stdio};
use std::time::Duration;

use crate::dependency_writers::finish_within;

fn placement(args: &[&Path]) -> Output {
    let child = Command::new(env!("CARGO_BIN_EXE_ufcsr-analyze"))
        .arg("placement")
        .args(args)
        .args(["--min-dwell-s", "0", "-q"])
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    finish_within(child, Duration::from_secs(60), "placement")
}

#[test]
fn a_bad_mesh_is_refused_before_any_table_is_written() {
    let dir = tempfile::tempdir().unwrap();
    let archive = crate::common::placement_archive(dir.path(), "archive", false);
    let mesh = dir.path().join("bad.glb");
    std::fs::write(&mesh, "not a glTF model").unwrap();
    let out = dir.path().join("out");
    let output = placement(&[&archive, Path::new("--mesh"), &mesh, Path::new("--out"), &out]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("bad.glb"), "{stderr}");
    let written: Vec<_> =
        std::fs::read_dir(&out).map(|e| e.flatten().map(|e| e.file_name()).collect()).unwrap_or_default();
    assert!(written.is_empty(), "written before the mesh was refused: {written:?}");
}

#[test]
fn a_placement_table_that_is_a_fifo_is_refused_as_not_a_regular_file() {
    let dir = tempfile::tempdir().unwrap();
    let fifo = |path: &Path| assert!(Command::new("mkfifo").arg(path).status().unwrap().success());
    // Given by name, and found in an archive's results/.
    let named = dir.path().join("table.csv");
    fifo(&named);
    let archive = dir.path().join("archive");
    std::fs::create_dir_all(archive.join("results")).unwrap();
    fifo(&archive.join("results/placement-frames.csv"));
    for (input, shown) in [(named.clone(), "table.csv"), (archive.clone(), "results/placement-frames.csv")] {
        let output = placement(&[&input, Path::new("--out"), &dir.path().join("out")]);
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(2), "{stderr}");
        assert!(
            stderr.contains(shown) && stderr.contains("FIFO") && stderr.contains("not a regular file"),
            "{stderr}"
        );
        assert!(!stderr.contains("no placement-frames.csv here"), "{stderr}");
    }
}
