//! Silent wrong numbers that are now right (issue 33, item 4): an eye looking
//! straight up once turned its camera to +X and measured a plate overhead as
//! 0; it now sees the plate in the middle of its image and measures its
//! closed-form solid angle. (The other silent numbers — an occluder lying on
//! the vehicle, faces two parts share, a frame longer than its scenario, the
//! Unity clips' speed jumps — are refused or warned by name; their tests sit
//! beside the checks in `archive/scene_checks.rs`, `unobstructed/points.rs`
//! and the external `unity_reference`.)

use glam::{DVec3, dvec3, vec3};
use ufcsr_capture::{
    Mesh, Obstacles, Scenario, Scene, Tracer, background_texel, eye_frames, scene::Key, scene::Motion,
    scene::Occluders, scene::Track, scene::ValueOrTrack, surface_samples, unwrap_islands_avoiding,
    visible_solid_angle,
};

#[test]
fn an_eye_looking_straight_up_sees_a_plate_overhead_with_its_solid_angle() {
    // A 2 × 2 m plate 3.25 m above the eyes, facing down: 0.3464 sr.
    let (half, above, eye_height) = (1.0_f64, 3.25_f64, 1.75_f64);
    let exact = 4.0 * (half * half / (above * (2.0 * half * half + above * above).sqrt())).atan();
    assert!((exact - 0.3464).abs() < 1e-4, "{exact}");
    let z = (eye_height + above) as f32;
    let mut plate = Mesh::default();
    plate.add_quad("plate", vec3(-1.0, -1.0, z), vec3(-1.0, 1.0, z), vec3(1.0, 1.0, z), vec3(1.0, -1.0, z));
    let mut scene = Scene::demo();
    scene.vehicle = plate;
    scene.occluders = Occluders::default();
    scene.rig.pedestrian = ValueOrTrack::Fixed([0.0, 0.0, 0.0]);
    scene.rig.eye_height_m = eye_height;
    scene.rig.ipd_m = 0.0;
    // The head turns to the plate's centre: straight up.
    scene.rig.look_at_vehicle = [0.0, 0.0, eye_height + above];
    scene.scenarios = vec![Scenario {
        name: "still".into(),
        duration_s: 0.0,
        motion: Motion {
            position: Track::new(vec![Key::linear(0.0, [0.0; 3])]).unwrap(),
            yaw_deg: Track::new(vec![Key::linear(0.0, [0.0])]).unwrap(),
        },
    }];
    let palette = [64, 64];
    let unwrapped = unwrap_islands_avoiding(&scene.vehicle, palette, background_texel(palette)).unwrap();
    let samples = surface_samples(&scene.vehicle, &unwrapped, 1.0, 7, 4);
    let obstacles = Obstacles::new(&scene);
    let (frames, _) = eye_frames(&scene, &scene.scenarios[0], &[0], &obstacles).unwrap();
    for (eye, frame) in frames.iter().enumerate() {
        let seen: f64 = samples
            .samples
            .iter()
            .filter_map(|sample| visible_solid_angle(sample, frame, &obstacles, Tracer::Hierarchy))
            .sum();
        // The exact measure's stated accuracy for a plate (the closed-form test in `unobstructed`).
        assert!((seen - exact).abs() / exact < 1e-4, "eye {eye}: {seen} sr, not {exact}");
    }
    // And the plate's centre is the middle of both images.
    let pose = scene.scenarios[0].motion.pose(0.0);
    for camera in scene.rig.cameras(0.0, &pose) {
        let clip = camera.view_proj * dvec3(0.0, 0.0, eye_height + above).extend(1.0);
        assert!(clip.w > 0.0 && (clip.x / clip.w).abs() < 1e-9 && (clip.y / clip.w).abs() < 1e-9, "{clip}");
        assert!(camera.position.is_finite() && camera.position.distance(DVec3::Z * eye_height) < 1e-12);
    }
}
