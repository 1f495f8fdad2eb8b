//! Uncertainty over the observer: one deterministic pedestrian is not a
//! population.
//!
//! [`run_observer_study`] captures one scenario from a grid of observers —
//! positions along a kerb segment × eye heights over a range — with the fused
//! path (no PNGs), and reports per part, over the observers, the mean and the
//! spread of the visible angular area (deg²·s), its share, the paper's count
//! share, and how often the part is among the five with the largest angular
//! area. The grid is stratified (each observer at the middle of its cell), so
//! the mean over observers estimates the mean over a pedestrian uniformly
//! placed on the segment with a uniformly distributed eye height; the
//! interval of that mean is a seeded bootstrap over observers, and the spread
//! (2.5th–97.5th percentile of the observers' values) says how much one
//! pedestrian may differ from the mean.

use std::path::{Path, PathBuf};
use std::time::Instant;

use serde::Serialize;
use ufcsr::Dedupe;

use crate::error::{CaptureError, Result};
use crate::exact::accuracy::SplitMix;
use crate::job::{CaptureOptions, CaptureSetup};
use crate::scene::Scene;
use crate::scene::track::ValueOrTrack;
use crate::study::{Setting, StudyMeasure, count_every_nth_frame, frame_table, rendered_per_eye_frame};

/// The most observers one study captures (each is a full capture).
pub const MAX_OBSERVERS: u32 = 400;

/// Bootstrap replicates for the interval of the mean.
const REPLICATES: u32 = 1000;

/// Which observers to sample, and at which setting.
#[derive(Debug, Clone)]
pub struct ObserverOptions {
    pub scenario: String,
    /// The kerb segment's ends on the ground, world `[x, y]` metres; `None`
    /// keeps the rig's pedestrian, standing or walking (then `positions`
    /// must be 1). A walking pedestrian cannot be put on a kerb.
    pub kerb: Option<[[f64; 2]; 2]>,
    /// Positions along the segment, each at the middle of an equal piece.
    pub positions: u32,
    /// Eye heights `[lowest, highest]`, metres above the pedestrian's ground point.
    pub eye_heights_m: [f64; 2],
    /// Eye heights over the range, each at the middle of an equal piece.
    pub heights: u32,
    pub ppd: f64,
    pub frame_step: u32,
    /// Capture settings; `out` is the study folder (one sub-folder per observer).
    pub capture: CaptureOptions,
}

/// One observer's capture, per legend part.
#[derive(Debug, Clone, Serialize)]
pub struct Observer {
    /// Ground point, world metres (for a walking pedestrian, where the walk starts).
    pub position: [f64; 3],
    pub eye_height_m: f64,
    /// Wall seconds of this observer's capture, count and results (the
    /// shared set-up is [`ObserverStudy::setup_seconds`]).
    pub seconds: f64,
    /// Per part (the study's `parts` order): visible angular area, deg²·s per eye.
    pub angular_area_deg2_s: Vec<f64>,
    /// Per part: texels seen per eye-frame, summed (the paper's count, `--dedupe frame`).
    pub count: Vec<f64>,
    /// The observer's results folder.
    pub results: PathBuf,
}

/// A value over the observers: their mean, the 95 % interval of that mean
/// (bootstrap over observers) and the observers' own 2.5–97.5 % spread.
#[derive(Debug, Clone, Copy, Serialize, PartialEq)]
pub struct Spread {
    pub mean: f64,
    pub mean_ci95: [f64; 2],
    pub p2_5: f64,
    pub p97_5: f64,
}

/// One part over the observers.
#[derive(Debug, Clone, Serialize)]
pub struct PartSpread {
    pub part: String,
    pub angular_area_deg2_s: Spread,
    /// % of the vehicle's angular area.
    pub angular_area_share_percent: Spread,
    /// % of the count's grand total.
    pub count_share_percent: Spread,
    /// Share of observers for whom the part is among the five with the
    /// largest angular area, 0–1.
    pub top5_frequency: f64,
}

/// A finished observer study.
#[derive(Debug, Clone, Serialize)]
pub struct ObserverStudy {
    pub scenario: String,
    pub ppd: f64,
    pub frame_step: u32,
    pub eye_heights_m: [f64; 2],
    pub kerb: Option<[[f64; 2]; 2]>,
    pub parts: Vec<String>,
    pub observers: Vec<Observer>,
    /// Sorted by mean angular area, largest first.
    pub summary: Vec<PartSpread>,
    /// Wall seconds for all observers.
    pub seconds: f64,
    /// Wall seconds of the set-up the observers share (unwrap, PIdT, the
    /// archive's files, renderer), built once and left out of each
    /// observer's `seconds`.
    pub setup_seconds: f64,
}

fn check(options: &ObserverOptions) -> Result<()> {
    let bad = |text: String| Err(CaptureError::BadOptions(text));
    let observers = u64::from(options.positions) * u64::from(options.heights);
    if options.positions == 0 || options.heights == 0 || observers > u64::from(MAX_OBSERVERS) {
        return bad(format!(
            "--positions × --heights must be between 1 and {MAX_OBSERVERS} observers, not {} × {}",
            options.positions, options.heights
        ));
    }
    if options.kerb.is_none() && options.positions != 1 {
        return bad("--positions above 1 needs a --kerb segment to place them on".into());
    }
    let [low, high] = options.eye_heights_m;
    if !(low.is_finite() && high.is_finite() && low > 0.0 && low <= high && high <= 3.0) {
        return bad(format!("--eye-heights must be LOW:HIGH with 0 < LOW ≤ HIGH ≤ 3 m, not {low}:{high}"));
    }
    if let Some(kerb) = options.kerb
        && kerb.iter().flatten().any(|v| !v.is_finite() || v.abs() > 1e6)
    {
        return bad(format!("--kerb ends must be finite and within ±1e6 m, not {kerb:?}"));
    }
    if !(options.ppd.is_finite() && options.ppd > 0.0) || options.frame_step == 0 {
        return bad("--ppd must be positive and --frame-step at least 1".into());
    }
    Ok(())
}

/// Where observer `i` of `n` stands on `[from, to]`: the middle of its piece.
fn stratified(from: f64, to: f64, i: u32, n: u32) -> f64 {
    from + (to - from) * (f64::from(i) + 0.5) / f64::from(n)
}

/// The observers' ground points and eye heights, positions outermost.
pub fn observer_grid(options: &ObserverOptions, pedestrian: [f64; 3]) -> Vec<([f64; 3], f64)> {
    let mut grid = Vec::new();
    for p in 0..options.positions {
        let position = match options.kerb {
            None => pedestrian,
            Some([a, b]) => [
                stratified(a[0], b[0], p, options.positions),
                stratified(a[1], b[1], p, options.positions),
                pedestrian[2],
            ],
        };
        for h in 0..options.heights {
            let [low, high] = options.eye_heights_m;
            grid.push((position, stratified(low, high, h, options.heights)));
        }
    }
    grid
}

/// Captures the scenario from every observer and summarises the parts over them.
pub fn run_observer_study(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    scene: &Scene,
    options: &ObserverOptions,
) -> Result<ObserverStudy> {
    check(options)?;
    let scenario = scene.scenario(&options.scenario)?;
    let start = Instant::now();
    if options.kerb.is_some() && matches!(scene.rig.pedestrian, ValueOrTrack::Keys(_)) {
        return Err(CaptureError::BadOptions(
            "--kerb places standing observers, but the scene's pedestrian walks: leave out --kerb to keep the walk \
             and vary the eye height"
                .into(),
        ));
    }
    let grid = observer_grid(options, scene.rig.anchor().to_array());
    let mut parts = Vec::new();
    let mut observers = Vec::with_capacity(grid.len());
    // Built by the first observer, in its folder, and handed to the others.
    let mut setup = None;
    for (index, &(position, eye_height_m)) in grid.iter().enumerate() {
        let place = ObserverPlace { index, position, eye_height_m };
        let (observer, observer_parts) = capture_observer(device, queue, scene, options, place, &mut setup)?;
        if index == 0 {
            parts = observer_parts;
        } else if observer_parts != parts {
            return Err(CaptureError::BadOptions("the observers' captures name different parts".into()));
        }
        eprintln!(
            "observers: {}/{} at ({:.2}, {:.2}) m, eye {:.3} m: {:.2} s",
            index + 1,
            grid.len(),
            position[0],
            position[1],
            eye_height_m,
            observer.seconds
        );
        observers.push(observer);
    }
    if parts.is_empty() {
        return Err(CaptureError::BadOptions(
            "the observer study needs a PIdT and legend to compare parts".into(),
        ));
    }
    let summary = summarize(&parts, &observers);
    let setup_seconds = setup.map_or(0.0, |setup: CaptureSetup| setup.seconds);
    Ok(ObserverStudy {
        scenario: scenario.name.clone(),
        ppd: options.ppd,
        frame_step: options.frame_step,
        eye_heights_m: options.eye_heights_m,
        kerb: options.kerb,
        parts,
        observers,
        summary,
        seconds: start.elapsed().as_secs_f64(),
        setup_seconds,
    })
}

/// Where one observer of the grid stands.
struct ObserverPlace {
    index: usize,
    /// Ground point, world metres.
    position: [f64; 3],
    eye_height_m: f64,
}

/// One observer: the fused count at the study's setting, reduced per part,
/// with the set-up the observers share (built by the first).
fn capture_observer(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    scene: &Scene,
    options: &ObserverOptions,
    place: ObserverPlace,
    setup: &mut Option<CaptureSetup>,
) -> Result<(Observer, Vec<String>)> {
    let ObserverPlace { index, position, eye_height_m } = place;
    let mut scene = scene.clone();
    if options.kerb.is_some() {
        scene.rig.pedestrian = ValueOrTrack::Fixed(position);
    }
    scene.rig.eye_height_m = eye_height_m;
    scene.rig.set_pixels_per_degree(options.ppd)?;
    scene.rig.check().map_err(|e| CaptureError::BadOptions(format!("observer {index}: {e}")))?;
    let out = options.capture.out.join(format!("observer-{index:03}"));
    let step = options.frame_step;
    let setting = Setting { name: &options.scenario, out: &out, step, dedupe: Dedupe::Frame };
    let (counted, _) = count_every_nth_frame(device, queue, &scene, &options.capture, &setting, setup)?;
    let table = frame_table(&counted, &out)?;
    let solid = rendered_per_eye_frame(table, StudyMeasure::AngularArea, &out)?;
    let count = rendered_per_eye_frame(table, StudyMeasure::Count, &out)?;
    // deg²·s per eye: Σ sr × (180/π)² × seconds per frame / 2 eyes.
    let seconds_per_frame = f64::from(step) / scene.rig.fps;
    let to_deg2_s = (180.0 / std::f64::consts::PI).powi(2) * seconds_per_frame / 2.0;
    let sum = |values: &crate::exact::accuracy::PerEyeFrame, scale: f64| -> Vec<f64> {
        let mut totals = vec![0.0; values.parts.len()];
        for (_, _, row) in &values.rows {
            totals.iter_mut().zip(row).for_each(|(t, v)| *t += v * scale);
        }
        totals
    };
    let observer = Observer {
        position,
        eye_height_m,
        seconds: counted.summary.seconds,
        angular_area_deg2_s: sum(&solid, to_deg2_s),
        count: sum(&count, 1.0),
        results: counted.written.result_json,
    };
    Ok((observer, solid.parts))
}

/// Shares in percent of the values' sum (all 0 when the sum is 0).
fn shares(values: &[f64]) -> Vec<f64> {
    let total: f64 = values.iter().sum();
    values.iter().map(|v| if total > 0.0 { 100.0 * v / total } else { 0.0 }).collect()
}

/// The indices of the five largest values (ties by index).
fn top5(values: &[f64]) -> Vec<usize> {
    let mut order: Vec<usize> = (0..values.len()).collect();
    order.sort_by(|&a, &b| values[b].total_cmp(&values[a]).then(a.cmp(&b)));
    order.truncate(5);
    order
}

/// Percentile `q` (0–1) of sorted values, by the nearest rank.
fn percentile(sorted: &[f64], q: f64) -> f64 {
    sorted[((q * (sorted.len() - 1) as f64).round() as usize).min(sorted.len() - 1)]
}

/// Mean, bootstrap interval of the mean (seeded), and 2.5–97.5 % spread.
pub fn spread(values: &[f64], seed: u64) -> Spread {
    let n = values.len();
    let mean = values.iter().sum::<f64>() / n as f64;
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    let mean_ci95 = if n < 2 {
        [mean, mean]
    } else {
        let mut random = SplitMix(seed);
        let mut means: Vec<f64> = (0..REPLICATES)
            .map(|_| (0..n).map(|_| values[(random.next() % n as u64) as usize]).sum::<f64>() / n as f64)
            .collect();
        means.sort_by(f64::total_cmp);
        [percentile(&means, 0.025).min(mean), percentile(&means, 0.975).max(mean)]
    };
    Spread { mean, mean_ci95, p2_5: percentile(&sorted, 0.025), p97_5: percentile(&sorted, 0.975) }
}

/// Per part over the observers, largest mean angular area first.
fn summarize(parts: &[String], observers: &[Observer]) -> Vec<PartSpread> {
    let area_shares: Vec<Vec<f64>> = observers.iter().map(|o| shares(&o.angular_area_deg2_s)).collect();
    let count_shares: Vec<Vec<f64>> = observers.iter().map(|o| shares(&o.count)).collect();
    let tops: Vec<Vec<usize>> = observers.iter().map(|o| top5(&o.angular_area_deg2_s)).collect();
    let column = |rows: &[Vec<f64>], p: usize| -> Vec<f64> { rows.iter().map(|r| r[p]).collect() };
    let areas: Vec<Vec<f64>> = observers.iter().map(|o| o.angular_area_deg2_s.clone()).collect();
    let mut summary: Vec<PartSpread> = parts
        .iter()
        .enumerate()
        .map(|(p, part)| {
            // One seed per part and measure: the intervals do not change from run to run.
            let seed = 0x5EED_0000 + p as u64 * 3;
            PartSpread {
                part: part.clone(),
                angular_area_deg2_s: spread(&column(&areas, p), seed),
                angular_area_share_percent: spread(&column(&area_shares, p), seed + 1),
                count_share_percent: spread(&column(&count_shares, p), seed + 2),
                top5_frequency: tops.iter().filter(|t| t.contains(&p)).count() as f64
                    / observers.len() as f64,
            }
        })
        .collect();
    summary.sort_by(|a, b| b.angular_area_deg2_s.mean.total_cmp(&a.angular_area_deg2_s.mean));
    summary
}

/// Writes `observers.json`, `observers.csv` (one row per observer and part)
/// and `observer-parts.csv` (one row per part); returns what was written.
pub fn write_observer_study(study: &ObserverStudy, dir: &Path) -> Result<Vec<PathBuf>> {
    std::fs::create_dir_all(dir).map_err(|e| CaptureError::io(dir, e))?;
    let json_path = dir.join("observers.json");
    let json =
        serde_json::to_vec_pretty(study).map_err(|e| CaptureError::bad_input(&json_path, e.to_string()))?;
    ufcsr::write_bytes_atomically(&json_path, &json)?;
    let mut per_observer = String::from("observer,x_m,y_m,eye_height_m,part,angular_area_deg2_s,count\n");
    for (i, o) in study.observers.iter().enumerate() {
        for (p, part) in study.parts.iter().enumerate() {
            per_observer.push_str(&format!(
                "{i},{},{},{},{},{},{}\n",
                o.position[0],
                o.position[1],
                o.eye_height_m,
                ufcsr::csv_field(part),
                o.angular_area_deg2_s[p],
                o.count[p]
            ));
        }
    }
    let observers_path = dir.join("observers.csv");
    ufcsr::write_bytes_atomically(&observers_path, per_observer.as_bytes())?;
    let mut per_part = String::from(
        "part,angular_area_deg2_s_mean,angular_area_deg2_s_ci95_low,angular_area_deg2_s_ci95_high,\
         angular_area_deg2_s_p2_5,angular_area_deg2_s_p97_5,area_share_percent_mean,area_share_percent_ci95_low,\
         area_share_percent_ci95_high,area_share_percent_p2_5,area_share_percent_p97_5,count_share_percent_mean,\
         count_share_percent_p2_5,count_share_percent_p97_5,top5_frequency\n",
    );
    for s in &study.summary {
        let (a, sh, c) = (&s.angular_area_deg2_s, &s.angular_area_share_percent, &s.count_share_percent);
        per_part.push_str(&format!(
            "{},{:.6},{:.6},{:.6},{:.6},{:.6},{:.4},{:.4},{:.4},{:.4},{:.4},{:.4},{:.4},{:.4},{:.4}\n",
            ufcsr::csv_field(&s.part),
            a.mean,
            a.mean_ci95[0],
            a.mean_ci95[1],
            a.p2_5,
            a.p97_5,
            sh.mean,
            sh.mean_ci95[0],
            sh.mean_ci95[1],
            sh.p2_5,
            sh.p97_5,
            c.mean,
            c.p2_5,
            c.p97_5,
            s.top5_frequency
        ));
    }
    let parts_path = dir.join("observer-parts.csv");
    ufcsr::write_bytes_atomically(&parts_path, per_part.as_bytes())?;
    Ok(vec![json_path, observers_path, parts_path])
}

#[cfg(test)]
mod tests {
    use super::*;

    fn options(kerb: Option<[[f64; 2]; 2]>, positions: u32, heights: u32) -> ObserverOptions {
        ObserverOptions {
            scenario: "A".into(),
            kerb,
            positions,
            eye_heights_m: [1.5, 1.9],
            heights,
            ppd: 6.0,
            frame_step: 30,
            capture: CaptureOptions::default(),
        }
    }

    #[test]
    fn the_grid_puts_each_observer_at_the_middle_of_its_cell() {
        let grid = observer_grid(&options(Some([[0.0, 0.0], [4.0, -2.0]]), 2, 4), [9.0, 9.0, 0.25]);
        assert_eq!(grid.len(), 8);
        // Positions at 1/4 and 3/4 of the segment, ground height kept; heights 1.55, 1.65, 1.75, 1.85.
        assert_eq!(grid[0].0, [1.0, -0.5, 0.25]);
        assert_eq!(grid[4].0, [3.0, -1.5, 0.25]);
        let heights: Vec<f64> = grid[..4].iter().map(|g| g.1).collect();
        for (h, want) in heights.iter().zip([1.55, 1.65, 1.75, 1.85]) {
            assert!((h - want).abs() < 1e-12, "{heights:?}");
        }
        // Without a kerb the rig's own position is kept.
        let grid = observer_grid(&options(None, 1, 1), [9.0, 9.0, 0.25]);
        assert_eq!(grid, vec![([9.0, 9.0, 0.25], 1.7)]);
    }

    #[test]
    fn bad_observer_options_are_refused_with_the_option_named() {
        let cases = [
            (options(None, 3, 1), "--kerb"),
            (options(Some([[0.0, 0.0], [1.0, 1.0]]), 0, 1), "--positions"),
            (options(Some([[0.0, 0.0], [1.0, 1.0]]), 30, 30), "--positions × --heights"),
            (ObserverOptions { eye_heights_m: [1.9, 1.5], ..options(None, 1, 1) }, "--eye-heights"),
            (ObserverOptions { eye_heights_m: [1.5, f64::NAN], ..options(None, 1, 1) }, "--eye-heights"),
            (options(Some([[0.0, 1e300], [1.0, 1.0]]), 2, 1), "--kerb"),
            (ObserverOptions { ppd: 0.0, ..options(None, 1, 1) }, "--ppd"),
        ];
        for (options, named) in cases {
            let message = check(&options).unwrap_err().to_string();
            assert!(message.contains(named), "{message} should name {named}");
        }
    }

    #[test]
    fn spread_of_known_values() {
        // Mean 2.5; the spread's ends are the smallest and largest of four values.
        let s = spread(&[1.0, 2.0, 3.0, 4.0], 1);
        assert!((s.mean - 2.5).abs() < 1e-12);
        assert_eq!((s.p2_5, s.p97_5), (1.0, 4.0));
        assert!(
            s.mean_ci95[0] >= 1.0 && s.mean_ci95[0] < 2.5 && s.mean_ci95[1] > 2.5 && s.mean_ci95[1] <= 4.0
        );
        // The same seed gives the same interval; one observer gives the point.
        assert_eq!(spread(&[1.0, 2.0, 3.0, 4.0], 1), s);
        assert_eq!(spread(&[7.0], 1).mean_ci95, [7.0, 7.0]);
    }

    #[test]
    fn top5_frequency_and_shares_over_observers() {
        let parts: Vec<String> = (0..6).map(|i| format!("p{i}")).collect();
        let observer = |area: [f64; 6]| Observer {
            position: [0.0; 3],
            eye_height_m: 1.75,
            seconds: 0.0,
            angular_area_deg2_s: area.to_vec(),
            count: area.to_vec(),
            results: PathBuf::new(),
        };
        // p5 is in the top five for one observer of two; p0 for none.
        let observers = [observer([0.0, 1.0, 2.0, 3.0, 4.0, 5.0]), observer([1.0, 2.0, 3.0, 4.0, 5.0, 0.0])];
        let summary = summarize(&parts, &observers);
        let find = |name: &str| summary.iter().find(|s| s.part == name).unwrap();
        assert_eq!(find("p5").top5_frequency, 0.5);
        assert_eq!(find("p0").top5_frequency, 0.5);
        assert_eq!(find("p4").top5_frequency, 1.0);
        // Shares: p4 is 4/15 and 5/15 of the two observers' totals.
        assert!((find("p4").angular_area_share_percent.mean - 100.0 * 4.5 / 15.0).abs() < 1e-9);
        assert_eq!(summary[0].part, "p4");
    }
}
