//! The parametric family from the command line and scene files:
//! `ufcsr capture demo --body van` captures the intersection with the van
//! (its parts in `parts.csv`, every pixel a labelled texel); `--body` with
//! `--traffic` is a usage error; a scene file's `"vehicle": {"body": …,
//! "dims": {…}}` builds the body at those dimensions, and refuses an unknown
//! body, a body with a mesh, and impossible dimensions naming the file and
//! the field.

use std::path::{Path, PathBuf};
use std::process::Command;

use serde_json::{Value, json};
use ufcsr_capture::{Scene, verify};

fn capture(args: &[&str], out: &Path) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_ufcsr"))
        .arg("capture")
        .args(args)
        .arg("--out")
        .arg(out)
        .args(["--palette-size", "256", "--ppd", "2", "--frames", "150,180", "-q"])
        .output()
        .expect("run ufcsr capture")
}

#[test]
fn demo_body_van_captures_the_van_with_its_parts_and_no_stray_pixel() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("van");
    let output = capture(&["demo", "--body", "van", "--scenario", "A"], &out);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    let parts = std::fs::read_to_string(out.join("parts.csv")).unwrap();
    for part in ["door_rear_left", "rear_doors", "windshield", "side_mirror_right", "front_license_plate"] {
        assert!(parts.contains(part), "parts.csv lacks {part}");
    }
    assert!(!parts.contains("truck_bed"), "the van has no bed");
    let manifest: Value = serde_json::from_slice(&std::fs::read(out.join("manifest.json")).unwrap()).unwrap();
    let vehicle = manifest["scene"]["vehicle"].as_str().unwrap_or_default();
    assert!(vehicle.contains("van"), "{manifest}");
    let (pixels, stray) = verify(&out).unwrap();
    assert!(pixels > 100 && stray == 0, "{pixels} vehicle pixels, {stray} stray");

    let output = capture(&["demo", "--body", "bus", "--traffic", "lead-car"], &dir.path().join("no"));
    assert_eq!(output.status.code(), Some(2), "{}", String::from_utf8_lossy(&output.stderr));
}

fn scene_with(dir: &Path, vehicle: Value) -> PathBuf {
    let fixture = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fixtures/scenes/demo.json");
    let mut scene: Value = serde_json::from_slice(&std::fs::read(fixture).unwrap()).unwrap();
    scene["vehicle"] = vehicle;
    let path = dir.join("scene.json");
    std::fs::write(&path, serde_json::to_vec_pretty(&scene).unwrap()).unwrap();
    path
}

#[test]
fn a_scene_files_body_takes_its_dims_and_impossible_ones_are_refused_naming_the_field() {
    let dir = tempfile::tempdir().unwrap();
    let path = scene_with(dir.path(), json!({"body": "sedan", "dims": {"length_m": 4.5, "height_m": 1.5}}));
    let scene = Scene::load(&path).unwrap();
    let (min, max) = scene.vehicle.bounds();
    assert!((max.x - min.x - 4.5).abs() < 1e-4 && (max.z - 1.5).abs() < 1e-4, "{min} {max}");
    assert!(scene.vehicle.parts.iter().any(|p| p == "trunk_lid"));

    let refused = |vehicle: Value, wanted: &[&str]| {
        let path = scene_with(dir.path(), vehicle);
        let error = Scene::load(&path).unwrap_err().to_string();
        assert!(error.contains("scene.json"), "{error}");
        for word in wanted {
            assert!(error.contains(word), "{error} lacks {word}");
        }
    };
    refused(json!({"body": "sedan", "dims": {"bonnet_height_m": 0.5}}), &["vehicle.dims", "bonnet_height_m"]);
    refused(json!({"body": "sedan", "dims": {"wheelbase_m": 9.0}}), &["wheelbase_m"]);
    refused(json!({"body": "tank"}), &["vehicle.body", "tank", "sedan, suv, van, pickup, bus"]);
    refused(json!({"body": "van", "mesh": "demo"}), &["mesh and a body"]);
    refused(json!({"dims": {"length_m": 4.0}}), &["vehicle.dims needs vehicle.body"]);
    refused(json!({"body": "van", "dims": {"lenght_m": 4.0}}), &["lenght_m"]);
}
