//! Issue 34: a re-run leaves nothing stale. `observers` with fewer
//! observers than an earlier study in the same folder removes the extra
//! `observer-NNN` folders; `placement` without a vehicle model removes the
//! earlier run's `placement.png` and `placement-views/` (they showed sets
//! the new answer may not choose).

use std::path::{Path, PathBuf};
use std::process::Command;

#[test]
fn observers_remove_the_folders_of_observers_an_earlier_study_had() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let stale = out.join("observer-005");
    std::fs::create_dir_all(stale.join("tiles")).unwrap();
    std::fs::write(stale.join("manifest.json"), "{}").unwrap();
    let output = Command::new(env!("CARGO_BIN_EXE_ufcsr-capture"))
        .args(["observers", "demo", "--scenario", "A", "--ppd", "2", "--palette-size", "256"])
        .args([
            "--frame-step",
            "90",
            "--kerb",
            "-6.5,-4.5:-4.5,-6.5",
            "--observers",
            "3",
            "--seed",
            "7",
            "-q",
        ])
        .arg("--out")
        .arg(&out)
        .env("XDG_RUNTIME_DIR", dir.path())
        .output()
        .unwrap();
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    assert!(!stale.exists(), "observer-005 of an earlier study is left");
    for index in 0..3 {
        assert!(out.join(format!("observer-{index:03}")).is_dir(), "observer {index}");
    }
}

/// The placement tests' archive (`common::placement_archive`).
fn archive(dir: &Path, name: &str, vehicle: bool) -> PathBuf {
    crate::common::placement_archive(dir, name, vehicle)
}

#[test]
fn placement_without_a_vehicle_removes_the_earlier_picture() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let run = |archive: &Path| {
        let output = Command::new(env!("CARGO_BIN_EXE_ufcsr-analyze"))
            .arg("placement")
            .arg(archive)
            .args(["--min-dwell-s", "0", "-q", "--out"])
            .arg(&out)
            .output()
            .unwrap();
        assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    };
    run(&archive(dir.path(), "with", true));
    assert!(out.join("placement.png").is_file() && out.join("placement-views").is_dir());
    run(&archive(dir.path(), "without", false));
    assert!(out.join("placement.json").is_file());
    assert!(!out.join("placement.png").exists(), "the earlier picture is left");
    assert!(!out.join("placement-views").exists(), "the earlier views are left");
}
