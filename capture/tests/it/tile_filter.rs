//! The tiles' PNG row filter changes the files, never the pixels: a capture
//! with Up-filtered tiles (the default, faster to decode) and one with the
//! png crate's adaptive choice write tiles that decode to the same pixels and
//! analyse to the same result.

use std::path::Path;

use ufcsr::{AnalyzeOptions, Manifest};
use ufcsr_capture::{Backend, CaptureOptions, Gpu, Scene, TileFilter, capture, read_rgb_png};

fn capture_with(gpu: &Gpu, scene: &Scene, out: &Path, tile_filter: TileFilter) {
    let scenario = scene.scenario("A").unwrap().clone();
    let options = CaptureOptions {
        out: out.to_path_buf(),
        palette: [512, 512],
        frames: "90-180/30".parse().unwrap(),
        tile_filter,
        encoder_threads: 1,
        ..CaptureOptions::default()
    };
    capture(&gpu.device, &gpu.queue, scene, &scenario, &options).unwrap();
}

fn analyze(archive: &Path) -> ufcsr::AnalysisResult {
    let options = AnalyzeOptions { archive: archive.to_path_buf(), ..Default::default() };
    ufcsr::analyze(&options, None).expect("ufcsr::analyze").result
}

#[test]
fn up_and_adaptive_tiles_hold_the_same_pixels_and_analyse_alike() {
    let gpu = [Backend::Vulkan, Backend::Gl]
        .into_iter()
        .find_map(|b| Gpu::create(b).ok())
        .expect("GPU tests need an adapter (Vulkan or GL)");
    let dir = tempfile::tempdir().unwrap();
    let mut scene = Scene::demo();
    scene.rig.set_pixels_per_degree(4.0).unwrap();
    let (up, adaptive) = (dir.path().join("up"), dir.path().join("adaptive"));
    capture_with(&gpu, &scene, &up, TileFilter::Up);
    capture_with(&gpu, &scene, &adaptive, TileFilter::Adaptive);
    let manifest = Manifest::load_from_dir(&up).unwrap().unwrap();
    let (mut tiles, mut different_files) = (0, 0);
    for file in manifest.tiles.iter().filter_map(|t| t.file.as_ref()) {
        assert_eq!(
            read_rgb_png(&up.join(file)).unwrap(),
            read_rgb_png(&adaptive.join(file)).unwrap(),
            "{file:?}"
        );
        tiles += 1;
        different_files +=
            usize::from(std::fs::read(up.join(file)).unwrap() != std::fs::read(adaptive.join(file)).unwrap());
    }
    assert!(tiles > 0, "no tile written");
    assert!(different_files > 0, "the filter changed no file: is it applied?");
    let (mut a, b) = (analyze(&up), analyze(&adaptive));
    a.settings = b.settings.clone();
    assert_eq!(a, b, "the analyzer's results differ");
}
