//! The observer study against known answers: each observer of two facing
//! plates sees their analytic solid angle from where it stands, the summary
//! is the mean over the observers (the command line's test is in
//! `cli/tests/it/observers_command.rs`).

use ufcsr_capture::{
    CaptureOptions, ObserverOptions, ValueOrTrack, run_observer_study, write_observer_study,
};

use crate::study_accuracy::{PLATES, analytic_sr, gpu, plates_scene};

#[test]
fn each_observer_sees_the_plates_analytic_solid_angle_from_where_it_stands() {
    let gpu = gpu();
    let scene = plates_scene();
    let dir = tempfile::tempdir().unwrap();
    let ppd = 8.0;
    let options = ObserverOptions {
        scenario: "still".into(),
        kerb: Some([[0.0, -0.6], [0.0, 0.6]]),
        positions: 2,
        eye_heights_m: [1.5, 1.9],
        heights: 2,
        ppd,
        frame_step: 1,
        capture: CaptureOptions {
            out: dir.path().to_path_buf(),
            palette: [256, 256],
            ..CaptureOptions::default()
        },
    };
    let study = run_observer_study(&gpu.device, &gpu.queue, &scene, &options).unwrap();
    assert_eq!(study.observers.len(), 4);
    let frames = scene.rig.frame_count(scene.scenarios[0].duration_s) as f64;
    // deg²·s per eye of one frame's solid angle summed over both eyes.
    let to_deg2_s = (180.0 / std::f64::consts::PI).powi(2) / scene.rig.fps / 2.0;
    for observer in &study.observers {
        let mut seen_from = scene.clone();
        seen_from.rig.pedestrian = ValueOrTrack::Fixed(observer.position);
        seen_from.rig.eye_height_m = observer.eye_height_m;
        for plate in PLATES {
            let p = study.parts.iter().position(|name| name == plate.0).unwrap();
            let want = analytic_sr(&seen_from, plate) * frames * to_deg2_s;
            let got = observer.angular_area_deg2_s[p];
            // The rendered outline band: below 0.1 / ppd relative (as for one observer).
            assert!((got / want - 1.0).abs() < 0.1 / ppd, "{observer:?} {}: {got} against {want}", plate.0);
        }
    }
    // Observers differ (the plates are seen from four places) and the summary is their mean.
    let near = study.parts.iter().position(|name| name == "near-axis").unwrap();
    let values: Vec<f64> = study.observers.iter().map(|o| o.angular_area_deg2_s[near]).collect();
    assert!(values.iter().any(|v| (v / values[0] - 1.0).abs() > 1e-3), "{values:?}");
    let summary = study.summary.iter().find(|s| s.part == "near-axis").unwrap();
    let mean = values.iter().sum::<f64>() / 4.0;
    assert!((summary.angular_area_deg2_s.mean - mean).abs() < 1e-9 * mean);
    let lowest = values.iter().copied().fold(f64::INFINITY, f64::min);
    let highest = values.iter().copied().fold(0.0, f64::max);
    assert_eq!((summary.angular_area_deg2_s.p2_5, summary.angular_area_deg2_s.p97_5), (lowest, highest));
    // Two parts: both are always in the top five, and the shares add to 100 %.
    assert!(study.summary.iter().all(|s| s.top5_frequency == 1.0));
    let share_sum: f64 = study.summary.iter().map(|s| s.angular_area_share_percent.mean).sum();
    assert!((share_sum - 100.0).abs() < 1e-9);
    // The tables: one row per observer and part, one per part.
    let written = write_observer_study(&study, dir.path()).unwrap();
    assert_eq!(written.len(), 3);
    let rows = std::fs::read_to_string(dir.path().join("observers.csv")).unwrap();
    assert_eq!(rows.lines().count(), 1 + 4 * 2);
    let parts = std::fs::read_to_string(dir.path().join("observer-parts.csv")).unwrap();
    assert_eq!(parts.lines().count(), 1 + 2);
}
