//! Answers are about people (issue 42 §6): a `--placement` capture puts a
//! median adult's eyes on the rig (the default population's median eye
//! height, a human IPD) and says so on the console, in `--json` and in the
//! manifest's rig; `--rig paper` gives the seed paper's eyes and with them
//! exactly the numbers of a capture at the paper's default rig.

use std::path::Path;
use std::process::Command;

/// `demo` scenario A, one frame, the exact measure of 1/4 of a 256² palette's texels, into `out`:
/// stdout, the manifest and the result.
fn measure(out: &Path, extra: &[&str]) -> (String, serde_json::Value, serde_json::Value) {
    let output = Command::new(env!("CARGO_BIN_EXE_ufcsr-capture"))
        .args(["demo", "--scenario", "A", "--palette-size", "256", "--frames", "150"])
        .args(["--measure", "unobstructed", "--sample", "1/4", "--json", "--out"])
        .arg(out)
        .args(extra)
        .output()
        .unwrap();
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    let read =
        |path: &Path| -> serde_json::Value { serde_json::from_slice(&std::fs::read(path).unwrap()).unwrap() };
    let stdout = String::from_utf8_lossy(&output.stdout).into_owned();
    (stdout, read(&out.join("manifest.json")), read(&out.join("results/result.json")))
}

#[test]
fn placement_answers_take_a_median_adult_and_rig_paper_gives_the_papers_numbers() {
    let dir = tempfile::tempdir().unwrap();
    let settings = |manifest: &serde_json::Value| {
        let s = &manifest["rig"]["settings"];
        (s["eye_height_m"].as_f64().unwrap(), s["ipd_m"].as_f64().unwrap())
    };
    let (stdout, manifest, _) = measure(&dir.path().join("people"), &["--placement"]);
    let median = ufcsr_capture::study::median_eye_height_m();
    assert!((median - 1.573).abs() < 0.01);
    assert_eq!(settings(&manifest), (median, ufcsr_capture::study::HUMAN_IPD_M));
    assert!(stdout.contains("a median US adult (eyes 1.57"), "{stdout}");
    let (stdout, manifest, paper) = measure(&dir.path().join("paper"), &["--placement", "--rig", "paper"]);
    assert_eq!(settings(&manifest), (1.75, 0.1103594));
    assert!(stdout.contains("the seed paper's rig (eyes 1.750 m high, 110.4 mm apart"), "{stdout}");
    // The paper's preset is the paper's default rig: the same measures as a capture without --placement.
    let (_, manifest, plain) = measure(&dir.path().join("plain"), &[]);
    assert_eq!(settings(&manifest), (1.75, 0.1103594));
    assert_eq!(paper["measures"]["parts"], plain["measures"]["parts"]);
    assert_eq!(paper["grand_total"], plain["grand_total"]);
}
