//! A capture whose palette needs more than 2^24 texels: the renderer draws
//! 32-bit texel ids (alpha carries the high byte), the tiles that show
//! texels above 2^24 are RGBA, the manifest says `ufcsr-manifest/2` and
//! `"texel_ids": "rgba32"`, and every pixel names a labelled texel of the
//! palette or the background, as a 24-bit capture's do.

use ufcsr::{AnalyzeOptions, Manifest, format::TexelIds};
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

#[test]
fn counting_while_rendering_refuses_a_palette_above_2_24_texels_before_preparing_it() {
    let gpu = Gpu::create(Backend::Auto).unwrap_or_else(|e| panic!("GPU tests need an adapter: {e}"));
    let dir = tempfile::tempdir().unwrap();
    let scene = Scene::demo();
    let options = CaptureOptions {
        out: dir.path().join("counted"),
        palette: [8192, 4096],
        ..CaptureOptions::default()
    };
    let scenario = scene.scenario("D").unwrap().clone();
    let refused = ufcsr_capture::capture_counted(
        &gpu.device,
        &gpu.queue,
        &scene,
        &scenario,
        &options,
        ufcsr::Dedupe::Frame,
    );
    let error = match refused {
        Ok(_) => panic!("--count counted a palette of 32-bit texel ids"),
        Err(error) => error.to_string(),
    };
    assert!(error.contains("8192x4096") && error.contains("--count"), "{error}");
    assert!(!options.out.join("pidt.png").exists(), "refused before the palette was unwrapped");
}
