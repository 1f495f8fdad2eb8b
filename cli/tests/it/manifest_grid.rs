//! `ufcsr-analyze manifest` does not guess what it cannot know (issue 42 §5):
//! with tiles missing and no grid given, the tiles present do not tell the
//! grid (the bundled capture without its empty tiles spans 4 × 3 of its
//! 5 × 5, which analysed as 8 px/° for 10 and a windshield 33 % short), so
//! it is refused until `--grid` (or the rig's tiles) gives it; and a PIdT
//! that is not the palette's size is refused here, naming the file, not one
//! command later by the analysis.

use crate::external_manifest::{analysis, assert_same_measures, copy_labels, example, manifest, stderr};
use ufcsr::Dedupe;

const UNITY: &str = r"(?P<eye>Left|Right)_(?P<frame>\d+)_(?P<row>\d+)_(?P<col>\d+)\.png$";

#[test]
fn missing_tiles_without_a_grid_are_refused_and_the_grid_given_gives_the_captures_measures() {
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
    let more = ["--palette-size", "512", "--fps", "60", "--fov", "107", "--missing-tiles-empty"];
    let refused = manifest(dir.path(), &[&args[..], &more[..]].concat());
    assert_eq!(refused.status.code(), Some(2), "{}", stderr(&refused));
    let message = stderr(&refused);
    assert!(message.contains("4 columns × 3 rows") && message.contains("--grid COLUMNSxROWS"), "{message}");
    assert!(!unity.join("manifest.json").exists(), "nothing written on refusal");
    for bad in ["5", "0x5", "5x", "ax5"] {
        let output = manifest(dir.path(), &[&args[..], &more[..], &["--grid", bad]].concat());
        assert_eq!(output.status.code(), Some(2), "--grid {bad}");
    }
    let output = manifest(dir.path(), &[&args[..], &more[..], &["--grid", "5x5", "--json"]].concat());
    assert!(output.status.success(), "{}", stderr(&output));
    let summary: serde_json::Value = serde_json::from_slice(&output.stdout).unwrap();
    assert_eq!(summary["grid_columns_rows"], serde_json::json!([5, 5]));
    assert_eq!(summary["eye_pixels"], serde_json::json!([640, 810]));
    let (ours, theirs) = (dir.path().join("ours"), dir.path().join("capture"));
    analysis(&unity, Dedupe::Frame, &ours);
    analysis(&example(), Dedupe::Frame, &theirs);
    assert_same_measures(&ours, &theirs, 1e-9);
}

#[test]
fn a_pidt_that_is_not_the_palettes_size_is_refused_at_manifest_naming_it() {
    let dir = tempfile::tempdir().unwrap();
    let frames = dir.path().join("frames");
    std::fs::create_dir_all(&frames).unwrap();
    for tile in ufcsr::Manifest::load_from_dir(&example()).unwrap().unwrap().tiles.iter().filter(|t| !t.empty)
    {
        let name = tile.file.as_ref().unwrap();
        let target = frames.join(name);
        std::fs::create_dir_all(target.parent().unwrap()).unwrap();
        std::fs::copy(example().join(name), target).unwrap();
    }
    copy_labels(&frames);
    // The bundled PIdT is 512²: against the default 4096² palette, and against 1024².
    let args = ["frames", "--pidt", "frames/pidt.png", "--legend", "frames/parts.csv", "--rig", "rig.json"];
    std::fs::write(dir.path().join("rig.json"), r#"{"tiles": [5, 5], "fps": 60, "horizontal_fov_deg": 107}"#)
        .unwrap();
    for palette in [&[][..], &["--palette-size", "1024"][..]] {
        let refused = manifest(dir.path(), &[&args[..], palette, &["--missing-tiles-empty"]].concat());
        assert_eq!(refused.status.code(), Some(2), "{}", stderr(&refused));
        let message = stderr(&refused);
        assert!(message.contains("pidt.png") && message.contains("the PIdT is 512×512 texels"), "{message}");
        assert!(message.contains("--palette-size 512x512"), "{message}");
        assert!(!frames.join("manifest.json").exists());
    }
    let ok = manifest(dir.path(), &[&args[..], &["--palette-size", "512", "--missing-tiles-empty"]].concat());
    assert!(ok.status.success(), "{}", stderr(&ok));
}
