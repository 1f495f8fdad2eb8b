//! Issue 34: the observer study never replaces its own scene file. A scene
//! file named `observers.json` (or `observers.csv`, `observer-parts.csv`)
//! in `--out` used to be replaced by the study's table; it is refused
//! before anything is captured, naming both files, as `study` refuses a
//! scene named `study.json`.

use std::path::PathBuf;
use std::process::Command;

#[test]
fn observers_never_replace_a_scene_file_named_like_its_tables() {
    let scene = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fixtures/scenes/demo.json");
    for name in ["observers.json", "observers.csv", "observer-parts.csv"] {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("out");
        std::fs::create_dir_all(&out).unwrap();
        let input = out.join(name);
        std::fs::copy(&scene, &input).unwrap();
        let before = std::fs::read(&input).unwrap();
        let output = Command::new(env!("CARGO_BIN_EXE_ufcsr-capture"))
            .arg("observers")
            .arg(&input)
            .args(["--scenario", "A", "--ppd", "2", "--palette-size", "256", "--frame-step", "90"])
            .args(["--kerb", "-6.5,-4.5:-4.5,-6.5", "--observers", "3", "--seed", "7", "-q", "--out"])
            .arg(&out)
            .env("XDG_RUNTIME_DIR", dir.path())
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(2), "{name}: {stderr}");
        assert!(stderr.contains("overwrite the input") && stderr.contains(name), "{name}: {stderr}");
        assert_eq!(std::fs::read(&input).unwrap(), before, "{name}: the scene file was replaced");
        assert!(!out.join("observer-000").exists(), "{name}: captured before refusing");
    }
}
