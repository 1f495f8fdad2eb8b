//! Extreme cases with known answers, counted straight from the renderer:
//! a wall 0.35 m from the eyes (just beyond the 0.3 m near plane) fills the
//! view and counts its visible area in texels; the truck 900 m away is
//! smaller than a few pixels, each pixel shows a different texel, and the
//! result says the count depends on resolution; a scene moved 10 km from the
//! origin counts, texel for texel, as at the origin.

use glam::{DVec3, dvec3, vec3};
use ufcsr::{AnalysisResult, Dedupe};
use ufcsr_capture::{
    Backend, CaptureOptions, Gpu, Mesh, Rig, Scenario, Scene, scene::Key, scene::Motion, scene::Occluders,
    scene::Track, scene::ValueOrTrack,
};

fn gpu() -> Gpu {
    Gpu::create(Backend::Auto).expect("a Vulkan or GL driver (Mesa's lavapipe or llvmpipe will do)")
}

/// A vehicle standing still at `position` (yaw 0) for `frames` frames at 60 fps.
fn standing(position: DVec3, frames: u32) -> Scenario {
    let p = position.to_array();
    Scenario {
        name: "still".into(),
        duration_s: f64::from(frames - 1) / 60.0,
        motion: Motion {
            position: Track::new(vec![Key::linear(0.0, p)]).unwrap(),
            yaw_deg: Track::new(vec![Key::linear(0.0, [0.0])]).unwrap(),
        },
    }
}

fn scene(vehicle: Mesh, occluders: Occluders, rig: Rig, scenario: Scenario) -> Scene {
    Scene {
        name: "extreme".into(),
        vehicle,
        occluders,
        rig,
        scenarios: vec![scenario],
        info: ufcsr::format::SceneRecord { name: "extreme".into(), ..Default::default() },
        warnings: Vec::new(),
        input_files: Vec::new(),
        fleet: Vec::new(),
        vehicle_path: None,
    }
}

/// Counts the scene's only scenario (`--count`) and returns its result and texel counts.
fn count(gpu: &Gpu, scene: &Scene, palette: [u32; 2], dedupe: Dedupe) -> (AnalysisResult, Vec<u32>) {
    let dir = tempfile::tempdir().unwrap();
    let options = CaptureOptions { out: dir.path().join("a"), palette, ..CaptureOptions::default() };
    let counted =
        ufcsr_capture::capture_counted(&gpu.device, &gpu.queue, scene, &scene.scenarios[0], &options, dedupe)
            .unwrap();
    (counted.analysis.result, counted.analysis.texel_counts)
}

#[test]
fn a_wall_at_the_near_plane_fills_the_view_and_counts_its_visible_area() {
    let gpu = gpu();
    // A 4 m × 4 m wall facing the pedestrian, who looks along +x at its
    // centre line from 0.35 m (the near plane is at 0.3 m).
    let mut wall = Mesh::default();
    wall.add_quad(
        "wall",
        vec3(0.0, 2.0, 0.0),
        vec3(0.0, -2.0, 0.0),
        vec3(0.0, -2.0, 4.0),
        vec3(0.0, 2.0, 4.0),
    );
    let mut rig = Rig {
        pedestrian: ValueOrTrack::Fixed([0.0, 0.0, 0.0]),
        look_at_vehicle: [0.0, 0.0, 1.75],
        eye_pixels: [200, 250],
        tiles: [2, 2],
        ..Rig::default()
    };
    rig.set_pixels_per_degree(4.0).unwrap();
    let distance = 0.35;
    let scene = scene(wall, Occluders::default(), rig.clone(), standing(dvec3(distance, 0.0, 0.0), 2));
    let (result, _) = count(&gpu, &scene, [512, 512], Dedupe::Frame);
    // No pixel is background: the near plane clips nothing of the wall.
    assert_eq!(result.pixels.background, 0, "{:?}", result.pixels);
    assert_eq!(result.stray_pixels, 0);
    // Each eye-frame counts the texels of the visible rectangle once.
    let horizontal = 2.0 * distance * (rig.horizontal_fov_deg.to_radians() / 2.0).tan();
    let vertical = 2.0 * distance * (rig.vertical_fov_deg().to_radians() / 2.0).tan();
    let texels_per_m2 = texels_per_m2(&scene, [512, 512]);
    let expected = 2.0 * 2.0 * horizontal * vertical * texels_per_m2; // 2 frames × 2 eyes
    let got = result.grand_total as f64;
    assert!((got / expected - 1.0).abs() < 0.05, "grand total {got}, visible area says {expected:.0}");
    // Many pixels per texel: the report says counts saturate.
    let resolution = result.resolution.as_ref().unwrap();
    assert!(resolution.pixels_per_count > 4.0, "{}", resolution.pixels_per_count);
    assert!(result.warnings.iter().any(|w| w.contains("saturate")), "{:?}", result.warnings);
}

fn texels_per_m2(scene: &Scene, palette: [u32; 2]) -> f64 {
    ufcsr_capture::unwrap_islands_avoiding(&scene.vehicle, palette, ufcsr_capture::background_texel(palette))
        .unwrap()
        .texels_per_m2
}

#[test]
fn the_truck_900_m_away_counts_one_texel_per_pixel_and_warns() {
    let gpu = gpu();
    let demo = Scene::demo();
    let mut rig = Rig { pedestrian: ValueOrTrack::Fixed([0.0, 0.0, 0.0]), ..demo.rig.clone() };
    rig.set_pixels_per_degree(20.0).unwrap();
    let scene = scene(demo.vehicle.clone(), Occluders::default(), rig, standing(dvec3(900.0, 0.0, 0.0), 3));
    let (result, _) = count(&gpu, &scene, [256, 256], Dedupe::Image);
    let texel_pixels = result.pixels.texel;
    assert!(texel_pixels > 20, "the truck should cover a few pixels at 900 m: {texel_pixels}");
    assert_eq!(result.stray_pixels, 0);
    // A pixel is ~0.8 m wide there and a texel ~3 cm: no two pixels show one texel.
    assert_eq!(result.grand_total, texel_pixels);
    let resolution = result.resolution.as_ref().unwrap();
    assert_eq!(resolution.sub_pixel_frame_share, Some(1.0));
    assert!(result.warnings.iter().any(|w| w.contains("smaller than a pixel")), "{:?}", result.warnings);
}

#[test]
fn a_scene_10_km_from_the_origin_counts_as_at_the_origin() {
    let gpu = gpu();
    let demo = Scene::demo();
    let mut rig = demo.rig.clone();
    rig.set_pixels_per_degree(12.0).unwrap();
    let scenario = demo.scenario("B").unwrap().clone();
    let at_origin = Scene { rig: rig.clone(), scenarios: vec![scenario.clone()], ..demo.clone() };
    let offset = dvec3(8192.0, 8192.0, 0.0);
    let moved = moved_scene(&at_origin, offset);
    let (near, near_counts) = count(&gpu, &at_origin, [256, 256], Dedupe::Image);
    let (far, far_counts) = count(&gpu, &moved, [256, 256], Dedupe::Image);
    assert!(near.grand_total > 10_000 && near.stray_pixels == 0, "{}", near.grand_total);
    // Occluders hide part of the truck in this scenario, so their f32 world
    // coordinates matter too.
    assert!(near.pixels.background > 0);
    assert_eq!(near.grand_total, far.grand_total);
    assert_eq!(near.pixels.texel, far.pixels.texel);
    assert!(near_counts == far_counts, "per-texel counts differ 10 km from the origin");
}

/// `scene` with the pedestrian, the vehicle's track and every occluder moved by `offset`.
fn moved_scene(scene: &Scene, offset: DVec3) -> Scene {
    let mut moved = scene.clone();
    moved.rig.pedestrian = ValueOrTrack::Fixed((moved.rig.anchor() + offset).to_array());
    for scenario in &mut moved.scenarios {
        let keys = scenario
            .motion
            .position
            .keys
            .iter()
            .map(|key| {
                let mut key = key.clone();
                for axis in 0..3 {
                    key.value[axis] += offset[axis];
                }
                key
            })
            .collect();
        scenario.motion.position = Track::new(keys).unwrap();
    }
    for position in &mut moved.occluders.positions {
        *position += offset;
    }
    for object in &mut moved.occluders.objects {
        object.min += offset;
        object.max += offset;
    }
    moved
}

#[test]
fn the_full_palette_of_2_to_the_24_texels_names_only_labelled_texels() {
    // The paper's 4096² palette: UVs in f32 have ~4096 steps per texel at
    // u ≈ 1, and every pixel must still name a texel of its own triangle's
    // labelled chart, including in the top rows of the palette.
    let gpu = gpu();
    let demo = Scene::demo();
    let mut rig = Rig { pedestrian: ValueOrTrack::Fixed([0.0, 0.0, 0.0]), ..demo.rig.clone() };
    rig.set_pixels_per_degree(20.0).unwrap();
    // The truck 7 m away, side on: 2.7 mm texels under many pixels.
    let scene = scene(demo.vehicle.clone(), Occluders::default(), rig, standing(dvec3(7.0, 0.0, 0.0), 2));
    let (result, counts) = count(&gpu, &scene, [4096, 4096], Dedupe::Image);
    assert_eq!(result.stray_pixels, 0);
    let unlabelled = result.unlabelled.as_ref().unwrap();
    assert_eq!(unlabelled.total, 0, "pixels named unlabelled texels: {unlabelled:?}");
    let highest = counts.iter().rposition(|&c| c > 0).unwrap();
    assert!(highest >= 1 << 23, "the upper half of the palette was not reached: texel {highest}");
    assert!(result.grand_total > 10_000, "{}", result.grand_total);
}

#[test]
fn a_surface_seen_edge_on_is_not_counted_by_pixels_or_by_the_exact_measure() {
    use ufcsr_capture::{Obstacles, Tracer, eye_frames, surface_samples, texel_visibility};
    let gpu = gpu();
    // A horizontal 4 m square at exactly eye height (1.75 m): both eyes lie
    // in its plane, so it is seen exactly edge-on in every frame.
    let mut plate = Mesh::default();
    plate.add_quad(
        "plate",
        vec3(-2.0, -2.0, 1.75),
        vec3(2.0, -2.0, 1.75),
        vec3(2.0, 2.0, 1.75),
        vec3(-2.0, 2.0, 1.75),
    );
    let rig = Rig {
        pedestrian: ValueOrTrack::Fixed([0.0, 0.0, 0.0]),
        look_at_vehicle: [0.0, 0.0, 1.75],
        eye_pixels: [200, 250],
        tiles: [2, 2],
        ..Rig::default()
    };
    let scene = scene(plate, Occluders::default(), rig, standing(dvec3(6.0, 0.0, 0.0), 3));
    let (result, _) = count(&gpu, &scene, [256, 256], Dedupe::Image);
    assert_eq!(result.stray_pixels, 0);
    // A line at most: no more than one row of pixels per eye-frame.
    assert!(result.pixels.texel <= 6 * 200, "{} pixels show an edge-on plate", result.pixels.texel);
    // The exact measure: the eye is in the plane, so no point faces it.
    let palette = [256, 256];
    let unwrapped = ufcsr_capture::unwrap_islands_avoiding(
        &scene.vehicle,
        palette,
        ufcsr_capture::background_texel(palette),
    )
    .unwrap();
    let samples = surface_samples(&scene.vehicle, &unwrapped, 1.0, 1, 2);
    assert!(samples.texels.len() > 1000);
    let obstacles = Obstacles::new(&scene);
    let (frames, _) = eye_frames(&scene, &scene.scenarios[0], &[0, 1, 2], &obstacles).unwrap();
    let visibility =
        texel_visibility(&samples, &frames, &obstacles, scene.vehicle.parts.len(), Tracer::Hierarchy);
    assert_eq!(visibility.counts.iter().sum::<u32>(), 0);
}
