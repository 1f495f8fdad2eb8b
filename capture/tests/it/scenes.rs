//! Scene files under `fixtures/scenes/`: own glTF and OBJ vehicles (parts from
//! nodes or materials, renames, kept UVs), occluders of every kind, and the
//! demo expressed as a scene file, and traffic (moving occluders, a walking
//! pedestrian).

use std::path::PathBuf;

use ufcsr_capture::{Backend, CaptureOptions, FrameSelection, Gpu, Scene, capture, verify};

fn fixture(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fixtures/scenes").join(name)
}

fn low_res(scene: &mut Scene) {
    scene.rig.set_pixels_per_degree(3.0).unwrap();
}

#[test]
fn own_vehicles_load_with_their_parts() {
    let gltf = Scene::load(&fixture("gltf-vehicle.json")).unwrap();
    let mut parts = gltf.vehicle.parts.clone();
    parts.sort();
    assert_eq!(parts, ["cab", "cargo"]);
    assert_eq!(gltf.vehicle.triangles.len(), 18);
    // Y up / +Z forward became z up / x forward: the cab (front) is at +x.
    let (min, max) = gltf.vehicle.bounds();
    assert!((max.x - 3.0).abs() < 1e-6 && (min.x + 3.0).abs() < 1e-6, "{min} {max}");
    assert!((max.z - 3.2).abs() < 1e-6 && (min.z - 0.4).abs() < 1e-6, "{min} {max}");

    // The same truck as binary glTF, parts from materials.
    let glb = ufcsr_capture::load_vehicle(
        &fixture("box-truck.glb"),
        ufcsr_capture::scene::PartSource::Material,
        &ufcsr_capture::scene::Axes::default(),
    )
    .unwrap();
    assert_eq!(glb.triangles.len(), 18);
    assert_eq!(glb.parts.len(), 9);
    assert_eq!(glb.bounds(), gltf.vehicle.bounds());
    assert!(glb.uvs.is_some());

    let obj = Scene::load(&fixture("obj-vehicle.json")).unwrap();
    let mut parts = obj.vehicle.parts.clone();
    parts.sort();
    assert_eq!(
        parts,
        ["cargo_box", "mat_cab_left", "mat_cab_right", "mat_cab_top", "rear_doors", "windshield"]
    );
    // Ground, box, parked vehicle, and an environment mesh in one 20 m chunk.
    assert_eq!(obj.occluders.objects.len(), 4);
    let ufcsr_capture::scene::OccluderObject { min, max, .. } = obj.occluders.objects[3];
    // The glTF truck turned by 90°: its 6 m length now runs north-south.
    assert!((max.y - min.y - 6.0).abs() < 1e-5 && (max.x - min.x - 2.2).abs() < 1e-5, "{min} {max}");
}

#[test]
fn demo_scene_file_matches_the_built_in_demo() {
    let file = Scene::load(&fixture("demo.json")).unwrap();
    let demo = Scene::demo();
    assert_eq!(file.rig, demo.rig);
    assert_eq!(file.occluders.positions, demo.occluders.positions);
    assert_eq!(file.vehicle, demo.vehicle);
    let (a, b) = (file.scenario("A").unwrap(), demo.scenario("A").unwrap());
    for frame in 0..=180 {
        let t = f64::from(frame) / 60.0;
        let (p, q) = (a.motion.pose(t), b.motion.pose(t));
        assert!((p.position - q.position).length() < 1e-9 && (p.yaw_deg - q.yaw_deg).abs() < 1e-9, "t = {t}");
    }
}

#[test]
fn fixture_scenes_capture_without_stray_pixels() {
    let gpu = Gpu::create(Backend::Auto).unwrap_or_else(|e| panic!("GPU tests need an adapter: {e}"));
    let dir = tempfile::tempdir().unwrap();
    for (file, keep_uvs) in [
        ("demo.json", false),
        ("obj-vehicle.json", false),
        ("obj-vehicle.json", true),
        ("gltf-vehicle.json", true),
        ("traffic.json", false),
    ] {
        let mut scene = Scene::load(&fixture(file)).unwrap();
        low_res(&mut scene);
        let out = dir.path().join(format!("{file}-{keep_uvs}"));
        let options = CaptureOptions {
            out: out.clone(),
            palette: [256, 256],
            keep_uvs,
            frames: "0-180/30".parse::<FrameSelection>().unwrap(),
            ..CaptureOptions::default()
        };
        let scenario = scene.scenarios[0].clone();
        let summary = capture(&gpu.device, &gpu.queue, &scene, &scenario, &options).unwrap();
        let (vehicle, stray) = verify(&out).unwrap();
        eprintln!(
            "{file} keep_uvs={keep_uvs}: {} tiles written, {vehicle} vehicle pixels",
            summary.tally.written
        );
        assert_eq!(stray, 0, "{file}");
        assert!(vehicle > 100, "{file}: {vehicle}");
    }
}

#[test]
fn the_fleet_scene_measures_the_truck_and_the_lead_car_each_in_a_pass_of_its_own() {
    use ufcsr_capture::scene::{FollowOffset, FrameState, OccluderPath};
    let scene = Scene::load(&fixture("fleet.json")).unwrap();
    let names: Vec<&str> = scene.fleet.iter().map(|vehicle| vehicle.name.as_str()).collect();
    assert_eq!(names, ["truck", "lead-car"]);
    assert_eq!(scene.fleet[1].source, "occluders[1]");
    let scenario = &scene.scenarios[0];
    // The truck's pass is the scene itself: the lead car follows it, 9 m ahead.
    let truck = scene.measuring(0).unwrap();
    assert!(truck.fleet.is_empty() && truck.vehicle_path.is_none());
    assert_eq!(truck.info.measured.as_ref().unwrap().name, "truck");
    // The lead car's pass: it is measured 9 m ahead, the truck drives the scenario as an occluder.
    let lead = scene.measuring(1).unwrap();
    let ahead = FollowOffset { ahead_m: 9.0, ..FollowOffset::default() };
    assert_eq!(lead.vehicle_path, Some(OccluderPath::Follow(ahead)));
    assert_eq!(lead.occluders.moving.len(), 1);
    assert_eq!(lead.occluders.moving[0].name, "vehicle truck");
    for frame in [0, 90, 180] {
        let (in_truck, in_lead) = (
            FrameState::at(&truck, scenario, frame).unwrap(),
            FrameState::at(&lead, scenario, frame).unwrap(),
        );
        assert_eq!(
            in_lead.vehicle, in_truck.moving[0],
            "frame {frame}: the lead car is not where it followed"
        );
        assert_eq!(in_lead.moving[0], in_truck.vehicle, "frame {frame}: the truck is not on its track");
    }
    let record = lead.info.measured.unwrap();
    assert_eq!((record.name.as_str(), record.fleet.len()), ("lead-car", 2));
}
