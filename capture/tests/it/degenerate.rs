//! Every pixel of any mesh names a labelled texel: a generated vehicle made
//! of zero-area, needle, sliver, huge-aspect and overlapping triangles
//! ([`degenerate_vehicle`]) is rendered at several poses and distances, and
//! every non-background pixel must be a palette colour whose texel the PIdT
//! labels (what `ufcsr verify` checks on an archive).

use ufcsr_capture::{Backend, CaptureOptions, Gpu, capture, scene::degenerate_vehicle, verify};

use crate::render_check::{PALETTE, render_and_check};

/// Devices for every backend that works here; at least one must.
fn devices() -> Vec<Gpu> {
    let gpus: Vec<Gpu> =
        [Backend::Vulkan, Backend::Gl].into_iter().filter_map(|b| Gpu::create(b).ok()).collect();
    assert!(!gpus.is_empty(), "GPU tests need an adapter (Vulkan or GL)");
    gpus
}

#[test]
fn every_pixel_of_a_degenerate_mesh_names_a_labelled_texel() {
    for gpu in devices() {
        let (vehicle, stray) = render_and_check(&gpu, &degenerate_vehicle());
        eprintln!("{}: {vehicle} vehicle pixels, {stray} stray", gpu.describe());
        assert!(vehicle > 10_000, "{vehicle} vehicle pixels");
        assert_eq!(
            stray,
            0,
            "{}: {stray} of {} pixels name no labelled texel",
            gpu.describe(),
            vehicle + stray
        );
    }
}

#[test]
fn a_degenerate_vehicle_archive_verifies_with_no_stray_pixel() {
    // The demo intersection and its scenario A, with the degenerate vehicle.
    let mut scene = ufcsr_capture::Scene::demo();
    scene.vehicle = degenerate_vehicle();
    scene.rig.set_pixels_per_degree(4.0).unwrap();
    let scenario = scene.scenario("A").unwrap().clone();
    let dir = tempfile::tempdir().unwrap();
    let options = CaptureOptions {
        out: dir.path().join("degenerate"),
        palette: PALETTE,
        frames: "100-180/20".parse().unwrap(),
        encoder_threads: 1,
        ..CaptureOptions::default()
    };
    let gpu = Gpu::create(Backend::Auto).unwrap();
    capture(&gpu.device, &gpu.queue, &scene, &scenario, &options).unwrap();
    let (vehicle, stray) = verify(&options.out).unwrap();
    eprintln!("archive: {vehicle} vehicle pixels, {stray} stray");
    assert!(vehicle > 1000, "{vehicle} vehicle pixels");
    assert_eq!(stray, 0);
}
