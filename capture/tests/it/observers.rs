//! The observer study against known answers: each sampled observer of two
//! facing plates sees their analytic solid angle from where it stands, and
//! its resolution bound holds that error; the 95 % interval of the
//! population mean covers the population mean — known from a dense
//! quadrature of the analytic solid angle over the declared population — in
//! 90–99 % of seeds (the coverage `docs/science.md` states, measured on the
//! CPU with the study's own sampler and summary). The command line's test
//! is `cli/tests/it/observers_command.rs`.

use std::path::PathBuf;

use ufcsr::{ObserverPlace, ObserverPopulation, ObserverRecord, ObserverSampling, ResolutionCheck};
use ufcsr_capture::{
    CaptureOptions, IntervalKind, ObserverOptions, SampledObserver, Scene, ValueOrTrack, normal_cdf,
    run_observer_study, sample_observers, summarize_observers, write_observer_study,
};

use crate::study_accuracy::{PLATES, analytic_sr, gpu, plates_scene};

/// Pedestrians stand along this kerb, 4 m in front of the plates.
const KERB: ObserverPlace = ObserverPlace::Kerb { from: [0.0, -0.6], to: [0.0, 0.6] };

/// The plates seen from `position` with eyes at `eye_height_m`: solid angle summed over both eyes, sr.
fn seen_from(scene: &Scene, position: [f64; 3], eye_height_m: f64) -> Vec<f64> {
    let mut scene = scene.clone();
    scene.rig.pedestrian = ValueOrTrack::Fixed(position);
    scene.rig.eye_height_m = eye_height_m;
    PLATES.iter().map(|&plate| analytic_sr(&scene, plate)).collect()
}

#[test]
fn each_sampled_observer_sees_the_plates_analytic_solid_angle_within_its_resolution_bound() {
    let gpu = gpu();
    let scene = plates_scene();
    let dir = tempfile::tempdir().unwrap();
    let ppd = 8.0;
    let options = ObserverOptions {
        scenario: "still".into(),
        population: ObserverPopulation::us_adults(KERB),
        sampling: ObserverSampling::Random { observers: 4, seed: 3 },
        resolution_check: ResolutionCheck::Coarser { safety_factor: 3.0 },
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
    // deg²·s per eye of every frame's solid angle summed over both eyes (the plates stand still).
    let frames = f64::from(scene.rig.frame_count(scene.scenarios[0].duration_s));
    let to_deg2_s = (180.0 / std::f64::consts::PI).powi(2) / scene.rig.fps / 2.0 * frames;
    for observer in &study.observers {
        let want = seen_from(&scene, observer.position, observer.eye_height_m);
        let bound = observer.angular_area_bound_deg2_s.as_ref().unwrap();
        for (plate, want) in PLATES.iter().zip(want) {
            let p = study.parts.iter().position(|name| name == plate.0).unwrap();
            let (got, want) = (observer.angular_area_deg2_s[p], want * to_deg2_s);
            // The rendered outline band: below 0.1 / ppd relative; and the observer's own bound holds it.
            assert!((got / want - 1.0).abs() < 0.1 / ppd, "{observer:?} {}: {got} against {want}", plate.0);
            assert!(
                (got - want).abs() <= bound[p],
                "{}: error {} above its bound {}",
                plate.0,
                got - want,
                bound[p]
            );
            eprintln!("{}: error {:+.3e}, bound {:.3e} deg²·s", plate.0, got - want, bound[p]);
        }
    }
    // The summary: the mean, an interval around it that includes the mean bound, shares adding to 100 %.
    let near = study.summary.iter().find(|s| s.part == "near-axis").unwrap().angular_area_deg2_s;
    let [low, high] = near.mean_ci95.unwrap();
    let half = near.monte_carlo_half_width.unwrap() + near.resolution_bound.unwrap();
    assert!((high - near.mean - half).abs() < 1e-9 && (near.mean - low - half).abs() < 1e-9);
    let share_sum: f64 = study.summary.iter().map(|s| s.angular_area_share_percent.mean).sum();
    assert!((share_sum - 100.0).abs() < 1e-9);
    let written = write_observer_study(&study, dir.path()).unwrap();
    assert_eq!(written.len(), 3);
    let read: ufcsr::ObserverStudy =
        serde_json::from_slice(&std::fs::read(dir.path().join("observers.json")).unwrap()).unwrap();
    assert_eq!(read, study);
    let rows = std::fs::read_to_string(dir.path().join("observers.csv")).unwrap();
    assert_eq!(rows.lines().count(), 1 + 4 * 2);
}

/// The population mean of each plate's solid angle and share, by the
/// midpoint rule over the kerb (`cells` pieces) and each group's truncated
/// normal stature (`cells` × 8 pieces of ± truncate_sd).
fn population_mean(scene: &Scene, population: &ObserverPopulation, cells: u32) -> [Vec<f64>; 2] {
    let ObserverPlace::Kerb { from, to } = population.place else { panic!("a kerb") };
    let (t, steps) = (population.truncate_sd, cells * 8);
    let kept = normal_cdf(t) - normal_cdf(-t);
    let total_weight: f64 = population.groups.iter().map(|g| g.weight).sum();
    let (mut area, mut share) = (vec![0.0; PLATES.len()], vec![0.0; PLATES.len()]);
    for group in &population.groups {
        for k in 0..steps {
            let (z0, z1) = (
                -t + 2.0 * t * f64::from(k) / f64::from(steps),
                -t + 2.0 * t * f64::from(k + 1) / f64::from(steps),
            );
            let z_weight = (normal_cdf(z1) - normal_cdf(z0)) / kept;
            let eye = group.stature_mean_m + group.stature_sd_m * 0.5 * (z0 + z1) - group.eye_offset_m;
            for c in 0..cells {
                let u = (f64::from(c) + 0.5) / f64::from(cells);
                let position = [from[0] + (to[0] - from[0]) * u, from[1] + (to[1] - from[1]) * u, 0.0];
                let values = seen_from(scene, position, eye);
                let sum: f64 = values.iter().sum();
                let weight = group.weight / total_weight * z_weight / f64::from(cells);
                for (p, v) in values.iter().enumerate() {
                    area[p] += weight * v;
                    share[p] += weight * 100.0 * v / sum;
                }
            }
        }
    }
    [area, share]
}

/// Share of `seeds` whose interval covers the known mean (near-axis plate's
/// solid angle and its share), and the mean Monte Carlo half-width of the solid angle.
fn coverage(
    scene: &Scene,
    population: &ObserverPopulation,
    known: &[Vec<f64>; 2],
    n: u32,
    seeds: u64,
) -> (f64, f64, f64) {
    let parts: Vec<String> = PLATES.iter().map(|p| p.0.to_string()).collect();
    let (mut covered, mut covered_share, mut half) = (0, 0, 0.0);
    for seed in 0..seeds {
        let sampled =
            sample_observers(population, &ObserverSampling::Random { observers: n, seed }, [0.0; 3]).unwrap();
        let records: Vec<ObserverRecord> = sampled.iter().map(|o| record(scene, o)).collect();
        let summary = summarize_observers(&parts, &records, IntervalKind::MonteCarlo, ResolutionCheck::None);
        let near = summary.iter().find(|s| s.part == "near-axis").unwrap();
        let inside = |v: ufcsr::PopulationValue, known: f64| {
            let [low, high] = v.mean_ci95.unwrap();
            low <= known && known <= high
        };
        covered += usize::from(inside(near.angular_area_deg2_s, known[0][0]));
        covered_share += usize::from(inside(near.angular_area_share_percent, known[1][0]));
        half += near.angular_area_deg2_s.monte_carlo_half_width.unwrap() / seeds as f64;
    }
    (covered as f64 / seeds as f64, covered_share as f64 / seeds as f64, half)
}

fn record(scene: &Scene, observer: &SampledObserver) -> ObserverRecord {
    let values = seen_from(scene, observer.position, observer.eye_height_m);
    ObserverRecord {
        position: observer.position,
        group: observer.group.clone(),
        stature_m: observer.stature_m,
        eye_height_m: observer.eye_height_m,
        seconds: 0.0,
        angular_area_deg2_s: values.clone(),
        count: values,
        angular_area_bound_deg2_s: None,
        coarser: None,
        results: PathBuf::new(),
    }
}

#[test]
fn the_population_interval_covers_the_known_population_mean_in_90_to_99_percent_of_seeds() {
    let scene = plates_scene();
    let population = ObserverPopulation::us_adults(KERB);
    let known = population_mean(&scene, &population, 48);
    // The quadrature has converged: a coarser one agrees to 1e-4 relative.
    let coarse = population_mean(&scene, &population, 24);
    assert!((coarse[0][0] / known[0][0] - 1.0).abs() < 1e-4, "{coarse:?} {known:?}");
    let seeds = 400;
    let (area_16, share_16, half_16) = coverage(&scene, &population, &known, 16, seeds);
    let (area_64, share_64, half_64) = coverage(&scene, &population, &known, 64, seeds);
    println!(
        "coverage of the 95 % interval of the population mean over {seeds} seeds: 16 observers {:.1} % (solid angle), \
         {:.1} % (share); 64 observers {:.1} %, {:.1} %; mean half-width 16 → 64 observers: × {:.3}",
        100.0 * area_16,
        100.0 * share_16,
        100.0 * area_64,
        100.0 * share_64,
        half_64 / half_16
    );
    for coverage in [area_16, share_16, area_64, share_64] {
        assert!((0.90..=0.99).contains(&coverage), "coverage {coverage}");
    }
    // The interval shrinks like 1/√n: four times the observers, about half the width (t: 0.469).
    assert!((0.40..0.55).contains(&(half_64 / half_16)), "{}", half_64 / half_16);
}
