//! The resolution study: how much resolution and frame rate a scene needs.
//!
//! The paper's count changes meaning with pixels per degree: near the
//! vehicle one texel spans many pixels and counts once, far away texels are
//! smaller than a pixel and are sampled only sometimes. [`run_study`]
//! captures and counts one scenario at every combination of `ppd` and frame
//! step with the fused path (no PNGs), times each, compares each with the
//! reference (the finest setting: highest ppd, every frame) using
//! [`ufcsr::compare_parts`], marks the Pareto front of error against run
//! time, and names the cheapest setting within a tolerance.

pub mod plot;

use std::path::{Path, PathBuf};

use serde::Serialize;
use ufcsr::{Comparison, Dedupe, PartStats};

use crate::archive::{CaptureOptions, CaptureProgress, FrameSelection, capture_counted};
use crate::error::{CaptureError, Result};
use crate::scene::Scene;

/// What to study.
#[derive(Debug, Clone)]
pub struct StudyOptions {
    pub scenario: String,
    /// Pixels per degree to try (the highest is the reference).
    pub ppds: Vec<f64>,
    /// Every n-th frame (the smallest is the reference).
    pub frame_steps: Vec<u32>,
    /// Largest acceptable share L1 error, percentage points.
    pub tolerance_pp: f64,
    pub dedupe: Dedupe,
    /// Capture settings; `out` is the study folder (one sub-folder per setting).
    pub capture: CaptureOptions,
    /// Also compare every setting with the exact unobstructed measure of
    /// this share of the texels (every frame), in `out/unobstructed`.
    pub unobstructed_sample: Option<f64>,
}

/// One setting of a study.
#[derive(Debug, Clone, Serialize)]
pub struct StudyRow {
    pub ppd: f64,
    pub frame_step: u32,
    pub frames: u32,
    /// Wall seconds to capture and count (setup included).
    pub seconds: f64,
    pub grand_total: u64,
    pub texels_seen: u64,
    /// Against the reference setting.
    pub error: Comparison,
    /// Against the exact unobstructed measure, when the study made one.
    pub error_vs_unobstructed: Option<Comparison>,
    /// No other setting is both faster and closer to the reference.
    pub pareto: bool,
    /// The setting's results folder.
    pub results: PathBuf,
}

/// A finished study.
#[derive(Debug, Clone, Serialize)]
pub struct Study {
    pub scenario: String,
    pub reference: String,
    pub tolerance_pp: f64,
    pub rows: Vec<StudyRow>,
    /// Index into `rows` of the cheapest setting within the tolerance.
    pub cheapest_within_tolerance: Option<usize>,
}

impl StudyRow {
    pub fn label(&self) -> String {
        format!("{} px/° every {}", self.ppd, self.frame_step)
    }
}

/// Captures every setting and compares it with the reference.
#[allow(clippy::too_many_lines)] // still to split (issue 16; this file is being changed on another branch)
pub fn run_study(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    scene: &Scene,
    options: &StudyOptions,
) -> Result<Study> {
    if options.ppds.is_empty() || options.frame_steps.is_empty() {
        return Err(CaptureError::BadOptions("a study needs at least one --ppd and one --frame-step".into()));
    }
    if options.frame_steps.contains(&0) || options.ppds.iter().any(|p| !p.is_finite() || *p <= 0.0) {
        return Err(CaptureError::BadOptions(
            "--ppd values must be positive and --frame-step at least 1".into(),
        ));
    }
    let scenario = scene.scenario(&options.scenario)?;
    let mut ppds = options.ppds.clone();
    ppds.sort_by(|a, b| b.total_cmp(a));
    ppds.dedup();
    let mut steps = options.frame_steps.clone();
    steps.sort_unstable();
    steps.dedup();

    let mut runs: Vec<(f64, u32, u32, f64, ufcsr::AnalysisResult, PathBuf)> = Vec::new();
    for &ppd in &ppds {
        let mut scene = scene.clone();
        scene.rig.set_pixels_per_degree(ppd)?;
        let frame_count = scene.rig.frame_count(scenario.duration_s);
        for &step in &steps {
            let out = options.capture.out.join(format!("ppd{ppd}-step{step}"));
            let frames: FrameSelection = format!("0-{}/{step}", frame_count.saturating_sub(1)).parse()?;
            let capture = CaptureOptions {
                out: out.clone(),
                frames,
                progress: CaptureProgress::default(),
                ..options.capture.clone()
            };
            let counted = capture_counted(device, queue, &scene, scenario, &capture, options.dedupe)?;
            eprintln!(
                "study: {ppd} px/°, every {step} frame(s): {} frames in {:.2} s",
                counted.summary.frames, counted.summary.seconds
            );
            runs.push((
                ppd,
                step,
                counted.summary.frames,
                counted.summary.seconds,
                counted.analysis.result,
                counted.written.result_json,
            ));
        }
    }
    let unobstructed_parts: Option<Vec<PartStats>> = match options.unobstructed_sample {
        None => None,
        Some(sample) => {
            let capture = CaptureOptions {
                out: options.capture.out.join("unobstructed"),
                progress: CaptureProgress::default(),
                ..options.capture.clone()
            };
            let measure = crate::unobstructed::MeasureOptions { sample, ..Default::default() };
            let measured = crate::unobstructed::measure_unobstructed(
                device, queue, scene, scenario, &capture, &measure,
            )?;
            eprintln!(
                "study: unobstructed reference of {} texels over {} eye-frames in {:.2} s",
                measured.sampled_texels, measured.eye_frames, measured.seconds
            );
            Some(measured.analysis.result.parts)
        }
    };
    let reference_parts: Vec<PartStats> = runs[0].4.parts.clone();
    if reference_parts.is_empty() {
        return Err(CaptureError::BadOptions("the study needs a PIdT and legend to compare parts".into()));
    }
    let mut rows = Vec::with_capacity(runs.len());
    for (ppd, frame_step, frames, seconds, result, results) in runs {
        let error = ufcsr::compare_parts(&reference_parts, &result.parts, 5)?;
        let error_vs_unobstructed = unobstructed_parts
            .as_ref()
            .map(|exact| ufcsr::compare_parts(exact, &result.parts, 5))
            .transpose()?;
        rows.push(StudyRow {
            ppd,
            frame_step,
            frames,
            seconds,
            grand_total: result.grand_total,
            texels_seen: result.texels_seen,
            error,
            error_vs_unobstructed,
            pareto: false,
            results,
        });
    }
    mark_pareto_front(&mut rows);
    let cheapest_within_tolerance = rows
        .iter()
        .enumerate()
        .filter(|(_, row)| row.error.share_l1_pp <= options.tolerance_pp)
        .min_by(|(_, a), (_, b)| a.seconds.total_cmp(&b.seconds))
        .map(|(index, _)| index);
    Ok(Study {
        scenario: scenario.name.clone(),
        reference: rows[0].label(),
        tolerance_pp: options.tolerance_pp,
        rows,
        cheapest_within_tolerance,
    })
}

/// A row is on the front when no other row is at least as fast and at least
/// as close, and strictly better in one of the two.
fn mark_pareto_front(rows: &mut [StudyRow]) {
    let points: Vec<(f64, f64)> = rows.iter().map(|r| (r.seconds, r.error.share_l1_pp)).collect();
    for (i, row) in rows.iter_mut().enumerate() {
        let (time, error) = points[i];
        row.pareto = !points
            .iter()
            .enumerate()
            .any(|(j, &(t, e))| j != i && t <= time && e <= error && (t < time || e < error));
    }
}

/// Writes `study.csv`, `study.json`, `study.svg` and, when a TrueType font
/// is found for its labels, `study.png` into `dir`. Returns the files written.
pub fn write_study(study: &Study, dir: &Path) -> Result<Vec<PathBuf>> {
    std::fs::create_dir_all(dir).map_err(|e| CaptureError::io(dir, e))?;
    let mut written = Vec::new();
    let csv_path = dir.join("study.csv");
    let mut table = csv::Writer::from_path(&csv_path).map_err(|e| csv_error(&csv_path, e))?;
    table
        .write_record([
            "ppd",
            "frame_step",
            "frames",
            "seconds",
            "share_l1_pp",
            "share_max_pp",
            "share_max_part",
            "kendall_tau_total",
            "tied_pairs_total",
            "kendall_tau_average",
            "tied_pairs_average",
            "top5_overlap",
            "coverage_difference_pp",
            "grand_total",
            "texels_seen",
            "pareto",
            "share_l1_vs_unobstructed_pp",
            "kendall_tau_total_vs_unobstructed",
            "top5_overlap_vs_unobstructed",
        ])
        .map_err(|e| csv_error(&csv_path, e))?;
    for row in &study.rows {
        let e = &row.error;
        table
            .write_record([
                row.ppd.to_string(),
                row.frame_step.to_string(),
                row.frames.to_string(),
                format!("{:.3}", row.seconds),
                format!("{:.4}", e.share_l1_pp),
                format!("{:.4}", e.share_max_pp),
                e.share_max_part.clone(),
                format!("{:.4}", e.kendall_tau_total),
                e.tied_pairs_total.to_string(),
                format!("{:.4}", e.kendall_tau_average),
                e.tied_pairs_average.to_string(),
                e.top_k_overlap.to_string(),
                format!("{:.4}", e.coverage_difference_pp),
                row.grand_total.to_string(),
                row.texels_seen.to_string(),
                row.pareto.to_string(),
                row.error_vs_unobstructed.as_ref().map_or(String::new(), |u| format!("{:.4}", u.share_l1_pp)),
                row.error_vs_unobstructed
                    .as_ref()
                    .map_or(String::new(), |u| format!("{:.4}", u.kendall_tau_total)),
                row.error_vs_unobstructed.as_ref().map_or(String::new(), |u| u.top_k_overlap.to_string()),
            ])
            .map_err(|e| csv_error(&csv_path, e))?;
    }
    table.flush().map_err(|e| CaptureError::io(&csv_path, e))?;
    written.push(csv_path);

    let json_path = dir.join("study.json");
    let json =
        serde_json::to_vec_pretty(study).map_err(|e| CaptureError::bad_input(&json_path, e.to_string()))?;
    ufcsr::write_bytes_atomically(&json_path, &json)?;
    written.push(json_path);

    let svg_path = dir.join("study.svg");
    crate::study::plot::plot_svg(study, &svg_path)?;
    written.push(svg_path);
    let png_path = dir.join("study.png");
    if crate::study::plot::plot_png(study, &png_path)? {
        written.push(png_path);
    }
    Ok(written)
}

fn csv_error(path: &Path, error: csv::Error) -> CaptureError {
    CaptureError::bad_input(path, format!("writing CSV: {error}"))
}
