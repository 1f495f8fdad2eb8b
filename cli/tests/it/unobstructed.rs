//! The exact "unobstructed" measure, with known answers: the BVH answers
//! exactly as brute force; every sample lies in its triangle; the solid angle
//! of a square plate converges to the closed form as K grows and is 0 behind
//! a box; edge-on (eye in the hood's f32 plane), the near plane, a scene
//! 10 km from the origin and a vehicle ×0.01 / ×100 give the known answers;
//! the count converges in K; the CLI writes the measures block.

use std::process::Command;

use glam::{DMat4, DVec3, Vec3, dvec3};
use ufcsr_capture::{
    EyeFrame, Mesh, Obstacles, Scene, SurfaceSamples, TexelVisibility, Tracer, background_texel, eye_frame,
    eye_frames, scene::Occluders, scene::ValueOrTrack, scene::look_to, scene::reversed_z_perspective,
    surface_samples, texel_visibility, unwrap_islands_avoiding, visible_solid_angle,
};

const PALETTE: [u32; 2] = [256, 256];

fn samples_of(mesh: &Mesh, palette: [u32; 2], fraction: f64, k: u32) -> SurfaceSamples {
    let unwrapped = unwrap_islands_avoiding(mesh, palette, background_texel(palette)).unwrap();
    surface_samples(mesh, &unwrapped, fraction, 7, k)
}

fn measure(scene: &Scene, scenario: &str, frames: &[u32], samples: &SurfaceSamples) -> TexelVisibility {
    let obstacles = Obstacles::new(scene);
    let (eye_frames, _) = eye_frames(scene, scene.scenario(scenario).unwrap(), frames, &obstacles).unwrap();
    texel_visibility(samples, &eye_frames, &obstacles, scene.vehicle.parts.len(), Tracer::Hierarchy)
}

/// Per part: the count summed over the sampled texels, as shares in percent.
fn shares(scene: &Scene, samples: &SurfaceSamples, visibility: &TexelVisibility) -> Vec<f64> {
    let mut totals = vec![0.0; scene.vehicle.parts.len()];
    for (texel, &count) in samples.texels.iter().zip(&visibility.counts) {
        totals[texel.part as usize] += f64::from(count);
    }
    let sum: f64 = totals.iter().sum();
    totals.iter().map(|t| 100.0 * t / sum.max(1.0)).collect()
}

fn l1(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| (x - y).abs()).sum()
}

#[test]
fn the_hierarchy_answers_exactly_as_brute_force_on_sampled_points() {
    let scene = Scene::demo();
    let scenario = scene.scenario("A").unwrap();
    let samples = samples_of(&scene.vehicle, PALETTE, 0.05, 2);
    assert!(samples.samples.len() > 500, "{}", samples.samples.len());
    let obstacles = Obstacles::new(&scene);
    let (frames, _) = eye_frames(&scene, scenario, &[60, 120, 180], &obstacles).unwrap();
    let mut seen = 0;
    for frame in &frames {
        for sample in &samples.samples {
            let fast = visible_solid_angle(sample, frame, &obstacles, Tracer::Hierarchy);
            assert_eq!(fast, visible_solid_angle(sample, frame, &obstacles, Tracer::BruteForce));
            seen += usize::from(fast.is_some());
        }
    }
    assert!(seen > 100, "only {seen} sample-frames visible");
}

#[test]
fn the_occluder_memory_changes_no_answer_texel_for_texel() {
    // The CPU loop tries each sample's last blocker (and its neighbour's)
    // before the hierarchy; sample by sample by brute force, without any
    // memory, must give the same count and the same solid angle bit for bit.
    let scene = Scene::demo();
    let scenario = scene.scenario("A").unwrap();
    let samples = samples_of(&scene.vehicle, PALETTE, 0.05, 2);
    let obstacles = Obstacles::new(&scene);
    let (frames, _) = eye_frames(&scene, scenario, &[0, 30, 31, 32, 90, 91, 150, 180], &obstacles).unwrap();
    let remembered =
        texel_visibility(&samples, &frames, &obstacles, scene.vehicle.parts.len(), Tracer::Hierarchy);
    let (mut hidden, mut visible) = (0, 0);
    for (slot, texel) in samples.texels.iter().enumerate() {
        let (mut count, mut solid_angle_sr) = (0, 0.0);
        for frame in &frames {
            let mut seen = false;
            for sample in samples.of(texel) {
                match visible_solid_angle(sample, frame, &obstacles, Tracer::BruteForce) {
                    Some(solid_angle) => {
                        (seen, solid_angle_sr, visible) = (true, solid_angle_sr + solid_angle, visible + 1)
                    }
                    None => hidden += 1,
                }
            }
            count += u32::from(seen);
        }
        assert_eq!(remembered.counts[slot], count, "texel {}", texel.texel);
        assert_eq!(remembered.solid_angle_sr[slot], solid_angle_sr, "texel {}", texel.texel);
    }
    assert!(hidden > 1000 && visible > 1000, "{hidden} hidden, {visible} visible sample-eye-frames");
}

#[test]
fn every_sample_lies_inside_its_own_triangle_and_the_areas_add_up() {
    let scene = Scene::demo();
    for k in [1, 3] {
        let samples = samples_of(&scene.vehicle, PALETTE, 1.0, k);
        for sample in &samples.samples {
            let [a, b, c] = scene.vehicle.corners(sample.triangle as usize).map(|v| v.as_dvec3());
            let p = sample.position;
            let n = (b - a).cross(c - a);
            assert!((p - a).dot(n.normalize()).abs() < 1e-6, "a sample is off its plane");
            let w = [(b - p).cross(c - p).dot(n), (c - p).cross(a - p).dot(n), (a - p).cross(b - p).dot(n)];
            assert!(w.iter().all(|&w| w >= 0.0), "a sample lies outside its triangle: {w:?}");
        }
        // The pieces tile every triangle: their areas add up to the mesh's.
        let area: f64 = samples.area_per_part_m2.iter().sum();
        assert!(
            (area - scene.vehicle.area()).abs() < 1e-6 * area,
            "K = {k}: {area} against {}",
            scene.vehicle.area()
        );
    }
}

/// A square plate of side `side` in the plane x = 0 (part "plate"), centred on (0, 0, `height`).
fn plate(side: f32, height: f32) -> Mesh {
    let h = side / 2.0;
    let mut mesh = Mesh::default();
    let corner = |y: f32, z: f32| Vec3::new(0.0, y, height + z);
    mesh.add_quad("plate", corner(-h, -h), corner(h, -h), corner(h, h), corner(-h, h));
    mesh
}

/// The demo scene with `vehicle` at the origin, no occluders unless given.
fn scene_with(vehicle: Mesh, occluders: Occluders) -> Scene {
    let mut scene = Scene::demo();
    scene.vehicle = vehicle;
    scene.occluders = occluders;
    scene.rig.pedestrian = ValueOrTrack::Fixed([0.0, 0.0, 0.0]);
    scene
}

/// An eye at `eye` looking along `direction` (the vehicle at the origin, unrotated).
fn eye_looking(obstacles: &Obstacles, eye: DVec3, direction: DVec3) -> EyeFrame {
    let view_proj =
        reversed_z_perspective(60f64.to_radians(), 1.0, 0.3, 1000.0) * look_to(eye, direction, DVec3::Z);
    eye_frame(obstacles, &DMat4::IDENTITY, &[], eye, &view_proj)
}

fn solid_angle(samples: &SurfaceSamples, frame: &EyeFrame, obstacles: &Obstacles) -> f64 {
    samples.samples.iter().filter_map(|s| visible_solid_angle(s, frame, obstacles, Tracer::Hierarchy)).sum()
}

#[test]
fn a_square_plates_solid_angle_converges_to_the_closed_form_and_is_zero_behind_a_box() {
    let (side, distance) = (1.0f64, 1.5f64);
    let exact = 4.0 * (side * side / (4.0 * distance * distance + side * side)).asin();
    let scene = scene_with(plate(side as f32, 2.0), Occluders::default());
    let obstacles = Obstacles::new(&scene);
    let frame = eye_looking(&obstacles, dvec3(distance, 0.0, 2.0), -DVec3::X);
    // A coarse palette (the plate is ~10 texels across), so K matters.
    let errors: Vec<f64> = [1, 2, 4, 8]
        .iter()
        .map(|&k| {
            (solid_angle(&samples_of(&scene.vehicle, [16, 16], 1.0, k), &frame, &obstacles) - exact).abs()
                / exact
        })
        .collect();
    assert!(errors.windows(2).all(|pair| pair[1] < pair[0]), "errors do not shrink with K: {errors:?}");
    assert!(errors[3] < 1e-4, "{errors:?}");
    // A box between the eye and the plate hides all of it.
    let mut occluders = Occluders::default();
    occluders.add_box(dvec3(0.5, -1.0, 1.0), dvec3(0.7, 1.0, 3.0));
    let hidden = scene_with(plate(side as f32, 2.0), occluders);
    let obstacles = Obstacles::new(&hidden);
    let frame = eye_looking(&obstacles, dvec3(distance, 0.0, 2.0), -DVec3::X);
    assert_eq!(solid_angle(&samples_of(&hidden.vehicle, [16, 16], 1.0, 2), &frame, &obstacles), 0.0);
}

#[test]
fn the_near_plane_clips_points_and_the_geometry_in_front_of_it() {
    let scene = scene_with(plate(0.1, 2.0), Occluders::default());
    let samples = samples_of(&scene.vehicle, [32, 32], 1.0, 1);
    let seen_from = |scene: &Scene, distance: f64| {
        let obstacles = Obstacles::new(scene);
        solid_angle(&samples, &eye_looking(&obstacles, dvec3(distance, 0.0, 2.0), -DVec3::X), &obstacles)
    };
    // Nearer than the 0.3 m near plane: not visible; beyond it: visible.
    assert_eq!(seen_from(&scene, 0.25), 0.0);
    assert!(seen_from(&scene, 0.35) > 0.0);
    // A wall 0.2 m in front of the eye is clipped by the renderer: it hides nothing.
    let wall = |at: f64| {
        let mut occluders = Occluders::default();
        occluders.add_box(dvec3(at - 0.01, -1.0, 1.0), dvec3(at + 0.01, 1.0, 3.0));
        scene_with(plate(0.1, 2.0), occluders)
    };
    assert!(seen_from(&wall(0.8), 1.0) > 0.0);
    assert_eq!(seen_from(&wall(0.5), 1.0), 0.0);
}

#[test]
fn the_eye_in_the_hoods_f32_plane_sees_it_edge_on() {
    // The demo hood's top is at 1.15 m, which f32 cannot hold exactly.
    let mut scene = Scene::demo();
    let hood = scene.vehicle.parts.iter().position(|p| p == "hood").unwrap() as u32;
    let samples = samples_of(&scene.vehicle, PALETTE, 1.0, 1);
    let frames: Vec<u32> = (0..=180).step_by(30).collect();
    for eye_height in [1.15, 1.15 + 1e-6] {
        scene.rig.eye_height_m = eye_height;
        for scenario in ["A", "B"] {
            let visibility = measure(&scene, scenario, &frames, &samples);
            let hood_count: u32 = samples
                .texels
                .iter()
                .zip(&visibility.counts)
                .filter(|(t, _)| t.part == hood)
                .map(|(_, &c)| c)
                .sum();
            assert_eq!(hood_count, 0, "eye at {eye_height} m, scenario {scenario}");
            assert!(visibility.counts.iter().sum::<u32>() > 1000);
        }
    }
}

#[test]
fn a_scene_far_from_the_origin_measures_the_same_texel_for_texel() {
    let scene = Scene::demo();
    let samples = samples_of(&scene.vehicle, PALETTE, 1.0, 1);
    let frames: Vec<u32> = (0..181).step_by(15).collect();
    let near = measure(&scene, "A", &frames, &samples);
    // Everything 10 km along x and y: pedestrian, vehicle track and occluders.
    let mut far = scene.clone();
    far.rig.pedestrian = ValueOrTrack::Fixed((far.rig.anchor() + dvec3(10_000.0, 10_000.0, 0.0)).to_array());
    for position in &mut far.occluders.positions {
        position.x += 10_000.0;
        position.y += 10_000.0;
    }
    for scenario in &mut far.scenarios {
        for key in &mut scenario.motion.position.keys {
            key.value[0] += 10_000.0;
            key.value[1] += 10_000.0;
        }
    }
    let far = measure(&far, "A", &frames, &samples);
    let differing = near.counts.iter().zip(&far.counts).filter(|(a, b)| a != b).count();
    assert_eq!(differing, 0, "{differing} of {} texels differ", samples.texels.len());
    assert_eq!(near.part_seen, far.part_seen);
    let solid = |v: &TexelVisibility| v.solid_angle_sr.iter().sum::<f64>();
    assert!((solid(&near) - solid(&far)).abs() < 1e-9 * solid(&near));
    assert!(near.counts.iter().sum::<u32>() > 1000);
}

/// `scene` scaled by `factor` about the pedestrian's feet (vehicle, occluders, eyes, tracks).
fn scaled(scene: &Scene, factor: f64) -> Scene {
    let mut out = scene.clone();
    let anchor = scene.rig.anchor() * dvec3(1.0, 1.0, 0.0);
    for position in &mut out.vehicle.positions {
        *position *= factor as f32;
    }
    for position in &mut out.occluders.positions {
        *position = anchor + (*position - anchor) * factor;
    }
    out.rig.eye_height_m *= factor;
    out.rig.ipd_m *= factor;
    out.rig.near_m *= factor;
    out.rig.far_m *= factor;
    for value in &mut out.rig.look_at_vehicle {
        *value *= factor;
    }
    for scenario in &mut out.scenarios {
        for key in &mut scenario.motion.position.keys {
            for axis in 0..2 {
                key.value[axis] = anchor[axis] + (key.value[axis] - anchor[axis]) * factor;
            }
            key.value[2] *= factor;
            for slope in [&mut key.in_slope, &mut key.out_slope].into_iter().flatten() {
                *slope = slope.map(|v| v * factor);
            }
        }
    }
    out
}

#[test]
fn a_vehicle_scaled_by_a_hundredth_or_a_hundred_gives_the_same_shares() {
    let scene = Scene::demo();
    let frames: Vec<u32> = (0..181).step_by(30).collect();
    // One unwrap for all three, so that the same texels are sampled.
    let unwrapped = unwrap_islands_avoiding(&scene.vehicle, PALETTE, background_texel(PALETTE)).unwrap();
    let reference = {
        let samples = surface_samples(&scene.vehicle, &unwrapped, 1.0, 7, 1);
        shares(&scene, &samples, &measure(&scene, "B", &frames, &samples))
    };
    for factor in [0.01, 100.0] {
        let scene = scaled(&Scene::demo(), factor);
        let samples = surface_samples(&scene.vehicle, &unwrapped, 1.0, 7, 1);
        let shares = shares(&scene, &samples, &measure(&scene, "B", &frames, &samples));
        let difference = l1(&shares, &reference);
        assert!(difference < 0.01, "×{factor}: shares differ by {difference} pp (L1)");
    }
}

#[test]
fn the_any_part_count_converges_in_k() {
    // Shares at K = 1, 2, 4 against K = 8: the L1 difference shrinks.
    let scene = Scene::demo();
    // Scenario A: the truck comes out from behind the corner building, so
    // texels are partly hidden in many frames.
    let frames: Vec<u32> = (30..121).step_by(10).collect();
    let shares_at = |k: u32| {
        let samples = samples_of(&scene.vehicle, PALETTE, 1.0, k);
        shares(&scene, &samples, &measure(&scene, "A", &frames, &samples))
    };
    let finest = shares_at(8);
    let differences: Vec<f64> = [1, 2, 4].iter().map(|&k| l1(&shares_at(k), &finest)).collect();
    eprintln!("share L1 against K = 8 at K = 1, 2, 4: {differences:?} pp");
    assert!(differences.windows(2).all(|pair| pair[1] < pair[0]), "{differences:?}");
}

#[test]
fn a_vehicle_hidden_behind_a_building_is_never_counted() {
    // Scenario A starts with the truck behind the corner building (frame 0).
    let scene = Scene::demo();
    let samples = samples_of(&scene.vehicle, PALETTE, 0.2, 2);
    let visibility = measure(&scene, "A", &[0], &samples);
    assert_eq!(visibility.counts.iter().sum::<u32>(), 0);
    assert_eq!(visibility.solid_angle_sr.iter().sum::<f64>(), 0.0);
}

#[test]
fn the_cli_writes_an_unobstructed_result_with_the_measures_block() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("archive");
    let status = Command::new(env!("CARGO_BIN_EXE_ufcsr-capture"))
        .args(["demo", "--scenario", "A", "--palette-size", "256", "--frames", "120-180/20"])
        .args(["--measure", "unobstructed", "--sample", "1/4", "--texel-samples", "2", "-q", "--out"])
        .arg(&out)
        .stdout(std::process::Stdio::null())
        .status()
        .unwrap();
    assert!(status.success());
    let result: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("results/result.json")).unwrap()).unwrap();
    assert_eq!(result["measure"], "unobstructed");
    assert!(result["grand_total"].as_u64().unwrap() > 0);
    let measures = &result["measures"];
    // 20 frames at 60 fps: each eye-frame stands for 1/3 s.
    assert!((measures["seconds_per_frame"].as_f64().unwrap() - 1.0 / 3.0).abs() < 1e-12);
    let parts = measures["parts"].as_array().unwrap();
    let area: f64 = parts.iter().map(|p| p["angular_area_deg2_s"].as_f64().unwrap()).sum();
    let exposure = parts.iter().map(|p| p["exposure_s"].as_f64().unwrap()).fold(0.0, f64::max);
    assert!(area > 0.0);
    // Four frames of 1/3 s: no part is seen for longer than 4/3 s.
    assert!(exposure > 0.0 && exposure <= 4.0 / 3.0 + 1e-12, "{exposure}");
    let warnings = result["warnings"].as_array().unwrap();
    assert!(!warnings.iter().any(|w| w.as_str().unwrap().contains("unevenly")), "{warnings:?}");
    let csv = std::fs::read_to_string(out.join("results/unobstructed-parts.csv")).unwrap();
    assert!(csv.starts_with("part,texels,sampled,sampled_total,estimated_total,standard_error,"), "{csv}");
    assert!(!out.join("tiles").read_dir().is_ok_and(|mut d| d.next().is_some()), "no tiles are written");
}

#[test]
fn the_cli_measures_placements_that_the_analyzer_ranks() {
    // Scenario A, every part and 0.40 m × 0.15 m display patches (spaced 0.5 m so the test is
    // small); the table must be what `ufcsr placement` reads.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("archive");
    let status = Command::new(env!("CARGO_BIN_EXE_ufcsr-capture"))
        .args(["demo", "--scenario", "A", "--palette-size", "256", "--frames", "120-180/20"])
        .args(["--measure", "unobstructed", "--sample", "1/2", "--placement", "--display", "0.40x0.15"])
        .args(["--patch-spacing", "0.5", "-q", "--out"])
        .arg(&out)
        .stdout(std::process::Stdio::null())
        .status()
        .unwrap();
    assert!(status.success());
    let table =
        std::fs::read_to_string(out.join("results").join(ufcsr_capture::PLACEMENT_FRAMES_FILE)).unwrap();
    let header = table.lines().next().unwrap();
    assert_eq!(
        header,
        "frame,time_s,eye,distance_m,candidate,kind,solid_angle_sr,visible_fraction,view_angle_deg,\
         angular_height_deg,frame_s,mirror"
    );
    let parts = Scene::demo().vehicle.parts.len();
    let part_rows = table.lines().filter(|line| line.contains(",part,")).count();
    // Every part in every eye-frame: 4 frames × 2 eyes.
    assert_eq!(part_rows, parts * 8);
    assert!(table.lines().any(|line| line.contains(",patch,")), "some patch is visible");
    // Every patch the frames name has its footprint: 0.40 m × 0.15 m, unit normal and height axis.
    let footprints =
        std::fs::read_to_string(out.join("results").join(ufcsr_capture::PLACEMENT_PATCHES_FILE)).unwrap();
    let mut lines = footprints.lines();
    assert_eq!(lines.next().unwrap(), ufcsr_capture::PLACEMENT_PATCHES_COLUMNS.join(","));
    let rows: Vec<Vec<&str>> = lines.map(|line| line.split(',').collect()).collect();
    for row in &rows {
        let number = |i: usize| row[i].parse::<f64>().unwrap();
        let length = |i: usize| (number(i).powi(2) + number(i + 1).powi(2) + number(i + 2).powi(2)).sqrt();
        assert!((length(4) - 1.0).abs() < 1e-9 && (length(7) - 1.0).abs() < 1e-9, "{row:?}");
        assert_eq!((number(10), number(11)), (0.40, 0.15));
    }
    for line in table.lines().filter(|line| line.contains(",patch,")) {
        let name = line.split(',').nth(4).unwrap();
        assert!(rows.iter().any(|row| row[0] == name), "{name} has no footprint");
    }
    let placement = ufcsr::placement(&ufcsr::PlacementOptions::new(vec![out.clone()])).unwrap();
    let document = &placement.document;
    assert!(document.candidates.len() > parts, "parts and patches are candidates");
    assert!(
        document.combinations.iter().any(|c| c.kind == ufcsr::placement::CandidateKind::Part && c.k == 1)
    );
    assert!(
        document.combinations.iter().any(|c| c.kind == ufcsr::placement::CandidateKind::Patch && c.k == 1)
    );
    // Names carry the display size.
    assert!(
        document
            .candidates
            .iter()
            .filter(|c| c.kind == ufcsr::placement::CandidateKind::Patch)
            .all(|c| c.name.contains("@0.40x0.15@x"))
    );
    // Each patch names the parts it covers, its own among them, and is mountable under a list
    // exactly when every one of them is.
    let footprints =
        ufcsr::placement::read_footprints(&out.join("results").join(ufcsr_capture::PLACEMENT_FRAMES_FILE))
            .unwrap();
    let mut list = ufcsr::placement::default_not_mountable();
    list.push("bumper".into());
    let options =
        ufcsr::PlacementOptions { not_mountable: list.clone(), ..ufcsr::PlacementOptions::new(vec![out]) };
    let listed = ufcsr::placement(&options).unwrap().document;
    let patches: Vec<_> =
        listed.candidates.iter().filter(|c| c.kind == ufcsr::placement::CandidateKind::Patch).collect();
    assert!(patches.iter().any(|c| !c.mountable) && patches.iter().any(|c| c.mountable));
    for candidate in patches {
        let covers = &footprints[&candidate.name].covers;
        assert!(covers.iter().any(|p| candidate.name.starts_with(&format!("{p}@"))), "{covers:?}");
        let all = covers.iter().all(|p| ufcsr::placement::mountable(p, &list));
        assert_eq!(candidate.mountable, all, "{} covers {covers:?}", candidate.name);
    }
}

#[test]
fn placement_options_are_checked_before_any_ray_is_cast() {
    let dir = tempfile::tempdir().unwrap();
    for (args, message) in [
        (&["--placement", "--display", "0.4"][..], "expected WxH"),
        (&["--placement", "--display", "0x0.15"][..], "more than 0"),
        (&["--placement", "--display", "0.4x0.15", "--patch-spacing", "0.001"][..], "at least 0.01"),
    ] {
        let output = Command::new(env!("CARGO_BIN_EXE_ufcsr-capture"))
            .args(["demo", "--scenario", "A", "--palette-size", "256", "--frames", "120"])
            .args(["--measure", "unobstructed", "--sample", "1/4", "-q"])
            .args(args)
            .arg("--out")
            .arg(dir.path().join("archive"))
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(!output.status.success() && stderr.contains(message), "{args:?}: {stderr}");
    }
}

/// The warnings of the `results/result.json` a capture with `args` writes.
fn capture_warnings(dir: &std::path::Path, args: &[&str]) -> Vec<String> {
    let out = dir.join(args.join("_").replace(['/', ' '], "-"));
    let status = Command::new(env!("CARGO_BIN_EXE_ufcsr-capture"))
        .args(["demo", "--scenario", "A", "--palette-size", "256", "-q", "--out"])
        .arg(&out)
        .args(args)
        .stdout(std::process::Stdio::null())
        .status()
        .unwrap();
    assert!(status.success(), "{args:?}");
    let result: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("results/result.json")).unwrap()).unwrap();
    result["warnings"].as_array().unwrap().iter().map(|w| w.as_str().unwrap().to_string()).collect()
}

/// Frames 120, 130, 140, 160 and 180: both clocks count each as the smallest gap (10 frames,
/// 1/6 s), so their time totals are short of what the 20-frame gaps stand for, and both results
/// say so in the same words.
#[test]
fn unevenly_spaced_frames_are_warned_about_in_the_exact_and_the_rendered_result() {
    let dir = tempfile::tempdir().unwrap();
    let frames = ["--frames", "120-180/20,130"];
    let exact = capture_warnings(
        dir.path(),
        &[&frames[..], &["--measure", "unobstructed", "--sample", "1/4"]].concat(),
    );
    let rendered = capture_warnings(dir.path(), &[&frames[..], &["--count", "--ppd", "3"]].concat());
    let uneven = |warnings: &[String]| {
        warnings.iter().find(|w| w.contains("unevenly spaced (10 to 20 frames apart)")).cloned()
    };
    let said = uneven(&exact).unwrap_or_else(|| panic!("{exact:?}"));
    assert!(said.contains("the 5 frames stand for 0.833 s of the 1.000 s"), "{said}");
    assert_eq!(uneven(&rendered).as_ref(), Some(&said), "{rendered:?}");
}
