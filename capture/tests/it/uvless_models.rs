//! A model file without UVs — a plain OBJ of two plates, what a reviewer
//! writes to check the tool against closed forms — is counted, studied and
//! measured over observers (issue 42 §5): its own-UV field holds NaN, and a
//! derived equality made the mesh unequal to itself, so every `--count`
//! capture after the set-up was refused as "a different vehicle". The
//! observers' deg²·s are those of each observer's own `result.json`, also
//! when the scenario is shorter than the frame step (it once reported the
//! step's worth of seconds for a one-frame capture: 5× here).

use std::path::Path;

use ufcsr::{
    Dedupe, format::ObserverPlace, format::ObserverPopulation, format::ObserverSampling,
    format::ResolutionCheck,
};
use ufcsr_capture::{
    CaptureOptions, Scene, load_vehicle, run_observer_study, run_study, scene::Axes, scene::PartSource,
    study::ObserverOptions, study::StudyMeasure, study::StudyOptions,
};

use crate::study_accuracy::{gpu, plates_scene};

/// The plates scene with its vehicle read back from an OBJ without `vt` lines.
fn uvless_plates(dir: &Path) -> Scene {
    let mut scene = plates_scene();
    let mesh = &scene.vehicle;
    let mut obj = String::new();
    for (part, name) in mesh.parts.iter().enumerate() {
        obj.push_str(&format!("o {name}\n"));
        for (t, triangle) in mesh.triangles.iter().enumerate() {
            if mesh.triangle_part[t] as usize == part {
                // The default axes read +Z forward and +Y up: vehicle (x, y, z) is file (y, z, x).
                for &i in triangle {
                    let p = mesh.positions[i as usize];
                    obj.push_str(&format!("v {} {} {}\n", p.y, p.z, p.x));
                }
                obj.push_str("f -3 -2 -1\n");
            }
        }
    }
    let path = dir.join("plates.obj");
    std::fs::write(&path, obj).unwrap();
    let loaded = load_vehicle(&path, PartSource::Node, &Axes::default()).unwrap();
    assert!(loaded.uvs.is_none() && loaded.own_uvs.iter().all(|uv| uv.is_nan()), "the OBJ has no UVs");
    assert_eq!(loaded.parts, mesh.parts);
    scene.vehicle = loaded;
    scene
}

#[test]
fn a_model_without_uvs_is_studied_and_measured_over_observers() {
    let gpu = gpu();
    let dir = tempfile::tempdir().unwrap();
    let scene = uvless_plates(dir.path());
    let capture = |out: &str| CaptureOptions {
        out: dir.path().join(out),
        palette: [256, 256],
        ..CaptureOptions::default()
    };
    let study = StudyOptions {
        scenario: "still".into(),
        ppds: vec![4.0, 2.0],
        frame_steps: vec![1],
        tolerance_pp: 1.0,
        dedupe: Dedupe::Frame,
        measure: StudyMeasure::AngularArea,
        capture: capture("study"),
        exact_sample: None,
    };
    let studied = run_study(&gpu.device, &gpu.queue, &scene, &study).unwrap();
    assert_eq!(studied.rows.len(), 2);
    let frames = scene.rig.frame_count(scene.scenarios[0].duration_s);
    let frame_step = frames + 3;
    let observers = ObserverOptions {
        scenario: "still".into(),
        population: ObserverPopulation::us_adults(ObserverPlace::Kerb { from: [0.0, -0.6], to: [0.0, 0.6] }),
        sampling: ObserverSampling::Random { observers: 2, seed: 5 },
        resolution_check: ResolutionCheck::None,
        ppd: 4.0,
        // Longer than the scenario: one frame captured, standing for one frame's seconds.
        frame_step,
        capture: capture("observers"),
    };
    let measured = run_observer_study(&gpu.device, &gpu.queue, &scene, &observers).unwrap();
    assert_eq!(measured.observers.len(), 2);
    for observer in &measured.observers {
        let result: ufcsr::AnalysisResult =
            serde_json::from_slice(&std::fs::read(&observer.results).unwrap()).unwrap();
        let own = result.measures.unwrap();
        for (p, part) in measured.parts.iter().enumerate() {
            let want = own.part(part).unwrap().angular_area_deg2_s.unwrap();
            let got = observer.angular_area_deg2_s[p];
            assert!(
                want > 0.0 && (got / want - 1.0).abs() < 1e-9,
                "{part}: {got} deg²·s, result.json {want}"
            );
        }
    }
}
