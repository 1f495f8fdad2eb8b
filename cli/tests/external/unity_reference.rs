//! The paper's Unity scenarios (`../shared/ref/scenarios/unity-intersection.json`,
//! exported from the original project) replayed with the demo truck: every
//! scenario's archive verifies with no stray pixel and shows the truck, and
//! says by name where its speed jumps; the replay equals Unity's own curve
//! evaluation at every frame. Ignored with the reason when the export is
//! absent; a failure under `CI`.

use std::collections::BTreeMap;
use std::process::Command;

use libtest_mimic::Completion;
use serde::Deserialize;
use ufcsr_capture::{Scene, verify};

use crate::need::{Outcome, missing, shared_dir};

pub fn unity_scenarios_replay_with_the_demo_truck() -> Outcome {
    let reference = shared_dir().join("ref/scenarios/unity-intersection.json");
    if !reference.is_file() {
        return missing(&format!("{} (see shared/ref/scenarios/SOURCE.md)", reference.display()));
    }
    let dir = tempfile::tempdir().unwrap();
    let status = Command::new(env!("CARGO_BIN_EXE_ufcsr-capture"))
        .arg("unity")
        .arg(&reference)
        .arg("--out")
        .arg(dir.path())
        .args(["--scenario", "all", "--ppd", "3", "--palette-size", "256", "--frames", "0,90,180", "-q"])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&status.stderr);
    assert!(status.status.success(), "{stderr}");
    // The speed check names each clip's jumps, says they are in the keys
    // (Linear tangents) and which frames carry them.
    for scenario in ["A", "B", "C", "D"] {
        let jump = format!("scenario {scenario}: the vehicle accelerates or brakes harder than 3 g");
        let line =
            stderr.lines().find(|line| line.contains(&jump)).unwrap_or_else(|| panic!("{jump}: {stderr}"));
        assert!(
            line.contains("Linear tangents") && line.contains("in frames") && line.contains("--frames"),
            "{line}"
        );
    }
    for scenario in ["A", "B", "C", "D"] {
        let (vehicle, stray) = verify(&dir.path().join(scenario)).unwrap();
        assert_eq!(stray, 0);
        // The head turns to the truck, and no building stands in between.
        assert!(vehicle > 100, "scenario {scenario}: {vehicle}");
    }
    Ok(Completion::Completed)
}

/// The export's keys as written (Unity's frame, Unity's `Keyframe` fields).
#[derive(Deserialize)]
struct Export {
    scenarios: BTreeMap<String, Clip>,
}

#[derive(Deserialize)]
struct Clip {
    vehicle: Vec<Curve>,
}

#[derive(Deserialize)]
struct Curve {
    property: String,
    keys: Vec<UnityKey>,
}

#[derive(Deserialize)]
struct UnityKey {
    t: f64,
    value: [f64; 3],
    in_slope: [f64; 3],
    out_slope: [f64; 3],
}

/// Unity's `AnimationCurve.Evaluate` of one axis as Unity documents a
/// segment (`Keyframe`: a cubic Bézier in (time, value) whose inner control
/// points lie `weight` of the interval along the left key's out tangent and
/// the right key's in tangent; the export's weights are 1/3, Unity's default,
/// which is its Hermite segment), clamped outside the keys. Solved for the
/// curve parameter by bisection on time, not by the Hermite basis the replay uses.
fn unity_evaluate(keys: &[UnityKey], axis: usize, time: f64) -> f64 {
    let (first, last) = (&keys[0], &keys[keys.len() - 1]);
    if time <= first.t {
        return first.value[axis];
    }
    if time >= last.t {
        return last.value[axis];
    }
    let right = keys.iter().position(|key| key.t > time).unwrap();
    let (k0, k1) = (&keys[right - 1], &keys[right]);
    let (dt, weight) = (k1.t - k0.t, 1.0 / 3.0);
    let times = [k0.t, k0.t + weight * dt, k1.t - weight * dt, k1.t];
    let values = [
        k0.value[axis],
        k0.value[axis] + weight * dt * k0.out_slope[axis],
        k1.value[axis] - weight * dt * k1.in_slope[axis],
        k1.value[axis],
    ];
    let bezier = |p: [f64; 4], u: f64| {
        let v = 1.0 - u;
        v * v * v * p[0] + 3.0 * v * v * u * p[1] + 3.0 * v * u * u * p[2] + u * u * u * p[3]
    };
    let (mut lo, mut hi) = (0.0, 1.0);
    for _ in 0..100 {
        let mid = (lo + hi) / 2.0;
        if bezier(times, mid) < time { lo = mid } else { hi = mid }
    }
    bezier(values, (lo + hi) / 2.0)
}

pub fn the_replay_equals_unitys_curve_evaluation_and_the_jumps_are_in_the_keys() -> Outcome {
    let reference = shared_dir().join("ref/scenarios/unity-intersection.json");
    if !reference.is_file() {
        return missing(&format!("{} (see shared/ref/scenarios/SOURCE.md)", reference.display()));
    }
    let export: Export = serde_json::from_slice(&std::fs::read(&reference).unwrap()).unwrap();
    let scene = Scene::unity(&reference).unwrap();
    for (name, clip) in &export.scenarios {
        let curve = |property: &str| &clip.vehicle.iter().find(|c| c.property == property).unwrap().keys;
        let (position, euler) = (curve("position"), curve("euler_degrees"));
        let scenario = scene.scenario(name).unwrap();
        for frame in 0..=180 {
            let time = f64::from(frame) / 60.0;
            let pose = scenario.motion.pose(time);
            // Unity (x, y up, z) is our (x, z, y); our heading is 180° − Unity's yaw.
            let unity = [0, 2, 1].map(|axis| unity_evaluate(position, axis, time));
            let off = (pose.position - glam::DVec3::from(unity)).length();
            assert!(off < 1e-9, "scenario {name} frame {frame}: {off} m from Unity's curve");
            let yaw = 180.0 - unity_evaluate(euler, 1, time);
            assert!(
                (pose.yaw_deg - yaw).abs() < 1e-9,
                "scenario {name} frame {frame}: yaw {} vs {yaw}",
                pose.yaw_deg
            );
        }
        // The jumps are in the data: every position key's slopes are its
        // segments' secants (Unity's Linear tangents), so the speed changes
        // at each inner key within a frame, in Unity as in the replay.
        for pair in position.windows(2) {
            for axis in 0..3 {
                let secant = (pair[1].value[axis] - pair[0].value[axis]) / (pair[1].t - pair[0].t);
                for slope in [pair[0].out_slope[axis], pair[1].in_slope[axis]] {
                    assert!(
                        (slope - secant).abs() < 1e-4 * secant.abs().max(1.0),
                        "scenario {name}: {slope} vs {secant}"
                    );
                }
            }
        }
    }
    Ok(Completion::Completed)
}

/// The Unity rig and scenarios land where Unity has them (moved here from a
/// unit test that passed silently when the export was absent).
pub fn unity_scenarios_put_the_vehicle_where_unity_would() -> Outcome {
    let reference = shared_dir().join("ref/scenarios/unity-intersection.json");
    if !reference.is_file() {
        return missing(&format!("{} (see shared/ref/scenarios/SOURCE.md)", reference.display()));
    }
    let scene = Scene::unity(&reference).unwrap();
    let (rig, scenarios) = (&scene.rig, &scene.scenarios);
    assert_eq!(scenarios.len(), 4);
    assert_eq!(rig.eye_pixels, [6420, 8100]);
    assert!((rig.horizontal_fov_deg - 107.0).abs() < 1e-3, "{}", rig.horizontal_fov_deg);
    assert!((rig.ipd_m - 0.1103594).abs() < 1e-9);
    assert!((rig.eye_height_m - (272.699 - 271.54)).abs() < 1e-9);
    let a = &scenarios[0];
    assert_eq!(a.name, "A");
    // End of A in Unity: (-65.5, 271.59, 21.16) → x east -65.5, y north 21.16, z up 271.59.
    assert_eq!(a.motion.pose(3.0).position.to_array(), [-65.5, 21.16, 271.59]);
    for scenario in scenarios {
        // During the straight approach the truck must point where it drives:
        // this checks the yaw convention and the model's −X forward axis.
        let (p0, p1) = (scenario.motion.pose(2.0).position, scenario.motion.pose(2.2).position);
        let motion = (p1 - p0).truncate();
        if motion.length() < 0.5 {
            continue;
        }
        let yaw = scenario.motion.pose(2.0).yaw_deg.to_radians();
        let heading = glam::dvec2(yaw.cos(), yaw.sin());
        let cos = heading.dot(motion.normalize());
        assert!(cos > 0.95, "scenario {}: heading {heading:?} vs motion {motion:?}", scenario.name);
        // And it ends within a few metres of the pedestrian, who is in front of it.
        let end = scenario.motion.pose(scenario.duration_s);
        let to_pedestrian = (rig.anchor() - end.position).truncate();
        assert!(
            to_pedestrian.length() < 40.0,
            "scenario {} ends {} m away",
            scenario.name,
            to_pedestrian.length()
        );
    }
    Ok(Completion::Completed)
}
