//! Real vehicles: the Cesium milk truck from `../shared/ref/vehicles/`
//! (skipped with a message when absent, a failure when `CI` is set) through
//! `inspect`, region labelling, the partial-UV message and a tiny capture;
//! and the own-PIdT path (`--keep-uvs --pidt --parts`) on a fixture.

use std::path::{Path, PathBuf};

use ufcsr_capture::{
    Backend, CaptureOptions, FrameSelection, Gpu, InspectOptions, OwnLabels, Scene, UvState, capture,
    inspect, verify,
};

fn fixture(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fixtures/scenes").join(name)
}

/// The milk-truck scene when its model is there; `None` (skip) otherwise,
/// unless `CI` is set.
fn milk_truck_scene() -> Option<PathBuf> {
    let model = fixture("../../../shared/ref/vehicles/cesium-milk-truck.glb");
    if model.exists() {
        return Some(fixture("milk-truck.json"));
    }
    assert!(std::env::var_os("CI").is_none(), "CI: {} is missing", model.display());
    eprintln!("SKIP: {} not found (see shared/ref/vehicles/SOURCE.md)", model.display());
    None
}

#[test]
fn milk_truck_inspects_and_labels_into_named_parts() {
    let Some(scene) = milk_truck_scene() else { return };
    let out = tempfile::tempdir().unwrap();
    let inspection = inspect(&InspectOptions {
        input: scene.clone(),
        out: out.path().to_path_buf(),
        pixels_per_metre: Some(40.0),
    })
    .unwrap();
    // SOURCE.md: about 3.6k triangles. Y up, +Z forward: 4.87 m long, 2.79 m
    // wide, 2.58 m high, standing on the ground under its centre.
    assert_eq!(inspection.triangles, 3624);
    let (min, max) = inspection.bounds;
    let size = max - min;
    assert!(
        (size.x - 4.869).abs() < 0.01 && (size.y - 2.792).abs() < 0.01 && (size.z - 2.583).abs() < 0.01,
        "{size}"
    );
    assert!(inspection.ground_centre.length() < 0.01, "{}", inspection.ground_centre);
    assert_eq!((inspection.quality.degenerate, inspection.quality.slivers), (0, 0));
    assert!(inspection.warnings.is_empty(), "{:?}", inspection.warnings);
    // The glass and trim primitives have no TEXCOORD_0.
    let UvState::Partial(missing) = &inspection.uvs else { panic!("{:?}", inspection.uvs) };
    assert_eq!(missing.len(), 2);
    assert!(missing[0].contains("\"glass\"") && missing[1].contains("\"window_trim\""), "{missing:?}");

    let mut names: Vec<&str> = inspection.parts.iter().map(|p| p.name.as_str()).collect();
    names.sort_unstable();
    assert_eq!(
        names,
        ["bumper", "cab", "hood", "tank", "wheels_front", "wheels_rear", "window_trim", "windows"]
    );
    for part in &inspection.parts {
        assert!(part.area_m2 > 0.1 && part.triangles > 0, "{part:?}");
    }
    let total: f64 = inspection.parts.iter().map(|p| p.area_m2).sum();
    assert!((total - 64.816).abs() < 0.01, "{total}");
    // The cargo tank is the biggest body part, the cab next.
    let area = |name: &str| inspection.parts.iter().find(|p| p.name == name).map_or(0.0, |p| p.area_m2);
    assert!(area("tank") > area("cab") && area("cab") > area("hood"), "{:?}", inspection.parts);
    for file in ["inspect-side.png", "inspect-top.png", "inspect-front.png", "inspect-parts.csv"] {
        assert!(out.path().join(file).is_file(), "{file}");
    }
    let report = inspection.to_string();
    assert!(report.contains("expect_length_m 5: ok"), "{report}");

    // A wrong scale is caught: the same truck in "centimetres".
    let text = std::fs::read_to_string(&scene).unwrap().replace("\"scale\": 1.0", "\"scale\": 0.01");
    let copy = out.path().join("milk-truck-cm.json");
    std::fs::write(&copy, text.replace("../../../shared", &absolute(&fixture("../../../shared")))).unwrap();
    let wrong = Scene::load(&copy).unwrap();
    assert!(
        wrong.warnings.iter().any(|w| w.contains("expect_length_m") && w.contains("axes.scale")),
        "{:?}",
        wrong.warnings
    );
}

fn absolute(path: &Path) -> String {
    path.canonicalize().unwrap().display().to_string()
}

#[test]
fn milk_truck_keep_uvs_names_the_primitives_without_uvs_and_a_tiny_capture_verifies() {
    let Some(scene_path) = milk_truck_scene() else { return };
    let mut scene = Scene::load(&scene_path).unwrap();
    let error = ufcsr_capture::keep_uvs(&scene.vehicle, [1024, 1024]).unwrap_err().to_string();
    assert!(error.contains("primitive 1 of mesh 1") && error.contains("\"glass\""), "{error}");

    let gpu = Gpu::create(Backend::Auto).unwrap_or_else(|e| panic!("GPU tests need an adapter: {e}"));
    scene.rig.set_pixels_per_degree(2.0).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let options = CaptureOptions {
        out: dir.path().join("truck"),
        palette: [512, 512],
        frames: "0,30,60".parse::<FrameSelection>().unwrap(),
        ..CaptureOptions::default()
    };
    let summary = capture(&gpu.device, &gpu.queue, &scene, &scene.scenarios[0], &options).unwrap();
    assert_eq!(summary.parts, 8);
    assert!(summary.tally.written > 0);
    let (vehicle, stray) = verify(&options.out).unwrap();
    assert!(vehicle > 0);
    assert_eq!(stray, 0);
    let legend = std::fs::read_to_string(options.out.join("parts.csv")).unwrap();
    for part in ["hood", "cab", "tank", "bumper", "windows"] {
        assert!(legend.lines().any(|line| line.starts_with(&format!("{part},"))), "{legend}");
    }
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
    let own = OwnLabels { pidt: painted.out.join("pidt.png"), parts: legend.clone() };

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
        own_labels: Some(OwnLabels { pidt: own.pidt.clone(), parts: short }),
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
