//! The observer study's command line writes its tables and names bad
//! options (the library's tests are in `capture/tests/it/observers.rs`).

use std::process::Command;

#[test]
fn the_observers_command_writes_its_tables_and_names_bad_options() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("observers");
    let run = |extra: &[&str]| {
        Command::new(env!("CARGO_BIN_EXE_ufcsr-capture"))
            .args(["observers", "demo", "--scenario", "A", "--ppd", "2", "--palette-size", "256"])
            .args(["--frame-step", "90", "--out"])
            .arg(&out)
            .args(extra)
            .env("XDG_RUNTIME_DIR", dir.path())
            .output()
            .unwrap()
    };
    let output = run(&["--kerb", "-6.5,-4.5:-4.5,-6.5", "--observers", "3", "--seed", "7"]);
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(output.status.success(), "{stdout}\n{}", String::from_utf8_lossy(&output.stderr));
    assert!(
        stdout.contains("3 observers drawn from the population (seed 7)") && stdout.contains("CDC/NCHS"),
        "{stdout}"
    );
    for file in ["observers.json", "observers.csv", "observer-parts.csv"] {
        assert!(out.join(file).is_file(), "{file}");
    }
    let read = |out: &std::path::Path| -> ufcsr::format::ObserverStudy {
        serde_json::from_slice(&std::fs::read(out.join("observers.json")).unwrap()).unwrap()
    };
    assert_eq!(read(&out).displays, None, "no displays without --display");
    // Per display: two observers, each also measured exactly on a quarter of the texels.
    let displays = ["--display", "0.40x0.15", "--display-sample", "1/4"];
    let output = run(&[&["--observers", "2", "--resolution-check", "none"], &displays[..]].concat());
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(output.status.success(), "{stdout}\n{}", String::from_utf8_lossy(&output.stderr));
    assert!(stdout.contains("per candidate: legible s") && stdout.contains("0.25 texels"), "{stdout}");
    let table = std::fs::read_to_string(out.join("observer-displays.csv")).unwrap();
    assert!(table.starts_with("candidate,kind,legible_s_mean,"), "{table}");
    assert!(table.lines().any(|line| line.contains("@0.40x0.15@x") && line.contains(",patch,")), "{table}");
    // observers.json carries the same displays: every candidate of the table, both observers.
    let displays = read(&out).displays.expect("observers.json has displays with --display");
    assert_eq!((displays.display_m, displays.sample, displays.observers.len()), ([0.40, 0.15], 0.25, 2));
    assert_eq!(displays.summary.len() + 1, table.lines().count());
    let first = &displays.summary[0];
    assert!(
        table.lines().nth(1).unwrap().starts_with(&format!("{},{},", first.candidate, first.kind)),
        "{table}"
    );
    // A run without --display drops the earlier run's display table (it describes other observers).
    let output = run(&["--observers", "2", "--resolution-check", "none"]);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    assert!(!out.join("observer-displays.csv").exists() && read(&out).displays.is_none());
    // A bad sample is refused before anyone is captured.
    let refused = run(&["--display", "0.40x0.15", "--display-sample", "2"]);
    assert_ne!(refused.status.code(), Some(0));
    assert!(String::from_utf8_lossy(&refused.stderr).contains("--display-sample"), "{refused:?}");
    let bad = run(&["--kerb", "-6.5,-4.5"]);
    assert_eq!(bad.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&bad.stderr).contains("--kerb"));
    let no_kerb = run(&["--sampling", "grid", "--positions", "3"]);
    assert_ne!(no_kerb.status.code(), Some(0));
    assert!(String::from_utf8_lossy(&no_kerb.stderr).contains("--kerb"));
    let file = dir.path().join("population.json");
    std::fs::write(&file, r#"{"place": {"kind": "rig"}, "groups": []}"#).unwrap();
    let empty = run(&["--population", file.to_str().unwrap()]);
    assert_ne!(empty.status.code(), Some(0));
    assert!(String::from_utf8_lossy(&empty.stderr).contains("--group"));
    std::fs::write(&file, r#"{"place": {"kind": "moon"}}"#).unwrap();
    let malformed = run(&["--population", file.to_str().unwrap()]);
    assert!(String::from_utf8_lossy(&malformed.stderr).contains("population.json"), "{malformed:?}");
}
