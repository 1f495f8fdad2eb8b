//! Every pixel of any mesh names a labelled texel: a generated vehicle made
//! of zero-area, needle, sliver, huge-aspect and overlapping triangles
//! ([`degenerate_vehicle`]) is rendered at several poses and distances, and
//! every non-background pixel must be a palette colour whose texel the PIdT
//! labels (what `ufcsr-capture verify` checks on an archive).

use glam::dvec3;
use ufcsr::Color;
use ufcsr_capture::{
    Backend, CaptureOptions, Gpu, Mesh, Occluders, Palette, Pose, RenderSetup, Renderer, Rig, TileDraw,
    UNLABELLED_COLOR, capture, degenerate_vehicle, paint_pidt, unwrap_islands, vehicle_to_world,
    vehicle_vertices, verify,
};

const PALETTE: [u32; 2] = [1024, 1024];

/// Devices for every backend that works here; at least one must.
fn devices() -> Vec<Gpu> {
    let gpus: Vec<Gpu> =
        [Backend::Vulkan, Backend::Gl].into_iter().filter_map(|b| Gpu::create(b).ok()).collect();
    assert!(!gpus.is_empty(), "GPU tests need an adapter (Vulkan or GL)");
    gpus
}

/// (vehicle pixels, stray pixels) over both eyes of every pose.
fn render_and_check(gpu: &Gpu, mesh: &Mesh) -> (u64, u64) {
    let unwrapped = unwrap_islands(mesh, PALETTE).unwrap();
    let pidt = paint_pidt(mesh, &unwrapped);
    let vertices = vehicle_vertices(mesh, &unwrapped);
    let rig = Rig {
        pedestrian: [0.0, 0.0, 0.0],
        eye_height_m: 1.5,
        horizontal_fov_deg: 60.0,
        eye_pixels: [320, 240],
        tiles: [2, 2],
        look_at_vehicle: [0.0, 0.0, 1.1],
        ..Rig::default()
    };
    let palette = Palette::Canonical(PALETTE);
    let occluders = Occluders::default();
    let setup = RenderSetup {
        tile_size: rig.tile_pixels(),
        palette: &palette,
        background: Color::DEFAULT_BACKGROUND,
        vehicle: &vertices,
        occluders: &occluders,
        origin: rig.head(),
    };
    let renderer = Renderer::new(&gpu.device, &gpu.queue, &setup).unwrap();
    let poses = [
        (6.0, 0.0, 0.0),
        (5.0, 1.0, 37.0),
        (4.0, -1.0, 71.0),
        (9.0, -2.0, 93.0),
        (7.0, 2.0, 133.0),
        (14.0, 3.0, 181.0),
        (25.0, 1.0, 222.0),
        (40.0, -4.0, 250.0),
        (70.0, 6.0, 301.0),
        (8.0, 0.5, 89.9),
    ];
    let (mut vehicle, mut stray) = (0u64, 0u64);
    for (x, y, yaw_deg) in poses {
        let pose = Pose { position: dvec3(x, y, 0.0), yaw_deg };
        for camera in rig.cameras(&pose) {
            for tile in rig.all_tiles() {
                let clip_from_world = rig.tile_matrix(tile) * camera.view_proj;
                let draw = TileDraw {
                    clip_from_vehicle: clip_from_world * vehicle_to_world(&pose),
                    clip_from_world,
                    occluders: &[],
                };
                let rgba = renderer.render_tile(&gpu.device, &gpu.queue, &draw).unwrap();
                for p in rgba.chunks_exact(4) {
                    let color = Color::from_rgb(p[0], p[1], p[2]);
                    if color == Color::DEFAULT_BACKGROUND {
                        continue;
                    }
                    let index = color.packed();
                    let labelled = index < PALETTE[0] * PALETTE[1]
                        && pidt.at(index % PALETTE[0], index / PALETTE[0]) != UNLABELLED_COLOR;
                    if labelled {
                        vehicle += 1;
                    } else {
                        stray += 1;
                    }
                }
            }
        }
    }
    (vehicle, stray)
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

/// The Cesium milk truck from `../shared/ref/vehicles/` at the same poses
/// (skipped with a message when absent, a failure when `CI` is set).
#[test]
fn every_pixel_of_the_milk_truck_names_a_labelled_texel() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../fixtures/scenes");
    if !dir.join("../../../shared/ref/vehicles/cesium-milk-truck.glb").is_file() {
        assert!(std::env::var_os("CI").is_none(), "CI: the milk truck in ../shared/ref/vehicles is missing");
        eprintln!("skipped: ../shared/ref/vehicles/cesium-milk-truck.glb is absent");
        return;
    }
    let scene = ufcsr_capture::Scene::load(&dir.join("milk-truck.json")).unwrap();
    let gpu = Gpu::create(Backend::Auto).unwrap();
    let (vehicle, stray) = render_and_check(&gpu, &scene.vehicle);
    eprintln!("milk truck: {vehicle} vehicle pixels, {stray} stray");
    assert!(vehicle > 10_000, "{vehicle} vehicle pixels");
    assert_eq!(stray, 0);
}
