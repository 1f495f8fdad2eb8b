//! A real vehicle from `../shared/ref/vehicles/` (the Cesium milk truck, see
//! its SOURCE.md): `inspect`, region labelling, the partial-UV message, a tiny
//! capture, and every rendered pixel naming a labelled texel. Ignored with the
//! reason when the model is absent; a failure under `CI`.

use std::path::{Path, PathBuf};

use libtest_mimic::Completion;
use ufcsr_capture::{
    Backend, CaptureOptions, FrameSelection, Gpu, InspectOptions, Scene, UvState, capture, inspect, verify,
};

use crate::need::{Outcome, missing, repository, shared_dir};
use crate::render_check::render_and_check;

/// The milk-truck scene (`fixtures/scenes/milk-truck.json`) rewritten into
/// `work` to name the model in [`shared_dir`]; the skip when it is absent.
fn milk_truck_scene(work: &Path) -> Result<PathBuf, Outcome> {
    let shared = shared_dir();
    let model = shared.join("ref/vehicles/cesium-milk-truck.glb");
    if !model.is_file() {
        return Err(missing(&format!("{} (see shared/ref/vehicles/SOURCE.md)", model.display())));
    }
    let fixture = repository().join("fixtures/scenes/milk-truck.json");
    let text = std::fs::read_to_string(&fixture).unwrap();
    let absolute = shared.canonicalize().unwrap().display().to_string();
    let scene = work.join("milk-truck.json");
    std::fs::write(&scene, text.replace("../../../shared", &absolute)).unwrap();
    Ok(scene)
}

pub fn milk_truck_inspects_and_labels_into_named_parts() -> Outcome {
    let work = tempfile::tempdir().unwrap();
    let scene = match milk_truck_scene(work.path()) {
        Ok(scene) => scene,
        Err(skipped) => return skipped,
    };
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
    std::fs::write(&copy, text).unwrap();
    let wrong = Scene::load(&copy).unwrap();
    assert!(
        wrong.warnings.iter().any(|w| w.contains("expect_length_m") && w.contains("axes.scale")),
        "{:?}",
        wrong.warnings
    );
    Ok(Completion::Completed)
}

pub fn milk_truck_keep_uvs_names_the_primitives_without_uvs_and_a_tiny_capture_verifies() -> Outcome {
    let work = tempfile::tempdir().unwrap();
    let scene_path = match milk_truck_scene(work.path()) {
        Ok(scene) => scene,
        Err(skipped) => return skipped,
    };
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
    Ok(Completion::Completed)
}

/// The milk truck at the degenerate-mesh test's ten poses: no stray pixel.
pub fn every_pixel_of_the_milk_truck_names_a_labelled_texel() -> Outcome {
    let work = tempfile::tempdir().unwrap();
    let scene = match milk_truck_scene(work.path()) {
        Ok(scene) => Scene::load(&scene).unwrap(),
        Err(skipped) => return skipped,
    };
    let gpu = Gpu::create(Backend::Auto).unwrap();
    let (vehicle, stray) = render_and_check(&gpu, &scene.vehicle);
    eprintln!("milk truck: {vehicle} vehicle pixels, {stray} stray");
    assert!(vehicle > 10_000, "{vehicle} vehicle pixels");
    assert_eq!(stray, 0);
    Ok(Completion::Completed)
}
