//! Uncertainty over the observer: one pedestrian is not a population.
//!
//! [`run_observer_study`] draws observers from a declared population
//! ([`population`]: where people stand, how tall they are, with named
//! sources), captures the scenario from each with the fused path (no PNGs)
//! and reports per part, over the observers ([`interval`]), the population
//! mean of the visible angular area (deg²·s), its share and the paper's
//! count share, each with a 95 % interval of the population mean that
//! shrinks as observers are added, the 2.5–97.5 % spread over people, and
//! each observer's own resolution error folded in: a second, coarser
//! capture (half the ppd, twice the frame step) bounds it by a two-grid
//! convergence index. The old grid stays as an explicit option, with no
//! interval claimed for its mean. With a display size, [`displays`] does
//! the same per candidate display (and part) for its legible seconds, from
//! an exact measure of each observer.

pub(crate) mod displays;
pub(crate) mod interval;
pub(crate) mod observer;
pub(crate) mod population;

pub use observer::{
    HUMAN_IPD_M, ObserverPreset, PAPER_EYE_HEIGHT_M, PAPER_IPD_M, describe_observer, median_eye_height_m,
    people_by_default,
};

use std::path::{Path, PathBuf};
use std::time::Instant;

use ufcsr::{
    Dedupe, format::CoarserCapture, format::OBSERVERS_SCHEMA, format::ObserverPlace,
    format::ObserverPopulation, format::ObserverRecord, format::ObserverSampling, format::ObserverStudy,
    format::PartOverObservers, format::ResolutionCheck,
};

use crate::error::{CaptureError, Result};
use crate::job::{CaptureOptions, CaptureSetup};
use crate::scene::Scene;
use crate::scene::track::ValueOrTrack;
use crate::study::{Setting, StudyMeasure, count_every_nth_frame, frame_table, rendered_per_eye_frame};
use interval::{IntervalKind, population_value};
use population::{SampledObserver, sample_observers};

/// The default safety factor of the resolution bound: Roache's for a
/// two-grid convergence index (P. J. Roache, "Perspective: a method for
/// uniform reporting of grid refinement studies", J. Fluids Eng. 116, 1994).
pub const DEFAULT_SAFETY_FACTOR: f64 = 3.0;

/// Which observers to capture, and at which setting.
#[derive(Debug, Clone)]
pub struct ObserverOptions {
    pub scenario: String,
    pub population: ObserverPopulation,
    pub sampling: ObserverSampling,
    pub resolution_check: ResolutionCheck,
    pub ppd: f64,
    pub frame_step: u32,
    /// Capture settings; `out` is the study folder (one sub-folder per observer).
    pub capture: CaptureOptions,
}

fn check(options: &ObserverOptions, scene: &Scene) -> Result<()> {
    let bad = |text: &str| Err(CaptureError::BadOptions(text.into()));
    if !(options.ppd.is_finite() && options.ppd > 0.0) || options.frame_step == 0 {
        return bad("--ppd must be positive and --frame-step at least 1");
    }
    if let ResolutionCheck::Coarser { safety_factor } = options.resolution_check
        && !(safety_factor.is_finite() && safety_factor >= 1.0)
    {
        return bad("--safety-factor must be at least 1");
    }
    if options.population.place != ObserverPlace::Rig && matches!(scene.rig.pedestrian, ValueOrTrack::Keys(_))
    {
        return bad(
            "--kerb / --area place standing observers, but the scene's pedestrian walks: leave them out to keep \
             the walk and vary the eye height",
        );
    }
    Ok(())
}

/// The interval the study's sampling supports.
fn interval_kind(sampling: &ObserverSampling) -> IntervalKind {
    match sampling {
        ObserverSampling::Random { .. } => IntervalKind::MonteCarlo,
        ObserverSampling::Grid { .. } => IntervalKind::None,
    }
}

/// What the intervals of a study are, in one sentence (written with them).
fn interval_sentence(options: &ObserverOptions) -> String {
    let resolution = match options.resolution_check {
        ResolutionCheck::None => "the observers' resolution error is NOT included".to_string(),
        ResolutionCheck::Coarser { safety_factor } => format!(
            "widened by the mean of the observers' resolution bounds ({safety_factor} × |value − value at half the \
             ppd and twice the frame step|)"
        ),
    };
    match options.sampling {
        ObserverSampling::Random { .. } => format!(
            "95 % interval of the population mean: mean ± t(0.975, n−1)·s/√n over independently drawn observers, \
             {resolution}; it covers the sampling of observers and their resolution, not the population's \
             declared figures, the scene or the scenario"
        ),
        ObserverSampling::Grid { .. } => {
            format!("a grid of observers: no interval is claimed for its mean ({resolution})")
        }
    }
}

/// Captures the scenario from every observer and summarises the parts over them.
pub fn run_observer_study(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    scene: &Scene,
    options: &ObserverOptions,
) -> Result<ObserverStudy> {
    check(options, scene)?;
    // A scene file (or mesh) named observers.json, observers.csv,
    // observer-parts.csv (.png, .pdf) or observer-displays.csv in --out is refused, never
    // replaced nor removed as stale (as study does).
    crate::job::overwrite_guard::refuse_overwriting_inputs(
        &options.capture.out,
        &[OBSERVER_FILES.as_slice(), &[displays::OBSERVER_DISPLAYS_FILE]].concat(),
        &[],
        &crate::job::capture_inputs(scene, &options.capture),
    )?;
    let scenario = scene.scenario(&options.scenario)?;
    let start = Instant::now();
    let sampled = sample_observers(&options.population, &options.sampling, scene.rig.anchor().to_array())?;
    let mut parts = Vec::new();
    let mut observers = Vec::with_capacity(sampled.len());
    // Built by the first observer, in its folder, and handed to the others.
    let mut setup = None;
    for (index, observer) in sampled.iter().enumerate() {
        let (record, observer_parts) =
            capture_observer(device, queue, scene, options, (index, observer), &mut setup)?;
        if index == 0 {
            parts = observer_parts;
        } else if observer_parts != parts {
            return Err(CaptureError::BadOptions("the observers' captures name different parts".into()));
        }
        eprintln!(
            "observers: {}/{} at ({:.2}, {:.2}) m, eye {:.3} m: {:.2} s",
            index + 1,
            sampled.len(),
            record.position[0],
            record.position[1],
            record.eye_height_m,
            record.seconds
        );
        observers.push(record);
    }
    if parts.is_empty() {
        return Err(CaptureError::BadOptions(
            "the observer study needs a PIdT and legend to compare parts".into(),
        ));
    }
    let summary = summarize(&parts, &observers, interval_kind(&options.sampling), options.resolution_check);
    Ok(ObserverStudy {
        schema: OBSERVERS_SCHEMA.into(),
        scenario: scenario.name.clone(),
        ppd: options.ppd,
        frame_step: options.frame_step,
        population: options.population.clone(),
        sampling: options.sampling.clone(),
        resolution_check: options.resolution_check,
        interval: interval_sentence(options),
        parts,
        observers,
        summary,
        seconds: start.elapsed().as_secs_f64(),
        setup_seconds: setup.map_or(0.0, |setup: CaptureSetup| setup.seconds),
        displays: None,
    })
}

/// One capture of one observer: per part, deg²·s per eye and the count.
struct PartTotals {
    angular_area_deg2_s: Vec<f64>,
    count: Vec<f64>,
    parts: Vec<String>,
    seconds: f64,
    results: PathBuf,
}

/// The scene as `observer` sees it at `ppd`.
fn observer_scene(
    scene: &Scene,
    options: &ObserverOptions,
    observer: &SampledObserver,
    ppd: f64,
) -> Result<Scene> {
    let mut scene = scene.clone();
    if options.population.place != ObserverPlace::Rig {
        scene.rig.pedestrian = ValueOrTrack::Fixed(observer.position);
    }
    scene.rig.eye_height_m = observer.eye_height_m;
    scene.rig.set_pixels_per_degree(ppd)?;
    scene.rig.check().map_err(|e| CaptureError::BadOptions(format!("observer at {observer:?}: {e}")))?;
    Ok(scene)
}

/// The fused count of `scene` at every `step`-th frame into `out`, reduced per part.
fn capture_totals(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    (scene, options): (&Scene, &ObserverOptions),
    (out, step): (&Path, u32),
    setup: &mut Option<CaptureSetup>,
) -> Result<PartTotals> {
    let setting = Setting { name: &options.scenario, out, step, dedupe: Dedupe::Frame };
    let (counted, frames) = count_every_nth_frame(device, queue, scene, &options.capture, &setting, setup)?;
    let table = frame_table(&counted, out)?;
    let solid = rendered_per_eye_frame(table, StudyMeasure::AngularArea, out)?;
    let count = rendered_per_eye_frame(table, StudyMeasure::Count, out)?;
    // deg²·s per eye: Σ sr × (180/π)² × seconds per frame / 2 eyes, the seconds a
    // frame stands for read as the observer's own result.json reads them (the step
    // between the frames captured: one frame's worth when the scenario is shorter
    // than the step, not the step's).
    let to_deg2_s =
        (180.0 / std::f64::consts::PI).powi(2) * crate::exact::seconds_per_frame(scene, &frames) / 2.0;
    let sum = |values: &crate::exact::accuracy::PerEyeFrame, scale: f64| -> Vec<f64> {
        let mut totals = vec![0.0; values.parts.len()];
        for (_, _, row) in &values.rows {
            totals.iter_mut().zip(row).for_each(|(t, v)| *t += v * scale);
        }
        totals
    };
    Ok(PartTotals {
        angular_area_deg2_s: sum(&solid, to_deg2_s),
        count: sum(&count, 1.0),
        seconds: counted.summary.seconds,
        results: counted.written.result_json,
        parts: solid.parts,
    })
}

/// The coarser setting's frame step: twice the study's, unless the
/// scenario has too few frames for it to capture two (then the study's). A
/// capture of one frame stands for one frame's time (as its result.json
/// says), so a coarser capture of one frame of two would measure half the
/// fine one's time, and the bound would be that difference, not resolution.
fn coarser_step(step: u32, frames: u32) -> u32 {
    let doubled = step.saturating_mul(2);
    if crate::job::FrameSelection::every(doubled).frames(frames).len() >= 2 { doubled } else { step }
}

/// One observer: the fused count at the study's setting and, when asked,
/// the coarser one behind its resolution bound (set-up shared, built by the first).
fn capture_observer(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    scene: &Scene,
    options: &ObserverOptions,
    (index, observer): (usize, &SampledObserver),
    setup: &mut Option<CaptureSetup>,
) -> Result<(ObserverRecord, Vec<String>)> {
    // A link planted at observer-NNN is replaced by a real folder, never written through.
    let out = ufcsr::files::output_sub_dir(&options.capture.out, Path::new(&format!("observer-{index:03}")))?;
    let fine_scene = observer_scene(scene, options, observer, options.ppd)?;
    let fine = capture_totals(device, queue, (&fine_scene, options), (&out, options.frame_step), setup)?;
    let mut seconds = fine.seconds;
    let (mut coarser, mut bound) = (None, None);
    if let ResolutionCheck::Coarser { safety_factor } = options.resolution_check {
        let ppd = options.ppd / 2.0;
        let frames = fine_scene.rig.frame_count(scene.scenario(&options.scenario)?.duration_s);
        let step = coarser_step(options.frame_step, frames);
        let coarse_scene = observer_scene(scene, options, observer, ppd)?;
        let coarse =
            capture_totals(device, queue, (&coarse_scene, options), (&out.join("coarser"), step), setup)?;
        seconds += coarse.seconds;
        bound = Some(bounds(&fine.angular_area_deg2_s, &coarse.angular_area_deg2_s, safety_factor));
        coarser = Some(CoarserCapture {
            ppd,
            frame_step: step,
            angular_area_deg2_s: coarse.angular_area_deg2_s,
            count: coarse.count,
        });
    }
    let record = ObserverRecord {
        position: observer.position,
        group: observer.group.clone(),
        stature_m: observer.stature_m,
        eye_height_m: observer.eye_height_m,
        seconds,
        angular_area_deg2_s: fine.angular_area_deg2_s,
        count: fine.count,
        angular_area_bound_deg2_s: bound,
        coarser,
        results: fine.results,
    };
    Ok((record, fine.parts))
}

/// Per part, `safety_factor` × |fine − coarse|.
fn bounds(fine: &[f64], coarse: &[f64], safety_factor: f64) -> Vec<f64> {
    fine.iter().zip(coarse).map(|(f, c)| safety_factor * (f - c).abs()).collect()
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

/// One measure per observer and part, with its per-observer resolution
/// bounds when the coarser captures give them.
struct Measure {
    values: Vec<Vec<f64>>,
    bounds: Option<Vec<Vec<f64>>>,
}

impl Measure {
    /// `of` the fine capture's per-part values and `coarse` the coarser's.
    fn new(
        observers: &[ObserverRecord],
        of: impl Fn(&[f64], &[f64]) -> Vec<f64>,
        check: ResolutionCheck,
    ) -> Measure {
        let values =
            observers.iter().map(|o| of(o.angular_area_deg2_s.as_slice(), o.count.as_slice())).collect();
        let coarse: Vec<Option<Vec<f64>>> = observers
            .iter()
            .map(|o| {
                let coarse = o.coarser.as_ref()?;
                Some(of(coarse.angular_area_deg2_s.as_slice(), coarse.count.as_slice()))
            })
            .collect();
        Measure::from_rows(values, &coarse, check)
    }

    /// Per observer the values (one per column) and, where it was
    /// captured, the coarser setting's: the one path parts and displays
    /// ([`displays`]) take to their bounds.
    fn from_rows(values: Vec<Vec<f64>>, coarse: &[Option<Vec<f64>>], check: ResolutionCheck) -> Measure {
        let bounds = match check {
            ResolutionCheck::None => None,
            ResolutionCheck::Coarser { safety_factor } => values
                .iter()
                .zip(coarse)
                .map(|(fine, coarse)| Some(bounds(fine, coarse.as_deref()?, safety_factor)))
                .collect(),
        };
        Measure { values, bounds }
    }

    fn at(&self, part: usize, kind: IntervalKind) -> ufcsr::format::PopulationValue {
        let column = |rows: &[Vec<f64>]| -> Vec<f64> { rows.iter().map(|r| r[part]).collect() };
        let bounds = self.bounds.as_deref().map(column);
        population_value(&column(&self.values), bounds.as_deref(), kind)
    }
}

/// Per part over the observers, largest mean angular area first.
pub fn summarize(
    parts: &[String],
    observers: &[ObserverRecord],
    kind: IntervalKind,
    check: ResolutionCheck,
) -> Vec<PartOverObservers> {
    let area = Measure::new(observers, |area, _| area.to_vec(), check);
    let area_share = Measure::new(observers, |area, _| shares(area), check);
    let count_share = Measure::new(observers, |_, count| shares(count), check);
    let tops: Vec<Vec<usize>> = observers.iter().map(|o| top5(&o.angular_area_deg2_s)).collect();
    let mut summary: Vec<PartOverObservers> = parts
        .iter()
        .enumerate()
        .map(|(p, part)| PartOverObservers {
            part: part.clone(),
            angular_area_deg2_s: area.at(p, kind),
            angular_area_share_percent: area_share.at(p, kind),
            count_share_percent: count_share.at(p, kind),
            top5_frequency: tops.iter().filter(|t| t.contains(&p)).count() as f64 / observers.len() as f64,
        })
        .collect();
    summary.sort_by(|a, b| b.angular_area_deg2_s.mean.total_cmp(&a.angular_area_deg2_s.mean));
    summary
}

/// An optional number for a CSV cell (empty when absent).
fn cell(value: Option<f64>) -> String {
    value.map_or_else(String::new, |v| format!("{v:.6}"))
}

/// The files [`write_observer_study`] writes into the study's folder.
const OBSERVER_FILES: [&str; 5] =
    ["observers.json", "observers.csv", "observer-parts.csv", "observer-parts.png", "observer-parts.pdf"];

/// Writes `observers.json` (with the study's `displays` when it has them),
/// `observers.csv` (one row per observer and part), `observer-parts.csv`
/// (one row per part) and, with a font, its figure (`observer-parts.png`,
/// `.pdf`: each part's mean with its interval); returns what was written. Without displays an
/// earlier run's `observer-displays.csv` is removed: it describes other
/// observers.
pub fn write_observer_study(study: &ObserverStudy, dir: &Path) -> Result<Vec<PathBuf>> {
    ufcsr::files::create_output_dir(dir)?;
    let json_path = dir.join("observers.json");
    let json =
        serde_json::to_vec_pretty(study).map_err(|e| CaptureError::bad_file(&json_path, e.to_string()))?;
    ufcsr::files::write_bytes_atomically(&json_path, &json)?;
    let mut per_observer = String::from(
        "observer,x_m,y_m,group,stature_m,eye_height_m,part,angular_area_deg2_s,angular_area_bound_deg2_s,count\n",
    );
    for (i, o) in study.observers.iter().enumerate() {
        for (p, part) in study.parts.iter().enumerate() {
            let bound = o.angular_area_bound_deg2_s.as_ref().map(|b| b[p]);
            per_observer.push_str(&format!(
                "{i},{},{},{},{},{},{},{},{},{}\n",
                o.position[0],
                o.position[1],
                ufcsr::output::csv_field(o.group.as_deref().unwrap_or("")),
                o.stature_m.map_or_else(String::new, |s| s.to_string()),
                o.eye_height_m,
                ufcsr::output::csv_field(part),
                o.angular_area_deg2_s[p],
                bound.map_or_else(String::new, |b| b.to_string()),
                o.count[p]
            ));
        }
    }
    let observers_path = dir.join("observers.csv");
    ufcsr::files::write_bytes_atomically(&observers_path, per_observer.as_bytes())?;
    let parts_path = dir.join("observer-parts.csv");
    ufcsr::files::write_bytes_atomically(&parts_path, parts_table(study).as_bytes())?;
    let mut written = vec![json_path, observers_path, parts_path];
    written.extend(parts_figure(study).write(&dir.join("observer-parts"))?);
    remove_stale_observers(dir, study.observers.len())?;
    if study.displays.is_none() {
        ufcsr::files::remove_inside(dir, &dir.join(displays::OBSERVER_DISPLAYS_FILE))?;
    }
    Ok(written)
}

/// Parts drawn in the observers' figure at most (the largest mean angular area first).
const FIGURE_PARTS: usize = 20;

/// The per-part angular area over the observers as a figure (issue 44 §2,
/// `observer-parts.png` and `.pdf`): each part's population mean with its
/// 95 % interval (none on a grid), the largest first.
fn parts_figure(study: &ObserverStudy) -> ufcsr::output::IntervalFigure {
    let rows = study
        .summary
        .iter()
        .filter(|part| part.angular_area_deg2_s.mean > 0.0)
        .take(FIGURE_PARTS)
        .map(|part| ufcsr::output::IntervalRow {
            label: ufcsr::output::readable_part_name(&part.part),
            value: part.angular_area_deg2_s.mean,
            interval: part.angular_area_deg2_s.mean_ci95,
        })
        .collect();
    ufcsr::output::IntervalFigure {
        title: format!("Scenario {}: angular area per part over the observers", study.scenario),
        axis: "angular area per eye, mean over the observers (deg²·s; whiskers: 95 % interval)".into(),
        rows,
    }
}

/// Removes the `observer-NNN` folders of an earlier study into `dir` with
/// more observers than this one (`observer-003` … after a study of 3): they
/// describe observers the new tables do not list. Only inside `dir`, never
/// through a link.
fn remove_stale_observers(dir: &Path, observers: usize) -> Result<()> {
    let Ok(entries) = std::fs::read_dir(dir) else { return Ok(()) };
    for entry in entries.flatten() {
        let name = entry.file_name();
        let index =
            name.to_str().and_then(|n| n.strip_prefix("observer-")).and_then(|n| n.parse::<usize>().ok());
        if index.is_some_and(|index| index >= observers) {
            ufcsr::files::remove_inside(dir, &entry.path())?;
        }
    }
    Ok(())
}

/// `observer-parts.csv`: per part and measure, the mean, its interval (empty
/// on a grid), the Monte Carlo half-width, the resolution bound and the spread.
fn parts_table(study: &ObserverStudy) -> String {
    let measures = ["angular_area_deg2_s", "area_share_percent", "count_share_percent"];
    let columns =
        ["mean", "ci95_low", "ci95_high", "monte_carlo_half_width", "resolution_bound", "p2_5", "p97_5"];
    let mut header = vec!["part".to_string()];
    header.extend(measures.iter().flat_map(|m| columns.iter().map(move |c| format!("{m}_{c}"))));
    header.push("top5_frequency".into());
    let mut table = header.join(",") + "\n";
    for s in &study.summary {
        let mut row = vec![ufcsr::output::csv_field(&s.part)];
        for v in [&s.angular_area_deg2_s, &s.angular_area_share_percent, &s.count_share_percent] {
            row.extend([
                cell(Some(v.mean)),
                cell(v.mean_ci95.map(|c| c[0])),
                cell(v.mean_ci95.map(|c| c[1])),
                cell(v.monte_carlo_half_width),
                cell(v.resolution_bound),
                cell(Some(v.p2_5)),
                cell(Some(v.p97_5)),
            ]);
        }
        row.push(format!("{:.4}", s.top5_frequency));
        table.push_str(&(row.join(",") + "\n"));
    }
    table
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record(area: [f64; 6], coarse: Option<[f64; 6]>) -> ObserverRecord {
        ObserverRecord {
            position: [0.0; 3],
            group: None,
            stature_m: None,
            eye_height_m: 1.6,
            seconds: 0.0,
            angular_area_deg2_s: area.to_vec(),
            count: area.to_vec(),
            angular_area_bound_deg2_s: None,
            coarser: coarse.map(|c| CoarserCapture {
                ppd: 1.0,
                frame_step: 2,
                angular_area_deg2_s: c.to_vec(),
                count: c.to_vec(),
            }),
            results: PathBuf::new(),
        }
    }

    #[test]
    fn top5_frequency_and_shares_over_observers() {
        let parts: Vec<String> = (0..6).map(|i| format!("p{i}")).collect();
        // p5 is in the top five for one observer of two; p0 for the other.
        let observers =
            [record([0.0, 1.0, 2.0, 3.0, 4.0, 5.0], None), record([1.0, 2.0, 3.0, 4.0, 5.0, 0.0], None)];
        let summary = summarize(&parts, &observers, IntervalKind::MonteCarlo, ResolutionCheck::None);
        let find = |name: &str| summary.iter().find(|s| s.part == name).unwrap();
        assert_eq!(find("p5").top5_frequency, 0.5);
        assert_eq!(find("p0").top5_frequency, 0.5);
        assert_eq!(find("p4").top5_frequency, 1.0);
        // Shares: p4 is 4/15 and 5/15 of the two observers' totals.
        assert!((find("p4").angular_area_share_percent.mean - 100.0 * 4.5 / 15.0).abs() < 1e-9);
        assert_eq!(summary[0].part, "p4");
        assert!(find("p4").angular_area_deg2_s.resolution_bound.is_none());
    }

    #[test]
    fn the_resolution_bound_is_the_safety_factor_times_the_coarser_difference_averaged_over_observers() {
        let parts: Vec<String> = (0..6).map(|i| format!("p{i}")).collect();
        let a = record([1.0, 1.0, 1.0, 1.0, 1.0, 10.0], Some([1.0, 1.0, 1.0, 1.0, 1.0, 9.0]));
        let b = record([1.0, 1.0, 1.0, 1.0, 1.0, 12.0], Some([1.0, 1.0, 1.0, 1.0, 1.0, 12.5]));
        let check = ResolutionCheck::Coarser { safety_factor: 3.0 };
        let summary = summarize(&parts, &[a, b], IntervalKind::MonteCarlo, check);
        let p5 = summary.iter().find(|s| s.part == "p5").unwrap().angular_area_deg2_s;
        // Bounds 3 × 1 and 3 × 0.5: mean 2.25, added to t(0.975, 1) · s/√2 = 12.706 × 1.
        assert!((p5.resolution_bound.unwrap() - 2.25).abs() < 1e-12);
        let [low, high] = p5.mean_ci95.unwrap();
        assert!((high - 11.0 - 12.706 - 2.25).abs() < 1e-9, "{high}");
        // 11 − 12.706 − 2.25 is below 0, and a mean of areas cannot be: the low end is cut at 0.
        assert_eq!(low, 0.0);
        // A grid keeps the bound but claims no interval.
        let grid = summarize(&parts, &[record([1.0; 6], Some([1.0; 6]))], IntervalKind::None, check);
        assert_eq!(
            (grid[0].angular_area_deg2_s.mean_ci95, grid[0].angular_area_deg2_s.resolution_bound),
            (None, Some(0.0))
        );
    }

    #[test]
    fn the_coarser_step_doubles_unless_the_scenario_is_too_short() {
        assert_eq!(coarser_step(6, 181), 12);
        assert_eq!(coarser_step(1, 1), 1);
        // Two frames: a doubled step would capture one (a still plate's bound came out 1000x).
        assert_eq!(coarser_step(1, 2), 1);
        // Three: every 2nd frame keeps frame 0 alone (frame 2's step lies half outside).
        assert_eq!(coarser_step(1, 3), 1);
        assert_eq!(coarser_step(1, 4), 2);
        assert_eq!(coarser_step(3, 5), 3);
    }
}
