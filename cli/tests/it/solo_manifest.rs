//! `ufcsr manifest` on Unity Perception's SOLO output as it comes:
//! a generated SOLO folder (the bundled capture's eye images as two RGB
//! cameras' captures, with segmentation and depth files beside them and
//! frame files carrying Perception's 32-bit matrix, poses and timestamps)
//! becomes an archive without --fps or --fov whose counts and measures are
//! the capture's own; the files that are not FCSP frames are skipped and
//! counted; what SOLO cannot be is refused naming the file and the reason.

use crate::common;
use crate::external_manifest::{
    analysis, assert_same_counts, assert_same_measures, copy_labels, csv_column, example, example_eye_frames,
    manifest, stderr,
};
use crate::schemas::validator::{Schema, read_json};

use std::path::{Path, PathBuf};

use common::*;
use serde_json::{Value, json};
use ufcsr::Dedupe;

/// A 32-bit float as Perception's JSON writes it (its shortest decimal), read back.
fn as_written(value: f64) -> f64 {
    (value as f32).to_string().parse().unwrap()
}

/// Perception's matrix (the top-left 3×3 of Unity's projection, column-major,
/// 32-bit floats) of a centred camera `horizontal_deg` across.
fn unity_matrix(horizontal_deg: f64, [width, height]: [u32; 2]) -> Vec<f64> {
    let m00 = 1.0 / (horizontal_deg.to_radians() / 2.0).tan();
    let m11 = m00 * f64::from(width) / f64::from(height);
    [m00, 0.0, 0.0, 0.0, m11, 0.0, 0.0, 0.0, -1000.3 / 999.7].map(as_written).to_vec()
}

/// One RGB camera capture record as Perception 1.0 writes it.
fn rgb_capture(id: &str, file: &str, dimension: [u32; 2], x: f64, annotations: Value) -> Value {
    json!({
        "@type": "type.unity.com/unity.solo.RGBCamera",
        "id": id,
        "description": "an FCSP eye",
        "position": [x, 1.75, -4.0],
        "rotation": [0.0, 0.0, 0.0, 1.0],
        "velocity": [0.0, 0.0, 0.0],
        "acceleration": [0.0, 0.0, 0.0],
        "filename": file,
        "imageFormat": "Png",
        "dimension": [f64::from(dimension[0]), f64::from(dimension[1])],
        "projection": "Perspective",
        "matrix": unity_matrix(107.0, dimension),
        "annotations": annotations,
    })
}

fn annotation(kind: &str, file: &str) -> Value {
    json!({"@type": format!("type.unity.com/unity.solo.{kind}"), "id": kind, "sensorId": "LeftEye",
           "description": "", "imageFormat": "Png", "dimension": [2.0, 2.0], "filename": file})
}

fn write_json(path: &Path, value: &Value) {
    std::fs::create_dir_all(path.parent().unwrap()).unwrap();
    std::fs::write(path, serde_json::to_vec_pretty(value).unwrap()).unwrap();
}

/// The bundled capture as a SOLO dataset: step k is the capture's k-th
/// frame (frames 0, 20, …, 180 at 60 fps: every 1/3 s), each eye a camera
/// (`LeftEye`, `RightEye`) with one stitched 640×810 image; the left camera
/// also writes a semantic segmentation and a depth image (2×2, not frames),
/// and one stray PNG lies in the sequence folder.
fn solo_dataset(root: &Path) -> PathBuf {
    let sequence = root.join("sequence.0");
    let mut steps: Vec<u32> = Vec::new();
    let mut captures: std::collections::BTreeMap<u32, Vec<Value>> = Default::default();
    for ((frame, eye), tiles) in example_eye_frames() {
        let mut image = vec![BG; 640 * 810];
        for ((row, col), colors) in tiles {
            for (y, line) in colors.chunks(128).enumerate() {
                let start = (row as usize * 162 + y) * 640 + col as usize * 128;
                image[start..start + 128].copy_from_slice(line);
            }
        }
        if !steps.contains(&frame) {
            steps.push(frame);
        }
        let step = steps.iter().position(|f| *f == frame).unwrap();
        let (id, x) = if eye == "left" { ("LeftEye", -0.055) } else { ("RightEye", 0.055) };
        let file = format!("step{step}.{id}.png");
        rgb_png(&sequence.join(&file), 640, 810, &image);
        let annotations = if eye == "left" {
            let (segmentation, depth) =
                (format!("step{step}.{id}.semantic segmentation.png"), format!("step{step}.{id}.Depth.png"));
            rgb_png(&sequence.join(&segmentation), 2, 2, &[1, 2, 3, 4]);
            rgb_png(&sequence.join(&depth), 2, 2, &[5, 6, 7, 8]);
            json!([
                annotation("SemanticSegmentationAnnotation", &segmentation),
                annotation("DepthAnnotation", &depth)
            ])
        } else {
            json!([])
        };
        captures.entry(step as u32).or_default().push(rgb_capture(id, &file, [640, 810], x, annotations));
    }
    for (step, captures) in captures {
        let timestamp = as_written(f64::from(steps[step as usize]) / 60.0);
        let frame = json!({"frame": step + 3, "sequence": 0, "step": step, "timestamp": timestamp,
                           "captures": captures, "metrics": []});
        write_json(&sequence.join(format!("step{step}.frame_data.json")), &frame);
    }
    rgb_png(&sequence.join("stray.png"), 2, 2, &[9; 4]);
    write_json(&root.join("metadata.json"), &json!({"unityVersion": "2022.3", "perceptionVersion": "1.0.0"}));
    copy_labels(root);
    root.to_path_buf()
}

#[test]
fn a_solo_folder_becomes_an_archive_without_fps_or_fov_with_the_captures_measures() {
    let dir = tempfile::tempdir().unwrap();
    let solo = solo_dataset(&dir.path().join("solo"));
    let args =
        ["solo", "--pidt", "solo/pidt.png", "--legend", "solo/parts.csv", "--palette-size", "512", "--json"];
    let output = manifest(dir.path(), &args);
    assert!(output.status.success(), "{}", stderr(&output));
    let summary: Value = serde_json::from_slice(&output.stdout).unwrap();
    assert_eq!((summary["tiles"].as_u64(), summary["eye_frames"].as_u64()), (Some(20), Some(20)));
    assert_eq!(summary["eyes"], json!(["left", "right"]));
    assert_eq!(summary["times_from"], "SOLO timestamps");
    // Steps 1/3 s apart, timestamps as 32-bit floats: 3 steps per second within 1e-6.
    assert!((summary["fps"].as_f64().unwrap() - 3.0).abs() < 1e-6, "{}", summary["fps"]);
    assert!((summary["horizontal_fov_deg"].as_f64().unwrap() - 107.0).abs() < 1e-5);
    let skipped = &summary["solo"]["skipped"];
    assert_eq!(skipped["SemanticSegmentationAnnotation"], 10);
    assert_eq!(skipped["DepthAnnotation"], 10);
    assert_eq!(skipped["PNG named by no frame file"], 1);
    assert_eq!(summary["solo"]["skipped_total"], 21);
    assert_eq!(summary["solo"]["cameras"], json!({"LeftEye": "left", "RightEye": "right"}));

    let written = read_json(&solo.join("manifest.json"));
    Schema::load(&PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../docs/schemas/manifest.schema.json"))
        .assert_valid(&written, "the manifest of a SOLO folder");
    assert_eq!(written["tiles"][0]["file"], "sequence.0/step0.LeftEye.png");
    // Unity (x, y, z) is ufcsr (x, z, y); no rotation looks along Unity's +Z, ufcsr's +Y.
    let left = &written["frames"][0]["eyes"]["left"];
    assert_eq!(left["position"], json!([-0.055, -4.0, 1.75]));
    assert_eq!((&left["forward"], &left["up"]), (&json!([0.0, 1.0, 0.0]), &json!([0.0, 0.0, 1.0])));

    let (ours, capture) = (dir.path().join("ours"), dir.path().join("capture"));
    let per_image = analysis(&solo, Dedupe::Image, &ours);
    assert_same_counts(&per_image, &analysis(&example(), Dedupe::Frame, &capture));
    // The field of view and the frame interval come from 32-bit floats: 1e-5.
    assert_same_measures(&ours, &capture, 1e-5);
    let times: Vec<f64> =
        csv_column(&ours.join("frames.csv"), "time_s").iter().map(|t| t.parse().unwrap()).collect();
    assert!(times.iter().any(|t| (t - 3.0).abs() < 1e-6), "the last step's timestamp: {times:?}");
}

/// A 2×1 SOLO sequence: `cameras` RGB cameras, one step at 0 s and one at 0.1 s.
fn small_solo(root: &Path, cameras: &[&str], edit: impl Fn(&mut Value)) {
    let sequence = root.join("sequence.0");
    for step in 0..2u32 {
        let captures: Vec<Value> = cameras
            .iter()
            .map(|id| {
                let file = format!("step{step}.{id}.png");
                rgb_png(&sequence.join(&file), 2, 1, &[1, 2]);
                rgb_capture(id, &file, [2, 1], 0.0, json!([]))
            })
            .collect();
        let mut frame =
            json!({"sequence": 0, "step": step, "timestamp": f64::from(step) * 0.1, "captures": captures});
        edit(&mut frame);
        write_json(&sequence.join(format!("step{step}.frame_data.json")), &frame);
    }
}

/// The command on a broken SOLO folder: exit 2, `expected` on stderr, nothing written.
fn refused(dir: &Path, args: &[&str], expected: &[&str]) {
    let output = manifest(dir, args);
    let message = stderr(&output);
    assert_eq!(output.status.code(), Some(2), "{args:?}: {message}");
    for part in expected {
        assert!(message.contains(part), "{args:?}: expected {part:?} in {message:?}");
    }
    assert!(!dir.join("solo/manifest.json").exists(), "{args:?}: nothing written");
}

#[test]
fn solo_cameras_are_chosen_by_id_and_what_ufcsr_cannot_read_is_refused_with_the_reason() {
    let dir = tempfile::tempdir().unwrap();
    let at = dir.path();
    let solo = at.join("solo");
    small_solo(&solo, &["Left", "Right", "Beauty"], |_| {});
    refused(at, &["solo"], &["3 RGB cameras (Beauty, Left, Right)", "--solo-camera"]);
    refused(at, &["solo", "--pattern", "{frame}.png"], &["SOLO frame files", "--ignore-solo"]);
    let chosen = manifest(at, &["solo", "--solo-camera", "Left", "--solo-camera", "Right", "--json"]);
    assert!(chosen.status.success(), "{}", stderr(&chosen));
    let summary: Value = serde_json::from_slice(&chosen.stdout).unwrap();
    assert_eq!(summary["eyes"], json!(["left", "right"]));
    assert_eq!(summary["solo"]["skipped"]["camera Beauty (not --solo-camera)"], 2);
    assert!((summary["fps"].as_f64().unwrap() - 10.0).abs() < 1e-9, "one step per 0.1 s");
    std::fs::remove_file(solo.join("manifest.json")).unwrap();

    std::fs::remove_dir_all(&solo).unwrap();
    small_solo(&solo, &["camera"], |frame| frame["captures"][0]["matrix"][6] = json!(0.2));
    refused(at, &["solo"], &["step0.frame_data.json", "camera \"camera\" at step 0", "lens shift"]);
    std::fs::remove_dir_all(&solo).unwrap();
    small_solo(&solo, &["camera"], |frame| frame["captures"][0]["dimension"] = json!([4.0, 2.0]));
    refused(at, &["solo"], &["step0.camera.png", "is 2×1 pixels", "dimension says 4×2"]);
    std::fs::remove_dir_all(&solo).unwrap();
    small_solo(&solo, &["camera"], |frame| frame["captures"][0]["filename"] = json!("../outside.png"));
    refused(at, &["solo"], &["\"../outside.png\"", "does not lie inside its sequence folder"]);
    std::fs::remove_dir_all(&solo).unwrap();
    small_solo(&solo, &["camera"], |frame| frame["step"] = json!("one"));
    refused(at, &["solo"], &["step0.frame_data.json", "invalid Unity Perception SOLO frame file", "step"]);
    std::fs::remove_dir_all(&solo).unwrap();
    small_solo(&solo, &["camera"], |_| {});
    std::fs::rename(solo.join("sequence.0"), solo.join("sequence.1")).unwrap();
    small_solo(&solo, &["camera"], |_| {});
    refused(at, &["solo"], &["2 Unity Perception SOLO sequences", "one sequence folder at a time"]);
    let one = manifest(at, &["solo/sequence.1", "--out", "solo/"]);
    assert!(one.status.success(), "one sequence folder: {}", stderr(&one));
    assert_eq!(read_json(&solo.join("manifest.json"))["tiles"][0]["file"], "sequence.1/step0.camera.png");
}

/// `manifest solo --json`'s summary (the command must succeed).
fn solo_summary(dir: &Path) -> Value {
    let output = manifest(dir, &["solo", "--json"]);
    assert!(output.status.success(), "{}", stderr(&output));
    serde_json::from_slice(&output.stdout).unwrap()
}

#[test]
fn perception_before_1_0_takes_the_frame_rate_from_sensor_definitions() {
    let dir = tempfile::tempdir().unwrap();
    let solo = dir.path().join("solo");
    // Frame files without `timestamp`, as Perception before 1.0 wrote them.
    small_solo(&solo, &["Left"], |frame| {
        frame.as_object_mut().unwrap().remove("timestamp");
    });
    let definitions = json!({"sensorDefinitions": [
        {"@type": "type.unity.com/unity.solo.RGBCamera", "id": "Left", "modality": "camera",
         "simulationDeltaTime": 0.0166, "framesBetweenCaptures": 0},
        {"@type": "type.unity.com/unity.solo.RGBCamera", "id": "Other", "simulationDeltaTime": 0.5,
         "framesBetweenCaptures": 3}
    ]});
    write_json(&solo.join("sensor_definitions.json"), &definitions);
    let summary = solo_summary(dir.path());
    // Unity's own sample: 1 / (0.0166 s × (0 + 1)) = 60.24 captures per second.
    assert!((summary["fps"].as_f64().unwrap() - 1.0 / 0.0166).abs() < 1e-9, "{}", summary["fps"]);
    std::fs::remove_file(solo.join("manifest.json")).unwrap();
    // Every second simulation frame captured: half the rate.
    let mut definitions = definitions;
    definitions["sensorDefinitions"][0]["framesBetweenCaptures"] = json!(1);
    write_json(&solo.join("sensor_definitions.json"), &definitions);
    assert!((solo_summary(dir.path())["fps"].as_f64().unwrap() - 1.0 / 0.0332).abs() < 1e-9);
    std::fs::remove_file(solo.join("manifest.json")).unwrap();
    definitions["sensorDefinitions"][0]["simulationDeltaTime"] = json!(-1.0);
    write_json(&solo.join("sensor_definitions.json"), &definitions);
    refused(dir.path(), &["solo"], &["sensor_definitions.json", "simulationDeltaTime -1"]);
}

#[test]
fn a_solo_frame_file_that_is_a_fifo_is_refused_by_name() {
    let dir = tempfile::tempdir().unwrap();
    let solo = dir.path().join("solo");
    small_solo(&solo, &["Left"], |_| {});
    let fifo = solo.join("sequence.0/step2.frame_data.json");
    let made = std::process::Command::new("mkfifo").arg(&fifo).status().unwrap();
    assert!(made.success());
    refused(dir.path(), &["solo"], &["step2.frame_data.json", "not a regular file"]);
    std::fs::remove_file(&fifo).unwrap();
    std::os::unix::fs::symlink("/dev/zero", &fifo).unwrap();
    refused(dir.path(), &["solo"], &["step2.frame_data.json", "not a regular file"]);
}

#[test]
fn the_solo_png_walk_does_not_follow_links_out_of_the_dataset() {
    let dir = tempfile::tempdir().unwrap();
    let solo = dir.path().join("solo");
    small_solo(&solo, &["Left"], |_| {});
    let outside = dir.path().join("outside");
    for index in 0..3 {
        rgb_png(&outside.join(format!("other{index}.png")), 2, 1, &[1, 2]);
    }
    std::os::unix::fs::symlink(&outside, solo.join("sequence.0/elsewhere")).unwrap();
    std::os::unix::fs::symlink(outside.join("other0.png"), solo.join("sequence.0/linked.png")).unwrap();
    let summary = solo_summary(dir.path());
    let skipped = &summary["solo"]["skipped"];
    assert_eq!(skipped["link named by no frame file (not followed)"], 2, "{skipped}");
    assert!(skipped.get("PNG named by no frame file").is_none(), "the linked folder was walked: {skipped}");
}
