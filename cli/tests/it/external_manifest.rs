//! `ufcsr manifest`: a folder of frames rendered outside ufcsr
//! (Unity, Blender) becomes an archive the analyzer reads alone. Known
//! answers: the bundled capture renamed Unity-style (tiled) or stitched into
//! one image per eye and frame (untiled) gives the capture's own totals and
//! measures; --fps and --pixels-per-degree give frames.csv's times and
//! parts.csv's deg²·s exactly; every bad input is refused naming the file and
//! the problem, with exit code 2 and nothing written.

use crate::common;
use crate::schemas::validator::{Schema, read_json};

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::process::Output;

use common::*;
use ufcsr::{AnalyzeOptions, Dedupe, analyze, output::write_results};

const UNITY: &str = r"(?P<eye>Left|Right)_(?P<frame>\d+)_(?P<row>\d+)_(?P<col>\d+)\.png$";

pub(crate) fn example() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fixtures/example")
}

/// `ufcsr manifest ARGS` run in `cwd`.
pub(crate) fn manifest(cwd: &Path, args: &[&str]) -> Output {
    analyzer().current_dir(cwd).arg("manifest").args(args).output().unwrap()
}

pub(crate) fn stderr(output: &Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}

pub(crate) fn analysis(archive: &Path, dedupe: Dedupe, out: &Path) -> ufcsr::Analysis {
    let options =
        AnalyzeOptions { archive: archive.to_path_buf(), dedupe, frames: true, ..Default::default() };
    let mut analysis = analyze(&options, None).expect("analysis");
    write_results(&mut analysis, out).expect("write results");
    analysis
}

/// Every eye-frame of the bundled capture: (frame, eye) → its 5×5 tiles'
/// colours by (row, col), background where the capture wrote no file.
/// An eye-frame's tiles: (row, col) → packed colours.
pub(crate) type Tiles = BTreeMap<(u32, u32), Vec<u32>>;

pub(crate) fn example_eye_frames() -> BTreeMap<(u32, String), Tiles> {
    let manifest = ufcsr::Manifest::load_from_dir(&example()).unwrap().unwrap();
    let mut eye_frames: BTreeMap<(u32, String), Tiles> = BTreeMap::new();
    for tile in &manifest.tiles {
        let colors = match &tile.file {
            Some(file) => ufcsr::read_color_image(&example().join(file), |_| Ok(())).unwrap().colors,
            None => vec![BG; 128 * 162],
        };
        eye_frames.entry((tile.frame, tile.eye.clone())).or_default().insert((tile.row, tile.col), colors);
    }
    eye_frames
}

pub(crate) fn copy_labels(into: &Path) {
    for file in ["pidt.png", "parts.csv"] {
        std::fs::copy(example().join(file), into.join(file)).unwrap();
    }
}

pub(crate) fn assert_same_counts(ours: &ufcsr::Analysis, capture: &ufcsr::Analysis) {
    assert_eq!(ours.result.grand_total, capture.result.grand_total);
    let totals =
        |a: &ufcsr::Analysis| a.result.parts.iter().map(|p| (p.name.clone(), p.total)).collect::<Vec<_>>();
    assert_eq!(totals(ours), totals(capture));
    assert_eq!(ours.texel_counts, capture.texel_counts);
}

/// exposure_s and angular_area_deg2_s of every part, equal to `relative`.
pub(crate) fn assert_same_measures(ours: &Path, capture: &Path, relative: f64) {
    let measures = |dir: &Path| read_json(&dir.join("result.json"))["measures"]["parts"].clone();
    let (ours, capture) = (measures(ours), measures(capture));
    let parts = capture.as_array().unwrap();
    assert!(!parts.is_empty());
    for (a, b) in ours.as_array().unwrap().iter().zip(parts) {
        for key in ["exposure_s", "angular_area_deg2_s", "solid_angle_sr"] {
            let (x, y) = (a[key].as_f64().unwrap(), b[key].as_f64().unwrap());
            assert!((x - y).abs() <= relative * y.abs().max(1e-12), "{} {key}: {x} against {y}", a["name"]);
        }
    }
}

#[test]
fn unity_named_tiles_renamed_from_a_capture_give_the_captures_totals() {
    let dir = tempfile::tempdir().unwrap();
    let unity = dir.path().join("unity");
    for ((frame, eye), tiles) in example_eye_frames() {
        let eye = if eye == "left" { "Left" } else { "Right" };
        for ((row, col), colors) in tiles {
            rgb_png(&unity.join(format!("shots/{eye}_{frame:04}_{row}_{col}.png")), 128, 162, &colors);
        }
    }
    copy_labels(&unity);
    let args = ["unity", "--pattern", UNITY, "--pidt", "unity/pidt.png", "--legend", "unity/parts.csv"];
    let more = ["--palette-size", "512", "--fps", "60", "--fov", "107", "--json"];
    let output = manifest(dir.path(), &[&args[..], &more[..]].concat());
    assert!(output.status.success(), "{}", stderr(&output));
    let summary: serde_json::Value = serde_json::from_slice(&output.stdout).unwrap();
    assert_eq!((summary["tiles"].as_u64(), summary["eye_frames"].as_u64()), (Some(500), Some(20)));
    assert_eq!(summary["grid_columns_rows"], serde_json::json!([5, 5]));
    let written = read_json(&unity.join("manifest.json"));
    Schema::load(&PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../docs/schemas/manifest.schema.json"))
        .assert_valid(&written, "the manifest of ufcsr manifest");
    assert_eq!(written["pidt"], "pidt.png", "relative to the manifest, not the working directory");

    let (ours, capture) = (dir.path().join("ours"), dir.path().join("capture"));
    let by_frame = analysis(&unity, Dedupe::Frame, &ours);
    assert_same_counts(&by_frame, &analysis(&example(), Dedupe::Frame, &capture));
    assert_same_measures(&ours, &capture, 1e-9);
}

#[test]
fn a_renamed_capture_without_its_empty_tiles_needs_missing_tiles_empty() {
    let dir = tempfile::tempdir().unwrap();
    let unity = dir.path().join("unity");
    let capture = ufcsr::Manifest::load_from_dir(&example()).unwrap().unwrap();
    for tile in capture.tiles.iter().filter(|t| !t.empty) {
        let eye = if tile.eye == "left" { "Left" } else { "Right" };
        let name = format!("{eye}_{:04}_{}_{}.png", tile.frame, tile.row, tile.col);
        std::fs::create_dir_all(&unity).unwrap();
        std::fs::copy(example().join(tile.file.as_ref().unwrap()), unity.join(name)).unwrap();
    }
    copy_labels(&unity);
    let args = ["unity", "--pattern", UNITY, "--pidt", "unity/pidt.png", "--legend", "unity/parts.csv"];
    let refused = manifest(dir.path(), &[&args[..], &["--palette-size", "512"]].concat());
    assert_eq!(refused.status.code(), Some(2));
    assert!(
        stderr(&refused).contains("has no tile at row") && stderr(&refused).contains("--missing-tiles-empty")
    );
    // The written tiles alone span 4 × 3 of the 5 × 5 grid: the rig's tiles give the rest.
    std::fs::write(dir.path().join("rig.json"), r#"{"tiles": [5, 5], "fps": 60, "horizontal_fov_deg": 107}"#)
        .unwrap();
    let empty = ["--palette-size", "512", "--missing-tiles-empty", "--rig", "rig.json", "--json"];
    let output = manifest(dir.path(), &[&args[..], &empty[..]].concat());
    assert!(output.status.success(), "{}", stderr(&output));
    let summary: serde_json::Value = serde_json::from_slice(&output.stdout).unwrap();
    assert_eq!(summary["eye_pixels"], serde_json::json!([640, 810]));
    let (ours, capture) = (dir.path().join("ours"), dir.path().join("capture"));
    let by_frame = analysis(&unity, Dedupe::Frame, &ours);
    assert_same_counts(&by_frame, &analysis(&example(), Dedupe::Frame, &capture));
    // Frame 0 (no tile written) is no eye-frame here, but every part's measures agree.
    assert_same_measures(&ours, &capture, 1e-9);
}

#[test]
fn untiled_eye_images_give_the_captures_per_eye_frame_totals() {
    let dir = tempfile::tempdir().unwrap();
    let frames = dir.path().join("blender");
    for ((frame, eye), tiles) in example_eye_frames() {
        let mut image = vec![BG; 640 * 810];
        for ((row, col), colors) in tiles {
            for (y, line) in colors.chunks(128).enumerate() {
                let start = (row as usize * 162 + y) * 640 + col as usize * 128;
                image[start..start + 128].copy_from_slice(line);
            }
        }
        rgb_png(&frames.join(format!("f{frame:04}_{eye}.png")), 640, 810, &image);
    }
    copy_labels(&frames);
    let args = ["--pidt", "pidt.png", "--legend", "parts.csv", "--palette-size", "512", "--fps", "60"];
    let output = manifest(&frames, &[&["."], &args[..], &["--fov", "107x119.37"]].concat());
    assert!(output.status.success(), "{}", stderr(&output));
    let written = ufcsr::Manifest::load_from_dir(&frames).unwrap().unwrap();
    assert_eq!(written.tiles.len(), 20, "one image per eye and frame");
    assert!(written.tiles.iter().all(|t| (t.row, t.col) == (0, 0)));

    let (ours, capture) = (dir.path().join("ours"), dir.path().join("capture"));
    // One image per eye-frame: counting once per image is counting once per eye-frame.
    let per_image = analysis(&frames, Dedupe::Image, &ours);
    assert_same_counts(&per_image, &analysis(&example(), Dedupe::Frame, &capture));
    assert_same_measures(&ours, &capture, 1e-9);
}

/// A mono sequence, two 2×1 frames two frames apart: frame 0 shows texel 1
/// twice, frame 2 texels 1 and 2. Canonical 4×4 palette, one part A.
fn mono_sequence(dir: &Path) -> PathBuf {
    let shots = dir.join("shots");
    rgb_png(&shots.join("frame_0000.png"), 2, 1, &[1, 1]);
    rgb_png(&shots.join("frame_0002.png"), 2, 1, &[1, 2]);
    rgb_png(&shots.join("pidt.png"), 4, 4, &[0xFF0000; 16]);
    std::fs::write(shots.join("parts.csv"), "name,color\nA,#FF0000\n").unwrap();
    shots
}

pub(crate) fn csv_column(path: &Path, column: &str) -> Vec<String> {
    let mut reader = csv::Reader::from_path(path).unwrap();
    let at = reader.headers().unwrap().iter().position(|h| h == column).unwrap();
    reader.records().map(|row| row.unwrap()[at].to_string()).collect()
}

#[test]
fn fps_and_pixels_per_degree_fill_the_time_and_deg2_columns() {
    let dir = tempfile::tempdir().unwrap();
    let shots = mono_sequence(dir.path());
    let labels = ["--pidt", "shots/pidt.png", "--legend", "shots/parts.csv", "--palette-size", "4"];
    let rates = ["--pattern", "frame_{frame}.png", "--fps", "10", "--pixels-per-degree", "10"];
    let output = manifest(dir.path(), &[&["shots"], &labels[..], &rates[..]].concat());
    assert!(output.status.success(), "{}", stderr(&output));
    let out = dir.path().join("results");
    analysis(&shots, Dedupe::Image, &out);
    let frames_csv = out.join("frames.csv");
    assert_eq!(csv_column(&frames_csv, "frame"), ["0", "0", "2", "2"], "part A, then (unlabelled)");
    assert_eq!(csv_column(&frames_csv, "eye"), ["left"; 4], "no eye group: one eye, left");
    let times: Vec<f64> = csv_column(&frames_csv, "time_s").iter().map(|t| t.parse().unwrap()).collect();
    assert_eq!(times, [0.0, 0.0, 0.2, 0.2], "frame / fps");
    // 4 pixels of A; one frame step (2 frames at 10 fps) is 0.2 s; one eye:
    // 4 / 10² deg² × 0.2 s = 0.008 deg²·s; seen in 2 eye-frames: 0.4 s.
    let area: f64 = csv_column(&out.join("parts.csv"), "angular_area_deg2_s")[0].parse().unwrap();
    let exposure: f64 = csv_column(&out.join("parts.csv"), "exposure_s")[0].parse().unwrap();
    assert!((area - 0.008).abs() < 1e-9 && (exposure - 0.4).abs() < 1e-9, "{area} deg²·s, {exposure} s");
}

#[test]
fn frame_times_and_a_rig_file_give_times_distances_and_solid_angles() {
    let dir = tempfile::tempdir().unwrap();
    let shots = mono_sequence(dir.path());
    std::fs::write(dir.path().join("times.csv"), "frame,time_s,distance_m\n0,0.5,20\n1,0.6,19\n2,0.7,18\n")
        .unwrap();
    std::fs::write(
        dir.path().join("rig.json"),
        r#"{"rig": {"fps": 10, "horizontal_fov_deg": 90, "ipd_m": 0.06}}"#,
    )
    .unwrap();
    let args = [
        "shots",
        "--pattern",
        "frame_{frame}.png",
        "--pidt",
        "shots/pidt.png",
        "--legend",
        "shots/parts.csv",
    ];
    let more = ["--palette-size", "4", "--rig", "rig.json", "--frame-times", "times.csv"];
    let output = manifest(dir.path(), &[&args[..], &more[..]].concat());
    assert!(output.status.success(), "{}", stderr(&output));
    let written = read_json(&shots.join("manifest.json"));
    assert_eq!(written["rig"]["settings"]["ipd_m"], 0.06, "the rig file's fields are kept");
    assert_eq!(written["rig"]["pixels_per_degree"], 2.0 / 90.0);
    let out = dir.path().join("results");
    analysis(&shots, Dedupe::Image, &out);
    let frames_csv = out.join("frames.csv");
    assert_eq!(csv_column(&frames_csv, "time_s"), ["0.5", "0.5", "0.7", "0.7"]);
    assert_eq!(csv_column(&frames_csv, "distance_m"), ["20", "20", "18", "18"]);
    // A 2×1 eye 90° across: each pixel spans x in [0, 1] of the tangent
    // plane and y in [-0.5, 0.5], so two pixels subtend
    // 4·atan(1·0.5 / sqrt(1 + 1 + 0.25)) sr (one rectangle from the axis, mirrored).
    let solid: f64 = csv_column(&frames_csv, "solid_angle_sr")[0].parse().unwrap();
    let expected = 4.0 * (0.5f64 / 2.25f64.sqrt()).atan();
    assert!((solid - expected).abs() < 1e-9, "{solid} sr against {expected}");
}

#[test]
fn paths_on_the_command_line_are_relative_to_the_working_directory() {
    let dir = tempfile::tempdir().unwrap();
    mono_sequence(&dir.path().join("work"));
    let output = manifest(
        &dir.path().join("work"),
        &[
            "shots",
            "--pattern",
            "frame_{frame}.png",
            "--pidt",
            "shots/pidt.png",
            "--palette-size",
            "4",
            "--out",
            ".",
        ],
    );
    assert!(output.status.success(), "{}", stderr(&output));
    let written = read_json(&dir.path().join("work/manifest.json"));
    assert_eq!(written["pidt"], "shots/pidt.png", "relative to the manifest in work/");
    assert_eq!(written["tiles"][0]["file"], "shots/frame_0000.png");
    // A manifest can only name files inside its folder.
    rgb_png(&dir.path().join("elsewhere.png"), 4, 4, &[0xFF0000; 16]);
    let outside = manifest(
        &dir.path().join("work"),
        &["shots", "--pattern", "frame_{frame}.png", "--pidt", "../elsewhere.png"],
    );
    assert_eq!(outside.status.code(), Some(2));
    assert!(
        stderr(&outside).contains("../elsewhere.png")
            && stderr(&outside).contains("outside the manifest's folder")
    );
}

/// Runs the command on a broken folder: exit 2, `expected` on stderr, no manifest.
fn refused(dir: &Path, args: &[&str], expected: &[&str]) {
    let output = manifest(dir, args);
    let message = stderr(&output);
    assert_eq!(output.status.code(), Some(2), "{args:?}: {message}");
    for part in expected {
        assert!(message.contains(part), "{args:?}: expected {part:?} in {message:?}");
    }
    assert!(!dir.join("frames/manifest.json").exists(), "{args:?}: nothing written");
}

#[test]
fn each_bad_input_is_refused_naming_the_file_and_the_problem() {
    let dir = tempfile::tempdir().unwrap();
    let at = dir.path();
    let frames = at.join("frames");
    rgb_png(&frames.join("Left_0001_0_0.png"), 2, 1, &[1, 2]);
    rgb_png(&frames.join("Left_0001_0_1.png"), 2, 1, &[1, BG]);
    let unity = ["frames", "--pattern", UNITY];
    refused(at, &["frames"], &["frames", "2 PNG file(s) do not match --pattern", "Left_0001_0_0.png"]);
    refused(at, &["nowhere"], &["nowhere", "not a folder"]);
    refused(at, &["frames", "--pattern", "{frame}.jpg"], &["frames", "do not match"]);

    rgb_png(&frames.join("sub/Left_0001_0_1.png"), 2, 1, &[1, BG]);
    refused(
        at,
        &unity,
        &["sub/Left_0001_0_1.png", "frame 1, eye left, row 0, col 1", "each tile must be one file"],
    );
    std::fs::remove_dir_all(frames.join("sub")).unwrap();

    rgb_png(&frames.join("Right_0001_0_0.png"), 2, 1, &[1, 2]);
    refused(at, &unity, &["frame 1, eye right has no tile at row 0, col 1", "1 rows × 2 columns"]);
    rgb_png(&frames.join("Right_0001_0_1.png"), 2, 2, &[1, 2, 3, 4]);
    refused(at, &unity, &["Right_0001_0_1.png", "is 2×2 pixels", "must have the same size"]);
    std::fs::write(frames.join("Right_0001_0_1.png"), b"GIF89a not a png").unwrap();
    refused(at, &unity, &["Right_0001_0_1.png", "not a readable PNG", "no PNG signature"]);
    let mut damaged = std::fs::read(frames.join("Right_0001_0_0.png")).unwrap();
    damaged[17] ^= 0xFF;
    std::fs::write(frames.join("Right_0001_0_1.png"), &damaged).unwrap();
    refused(at, &unity, &["Right_0001_0_1.png", "CRC does not match"]);
    rgb_png(&frames.join("Right_0001_0_1.png"), 2, 1, &[1, BG]);

    std::fs::write(at.join("rig.json"), "{\"fps\": 60,").unwrap();
    refused(at, &[&unity[..], &["--rig", "rig.json"]].concat(), &["rig.json", "not a JSON rig description"]);
    std::fs::write(at.join("rig.json"), r#"{"fps": 60, "fov": 90}"#).unwrap();
    refused(at, &[&unity[..], &["--rig", "rig.json"]].concat(), &["rig.json", "unknown rig field \"fov\""]);
    std::fs::write(at.join("rig.json"), r#"{"eye_pixels": [640, 810]}"#).unwrap();
    refused(at, &[&unity[..], &["--rig", "rig.json"]].concat(), &["rig.json", "eye images are 4×1 pixels"]);
    std::fs::write(at.join("times.csv"), "frame,time_s\n0,0\n").unwrap();
    refused(
        at,
        &[&unity[..], &["--frame-times", "times.csv"]].concat(),
        &["times.csv", "no row for frame 1"],
    );
    refused(at, &[&unity[..], &["--fov", "90x80"]].concat(), &["--fov 90x80", "vertical field of view"]);
    refused(at, &["frames", "--pattern", "(?P<eye>x)"], &["no `frame` group"]);
    let ok = manifest(at, &unity);
    assert!(ok.status.success(), "the repaired folder: {}", stderr(&ok));
    let eyes: BTreeSet<String> =
        ufcsr::Manifest::load_from_dir(&frames).unwrap().unwrap().tiles.into_iter().map(|t| t.eye).collect();
    assert_eq!(eyes, BTreeSet::from(["left".to_string(), "right".to_string()]));
}

#[test]
fn the_schema_takes_a_partial_rig_only_from_manifests_without_a_capture_record() {
    let schema =
        Schema::load(&PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../docs/schemas/manifest.schema.json"));
    let mut external = serde_json::json!({
        "schema": "ufcsr-manifest/1",
        "tiles": [{"file": "f0000_left.png", "frame": 0, "eye": "left", "row": 0, "col": 0, "time_s": 0.0}],
        "rig": {"settings": {"fps": 60.0, "eye_pixels": [640, 810], "tiles": [1, 1]}, "tile_pixels": [640, 810]}
    });
    schema.assert_valid(&external, "an external manifest with what is known of its rig");
    external["capture"] = serde_json::json!({"tool": "ufcsr-capture", "tiles_rendered": 1, "tiles_culled": 0, "tiles_background_only": 0});
    assert!(schema.check(&external).is_err(), "ufcsr-capture records the whole rig");
}
