//! A capture whose palette needs more than 2^24 texels: the renderer draws
//! 32-bit texel ids (alpha carries the high byte), the tiles that show
//! texels above 2^24 are RGBA, the manifest says `ufcsr-manifest/2` and
//! `"texel_ids": "rgba32"`, and every pixel names a labelled texel of the
//! palette or the background, as a 24-bit capture's do; counted while
//! rendering (`--count`), such a capture gives what its PNG tiles give.

use ufcsr::{AnalyzeOptions, Dedupe, Manifest, TrimMode, format::TexelIds};
use ufcsr_capture::{Backend, CaptureOptions, FrameSelection, Gpu, Scene, capture, verify};

#[test]
fn a_capture_with_a_palette_above_2_24_texels_draws_32_bit_ids_that_all_name_labelled_texels() {
    let gpu = Gpu::create(Backend::Auto).unwrap_or_else(|e| panic!("GPU tests need an adapter: {e}"));
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("bus-sized");
    let mut scene = Scene::demo();
    scene.rig.set_pixels_per_degree(3.0).unwrap();
    // 2^25 texels: half the palette's ids are above 2^24.
    let options = CaptureOptions {
        out: out.clone(),
        palette: [8192, 4096],
        frames: "150-180/30".parse::<FrameSelection>().unwrap(),
        ..CaptureOptions::default()
    };
    let scenario = scene.scenario("D").unwrap().clone();
    capture(&gpu.device, &gpu.queue, &scene, &scenario, &options).unwrap();

    let manifest = Manifest::load_from_dir(&out).unwrap().unwrap();
    assert_eq!(manifest.schema.as_deref(), Some("ufcsr-manifest/2"));
    assert_eq!(manifest.texel_ids, Some(TexelIds::Rgba32));
    let (vehicle, stray) = verify(&out).unwrap();
    assert_eq!(stray, 0, "every pixel names a labelled texel or the background");
    assert!(vehicle > 1000, "{vehicle}");

    let analysis =
        ufcsr::analyze(&AnalyzeOptions { archive: out.clone(), ..Default::default() }, None).unwrap();
    let result = &analysis.result;
    assert_eq!(analysis.texel_counts.len(), 8192 * 4096);
    assert_eq!((result.stray_pixels, result.images.failed), (0, 0));
    assert_eq!(result.pixels.texel, vehicle);
    let above = analysis.texel_counts[1 << 24..].iter().filter(|&&c| c > 0).count();
    assert!(above > 0, "no texel above 2^24 was seen");
    assert_eq!(result.unlabelled.as_ref().unwrap().total, 0, "every counted texel is a part's");
}

/// `result.json` as JSON with what differs between two archives of one
/// capture blanked: their folders, and the archive identity (a digest of
/// the manifest file, which each capture writes anew).
fn comparable(result: &ufcsr::AnalysisResult) -> serde_json::Value {
    let mut value = serde_json::to_value(result).unwrap();
    for field in ["archive_identity", "archive", "parts", "pidt"] {
        value["settings"][field] = serde_json::Value::Null;
    }
    value
}

/// Known answer: the capture written as PNG tiles and analysed
/// (`ufcsr::analyze`, trimming off as the fused path has nothing to trim).
/// `--dedupe frame` here; the other dedupe modes' bookkeeping is the
/// analyzer's (`tests/it/rgba32_ids.rs` counts tiles in memory with each).
#[test]
fn counting_while_rendering_a_palette_above_2_24_texels_gives_what_its_png_tiles_give() {
    let gpu = Gpu::create(Backend::Auto).unwrap_or_else(|e| panic!("GPU tests need an adapter: {e}"));
    let dir = tempfile::tempdir().unwrap();
    let mut scene = Scene::demo();
    scene.rig.set_pixels_per_degree(3.0).unwrap();
    let scenario = scene.scenario("D").unwrap().clone();
    let options = |name: &str| CaptureOptions {
        out: dir.path().join(name),
        palette: [8192, 4096],
        frames: "150-180/30".parse::<FrameSelection>().unwrap(),
        ..CaptureOptions::default()
    };
    let (written, counted) = (options("written"), options("counted"));
    capture(&gpu.device, &gpu.queue, &scene, &scenario, &written).unwrap();
    let png = AnalyzeOptions {
        archive: written.out.clone(),
        dedupe: Dedupe::Frame,
        trim: TrimMode::Off,
        frames: true,
        texel_area: true,
        ..Default::default()
    };
    let png = ufcsr::analyze(&png, None).unwrap();
    let counted =
        ufcsr_capture::capture_counted(&gpu.device, &gpu.queue, &scene, &scenario, &counted, Dedupe::Frame)
            .unwrap();
    let manifest = Manifest::load_from_dir(&dir.path().join("counted")).unwrap().unwrap();
    assert_eq!(manifest.texel_ids, Some(TexelIds::Rgba32));
    let counted = counted.analysis;
    let above = counted.texel_counts[1 << 24..].iter().filter(|&&c| c > 0).count();
    assert!(above > 0, "no texel above 2^24 was seen");
    assert!(counted.texel_counts == png.texel_counts, "the texel counts differ");
    assert_eq!(counted.result.parts, png.result.parts);
    assert!(counted.frames.is_some() && counted.frames == png.frames, "frames.csv differs");
    // The per-texel angular area from the same integer sums: the same bits.
    assert!(counted.texel_angular_area.is_some());
    assert!(counted.texel_angular_area == png.texel_angular_area, "the angular areas differ");
    // All of result.json: pixels, strays, per-frame counts, measures, notes.
    assert_eq!(comparable(&counted.result), comparable(&png.result));
}
