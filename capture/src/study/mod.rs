//! The resolution study: which resolution and frame rate give numbers close
//! to the truth, and at what cost.
//!
//! [`run_study`] captures and counts one scenario at every combination of
//! `ppd` and frame step with the fused path (no PNGs), times each, and
//! compares each with the exact counterpart of the studied measure
//! ([`StudyMeasure`]: the count ↔ any-part visibility, the angular area ↔
//! the ray-traced solid angle), computed once by the ray tracer on every
//! frame any setting uses: each setting on its own eye-frames, with a 95 %
//! interval ([`crate::exact::accuracy`]). The Pareto front of error
//! against cost and the recommendation (the cheapest setting whose
//! interval lies within the tolerance) use that error; when no setting is
//! within it the study says so and names the closest. *Cost* is the pixels
//! rendered ([`StudyRow::pixels_rendered`]), a function of the scene and the
//! setting, so the pick does not swap between two near-equal settings with
//! the machine's load; the measured seconds are reported beside it. The comparison with
//! the finest setting stays, as *precision* (self-consistency, not
//! accuracy), and is what the front uses only with `--no-exact`.
//!
//! [`observers`] is the other question a study answers: how much the answer
//! depends on the pedestrian (kerb position, eye height).

pub(crate) mod observers;
pub(crate) mod offsets;
pub(crate) mod plot;
pub(crate) mod reference;

pub use observers::displays::{
    DisplayOptions, DisplayStudy, OBSERVER_DISPLAYS_FILE, ObserverLegible, run_observer_displays,
    summarize_displays, write_display_study,
};
pub use observers::interval::{IntervalKind, percentile, population_value};
pub use observers::population::{
    MAX_OBSERVERS, SampledObserver, check_population, eye_height_quantile, normal_cdf, sample_observers,
};
pub use observers::{
    DEFAULT_SAFETY_FACTOR, HUMAN_IPD_M, ObserverOptions, ObserverPreset, PAPER_EYE_HEIGHT_M, PAPER_IPD_M,
    describe_observer, median_eye_height_m, people_by_default, run_observer_study,
    summarize as summarize_observers, write_observer_study,
};
pub use offsets::{FrameValues, IntervalOptions, error_at_offset, setting_error};

use std::path::{Path, PathBuf};

use serde::Serialize;
use ufcsr::Dedupe;
pub use ufcsr::{
    format::ErrorVsExact, format::ExactReference, format::Study, format::StudyPick, format::StudyRow,
};

use crate::error::{CaptureError, Result};
use crate::exact::accuracy::{PerEyeFrame, share_error, totals};
use crate::job::{CaptureOptions, CaptureProgress, CaptureSetup, CountedCapture, FrameSelection};
use crate::scene::Scene;
pub use reference::{StudyTables, exact_tables};

/// What a study compares.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum StudyMeasure {
    /// The paper's count, once per eye-frame (texels seen per eye-frame) ↔
    /// any-part visibility.
    Count,
    /// Visible angular area (solid angle of the pixels) ↔ the ray-traced
    /// solid angle.
    AngularArea,
}

impl StudyMeasure {
    pub fn name(self) -> &'static str {
        match self {
            StudyMeasure::Count => "count",
            StudyMeasure::AngularArea => "angular-area",
        }
    }
}

/// Bootstrap replicates for the 95 % intervals (per imputed offset).
pub const BOOTSTRAP_REPLICATES: u32 = 1000;

/// What to study.
#[derive(Debug, Clone)]
pub struct StudyOptions {
    pub scenario: String,
    /// Pixels per degree to try (the highest is the precision reference).
    pub ppds: Vec<f64>,
    /// Every n-th frame (the smallest is the precision reference).
    pub frame_steps: Vec<u32>,
    /// Largest acceptable share L1 error, percentage points.
    pub tolerance_pp: f64,
    pub dedupe: Dedupe,
    pub measure: StudyMeasure,
    /// Capture settings; `out` is the study folder (one sub-folder per setting).
    pub capture: CaptureOptions,
    /// The exact counterpart on this share of the texels (1 = all, the
    /// default), in `out/exact`; `None` skips it (`--no-exact`).
    pub exact_sample: Option<f64>,
}

/// One captured setting, before comparison.
struct Run {
    ppd: f64,
    step: u32,
    frames: Vec<u32>,
    seconds: f64,
    pixels_rendered: u64,
    grand_total: u64,
    texels_seen: u64,
    values: PerEyeFrame,
    results: PathBuf,
}

fn check(options: &StudyOptions) -> Result<()> {
    if options.ppds.is_empty() || options.frame_steps.is_empty() {
        return Err(CaptureError::BadOptions("a study needs at least one --ppd and one --frame-step".into()));
    }
    if options.frame_steps.contains(&0) || options.ppds.iter().any(|p| !p.is_finite() || *p <= 0.0) {
        return Err(CaptureError::BadOptions(
            "--ppd values must be positive and --frame-step at least 1".into(),
        ));
    }
    if let Some(sample) = options.exact_sample
        && !(sample > 0.0 && sample <= 1.0)
    {
        return Err(CaptureError::BadOptions(format!("--exact-sample must be in (0, 1], not {sample}")));
    }
    if !(options.tolerance_pp.is_finite() && options.tolerance_pp >= 0.0) {
        return Err(CaptureError::BadOptions("--tolerance must be a share error ≥ 0 pp".into()));
    }
    Ok(())
}

/// Captures every setting and compares it with the exact measure of every
/// frame and the finest setting.
pub fn run_study(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    scene: &Scene,
    options: &StudyOptions,
) -> Result<Study> {
    Ok(run_study_with_tables(device, queue, scene, options)?.0)
}

/// [`run_study`], and the per-frame tables it compared (empty without the
/// exact measure): what the coverage of its intervals is tested on.
pub fn run_study_with_tables(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    scene: &Scene,
    options: &StudyOptions,
) -> Result<(Study, StudyTables)> {
    check(options)?;
    // study.* beside the runs' archives (each checks its own files).
    crate::job::overwrite_guard::refuse_overwriting_inputs(
        &options.capture.out,
        &STUDY_FILES,
        &[],
        &crate::job::capture_inputs(scene, &options.capture),
    )?;
    let scenario = scene.scenario(&options.scenario)?;
    let mut ppds = options.ppds.clone();
    ppds.sort_by(|a, b| b.total_cmp(a));
    ppds.dedup();
    let mut steps = options.frame_steps.clone();
    steps.sort_unstable();
    steps.dedup();
    let mut runs = Vec::new();
    // Built by the first setting, in its folder, and handed to the others.
    let mut setup = None;
    for &ppd in &ppds {
        for &step in &steps {
            let setting = SettingRun { ppd, step, setup: &mut setup };
            runs.push(capture_setting(device, queue, scene, options, setting)?);
        }
    }
    let setup_seconds = setup.map_or(0.0, |setup| setup.seconds);
    let exact = options
        .exact_sample
        .map(|sample| reference::measure_exact(device, queue, scene, options, sample))
        .transpose()?;
    let parts = runs[0].values.parts.clone();
    if parts.is_empty() {
        return Err(CaptureError::BadOptions("the study needs a PIdT and legend to compare parts".into()));
    }
    let mut tables = match &exact {
        Some(exact) => reference::exact_tables(exact, options.measure, &parts)?,
        None => StudyTables::default(),
    };
    if exact.is_some() {
        for run in &runs {
            tables.add_rendered(run.ppd, &run.values, &run.results)?;
        }
    }
    let mut rows = compare_runs(runs, &parts, exact.is_some().then_some(&tables), options.measure)?;
    mark_pareto_front(&mut rows);
    let mut study = Study {
        scenario: scenario.name.clone(),
        measure: options.measure.name().into(),
        reference: rows[0].label(),
        exact: exact.map(|e| ExactReference {
            sample: options.exact_sample.unwrap_or(1.0),
            sampled_texels: e.sampled_texels,
            labelled_texels: e.labelled_texels,
            eye_frames: e.eye_frames,
            seconds: e.seconds,
            results: e.written.result_json.clone(),
        }),
        tolerance_pp: options.tolerance_pp,
        setup_seconds,
        rows,
        recommended: None,
        reason: None,
        closest: None,
    };
    recommend(&mut study);
    Ok((study, tables))
}

/// Every run against the exact measure of every frame (when there is one)
/// and the finest run.
fn compare_runs(
    runs: Vec<Run>,
    parts: &[String],
    tables: Option<&StudyTables>,
    measure: StudyMeasure,
) -> Result<Vec<StudyRow>> {
    let reference = totals(&runs[0].values.select(&runs[0].frames).unwrap_or_default(), parts.len());
    let mut rows = Vec::with_capacity(runs.len());
    for run in runs {
        let candidate = totals(&run.values.select(&run.frames).unwrap_or_default(), parts.len());
        let error_vs_exact = tables.map(|tables| compare_with_exact(&run, tables, measure)).transpose()?;
        rows.push(StudyRow {
            ppd: run.ppd,
            frame_step: run.step,
            frames: run.frames.len() as u32,
            seconds: run.seconds,
            pixels_rendered: run.pixels_rendered,
            grand_total: run.grand_total,
            texels_seen: run.texels_seen,
            precision: share_error(parts, &reference, &candidate),
            error_vs_exact,
            pareto: false,
            results: run.results,
        });
    }
    Ok(rows)
}

/// One setting against the exact measure of every frame, with its interval
/// over frame offsets ([`offsets`]).
fn compare_with_exact(run: &Run, tables: &StudyTables, measure: StudyMeasure) -> Result<ErrorVsExact> {
    let missing = || {
        CaptureError::bad_file(
            &run.results,
            format!("{} px/°: frames missing from the study's tables", run.ppd),
        )
    };
    let values = tables.values(run.ppd).ok_or_else(missing)?;
    let interval = IntervalOptions {
        step: run.step,
        // The frames the setting captured (`FrameSelection::every`).
        offset: crate::job::step_phase(run.step),
        relative_error: &tables.relative_error,
        replicates: BOOTSTRAP_REPLICATES,
        seed: 1,
    };
    setting_error(&tables.parts, measure.name(), values, &interval).ok_or_else(missing)
}

/// One setting of a study to capture, and the set-up the settings share
/// (none before the first).
struct SettingRun<'a> {
    ppd: f64,
    step: u32,
    setup: &'a mut Option<CaptureSetup>,
}

/// Captures and counts one setting with the fused path.
fn capture_setting(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    scene: &Scene,
    options: &StudyOptions,
    run: SettingRun,
) -> Result<Run> {
    let SettingRun { ppd, step, setup } = run;
    let mut scene = scene.clone();
    scene.rig.set_pixels_per_degree(ppd)?;
    // A link planted at ppdN-stepM is replaced by a real folder, never written through.
    let out = ufcsr::files::output_sub_dir(&options.capture.out, Path::new(&format!("ppd{ppd}-step{step}")))?;
    let setting = Setting { name: &options.scenario, out: &out, step, dedupe: options.dedupe };
    let (counted, frames) = count_every_nth_frame(device, queue, &scene, &options.capture, &setting, setup)?;
    eprintln!(
        "study: {ppd} px/°, every {step} frame(s): {} frames in {:.2} s ({:.3} s of it set-up)",
        counted.summary.frames, counted.summary.seconds, counted.summary.setup_seconds
    );
    Ok(Run {
        ppd,
        step,
        frames,
        seconds: counted.summary.seconds,
        pixels_rendered: counted.summary.pixels,
        grand_total: counted.analysis.result.grand_total,
        texels_seen: counted.analysis.result.texels_seen,
        values: rendered_per_eye_frame(frame_table(&counted, &out)?, options.measure, &out)?,
        results: counted.written.result_json,
    })
}

/// One capture of a study: the scenario, its folder, the frame step and
/// what one count means.
struct Setting<'a> {
    name: &'a str,
    out: &'a Path,
    step: u32,
    dedupe: Dedupe,
}

/// The fused count of `scene` (its rig as the setting needs it) at every
/// `step`-th frame into `out`, with `base`'s other capture settings; and
/// the frames it covered. `setup` is the set-up the study's captures share:
/// the first builds it in its own folder (timed apart, not in its
/// `seconds`), the others reuse it.
fn count_every_nth_frame(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    scene: &Scene,
    base: &CaptureOptions,
    setting: &Setting,
    setup: &mut Option<CaptureSetup>,
) -> Result<(CountedCapture, Vec<u32>)> {
    let scenario = scene.scenario(setting.name)?;
    let frame_count = scene.rig.frame_count(scenario.duration_s);
    let step = setting.step;
    let capture = CaptureOptions {
        out: setting.out.to_path_buf(),
        frames: FrameSelection::every(step),
        progress: CaptureProgress::default(),
        ..base.clone()
    };
    let setup = match setup {
        Some(setup) => setup,
        None => setup.insert(CaptureSetup::new(device, queue, scene, &capture)?),
    };
    let counted = setup.capture_counted(device, queue, scene, scenario, &capture, setting.dedupe)?;
    Ok((counted, FrameSelection::every(step).frames(frame_count)))
}

/// The per-eye-frame tallies a fused count keeps.
fn frame_table<'c>(counted: &'c CountedCapture, out: &Path) -> Result<&'c ufcsr::FrameTable> {
    counted.analysis.frames.as_ref().ok_or_else(|| {
        CaptureError::BadOptions(format!("{}: the fused count kept no per-eye-frame tallies", out.display()))
    })
}

/// The rendered measure per eye-frame and legend part (the `(unlabelled)`
/// slot left out): texels seen (count) or the pixels' solid angle, sr.
fn rendered_per_eye_frame(
    table: &ufcsr::FrameTable,
    measure: StudyMeasure,
    out: &Path,
) -> Result<PerEyeFrame> {
    let keep: Vec<usize> = (0..table.parts.len()).filter(|&p| !table.parts[p].starts_with('(')).collect();
    let mut rows = Vec::with_capacity(table.records.len());
    for record in &table.records {
        let ufcsr::FrameLabel::EyeFrame(eye_frame) = &record.label else {
            return Err(CaptureError::bad_file(out, "the study's capture has eye-frames without a manifest"));
        };
        let values = match measure {
            StudyMeasure::Count => keep.iter().map(|&p| record.texels[p] as f64).collect(),
            StudyMeasure::AngularArea => {
                let solid = record.solid_angle_sr.as_ref().ok_or_else(|| {
                    CaptureError::bad_file(out, "no solid angles per pixel (the manifest has no projection)")
                })?;
                keep.iter().map(|&p| solid[p]).collect()
            }
        };
        rows.push((eye_frame.frame, eye_frame.eye.clone(), values));
    }
    Ok(PerEyeFrame { parts: keep.iter().map(|&p| table.parts[p].clone()).collect(), rows })
}

/// A row is on the front when no other row is at least as cheap (pixels
/// rendered) and at least as close, and strictly better in one of the two.
fn mark_pareto_front(rows: &mut [StudyRow]) {
    let points: Vec<(f64, f64)> =
        rows.iter().map(|r| (r.pixels_rendered as f64, r.ranking_error())).collect();
    for (i, row) in rows.iter_mut().enumerate() {
        let (time, error) = points[i];
        row.pareto = !points
            .iter()
            .enumerate()
            .any(|(j, &(t, e))| j != i && t <= time && e <= error && (t < time || e < error));
    }
}

fn pick(row: &StudyRow) -> StudyPick {
    let exact = row.error_vs_exact.as_ref();
    StudyPick {
        setting: row.label(),
        ppd: row.ppd,
        frame_step: row.frame_step,
        seconds: row.seconds,
        pixels_rendered: row.pixels_rendered,
        against: if exact.is_some() { "exact" } else { "precision" }.into(),
        share_l1_pp: row.ranking_error(),
        ci95_pp: exact.map(|e| e.ci95_pp),
    }
}

/// The cheapest setting within the tolerance (by the upper end of its 95 %
/// interval against the exact measure, or its precision without one).
/// Cheapest by pixels rendered, a deterministic cost, not by measured
/// seconds (which swap two near-equal settings under load); between equal
/// costs the smaller error, then the earlier row.
fn recommend(study: &mut Study) {
    let tolerance = study.tolerance_pp;
    study.recommended = study
        .rows
        .iter()
        .filter(|row| row.upper_error() <= tolerance)
        .min_by(|a, b| {
            a.pixels_rendered.cmp(&b.pixels_rendered).then(a.upper_error().total_cmp(&b.upper_error()))
        })
        .map(pick);
    if study.recommended.is_some() {
        return;
    }
    // Closest by the same end of the interval the recommendation holds to the tolerance.
    let closest = study.rows.iter().min_by(|a, b| a.upper_error().total_cmp(&b.upper_error())).map(pick);
    let against =
        if study.exact.is_some() { "of the exact measure at 95 %" } else { "of the finest setting" };
    study.reason = Some(match &closest {
        Some(c) => format!(
            "no setting is within {tolerance} pp {against}: the closest is {} at {:.3} pp{}{}",
            c.setting,
            c.share_l1_pp,
            c.ci95_pp.map_or(String::new(), |[lo, hi]| format!(" (95 % {lo:.3}–{hi:.3} pp)")),
            reference_sampling_dominates(study).map_or(String::new(), |note| format!(". {note}"))
        ),
        None => "no settings".into(),
    });
    study.closest = closest;
}

/// When the exact reference sampled its texels (`--exact-sample`) and that
/// sampling alone moves a setting's error by half the tolerance or more
/// (`texel_sampling_pp`, a column of `study.csv`), the settings cannot be
/// judged against it: says so, and what to rerun with. The reference's
/// relative errors scale as √((1 − f)/f) in the sampled share f, so the
/// share suggested brings the shift to a quarter of the tolerance.
fn reference_sampling_dominates(study: &Study) -> Option<String> {
    let exact = study.exact.as_ref().filter(|e| e.sample < 1.0 && e.sample > 0.0)?;
    let shift = study
        .rows
        .iter()
        .filter_map(|r| r.error_vs_exact.as_ref().map(|e| e.texel_sampling_pp))
        .fold(0.0, f64::max);
    if shift < study.tolerance_pp / 2.0 {
        return None;
    }
    let f = exact.sample;
    let ratio = ((1.0 - f) / f).sqrt() * study.tolerance_pp / 4.0 / shift;
    let wanted = 1.0 / (1.0 + ratio * ratio);
    let advice = if wanted >= 0.5 {
        "every texel (leave --exact-sample out)".to_string()
    } else {
        format!(
            "--exact-sample 1/{} or more (or every texel: leave --exact-sample out)",
            (1.0 / wanted).floor()
        )
    };
    Some(format!(
        "The exact reference ray traced {:.4} of the texels, and its own sampling moves the settings' errors by \
         up to {shift:.2} pp (texel_sampling_pp in study.csv), not less than half the {} pp tolerance: the \
         reference's noise, not the settings, dominates these errors. Rerun with {advice}",
        f, study.tolerance_pp
    ))
}

/// The files [`write_study`] may write.
const STUDY_FILES: [&str; 4] = ["study.csv", "study.json", "study.svg", "study.png"];

/// Writes `study.csv`, `study.json`, `study.svg` and, when a TrueType font
/// is found for its labels, `study.png` into `dir`. Returns the files written.
pub fn write_study(study: &Study, dir: &Path) -> Result<Vec<PathBuf>> {
    ufcsr::files::create_output_dir(dir)?;
    let csv_path = dir.join("study.csv");
    write_csv(study, &csv_path)?;
    let json_path = dir.join("study.json");
    let json =
        serde_json::to_vec_pretty(study).map_err(|e| CaptureError::bad_file(&json_path, e.to_string()))?;
    ufcsr::files::write_bytes_atomically(&json_path, &json)?;
    let svg_path = dir.join("study.svg");
    crate::study::plot::plot_svg(study, &svg_path)?;
    let mut written = vec![csv_path, json_path, svg_path];
    let png_path = dir.join("study.png");
    if crate::study::plot::plot_png(study, &png_path)? {
        written.push(png_path);
    }
    Ok(written)
}

const CSV_HEADER: [&str; 25] = [
    "measure",
    "ppd",
    "frame_step",
    "frames",
    "seconds",
    "pixels_rendered",
    "share_l1_vs_exact_pp",
    "ci95_low_pp",
    "ci95_high_pp",
    "share_max_vs_exact_pp",
    "kendall_tau_b_vs_exact",
    "top5_overlap_vs_exact",
    "frame_step_pp",
    "frame_step_low_pp",
    "frame_step_high_pp",
    "resolution_pp",
    "imputed_offsets",
    "texel_sampling_pp",
    "precision_share_l1_pp",
    "precision_share_max_pp",
    "precision_kendall_tau_b",
    "precision_top5_overlap",
    "grand_total",
    "texels_seen",
    "pareto",
];

/// Writes `study.csv` through the file layer (never through a link planted
/// there, never blocking on a FIFO: issue 41).
fn write_csv(study: &Study, path: &Path) -> Result<()> {
    let mut table = csv::Writer::from_writer(Vec::new());
    table.write_record(CSV_HEADER).map_err(|e| csv_error(path, e))?;
    for row in &study.rows {
        let exact = row.error_vs_exact.as_ref();
        let field = |f: &dyn Fn(&ErrorVsExact) -> String| exact.map_or(String::new(), f);
        let p = &row.precision;
        table
            .write_record([
                study.measure.clone(),
                row.ppd.to_string(),
                row.frame_step.to_string(),
                row.frames.to_string(),
                format!("{:.3}", row.seconds),
                row.pixels_rendered.to_string(),
                field(&|e| format!("{:.4}", e.error.share_l1_pp)),
                field(&|e| format!("{:.4}", e.ci95_pp[0])),
                field(&|e| format!("{:.4}", e.ci95_pp[1])),
                field(&|e| format!("{:.4}", e.error.share_max_pp)),
                field(&|e| format!("{:.4}", e.error.kendall_tau_b)),
                field(&|e| e.error.top5_overlap.to_string()),
                field(&|e| format!("{:.4}", e.frame_step_pp)),
                field(&|e| format!("{:.4}", e.frame_step_range_pp[0])),
                field(&|e| format!("{:.4}", e.frame_step_range_pp[1])),
                field(&|e| format!("{:.4}", e.resolution_pp)),
                field(&|e| format!("{}/{}", e.imputed_offsets, e.offsets)),
                field(&|e| format!("{:.4}", e.texel_sampling_pp)),
                format!("{:.4}", p.share_l1_pp),
                format!("{:.4}", p.share_max_pp),
                format!("{:.4}", p.kendall_tau_b),
                p.top5_overlap.to_string(),
                row.grand_total.to_string(),
                row.texels_seen.to_string(),
                row.pareto.to_string(),
            ])
            .map_err(|e| csv_error(path, e))?;
    }
    let bytes = table.into_inner().map_err(|e| CaptureError::io(path, e.into_error()))?;
    Ok(ufcsr::files::write_bytes_atomically(path, &bytes)?)
}

fn csv_error(path: &Path, error: csv::Error) -> CaptureError {
    CaptureError::bad_file(path, format!("writing CSV: {error}"))
}

#[cfg(test)]
mod tests {
    use super::*;
    use ufcsr::format::ShareError;

    /// A setting whose cost is `seconds` million pixels (and `seconds` seconds).
    pub(super) fn row(ppd: f64, seconds: f64, precision: f64, exact: Option<(f64, [f64; 2])>) -> StudyRow {
        let error = |l1: f64| ShareError {
            share_l1_pp: l1,
            share_max_pp: l1 / 2.0,
            share_max_part: "hood".into(),
            kendall_tau_b: 1.0,
            top5_overlap: 5,
        };
        StudyRow {
            ppd,
            frame_step: 1,
            frames: 10,
            seconds,
            pixels_rendered: (seconds * 1e6) as u64,
            grand_total: 0,
            texels_seen: 0,
            precision: error(precision),
            error_vs_exact: exact.map(|(l1, ci95_pp)| ErrorVsExact {
                measure: "angular-area".into(),
                error: error(l1),
                ci95_pp,
                replicates: 0,
                frame_step_pp: 0.0,
                frame_step_range_pp: [0.0, 0.0],
                resolution_pp: l1,
                offsets: 1,
                imputed_offsets: 0,
                texel_sampling_pp: 0.0,
            }),
            pareto: false,
            results: PathBuf::new(),
        }
    }

    pub(super) fn study(rows: Vec<StudyRow>, exact: bool) -> Study {
        let exact = exact.then(|| ExactReference {
            sample: 1.0,
            sampled_texels: 1,
            labelled_texels: 1,
            eye_frames: 2,
            seconds: 1.0,
            results: PathBuf::new(),
        });
        let reference = rows[0].label();
        let mut study = Study {
            scenario: "A".into(),
            measure: "angular-area".into(),
            reference,
            exact,
            tolerance_pp: 1.0,
            setup_seconds: 0.5,
            rows,
            recommended: None,
            reason: None,
            closest: None,
        };
        mark_pareto_front(&mut study.rows);
        recommend(&mut study);
        study
    }

    #[test]
    fn the_study_recommends_by_the_exact_error_not_by_self_consistency() {
        // The finest setting agrees with itself (precision 0) but is 5 pp
        // from the truth; a coarser one is within 1 pp at 95 %.
        let s = study(
            vec![
                row(60.0, 10.0, 0.0, Some((5.0, [4.5, 5.5]))),
                row(30.0, 4.0, 3.0, Some((0.6, [0.4, 0.9]))),
                row(10.0, 1.0, 6.0, Some((0.8, [0.5, 1.4]))),
            ],
            true,
        );
        let recommended = s.recommended.as_ref().unwrap();
        // 10 px/° is cheaper, but its interval reaches past 1 pp.
        assert_eq!((recommended.ppd, recommended.against.as_str()), (30.0, "exact"));
        assert_eq!(recommended.ci95_pp, Some([0.4, 0.9]));
        // Front by the exact error: 60 px/° is dominated.
        assert_eq!(s.rows.iter().map(|r| r.pareto).collect::<Vec<_>>(), [false, true, true]);
    }

    #[test]
    fn with_no_setting_within_tolerance_the_study_says_so_and_names_the_closest() {
        let s = study(
            vec![
                row(60.0, 10.0, 0.0, Some((12.5, [11.0, 14.0]))),
                row(30.0, 4.0, 3.0, Some((15.0, [13.0, 17.0]))),
            ],
            true,
        );
        assert!(s.recommended.is_none());
        let reason = s.reason.as_deref().unwrap();
        assert!(reason.contains("no setting is within 1 pp of the exact measure"), "{reason}");
        assert!(reason.contains("60 px/° every 1 at 12.500 pp (95 % 11.000–14.000 pp)"), "{reason}");
        assert_eq!(s.closest.as_ref().unwrap().ppd, 60.0);
        // study.json reads back as the same study.
        let back: Study = serde_json::from_slice(&serde_json::to_vec_pretty(&s).unwrap()).unwrap();
        assert_eq!(back, s);
    }

    #[test]
    fn when_the_references_own_sampling_dominates_the_study_says_so_and_what_to_rerun_with() {
        // A 1/16 sample whose noise moves every setting by 6.16 pp (a 512² palette): every texel.
        let sampled = |shift: f64| {
            let mut s = study(
                vec![
                    row(60.0, 10.0, 0.0, Some((6.4, [6.2, 6.6]))),
                    row(30.0, 4.0, 3.0, Some((6.6, [6.3, 6.9]))),
                ],
                true,
            );
            s.exact.as_mut().unwrap().sample = 1.0 / 16.0;
            s.rows.iter_mut().for_each(|r| r.error_vs_exact.as_mut().unwrap().texel_sampling_pp = shift);
            recommend(&mut s);
            s.reason.unwrap()
        };
        let reason = sampled(6.16);
        assert!(reason.contains("no setting is within 1 pp"), "{reason}");
        assert!(reason.contains("up to 6.16 pp (texel_sampling_pp in study.csv)"), "{reason}");
        assert!(reason.contains("reference's noise, not the settings, dominates"), "{reason}");
        assert!(reason.contains("Rerun with every texel (leave --exact-sample out)"), "{reason}");
        // 0.6 pp at 1/16: √15 · 0.25 / 0.6 = 1.61, a share of 1 / (1 + 1.61²) = 0.278: 1/3 or more.
        assert!(sampled(0.6).contains("Rerun with --exact-sample 1/3 or more"), "{}", sampled(0.6));
        // Below half the tolerance, or against every texel, nothing is added.
        assert!(!sampled(0.4).contains("dominates"));
        let every = study(vec![row(60.0, 10.0, 0.0, Some((6.4, [6.2, 6.6])))], true);
        assert!(!every.reason.unwrap().contains("dominates"));
    }

    #[test]
    fn without_the_exact_measure_the_study_falls_back_to_precision() {
        let s = study(vec![row(60.0, 10.0, 0.0, None), row(30.0, 4.0, 0.7, None)], false);
        let recommended = s.recommended.unwrap();
        assert_eq!((recommended.ppd, recommended.against.as_str()), (30.0, "precision"));
    }

    #[test]
    fn the_pick_is_the_cheapest_by_pixels_rendered_whatever_seconds_were_measured() {
        // Two near-equal settings both within 1 pp: 20 px/° every 4th renders fewer pixels
        // than 30 px/° every 2nd. Under load the measured seconds may come out either way;
        // the pick and the front must not move.
        let rows = |fast_is_coarse: bool| {
            let (coarse_s, fine_s) = if fast_is_coarse { (1.0, 1.1) } else { (1.1, 1.0) };
            let mut coarse = row(20.0, coarse_s, 0.5, Some((0.5, [0.3, 0.8])));
            let mut fine = row(30.0, fine_s, 0.3, Some((0.3, [0.2, 0.5])));
            coarse.pixels_rendered = 1_000_000;
            fine.pixels_rendered = 1_125_000;
            vec![row(60.0, 10.0, 0.0, Some((0.1, [0.05, 0.2]))), fine, coarse]
        };
        let picks: Vec<StudyPick> =
            [true, false].map(|fast| study(rows(fast), true).recommended.unwrap()).into_iter().collect();
        assert_eq!((picks[0].ppd, picks[1].ppd), (20.0, 20.0));
        assert_eq!(picks[0].pixels_rendered, 1_000_000);
        // The measured seconds are kept as reported.
        assert_eq!((picks[0].seconds, picks[1].seconds), (1.0, 1.1));
        let fronts = [true, false]
            .map(|fast| study(rows(fast), true).rows.iter().map(|r| r.pareto).collect::<Vec<_>>());
        assert_eq!(fronts[0], fronts[1]);
        // Equal cost: the smaller upper end wins, whatever the order of the rows.
        let mut tie = rows(true);
        tie[1].pixels_rendered = 1_000_000;
        assert_eq!(study(tie.clone(), true).recommended.unwrap().ppd, 30.0);
        tie.reverse();
        assert_eq!(study(tie, true).recommended.unwrap().ppd, 30.0);
    }
}
