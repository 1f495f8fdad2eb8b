//! The observer study's command line writes its tables and names a bad
//! kerb (moved from `capture/tests/it/observers.rs`, whose other test runs the
//! library).

use std::process::Command;

#[test]
fn the_observers_command_writes_its_tables_and_names_a_bad_kerb() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("observers");
    let run = |extra: &[&str]| {
        Command::new(env!("CARGO_BIN_EXE_ufcsr-capture"))
            .args(["observers", "demo", "--scenario", "A", "--ppd", "2", "--palette-size", "128"])
            .args(["--frame-step", "90", "--heights", "2", "--out"])
            .arg(&out)
            .args(extra)
            .env("XDG_RUNTIME_DIR", dir.path())
            .output()
            .unwrap()
    };
    let output = run(&["--kerb", "-6.5,-4.5:-4.5,-6.5", "--positions", "2"]);
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(output.status.success(), "{stdout}\n{}", String::from_utf8_lossy(&output.stderr));
    assert!(stdout.contains("4 observers") && stdout.contains("angular area"), "{stdout}");
    for file in ["observers.json", "observers.csv", "observer-parts.csv"] {
        assert!(out.join(file).is_file(), "{file}");
    }
    let bad = run(&["--kerb", "-6.5,-4.5"]);
    assert_eq!(bad.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&bad.stderr).contains("--kerb"));
    let no_kerb = run(&["--positions", "3"]);
    assert_ne!(no_kerb.status.code(), Some(0));
    assert!(String::from_utf8_lossy(&no_kerb.stderr).contains("--kerb"));
}
