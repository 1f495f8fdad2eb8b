//! Capture settings that cannot be represented are clear errors, never an
//! archive with `null` positions or no frames, and `--resume` redoes tiles
//! that do not decode completely.

use std::path::Path;
use std::process::{Command, Output};

fn capture(args: &[&str], out: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_ufcsr-capture"))
        .args(args)
        .arg("--out")
        .arg(out)
        .args(["--ppd", "3", "--palette-size", "256", "-q"])
        .output()
        .expect("run ufcsr-capture")
}

fn demo_scene_with(replace: &str, by: &str, dir: &Path) -> std::path::PathBuf {
    let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../fixtures/scenes/demo.json"))
        .unwrap();
    assert!(text.contains(replace));
    let path = dir.join("scene.json");
    std::fs::write(&path, text.replacen(replace, by, 1)).unwrap();
    path
}

fn stderr(output: &Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}

#[test]
fn huge_positions_slopes_and_durations_are_errors_not_nulls() {
    let dir = tempfile::tempdir().unwrap();
    for (replace, by, expect) in [
        ("[-29.35, -14.0, 0.0]", "[-1e308, -14.0, 0.0]", "not a street scene"),
        ("\"in_slope\": [8, 0, 0]", "\"in_slope\": [1e308, 0, 0]", "not a street scene"),
        ("\"duration_s\": 3.0", "\"duration_s\": 1e308", "duration"),
    ] {
        let scene = demo_scene_with(replace, by, dir.path());
        let out = dir.path().join("archive");
        let output = capture(&["scene", scene.to_str().unwrap()], &out);
        assert!(!output.status.success(), "{by}: accepted");
        assert!(stderr(&output).contains(expect), "{by}: {}", stderr(&output));
        assert!(!out.join("manifest.json").exists(), "{by}: wrote a manifest");
    }
}

#[test]
fn selecting_no_frame_is_an_error() {
    let dir = tempfile::tempdir().unwrap();
    let output = capture(&["demo", "--frames", "500-600"], &dir.path().join("archive"));
    assert!(!output.status.success());
    assert!(stderr(&output).contains("no frame selected"), "{}", stderr(&output));
}

#[test]
fn renaming_a_part_to_nothing_is_an_error() {
    let dir = tempfile::tempdir().unwrap();
    let scene =
        demo_scene_with("\"mesh\": \"demo\"", "\"mesh\": \"demo\", \"rename\": {\"hood\": \"\"}", dir.path());
    let output = capture(&["scene", scene.to_str().unwrap()], &dir.path().join("archive"));
    assert!(!output.status.success(), "accepted an empty part name");
    assert!(stderr(&output).contains("empty name"), "{}", stderr(&output));
}

#[test]
fn resume_redoes_a_truncated_tile() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("archive");
    assert!(capture(&["demo", "--frames", "170-180"], &out).status.success());
    let manifest = ufcsr::Manifest::load_from_dir(&out).unwrap().unwrap();
    let tile = manifest.tiles.iter().find_map(|t| t.file.clone()).expect("a written tile");
    let path = out.join(&tile);
    let whole = std::fs::read(&path).unwrap();
    std::fs::write(&path, &whole[..whole.len() / 2]).unwrap();
    assert!(capture(&["demo", "--frames", "170-180", "--resume"], &out).status.success());
    assert_eq!(std::fs::read(&path).unwrap(), whole, "the truncated tile was kept");
}

#[test]
fn a_frame_list_of_billions_is_refused_before_it_is_built() {
    let error = "0-4294967295".parse::<ufcsr_capture::FrameSelection>().unwrap_err().to_string();
    assert!(error.contains("more than"), "{error}");
    assert!("0-180/10".parse::<ufcsr_capture::FrameSelection>().is_ok());
}

#[test]
fn a_gltf_whose_nodes_form_a_cycle_is_an_error() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("cycle.gltf");
    // Node 0 is its own child: the loader must not grow forever.
    std::fs::write(&path, r#"{"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"children": [0]}]}"#)
        .unwrap();
    let loaded =
        ufcsr_capture::load_vehicle(&path, ufcsr_capture::scene::PartSource::Node, &Default::default());
    let Err(error) = loaded else { panic!("a cycle must be refused") };
    let error = error.to_string();
    assert!(error.contains("appears twice"), "{error}");
}
