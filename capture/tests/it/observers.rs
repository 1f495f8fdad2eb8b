//! The observer study against known answers: each sampled observer of two
//! facing plates sees their analytic solid angle from where it stands, and
//! its resolution bound holds that error; the 95 % interval of the
//! population mean covers the population mean — known from a dense
//! quadrature of the analytic solid angle over the declared population — in
//! 90–99 % of seeds (the coverage `docs/science.md` states, measured on the
//! CPU with the study's own sampler and summary). The command line's test
//! is `cli/tests/it/observers_command.rs`.

use std::path::PathBuf;

use ufcsr::{
    format::ObserverPlace, format::ObserverPopulation, format::ObserverRecord, format::ObserverSampling,
    format::ResolutionCheck,
};
use ufcsr_capture::{
    CaptureOptions, Scene, run_observer_study, scene::ValueOrTrack, study::DisplayOptions,
    study::IntervalKind, study::ObserverLegible, study::ObserverOptions, study::SampledObserver,
    study::normal_cdf, study::run_observer_displays, study::sample_observers, study::summarize_displays,
    study::summarize_observers, study::write_display_study, study::write_observer_study,
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
    // observers.json, observers.csv, observer-parts.csv and, with a font, its figure (.png, .pdf).
    let figures = if ufcsr::output::plot_font_available() { 2 } else { 0 };
    assert_eq!(written.len(), 3 + figures, "{written:?}");
    let read: ufcsr::format::ObserverStudy =
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
        let inside = |v: ufcsr::format::PopulationValue, known: f64| {
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

/// The display test's wall: its top edge nearest the plate (world x, height).
const WALL_TOP: (f64, f64) = (2.0, 1.25);
/// The plate the displays go on: world x of its plane, and its z range.
const PLATE_X: f64 = 4.0;
/// A 0.40 × 0.15 m display centred this high (a row of the 0.10 m patch grid on the plate).
const LOW_PATCH_Z: f64 = 0.95;

/// A 1 m × 1 m plate (y −0.5…0.5, z 0.5…1.5) facing the kerb 4 m away behind a
/// wall (x 1.9…2.0, top 1.25 m): for an eye at height e (x ≈ 0) the wall's
/// shadow on the plate reaches z0 = e + (1.25 − e)·(4 − x)/(2 − x), so a
/// patch is 80 % visible, the placement rule's threshold, from some eye
/// heights and not others; still for 2 s at 10 fps.
fn wall_scene() -> Scene {
    use glam::{dvec3, vec3};
    let mut scene = crate::study_accuracy::plates_scene();
    let mut mesh = ufcsr_capture::Mesh::default();
    mesh.add_quad(
        "plate",
        vec3(0.0, -0.5, 0.5),
        vec3(0.0, 0.5, 0.5),
        vec3(0.0, 0.5, 1.5),
        vec3(0.0, -0.5, 1.5),
    );
    scene.vehicle = mesh;
    scene.occluders.add_box(dvec3(1.9, -3.0, 0.0), dvec3(WALL_TOP.0, 3.0, WALL_TOP.1));
    scene.rig.look_at_vehicle = [0.0, 0.0, 1.0];
    scene.rig.fps = 10.0;
    scene.scenarios[0].duration_s = 2.0;
    scene
}

/// The visible share of the low patch (z 0.875…1.025) for the better eye.
fn low_patch_visible(scene: &Scene, position: [f64; 3], eye_height_m: f64) -> f64 {
    let mut scene = scene.clone();
    scene.rig.pedestrian = ValueOrTrack::Fixed(position);
    scene.rig.eye_height_m = eye_height_m;
    let pose = scene.scenarios[0].motion.pose(0.0);
    let (bottom, top) = (LOW_PATCH_Z - 0.075, LOW_PATCH_Z + 0.075);
    scene
        .rig
        .cameras(0.0, &pose)
        .iter()
        .map(|camera| {
            let eye = camera.position;
            let shadow = eye.z + (WALL_TOP.1 - eye.z) * (PLATE_X - eye.x) / (WALL_TOP.0 - eye.x);
            ((top - shadow.max(bottom)) / (top - bottom)).clamp(0.0, 1.0)
        })
        .fold(0.0, f64::max)
}

#[test]
fn each_observer_reads_a_display_behind_a_wall_exactly_when_the_wall_leaves_four_fifths_of_it() {
    let gpu = gpu();
    let scene = wall_scene();
    let dir = tempfile::tempdir().unwrap();
    let options = ObserverOptions {
        scenario: "still".into(),
        population: ObserverPopulation::us_adults(KERB),
        sampling: ObserverSampling::Random { observers: 6, seed: 5 },
        resolution_check: ResolutionCheck::Coarser { safety_factor: 3.0 },
        ppd: 4.0,
        frame_step: 2,
        capture: CaptureOptions {
            out: dir.path().to_path_buf(),
            palette: [256, 256],
            ..CaptureOptions::default()
        },
    };
    let displays = DisplayOptions { display_m: [0.40, 0.15], spacing_m: 0.10, sample: 1.0 };
    let study = run_observer_displays(&gpu.device, &gpu.queue, &scene, &options, &displays).unwrap();
    let sampled = sample_observers(&options.population, &options.sampling, [0.0; 3]).unwrap();
    assert_eq!(study.observers.len(), sampled.len());
    let low = "plate@0.40x0.15@x0.00y0.05z0.95";
    let high = "plate@0.40x0.15@x0.00y0.05z1.35";
    // Frames 0, 2, … 18 of 21, 0.2 s each (frame 20's step would lie past the scenario's end): a
    // display legible throughout scores the scenario's 2 s.
    let whole = 10.0 * 0.2;
    let (mut read, mut not_read) = (0, 0);
    for (observer, legible) in sampled.iter().zip(&study.observers) {
        assert!((legible.fine[high] - whole).abs() < 1e-9, "{observer:?}: {:?}", legible.fine.get(high));
        let visible = low_patch_visible(&scene, observer.position, observer.eye_height_m);
        let got = legible.fine.get(low).copied().unwrap_or(0.0);
        // Sample points stand for 4 mm texels: 0.03 of the patch's height either side is undecided.
        if visible >= 0.83 {
            assert!((got - whole).abs() < 1e-9, "{observer:?}: {visible:.3} visible, {got} s");
            read += 1;
        } else if visible <= 0.77 {
            assert_eq!(got, 0.0, "{observer:?}: {visible:.3} visible");
            not_read += 1;
        }
    }
    assert!(read > 0 && not_read > 0, "the draws fall on both sides of the wall's line: {read} {not_read}");
    // The summary: the parts' path, with each observer's frame-step bound, 3 × |2.0 − 2.0| s: the
    // coarser check's every 4th frame (0–16, 0.4 s each) stands for the same 2 s. Keeping each
    // setting's last frame too read 2.2 and 2.4 s, a 0.6 s bound made by that rule alone.
    let summary = study.summary.iter().find(|s| s.candidate == high).unwrap().legible_s;
    assert!((summary.mean - whole).abs() < 1e-9);
    assert!(summary.resolution_bound.unwrap().abs() < 1e-9, "{summary:?}");
    let [from, to] = summary.mean_ci95.unwrap();
    assert!((from - whole).abs() < 1e-9 && (to - whole).abs() < 1e-9, "{from} {to}");
    // observers.json's `displays` carries the same values.
    let record = study.record();
    assert_eq!((record.display_m, record.spacing_m, &record.summary), ([0.40, 0.15], 0.10, &study.summary));
    assert!(
        record
            .observers
            .iter()
            .zip(&study.observers)
            .all(|(r, o)| r.legible_s == o.fine && r.coarser_legible_s == o.coarse)
    );
    let written = write_display_study(&study, dir.path()).unwrap();
    let table = std::fs::read_to_string(written).unwrap();
    assert_eq!(table.lines().count(), 1 + study.summary.len());
    assert!(table.lines().any(|line| line.starts_with(&format!("{high},patch,2.000000,"))), "{table}");
}

/// The population share of eye heights at least `eye_m`, from each group's
/// truncated normal stature (closed form).
fn share_at_least(population: &ObserverPopulation, eye_m: f64) -> f64 {
    let t = population.truncate_sd;
    let kept = normal_cdf(t) - normal_cdf(-t);
    let total: f64 = population.groups.iter().map(|g| g.weight).sum();
    population
        .groups
        .iter()
        .map(|g| {
            let z = ((eye_m + g.eye_offset_m - g.stature_mean_m) / g.stature_sd_m).clamp(-t, t);
            g.weight / total * (normal_cdf(t) - normal_cdf(z)) / kept
        })
        .sum()
}

#[test]
fn the_display_interval_covers_the_known_population_mean_of_legible_seconds_in_90_to_99_percent_of_seeds() {
    // The wall's display read for 2 s by eyes above e* and not at all below (the
    // test above; its eyes stand at x ≈ 0): the population mean is 2 s × P(eye ≥ e*),
    // a share of one mixture of truncated normals; e* from z0 = bottom + 0.2 H.
    let population = ObserverPopulation::us_adults(KERB);
    let threshold_z = LOW_PATCH_Z - 0.075 + 0.2 * 0.15;
    // z0 = e + (w − e)·4/2 = 2w − e ≤ threshold_z.
    let e_star = 2.0 * WALL_TOP.1 - threshold_z;
    let known = 2.0 * share_at_least(&population, e_star);
    assert!((0.2..0.8).contains(&(known / 2.0)), "{known}");
    let patch = "plate@0.40x0.15@x0.00y0.05z0.95";
    let kinds: std::collections::BTreeMap<String, String> = [(patch.to_string(), "patch".to_string())].into();
    let coverage = |n: u32, seeds: u64| {
        let mut covered = 0;
        for seed in 0..seeds {
            let sampled =
                sample_observers(&population, &ObserverSampling::Random { observers: n, seed }, [0.0; 3])
                    .unwrap();
            let observers: Vec<ObserverLegible> = sampled
                .iter()
                .map(|o| {
                    let seconds = if o.eye_height_m >= e_star { 2.0 } else { 0.0 };
                    ObserverLegible { fine: [(patch.to_string(), seconds)].into(), coarse: None }
                })
                .collect();
            let summary =
                summarize_displays(&kinds, &observers, IntervalKind::MonteCarlo, ResolutionCheck::None);
            let [low, high] = summary[0].legible_s.mean_ci95.unwrap();
            covered += usize::from(low <= known && known <= high);
        }
        covered as f64 / seeds as f64
    };
    let (at_16, at_64) = (coverage(16, 400), coverage(64, 400));
    println!(
        "coverage of the 95 % interval of a display's mean legible seconds over 400 seeds: 16 observers {:.1} %, \
         64 observers {:.1} %",
        100.0 * at_16,
        100.0 * at_64
    );
    for coverage in [at_16, at_64] {
        assert!((0.90..=0.99).contains(&coverage), "coverage {coverage}");
    }
}
