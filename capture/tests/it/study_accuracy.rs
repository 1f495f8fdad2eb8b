//! The rendered angular area against known answers: flat plates facing the
//! eyes at known distances, off the optical axis. Their solid angle is
//! analytic; the rendered one (each pixel weighted by the solid angle it
//! subtends in the rectilinear eye) converges to it as pixels per degree
//! grow, the exact measure gives it directly, and the study, comparing the
//! two, recommends by that error.

use glam::{DVec3, dvec3, vec3};
use ufcsr::Dedupe;
use ufcsr_capture::{
    Backend, CaptureOptions, Gpu, MeasureOptions, Mesh, Rig, Scenario, Scene, capture_counted,
    measure_unobstructed, run_study, scene::Key, scene::Motion, scene::Occluders, scene::Track,
    study::StudyMeasure, study::StudyOptions,
};

pub(crate) fn gpu() -> Gpu {
    Gpu::create(Backend::Auto).expect("a Vulkan or GL driver (Mesa's lavapipe or llvmpipe will do)")
}

/// Distance of the plates' plane from the eyes, metres.
const DISTANCE: f64 = 4.0;
/// The plates, `(name, y0, y1, z0, z1)` in the plane x = DISTANCE (world).
pub(crate) const PLATES: [(&str, f64, f64, f64, f64); 2] =
    [("near-axis", -0.6, 0.3, 1.0, 2.2), ("off-axis", 0.6, 1.3, 0.4, 1.2)];

/// Two plates facing the pedestrian 4 m away; the head turns 32° to the
/// right of them (towards y = −2.5 m), so they lie 20°–50° off the axis,
/// where a pixel subtends markedly less than a central one.
pub(crate) fn plates_scene() -> Scene {
    let mut mesh = Mesh::default();
    for (name, y0, y1, z0, z1) in PLATES {
        let (y0, y1, z0, z1) = (y0 as f32, y1 as f32, z0 as f32, z1 as f32);
        mesh.add_quad(name, vec3(0.0, y0, z0), vec3(0.0, y1, z0), vec3(0.0, y1, z1), vec3(0.0, y0, z1));
    }
    let rig = Rig {
        pedestrian: ufcsr_capture::scene::ValueOrTrack::Fixed([0.0, 0.0, 0.0]),
        look_at_vehicle: [0.0, -2.5, 1.75],
        tiles: [2, 2],
        ..Rig::default()
    };
    let position = dvec3(DISTANCE, 0.0, 0.0).to_array();
    let scenario = Scenario {
        name: "still".into(),
        duration_s: 1.0 / 60.0,
        motion: Motion {
            position: Track::new(vec![Key::linear(0.0, position)]).unwrap(),
            yaw_deg: Track::new(vec![Key::linear(0.0, [0.0])]).unwrap(),
        },
    };
    Scene {
        name: "plates".into(),
        vehicle: mesh,
        occluders: Occluders::default(),
        rig,
        scenarios: vec![scenario],
        info: ufcsr::format::SceneRecord { name: "plates".into(), ..Default::default() },
        warnings: Vec::new(),
        input_files: Vec::new(),
        fleet: Vec::new(),
        vehicle_path: None,
    }
}

/// `F(u, v)`: the solid angle of the rectangle `[0, u] × [0, v]` at unit distance.
fn corner(u: f64, v: f64) -> f64 {
    (u * v / (1.0 + u * u + v * v).sqrt()).atan()
}

/// The plate's solid angle summed over both eyes, sr (per frame).
pub(crate) fn analytic_sr(scene: &Scene, (_, y0, y1, z0, z1): (&str, f64, f64, f64, f64)) -> f64 {
    let rig = &scene.rig;
    let pose = scene.scenarios[0].motion.pose(0.0);
    rig.cameras(0.0, &pose)
        .iter()
        .map(|camera| {
            let eye: DVec3 = camera.position;
            let d = DISTANCE - eye.x;
            let (u0, u1) = ((y0 - eye.y) / d, (y1 - eye.y) / d);
            let (v0, v1) = ((z0 - eye.z) / d, (z1 - eye.z) / d);
            (corner(u1, v1) - corner(u0, v1) - corner(u1, v0) + corner(u0, v0)).abs()
        })
        .sum()
}

/// The rendered solid angle per part (both eyes, per frame) at `ppd`.
fn rendered_sr(gpu: &Gpu, scene: &Scene, ppd: f64) -> Vec<f64> {
    let dir = tempfile::tempdir().unwrap();
    let mut scene = scene.clone();
    scene.rig.set_pixels_per_degree(ppd).unwrap();
    let options =
        CaptureOptions { out: dir.path().join("a"), palette: [256, 256], ..CaptureOptions::default() };
    let counted =
        capture_counted(&gpu.device, &gpu.queue, &scene, &scene.scenarios[0], &options, Dedupe::Frame)
            .unwrap();
    let measures = counted.analysis.result.measures.expect("--count keeps the measures");
    let frames = counted.summary.frames as f64;
    PLATES.iter().map(|(name, ..)| measures.part(name).unwrap().solid_angle_sr.unwrap() / frames).collect()
}

#[test]
fn a_plate_facing_the_eye_renders_its_analytic_solid_angle_as_ppd_grows() {
    let gpu = gpu();
    let scene = plates_scene();
    let exact: Vec<f64> = PLATES.iter().map(|&plate| analytic_sr(&scene, plate)).collect();
    let ppds = [2.0, 4.0, 8.0, 16.0];
    let mut errors = Vec::new();
    for ppd in ppds {
        let rendered = rendered_sr(&gpu, &scene, ppd);
        let error: Vec<f64> = rendered.iter().zip(&exact).map(|(r, e)| (r / e - 1.0).abs()).collect();
        eprintln!("{ppd} px/°: relative error {error:?}");
        errors.push(error);
    }
    for (error, ppd) in errors.iter().zip(ppds) {
        // The outline band: relative error below 0.1 / ppd for these plates.
        for e in error {
            assert!(*e < 0.1 / ppd, "{ppd} px/°: relative error {e}");
        }
    }
    // 16 px/°: within 0.5 %.
    assert!(errors[3].iter().all(|e| *e < 5e-3), "{:?}", errors[3]);
}

#[test]
fn the_exact_measure_gives_a_plates_analytic_solid_angle() {
    let gpu = gpu();
    let scene = plates_scene();
    let dir = tempfile::tempdir().unwrap();
    let options =
        CaptureOptions { out: dir.path().join("exact"), palette: [256, 256], ..CaptureOptions::default() };
    let measured = measure_unobstructed(
        &gpu.device,
        &gpu.queue,
        &scene,
        &scene.scenarios[0],
        &options,
        &MeasureOptions::default(),
    )
    .unwrap();
    let frames = measured.frames.len() as f64;
    for plate in PLATES {
        let estimate = measured.estimates.iter().find(|e| e.part == plate.0).unwrap();
        let (got, want) = (estimate.estimated_solid_angle_sr / frames, analytic_sr(&scene, plate));
        // Midpoint rule over texels of a few cm: a relative error far below the rendered one.
        assert!((got / want - 1.0).abs() < 1e-3, "{}: {got} sr against {want} sr", plate.0);
    }
}

#[test]
fn the_study_of_the_plates_recommends_by_the_error_against_the_exact_solid_angle() {
    let gpu = gpu();
    let scene = plates_scene();
    let dir = tempfile::tempdir().unwrap();
    let options = StudyOptions {
        scenario: "still".into(),
        ppds: vec![2.0, 12.0],
        frame_steps: vec![1],
        tolerance_pp: 0.5,
        dedupe: Dedupe::Frame,
        measure: StudyMeasure::AngularArea,
        capture: CaptureOptions {
            out: dir.path().to_path_buf(),
            palette: [256, 256],
            ..CaptureOptions::default()
        },
        exact_sample: Some(1.0),
    };
    let study = run_study(&gpu.device, &gpu.queue, &scene, &options).unwrap();
    let error = |ppd: f64| {
        let row = study.rows.iter().find(|r| r.ppd == ppd).unwrap();
        row.error_vs_exact.as_ref().unwrap().error.share_l1_pp
    };
    eprintln!("share L1 vs exact: 2 px/° {:.4} pp, 12 px/° {:.4} pp", error(2.0), error(12.0));
    assert!(error(12.0) < error(2.0), "finer is closer to the exact solid angle");
    assert!(error(12.0) < 0.5);
    // One frame step: nothing to resample, the interval is the point.
    let row = &study.rows[0];
    let exact = row.error_vs_exact.as_ref().unwrap();
    assert_eq!(exact.ci95_pp, [exact.error.share_l1_pp; 2]);
    assert_eq!(exact.measure, "angular-area");
    // Recommended: within 0.5 pp of the exact measure.
    let recommended = study.recommended.as_ref().expect("a setting within tolerance");
    assert_eq!(recommended.against, "exact");
    assert!(recommended.share_l1_pp <= 0.5);
    // The precision of the finest setting against itself is 0, whatever the truth.
    assert_eq!(row.precision.share_l1_pp, 0.0);
}
