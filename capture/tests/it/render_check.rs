//! Renders a vehicle at ten poses through both eyes and counts its pixels:
//! every non-background pixel must name a texel the PIdT labels (what
//! `ufcsr verify` checks on an archive). Shared by the degenerate-mesh
//! tests (`tests/it/degenerate.rs`) and the milk truck from `../shared`
//! (`tests/external/milk_truck.rs`, included there by path).

use glam::dvec3;
use ufcsr::Color;
use ufcsr_capture::{
    Gpu, GpuPalette, Mesh, RenderSetup, Renderer, Rig, TileDraw, UNLABELLED_COLOR, paint_pidt,
    scene::Occluders, scene::Pose, scene::vehicle_to_world, unwrap_islands, vehicle_vertices,
};

/// The palette both callers render with.
pub const PALETTE: [u32; 2] = [1024, 1024];

/// (vehicle pixels, stray pixels) over both eyes of every pose.
pub fn render_and_check(gpu: &Gpu, mesh: &Mesh) -> (u64, u64) {
    let unwrapped = unwrap_islands(mesh, PALETTE).unwrap();
    let pidt = paint_pidt(mesh, &unwrapped);
    let vertices = vehicle_vertices(mesh, &unwrapped);
    let rig = Rig {
        pedestrian: ufcsr_capture::scene::ValueOrTrack::Fixed([0.0, 0.0, 0.0]),
        eye_height_m: 1.5,
        horizontal_fov_deg: 60.0,
        eye_pixels: [320, 240],
        tiles: [2, 2],
        look_at_vehicle: [0.0, 0.0, 1.1],
        ..Rig::default()
    };
    let palette = GpuPalette::Canonical(PALETTE);
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
        for camera in rig.cameras(0.0, &pose) {
            for tile in rig.all_tiles() {
                let clip_from_world = rig.tile_matrix(tile) * camera.view_proj;
                let draw = TileDraw {
                    moving: &[],
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
