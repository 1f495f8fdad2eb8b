//! The own-PIdT path (`--keep-uvs --pidt --parts`) on a fixture vehicle. The
//! real vehicle from `../shared` (the Cesium milk truck) is tested in
//! `tests/external/milk_truck.rs`, whose harness reports it ignored when absent.

use std::path::PathBuf;

use ufcsr_capture::{Backend, CaptureOptions, FrameSelection, Gpu, OwnLabelFiles, Scene, capture, verify};

fn fixture(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fixtures/scenes").join(name)
}

#[test]
fn own_pidt_and_legend_are_used_as_is() {
    let gpu = Gpu::create(Backend::Auto).unwrap_or_else(|e| panic!("GPU tests need an adapter: {e}"));
    let mut scene = Scene::load(&fixture("gltf-vehicle.json")).unwrap();
    scene.rig.set_pixels_per_degree(2.0).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let base = CaptureOptions {
        palette: [256, 256],
        keep_uvs: true,
        frames: "0,30".parse::<FrameSelection>().unwrap(),
        ..CaptureOptions::default()
    };
    // A PIdT "painted elsewhere": the one a first capture paints, with the
    // parts renamed in its legend.
    let painted = CaptureOptions { out: dir.path().join("painted"), ..base.clone() };
    capture(&gpu.device, &gpu.queue, &scene, &scene.scenarios[0], &painted).unwrap();
    let legend_text = std::fs::read_to_string(painted.out.join("parts.csv")).unwrap();
    let legend = dir.path().join("legend.csv");
    std::fs::write(&legend, legend_text.replace("cab,", "front box,").replace("cargo,", "rear box,"))
        .unwrap();
    let own = OwnLabelFiles { pidt: painted.out.join("pidt.png"), parts: legend.clone() };

    let options =
        CaptureOptions { out: dir.path().join("own"), own_labels: Some(own.clone()), ..base.clone() };
    let summary = capture(&gpu.device, &gpu.queue, &scene, &scene.scenarios[0], &options).unwrap();
    assert!(summary.warnings.is_empty(), "{:?}", summary.warnings);
    assert_eq!(std::fs::read(options.out.join("pidt.png")).unwrap(), std::fs::read(&own.pidt).unwrap());
    let written = std::fs::read_to_string(options.out.join("parts.csv")).unwrap();
    assert!(written.contains("front box,") && written.contains("rear box,"), "{written}");
    assert_eq!(verify(&options.out).unwrap().1, 0);

    // A legend that leaves a part out: counted and reported, not dropped.
    let short = dir.path().join("short.csv");
    let first_two: Vec<&str> = legend_text.lines().take(2).collect();
    std::fs::write(&short, first_two.join("\n")).unwrap();
    let options = CaptureOptions {
        out: dir.path().join("short"),
        own_labels: Some(OwnLabelFiles { pidt: own.pidt.clone(), parts: short }),
        ..base.clone()
    };
    let summary = capture(&gpu.device, &gpu.queue, &scene, &scene.scenarios[0], &options).unwrap();
    assert_eq!(summary.warnings.len(), 2, "{:?}", summary.warnings);
    assert!(summary.warnings[0].contains("does not list"), "{:?}", summary.warnings);

    // Wrong size, and without --keep-uvs: clear errors.
    let options = CaptureOptions {
        out: dir.path().join("big"),
        palette: [512, 512],
        own_labels: Some(own.clone()),
        ..base.clone()
    };
    let error =
        capture(&gpu.device, &gpu.queue, &scene, &scene.scenarios[0], &options).unwrap_err().to_string();
    assert!(error.contains("pidt.png") && error.contains("256×256, expected 512×512"), "{error}");
    let options =
        CaptureOptions { out: dir.path().join("islands"), keep_uvs: false, own_labels: Some(own), ..base };
    let error =
        capture(&gpu.device, &gpu.queue, &scene, &scene.scenarios[0], &options).unwrap_err().to_string();
    assert!(error.contains("--pidt needs --keep-uvs"), "{error}");
}
