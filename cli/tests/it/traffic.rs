//! Moving occluders and a walking pedestrian, with known answers: a box
//! driving across the line of sight hides the demo truck in exactly the
//! frames it covers it, for the renderer (with and without culling, scissor
//! and the occlusion query) and the exact measure alike; a `follow`
//! occluder stands where the vehicle frame says, in the manifest; a walking
//! pedestrian's eyes in the manifest follow the walk (both manifests hold
//! to the published schema); `scene.glb` holds the moving box in its own
//! frame; the placement measure sees no part in the covered frames;
//! the map draws a moving box on its path; `demo --traffic` captures every
//! scenario with the twin posed; an eye inside a moving occluder is a warning; bad tracks and offsets are refused with the
//! file and the key named.

use std::path::{Path, PathBuf};
use std::process::Command;

use glam::{DVec3, dvec3};
use serde_json::{Value, json};
use ufcsr_capture::{
    Obstacles, Scene, Tracer, background_texel, eye_frames, surface_samples, texel_visibility,
    unwrap_islands_avoiding,
};

/// The truck stands at the origin facing +x; the pedestrian 15 m ahead of
/// it looks back at it. A 0.5 m × 4 m × 3 m box crosses the line of sight
/// 8.5 m from the truck, its centre going from y = −5 to y = +5 in the
/// second the scenario lasts (10 fps: y = −5 + frame). The truck's outline
/// reaches |y| ≤ 0.6 m where the box is, so the box (|y − c| ≤ 2) hides
/// all of it for |c| ≤ 1 (frames 4–6), part of it for |c| = 2 (frames 3
/// and 7) and none of it for |c| ≥ 3. A copy of the truck follows 60 m to
/// its left, out of view.
fn moving_box_scene() -> Value {
    json!({
        "name": "moving-box",
        "vehicle": {"mesh": "demo"},
        "occluders": [
            {"box": {"min": [-0.25, -2.0, 0.0], "max": [0.25, 2.0, 3.0],
                     "position": [{"t": 0.0, "value": [8.5, -5.0, 0.0]}, {"t": 1.0, "value": [8.5, 5.0, 0.0]}]}},
            {"vehicle": {"follow": {"ahead_m": 2.0, "left_m": 60.0, "yaw_deg": 180.0}}}
        ],
        "rig": {"pedestrian": [15.0, 0.0, 0.0], "eye_pixels": [100, 120], "tiles": [2, 2], "fps": 10,
                "look_at_vehicle": [0.0, 0.0, 0.95]},
        "scenarios": {"S": {"duration_s": 1.0, "position": [{"t": 0.0, "value": [0.0, 0.0, 0.0]}],
                            "yaw_deg": [{"t": 0.0, "value": 0.0}]}}
    })
}

const HIDDEN: [usize; 3] = [4, 5, 6];

fn write_scene(dir: &Path, name: &str, scene: &Value) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, serde_json::to_vec_pretty(scene).unwrap()).unwrap();
    path
}

fn capture(scene: &Path, out: &Path, extra: &[&str]) -> Value {
    let (ok, stderr) = run_scene(scene, out, extra);
    assert!(ok, "ufcsr-capture failed: {stderr}");
    serde_json::from_slice(&std::fs::read(out.join("manifest.json")).unwrap()).unwrap()
}

/// Per frame, the tiles (both eyes) that show the vehicle.
fn tiles_with_vehicle(manifest: &Value) -> Vec<u64> {
    let frames = manifest["frames"].as_array().unwrap();
    frames
        .iter()
        .map(|f| {
            f["tiles_with_vehicle"]["left"].as_u64().unwrap()
                + f["tiles_with_vehicle"]["right"].as_u64().unwrap()
        })
        .collect()
}

#[test]
fn a_moving_box_hides_the_truck_in_exactly_the_frames_it_covers_it_rendered_and_exact() {
    let dir = tempfile::tempdir().unwrap();
    let path = write_scene(dir.path(), "moving-box.json", &moving_box_scene());

    // Rendered: culling, scissor and the occlusion query on, then all off.
    let manifest = capture(&path, &dir.path().join("fast"), &[]);
    let manifest_schema = crate::schemas::schema("manifest.schema.json");
    crate::schemas::assert_file_valid(&manifest_schema, &dir.path().join("fast/manifest.json"));
    let fast = tiles_with_vehicle(&manifest);
    let slow = tiles_with_vehicle(&capture(&path, &dir.path().join("slow"), &["--no-cull", "--no-scissor"]));
    assert_eq!(fast, slow, "culling, scissor or the occlusion query changed what is seen");
    for (frame, &tiles) in fast.iter().enumerate() {
        assert_eq!(
            tiles == 0,
            HIDDEN.contains(&frame),
            "frame {frame}: {tiles} tiles show the truck ({fast:?})"
        );
    }
    assert!(
        manifest["capture"]["tiles_hidden"].as_u64().unwrap() > 0,
        "the occlusion query never skipped a tile"
    );
    // scene.glb: the moving box at the world origin in its own frame (glTF axes: y, z, x).
    let glb = gltf::Gltf::open(dir.path().join("fast/scene.glb")).unwrap();
    let node =
        glb.document.nodes().find(|n| n.name() == Some("box #0")).expect("the moving box in scene.glb");
    assert_eq!(node.transform().decomposed().0, [0.0, 0.0, 0.0]);
    let bounds = node.mesh().unwrap().primitives().next().unwrap().bounding_box();
    assert_eq!((bounds.min, bounds.max), ([-2.0, 0.0, -0.25], [2.0, 3.0, 0.25]));
    assert!(glb.document.nodes().any(|n| n.name() == Some("vehicle #1")));

    // Exact: no sample of the truck is visible to either eye in exactly those frames.
    let scene = Scene::load(&path).unwrap();
    let palette = [256, 256];
    let unwrapped = unwrap_islands_avoiding(&scene.vehicle, palette, background_texel(palette)).unwrap();
    let samples = surface_samples(&scene.vehicle, &unwrapped, 0.25, 3, 1);
    let obstacles = Obstacles::new(&scene);
    let frames: Vec<u32> = (0..=10).collect();
    let (eye_frames, _) = eye_frames(&scene, &scene.scenarios[0], &frames, &obstacles).unwrap();
    let parts = scene.vehicle.parts.len();
    let visibility = texel_visibility(&samples, &eye_frames, &obstacles, parts, Tracer::Hierarchy);
    let seen = |eye_frame: usize| (0..parts).any(|p| visibility.part_seen[p * eye_frames.len() + eye_frame]);
    for frame in 0..=10 {
        let visible = seen(2 * frame) || seen(2 * frame + 1);
        assert_eq!(!visible, HIDDEN.contains(&frame), "frame {frame}: the exact measure disagrees");
    }
    // Brute force (every triangle, moved into the box's frame) agrees with the hierarchy.
    for eye_frame in &eye_frames[6..10] {
        for sample in samples.samples.iter().step_by(7) {
            assert_eq!(
                ufcsr_capture::visible_solid_angle(sample, eye_frame, &obstacles, Tracer::Hierarchy),
                ufcsr_capture::visible_solid_angle(sample, eye_frame, &obstacles, Tracer::BruteForce)
            );
        }
    }
}

/// Runs `ufcsr-capture INPUT… --out OUT` at a 256² palette with `extra`,
/// returning whether it succeeded and its standard error.
fn run(input: &[&str], out: &Path, extra: &[&str]) -> (bool, String) {
    let output = Command::new(env!("CARGO_BIN_EXE_ufcsr-capture"))
        .args(input)
        .arg("--out")
        .arg(out)
        .args(["--palette-size", "256", "-q"])
        .args(extra)
        .output()
        .expect("run ufcsr-capture");
    (output.status.success(), String::from_utf8_lossy(&output.stderr).into_owned())
}

/// `ufcsr capture scene SCENE` (see [`run`]).
fn run_scene(scene: &Path, out: &Path, extra: &[&str]) -> (bool, String) {
    run(&["scene", scene.to_str().unwrap()], out, extra)
}

#[test]
fn placement_behind_a_moving_box_sees_no_part_in_exactly_the_covered_frames() {
    let dir = tempfile::tempdir().unwrap();
    let path = write_scene(dir.path(), "moving-box.json", &moving_box_scene());
    let out = dir.path().join("placement");
    let (ok, stderr) =
        run_scene(&path, &out, &["--measure", "unobstructed", "--sample", "1/4", "--placement"]);
    assert!(ok, "{stderr}");
    let mut table = csv::Reader::from_path(out.join("results/placement-frames.csv")).unwrap();
    let headers = table.headers().unwrap().clone();
    let column = |name: &str| headers.iter().position(|h| h == name).unwrap();
    let (frame, kind, solid_angle) = (column("frame"), column("kind"), column("solid_angle_sr"));
    let mut per_frame = [0.0f64; 11];
    for row in table.records() {
        let row = row.unwrap();
        if &row[kind] == "part" {
            per_frame[row[frame].parse::<usize>().unwrap()] += row[solid_angle].parse::<f64>().unwrap();
        }
    }
    for (number, &sr) in per_frame.iter().enumerate() {
        assert_eq!(
            sr == 0.0,
            HIDDEN.contains(&number),
            "frame {number}: {sr} sr of the truck seen ({per_frame:?})"
        );
    }
}

#[test]
fn the_manifest_records_each_moving_occluders_pose_and_a_follow_offset_in_the_vehicle_frame() {
    let dir = tempfile::tempdir().unwrap();
    let mut scene = moving_box_scene();
    // The vehicle drives north-east now, so the follow offset is turned by its yaw.
    scene["scenarios"]["S"]["position"] =
        json!([{"t": 0.0, "value": [-20.0, -30.0, 0.0]}, {"t": 1.0, "value": [-15.0, -25.0, 0.0]}]);
    scene["scenarios"]["S"]["yaw_deg"] = json!([{"t": 0.0, "value": 45.0}]);
    let path = write_scene(dir.path(), "follow.json", &scene);
    let manifest = capture(&path, &dir.path().join("out"), &["--frames", "0,5,10"]);
    for record in manifest["frames"].as_array().unwrap() {
        let time_s = record["time_s"].as_f64().unwrap();
        let occluders = record["occluders"].as_array().unwrap();
        assert_eq!(occluders.len(), 2, "{record}");
        let point = |v: &Value| dvec3(v[0].as_f64().unwrap(), v[1].as_f64().unwrap(), v[2].as_f64().unwrap());
        assert_eq!(occluders[0]["name"], "box #0");
        assert!((point(&occluders[0]["position"]) - dvec3(8.5, -5.0 + 10.0 * time_s, 0.0)).length() < 1e-6);
        assert_eq!(occluders[1]["name"], "vehicle #1");
        let vehicle = point(&record["vehicle"]["position"]);
        // 2 m ahead and 60 m left of a vehicle heading 45°: ahead (1, 1)/√2, left (−1, 1)/√2.
        let (ahead, left) = (dvec3(1.0, 1.0, 0.0).normalize(), dvec3(-1.0, 1.0, 0.0).normalize());
        let expected = vehicle + ahead * 2.0 + left * 60.0;
        assert!((point(&occluders[1]["position"]) - expected).length() < 1e-5, "{record}");
        assert!((occluders[1]["yaw_deg"].as_f64().unwrap() - 225.0).abs() < 1e-9);
    }
}

#[test]
fn a_walking_pedestrians_eyes_in_the_manifest_follow_the_walk() {
    let dir = tempfile::tempdir().unwrap();
    let mut scene = moving_box_scene();
    scene["occluders"] = json!([]);
    // Stepping off the kerb: 1.4 m/s across the truck's path, 1 s.
    scene["rig"]["pedestrian"] =
        json!([{"t": 0.0, "value": [15.0, -4.0, 0.15]}, {"t": 1.0, "value": [15.0, -2.6, 0.0]}]);
    let path = write_scene(dir.path(), "walk.json", &scene);
    let manifest = capture(&path, &dir.path().join("out"), &[]);
    let manifest_schema = crate::schemas::schema("manifest.schema.json");
    crate::schemas::assert_file_valid(&manifest_schema, &dir.path().join("out/manifest.json"));
    let eye_height = manifest["rig"]["settings"]["eye_height_m"].as_f64().unwrap();
    for record in manifest["frames"].as_array().unwrap() {
        let t = record["time_s"].as_f64().unwrap();
        let walk = dvec3(15.0, -4.0 + 1.4 * t, 0.15 * (1.0 - t));
        let point = |v: &Value| dvec3(v[0].as_f64().unwrap(), v[1].as_f64().unwrap(), v[2].as_f64().unwrap());
        assert!((point(&record["pedestrian"]) - walk).length() < 1e-6, "{record}");
        let (left, right) =
            (point(&record["eyes"]["left"]["position"]), point(&record["eyes"]["right"]["position"]));
        let head = (left + right) / 2.0;
        assert!((head - (walk + DVec3::Z * eye_height)).length() < 1e-6, "t {t}: head {head}");
        // The head still turns to the truck: its forward points at the look-at point.
        let forward = point(&record["eyes"]["left"]["forward"]);
        let to_truck = (dvec3(0.0, 0.0, 0.95) - head).normalize();
        assert!(forward.dot(to_truck) > 1.0 - 1e-6, "t {t}: {forward} vs {to_truck}");
    }
    assert_eq!(manifest["rig"]["settings"]["pedestrian"].as_array().unwrap().len(), 2, "the walk's keys");
}

#[test]
fn an_eye_inside_a_moving_occluder_is_a_warning_naming_it_and_the_frames() {
    let dir = tempfile::tempdir().unwrap();
    let mut scene = moving_box_scene();
    // The box now crosses right over the pedestrian (x = 15): an eye is in
    // it while |c| < 2 + 0.055, frames 3–7.
    scene["occluders"][0]["box"]["position"] =
        json!([{"t": 0.0, "value": [15.0, -5.0, 0.0]}, {"t": 1.0, "value": [15.0, 5.0, 0.0]}]);
    let path = write_scene(dir.path(), "through.json", &scene);
    let manifest = capture(&path, &dir.path().join("out"), &[]);
    let warnings = manifest["warnings"].as_array().expect("warnings in the manifest");
    let warning =
        warnings.iter().filter_map(Value::as_str).find(|w| w.contains("inside the moving occluder"));
    assert_eq!(
        warning,
        Some(
            "an eye is inside the moving occluder box #0 in frames 3-7: it hides the whole vehicle then; check \
             its track (or follow offset) and the pedestrian's"
        ),
        "{warnings:?}"
    );
}

#[test]
fn bad_tracks_and_offsets_are_refused_naming_the_file_and_the_key() {
    let dir = tempfile::tempdir().unwrap();
    let cases: [(&str, Value, &[&str]); 5] = [
        (
            "unsorted.json",
            json!([{"box": {"min": [0, 0, 0], "max": [1, 1, 1],
                            "position": [{"t": 1.0, "value": [0, 0, 0]}, {"t": 0.5, "value": [1, 0, 0]}]}}]),
            &["occluders[0] (box #0)", "position", "must increase"],
        ),
        (
            "huge.json",
            json!([{"vehicle": {"follow": {"ahead_m": 1e9}}}]),
            &["occluders[0] (vehicle #0)", "follow.ahead_m", "not a street scene"],
        ),
        (
            "both.json",
            json!([{"pedestrian": {"follow": {"left_m": 3}, "position": [0, 0, 0]}}]),
            &["occluders[0] (pedestrian #0)", "either follow or position"],
        ),
        (
            "yaw.json",
            json!([{"mesh": {"path": "x.glb", "yaw_deg": [{"t": 0, "value": 1e300}]}}]),
            &["occluders[0] (mesh #0 x.glb)", "yaw_deg", "not a street scene"],
        ),
        ("nowhere.json", json!([{"vehicle": {}}]), &["occluders[0] (vehicle #0)", "a position"]),
    ];
    for (name, occluders, expected) in cases {
        let mut scene = moving_box_scene();
        scene["occluders"] = occluders;
        let path = write_scene(dir.path(), name, &scene);
        let error = Scene::load(&path).unwrap_err().to_string();
        assert!(error.contains(name), "{error}");
        for part in expected {
            assert!(error.contains(part), "{name}: {error:?} does not name {part:?}");
        }
    }
    let mut scene = moving_box_scene();
    scene["rig"]["pedestrian"] = json!([{"t": 0, "value": [0, 0, 0]}, {"t": 1, "value": [1e7, 0, 0]}]);
    let error = Scene::load(&write_scene(dir.path(), "walk.json", &scene)).unwrap_err().to_string();
    for part in ["walk.json", "pedestrian (a walk)", "not a street scene"] {
        assert!(error.contains(part), "the walk: {error:?} does not name {part:?}");
    }
}

/// Issue 41: a box with `min` above `max` (inside out) was accepted.
#[test]
fn an_occluder_box_with_min_above_max_is_refused_naming_the_file_and_the_field() {
    let dir = tempfile::tempdir().unwrap();
    let mut scene = moving_box_scene();
    scene["occluders"] = json!([{"box": {"min": [30, 30, 2], "max": [31, 31, 1]}}]);
    let path = write_scene(dir.path(), "inside-out.json", &scene);
    let error = Scene::load(&path).unwrap_err().to_string();
    for part in ["inside-out.json", "occluders[0] (box #0)", "box.min[2] 2 is above box.max[2] 1"] {
        assert!(error.contains(part), "{error:?} does not name {part:?}");
    }
    // A flat box (min equal to max on an axis) is still a box.
    scene["occluders"] = json!([{"box": {"min": [30, 30, 1], "max": [31, 31, 1]}}]);
    Scene::load(&write_scene(dir.path(), "flat.json", &scene)).unwrap();
}

#[test]
fn the_demo_with_traffic_captures_every_scenario_with_the_twin_posed_in_each_frame() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("lead");
    let (ok, stderr) = run(
        &["demo", "--traffic", "lead-car", "--scenario", "all"],
        &out,
        &["--ppd", "2", "--frames", "0-180/90"],
    );
    assert!(ok, "{stderr}");
    let manifest_schema = crate::schemas::schema("manifest.schema.json");
    for name in ["A", "B", "C", "D"] {
        crate::schemas::assert_file_valid(&manifest_schema, &out.join(name).join("manifest.json"));
        let manifest: Value =
            serde_json::from_slice(&std::fs::read(out.join(name).join("manifest.json")).unwrap()).unwrap();
        assert_eq!(manifest["scenario"]["name"], name);
        for record in manifest["frames"].as_array().unwrap() {
            let lead = &record["occluders"][0];
            assert_eq!(lead["name"], "lead pickup", "{record}");
            let yaw = record["vehicle"]["yaw_deg"].as_f64().unwrap();
            assert!((lead["yaw_deg"].as_f64().unwrap() - yaw).abs() < 1e-9);
            let (truck, twin) = (&record["vehicle"]["position"], &lead["position"]);
            let gap =
                (0..2).map(|i| (twin[i].as_f64().unwrap() - truck[i].as_f64().unwrap()).powi(2)).sum::<f64>();
            assert!((gap.sqrt() - ufcsr_capture::scene::LEAD_CAR_AHEAD_M).abs() < 1e-5, "{record}");
        }
    }
}

#[test]
fn the_map_draws_the_moving_box_on_its_path_across_the_line_of_sight() {
    // The box's centre runs along x = 8.5 from y = −5 to y = 5: the map's
    // path of it passes (8.5, 3) in the moving occluders' blue.
    let dir = tempfile::tempdir().unwrap();
    let path = write_scene(dir.path(), "moving-box.json", &moving_box_scene());
    let out = dir.path().join("counted");
    capture(&path, &out, &["--count"]);
    assert_eq!(out.join("results/map.png").is_file(), ufcsr::output::plot_font_available());
    if !ufcsr::output::plot_font_available() {
        return;
    }
    let manifest = ufcsr::Manifest::load_from_dir(&out).unwrap().unwrap();
    let track = ufcsr::ScenarioTrack::from_manifest(&manifest).unwrap();
    let scene = Ok(ufcsr::output::SceneShapes::read(&out.join("scene.glb")).unwrap());
    let map = dir.path().join("map.png");
    let content =
        ufcsr::output::MapContent { track: &track, scene, vehicle: None, title: "moving box".into() };
    let frame = ufcsr::output::write_scenario_map(&map, &content).unwrap();
    let image = ufcsr::read_color_image(&map, |_| Ok(())).unwrap();
    let (x, y) = frame.pixel([8.5, 3.0]);
    let drawn = image.colors[y as usize * image.width as usize + x as usize];
    assert_eq!(drawn, 0x46_6EC8, "the box's path is not blue at (8.5, 3): {drawn:06X}");
    // A --count capture has no tile images: the report says why there is no strip.
    let page = std::fs::read_to_string(out.join("results/report.html")).unwrap();
    assert!(page.contains("No frame strip") && page.contains("--count"), "{page}");
}
