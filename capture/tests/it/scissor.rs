//! Leaving out what the scene does not need changes nothing: captures with
//! the scissor (and the hidden-tile skip) and with `--no-scissor` write the
//! same tiles byte for byte, list the same tiles in the manifest and analyse
//! to the same result, while the scissor leaves pixels out and says so.

use std::path::Path;

use ufcsr::{AnalyzeOptions, Dedupe, Manifest};
use ufcsr_capture::{
    Backend, CaptureOptions, Gpu, Scene, Summary, capture, scene::degenerate_vehicle, verify,
};

fn capture_with(gpu: &Gpu, scene: &Scene, scenario: &str, out: &Path, no_scissor: bool) -> Summary {
    let scenario = scene.scenario(scenario).unwrap().clone();
    let options = CaptureOptions {
        out: out.to_path_buf(),
        palette: [512, 512],
        frames: "0-180/15".parse().unwrap(),
        no_scissor,
        encoder_threads: 1,
        ..CaptureOptions::default()
    };
    capture(&gpu.device, &gpu.queue, scene, &scenario, &options).unwrap()
}

fn analyze(archive: &Path) -> ufcsr::AnalysisResult {
    let options =
        AnalyzeOptions { archive: archive.to_path_buf(), dedupe: Dedupe::Frame, ..Default::default() };
    ufcsr::analyze(&options, None).expect("ufcsr::analyze").result
}

fn same_archives(scissored: &Path, whole: &Path) {
    let (a, b) = (
        Manifest::load_from_dir(scissored).unwrap().unwrap(),
        Manifest::load_from_dir(whole).unwrap().unwrap(),
    );
    let listed = |m: &Manifest| serde_json::to_value(&m.tiles).unwrap();
    assert_eq!(listed(&a), listed(&b), "the manifests list different tiles");
    let mut files = 0;
    for tile in &a.tiles {
        let Some(file) = &tile.file else { continue };
        let (x, y) = (std::fs::read(scissored.join(file)).unwrap(), std::fs::read(whole.join(file)).unwrap());
        assert!(x == y, "{} differs", file.display());
        files += 1;
    }
    assert!(files > 0, "no tile written");
    for file in ["pidt.png", "parts.csv"] {
        assert_eq!(
            std::fs::read(scissored.join(file)).unwrap(),
            std::fs::read(whole.join(file)).unwrap(),
            "{file}"
        );
    }
    let (mut x, y) = (analyze(scissored), analyze(whole));
    x.settings = y.settings.clone();
    assert_eq!(x, y, "the analyzer's results differ");
    assert_eq!(verify(scissored).unwrap(), verify(whole).unwrap());
}

/// Devices for every backend that works here; at least one must.
fn devices() -> Vec<Gpu> {
    let gpus: Vec<Gpu> =
        [Backend::Vulkan, Backend::Gl].into_iter().filter_map(|b| Gpu::create(b).ok()).collect();
    assert!(!gpus.is_empty(), "GPU tests need an adapter (Vulkan or GL)");
    gpus
}

#[test]
fn scissored_captures_write_the_same_tiles_as_whole_tiles() {
    for gpu in devices() {
        eprintln!("adapter: {}", gpu.describe());
        check_backend(&gpu);
    }
}

fn check_backend(gpu: &Gpu) {
    let dir = tempfile::tempdir().unwrap();
    let mut demo = Scene::demo();
    demo.rig.set_pixels_per_degree(4.0).unwrap();
    let mut degenerate = demo.clone();
    degenerate.vehicle = degenerate_vehicle();
    for (name, scene, scenario) in
        [("demo-A", &demo, "A"), ("demo-C", &demo, "C"), ("degenerate-B", &degenerate, "B")]
    {
        let (scissored, whole) =
            (dir.path().join(format!("{name}-scissor")), dir.path().join(format!("{name}-whole")));
        let cut = capture_with(gpu, scene, scenario, &scissored, false);
        let full = capture_with(gpu, scene, scenario, &whole, true);
        eprintln!(
            "{name}: scissor left out {} of {} pixels, {} tiles hidden; rendered {} vs {} tiles",
            cut.tally.pixels_scissored, cut.pixels, cut.tally.hidden, cut.tally.rendered, full.tally.rendered
        );
        assert_eq!((full.tally.pixels_scissored, full.tally.hidden), (0, 0));
        assert!(cut.tally.pixels_scissored > 0, "{name}: the scissor left nothing out");
        // Frame 0: a corner building hides the truck from tiles its bounds touch.
        assert!(
            cut.tally.hidden > 0 && cut.tally.rendered + cut.tally.hidden == full.tally.rendered,
            "{name}"
        );
        assert_eq!(cut.tally.written, full.tally.written, "{name}");
        // The summary's kinds partition the tiles: hidden ones are not also
        // "background only", and background-only tiles are rendered ones.
        for summary in [&cut, &full] {
            assert_eq!(summary.tally.accounted(), summary.tiles, "{name}: {:?}", summary.tally);
            assert!(summary.tally.background <= summary.tally.rendered, "{name}: {:?}", summary.tally);
            assert_eq!(summary.tally.written + summary.tally.background, summary.tally.rendered, "{name}");
        }
        same_archives(&scissored, &whole);
        let manifest = Manifest::load_from_dir(&scissored).unwrap().unwrap();
        let capture = manifest.capture.expect("a capture record");
        assert_eq!(capture.pixels_scissored, Some(cut.tally.pixels_scissored), "{name}");
        assert_eq!(capture.tiles_hidden, Some(cut.tally.hidden), "{name}");
    }
}
