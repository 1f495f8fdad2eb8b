//! Issue 34: a capture that sees nothing says so. A box occluder around the
//! standing truck hides it in every frame: the capture still writes its
//! (empty) archive, but warns on stderr that no tile shows the vehicle,
//! where it used to exit 0 without a word. The same truck without the box
//! gives no such warning.

use std::process::Command;

fn capture_with(occluders: &str) -> (bool, String) {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("scene.json");
    std::fs::write(
        &scene,
        format!(
            r#"{{ "vehicle": {{"mesh": "demo"}}, "rig": {{"pedestrian": [-8, -8, 0]}}, "occluders": [{{"ground": {{"z": 0}}}}{occluders}],
  "scenarios": {{"S": {{"duration_s": 1.0, "position": [{{"t": 0, "value": [0, 0, 0]}}],
  "yaw_deg": [{{"t": 0, "value": 0}}]}}}}}}"#
        ),
    )
    .unwrap();
    let output = Command::new(env!("CARGO_BIN_EXE_ufcsr-capture"))
        .arg("scene")
        .arg(&scene)
        .args(["--ppd", "3", "--palette-size", "256", "--frames", "0-30/30", "-q", "--out"])
        .arg(dir.path().join("out"))
        .env("XDG_RUNTIME_DIR", dir.path())
        .output()
        .unwrap();
    (output.status.success(), String::from_utf8_lossy(&output.stderr).into_owned())
}

#[test]
fn a_capture_that_sees_no_vehicle_warns_and_one_that_sees_it_does_not() {
    let (ok, stderr) = capture_with(r#", {"box": {"min": [-4, -4, -1], "max": [4, 4, 6]}}"#);
    assert!(ok, "{stderr}");
    assert!(stderr.contains("no tile") && stderr.contains("shows any of the vehicle"), "{stderr}");
    let (ok, stderr) = capture_with("");
    assert!(ok, "{stderr}");
    assert!(!stderr.contains("shows any of the vehicle"), "{stderr}");
}
