//! The exact "unobstructed" measure: the BVH answers exactly as brute force
//! on every sampled point and eye-frame, a scene 10 km from the origin gives
//! the same counts as at the origin, a vehicle hidden behind a building is
//! never counted, the CLI writes a result with `measure: "unobstructed"`, and
//! the GPU version (f64 compute) counts exactly as the CPU on every point.

use std::process::Command;

use ufcsr_capture::scene::Scene;
use ufcsr_capture::unobstructed::{Obstacles, count_unobstructed, eye_frames, surface_points, unobstructed};
use ufcsr_capture::unwrap::{background_texel, unwrap_islands_avoiding};

const PALETTE: [u32; 2] = [256, 256];

fn demo_points(scene: &Scene, fraction: f64) -> Vec<ufcsr_capture::unobstructed::SurfacePoint> {
    let unwrapped = unwrap_islands_avoiding(&scene.vehicle, PALETTE, background_texel(PALETTE)).unwrap();
    surface_points(scene, &unwrapped, fraction, 7).0
}

#[test]
fn the_hierarchy_answers_exactly_as_brute_force_on_sampled_points() {
    let scene = Scene::demo();
    let scenario = scene.scenario("A").unwrap();
    let points = demo_points(&scene, 0.1);
    assert!(points.len() > 500, "{}", points.len());
    let (frames, _) = eye_frames(&scene, scenario, &[60, 120, 180]);
    let obstacles = Obstacles::new(&scene);
    let mut seen = 0;
    for frame in &frames {
        for point in &points {
            let fast = unobstructed(point, frame, &obstacles, false);
            assert_eq!(fast, unobstructed(point, frame, &obstacles, true), "texel {}", point.texel);
            seen += usize::from(fast);
        }
    }
    assert!(seen > 100, "only {seen} point-frames unobstructed");
}

#[test]
fn every_point_lies_inside_its_own_triangle() {
    let scene = Scene::demo();
    let points = demo_points(&scene, 0.2);
    for point in &points {
        let [a, b, c] = scene.vehicle.corners(point.triangle).map(|v| v.as_dvec3());
        let p = point.position;
        let n = (b - a).cross(c - a);
        assert!((p - a).dot(n.normalize()).abs() < 1e-6, "texel {} is off its plane", point.texel);
        // Barycentric weights from sub-triangle areas: all positive inside.
        let w = [(b - p).cross(c - p).dot(n), (c - p).cross(a - p).dot(n), (a - p).cross(b - p).dot(n)];
        assert!(w.iter().all(|&w| w > 0.0), "texel {} lies outside its triangle: {w:?}", point.texel);
    }
}

#[test]
fn a_scene_far_from_the_origin_counts_the_same() {
    let scene = Scene::demo();
    let scenario = scene.scenario("A").unwrap().clone();
    let points = demo_points(&scene, 0.05);
    let frames: Vec<u32> = (0..181).step_by(30).collect();
    let near = {
        let (eye_frames, _) = eye_frames(&scene, &scenario, &frames);
        count_unobstructed(&points, &eye_frames, &Obstacles::new(&scene))
    };
    // Everything 10 km along x: pedestrian, vehicle track and occluders.
    let mut far_scene = scene.clone();
    far_scene.rig.pedestrian[0] += 10_000.0;
    for position in &mut far_scene.occluders.positions {
        position.x += 10_000.0;
    }
    let mut far_scenario = scenario.clone();
    for key in &mut far_scenario.motion.position.keys {
        key.value[0] += 10_000.0;
    }
    let (eye_frames, _) = eye_frames(&far_scene, &far_scenario, &frames);
    let far = count_unobstructed(&points, &eye_frames, &Obstacles::new(&far_scene));
    let differing = near.iter().zip(&far).filter(|(a, b)| a != b).count();
    // Occluders are f64 in the world frame: nothing moves, nothing flips.
    assert_eq!(differing, 0, "{differing} of {} points differ", points.len());
    assert!(near.iter().sum::<u32>() > 0);
}

#[test]
fn a_vehicle_hidden_behind_a_building_is_never_counted() {
    // Scenario A starts with the truck behind the corner building (frame 0).
    let scene = Scene::demo();
    let scenario = scene.scenario("A").unwrap();
    let points = demo_points(&scene, 0.2);
    let (frames, _) = eye_frames(&scene, scenario, &[0]);
    let counts = count_unobstructed(&points, &frames, &Obstacles::new(&scene));
    assert_eq!(counts.iter().sum::<u32>(), 0);
}

#[test]
fn the_cli_writes_an_unobstructed_result() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("archive");
    let status = Command::new(env!("CARGO_BIN_EXE_ufcsr-capture"))
        .args(["demo", "--scenario", "A", "--palette-size", "256", "--frames", "120-180/20"])
        .args(["--measure", "unobstructed", "--sample", "1/4", "-q", "--out"])
        .arg(&out)
        .stdout(std::process::Stdio::null())
        .status()
        .unwrap();
    assert!(status.success());
    let result: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("results/result.json")).unwrap()).unwrap();
    assert_eq!(result["measure"], "unobstructed");
    assert!(result["grand_total"].as_u64().unwrap() > 0);
    let csv = std::fs::read_to_string(out.join("results/unobstructed-parts.csv")).unwrap();
    assert!(csv.starts_with("part,texels,sampled,sampled_total,estimated_total,standard_error"), "{csv}");
    assert!(!out.join("tiles").read_dir().is_ok_and(|mut d| d.next().is_some()), "no tiles are written");
}

#[test]
fn the_gpu_measure_equals_the_cpu_measure_on_every_sampled_point() {
    let gpu = ufcsr_capture::gpu::Gpu::create(ufcsr_capture::gpu::Backend::Auto).expect("a GPU or lavapipe");
    if !gpu.device.features().contains(wgpu::Features::SHADER_F64) {
        assert!(std::env::var_os("CI").is_none(), "CI: lavapipe has SHADER_F64; this adapter does not");
        eprintln!("SKIPPED: {} has no SHADER_F64", gpu.describe());
        return;
    }
    let scene = Scene::demo();
    let obstacles = Obstacles::new(&scene);
    let points = demo_points(&scene, 0.1);
    // Scenario A: the truck comes out from behind the corner building, so
    // the scene's occluders decide many of these.
    let scenario = scene.scenario("A").unwrap();
    let (frames, _) = eye_frames(&scene, scenario, &[0, 30, 60, 90, 120, 150, 180]);
    let cpu = count_unobstructed(&points, &frames, &obstacles);
    let on_gpu = ufcsr_capture::unobstructed_gpu::count_unobstructed_gpu(
        &gpu.device,
        &gpu.queue,
        &points,
        &frames,
        &obstacles,
    )
    .unwrap();
    let differing: Vec<usize> = (0..points.len()).filter(|&i| cpu[i] != on_gpu[i]).collect();
    assert!(
        differing.is_empty(),
        "{} of {} points differ, e.g. texel {}: cpu {} gpu {}",
        differing.len(),
        points.len(),
        points[differing[0]].texel,
        cpu[differing[0]],
        on_gpu[differing[0]]
    );
    let total: u32 = cpu.iter().sum();
    assert!(total > 1000 && total < points.len() as u32 * frames.len() as u32, "{total}");
}

#[test]
fn measuring_on_the_gpu_writes_the_cpu_result() {
    let dir = tempfile::tempdir().unwrap();
    let run = |on: &str| {
        let out = dir.path().join(on);
        let output = Command::new(env!("CARGO_BIN_EXE_ufcsr-capture"))
            .args(["demo", "--scenario", "B", "--palette-size", "256", "--frames", "0-180/30"])
            .args(["--measure", "unobstructed", "--sample", "1/3", "--measure-on", on, "-q", "--out"])
            .arg(&out)
            .output()
            .unwrap();
        assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
        let mut result: serde_json::Value =
            serde_json::from_slice(&std::fs::read(out.join("results/result.json")).unwrap()).unwrap();
        // Only the paths and the note naming the device may differ.
        for field in ["archive", "pidt", "parts"] {
            result["settings"][field] = serde_json::Value::Null;
        }
        let notes = result["notes"]
            .as_array()
            .unwrap()
            .iter()
            .map(|n| n.as_str().unwrap().to_owned())
            .collect::<Vec<_>>();
        assert!(notes.iter().any(|n| n.contains(if on == "gpu" {
            "computed on the GPU"
        } else {
            "computed on the CPU"
        })));
        result["notes"] = serde_json::Value::Null;
        result
    };
    let cpu = run("cpu");
    if !ufcsr_capture::gpu::Gpu::create(ufcsr_capture::gpu::Backend::Auto)
        .is_ok_and(|g| g.device.features().contains(wgpu::Features::SHADER_F64))
    {
        assert!(std::env::var_os("CI").is_none(), "CI: lavapipe has SHADER_F64; this adapter does not");
        eprintln!("SKIPPED: no SHADER_F64 on this adapter");
        return;
    }
    assert_eq!(cpu, run("gpu"));
    assert!(cpu["grand_total"].as_u64().unwrap() > 0);
}
