//! `ufcsr capture … --measure unobstructed`: one scenario measured exactly.
//!
//! Writes the archive skeleton (manifest, PIdT, legend, vehicle.glb; no
//! tiles), the analyzer's results for the per-texel counts (`measure:
//! "unobstructed"`) with a `measures` block holding the ray-traced
//! `angular_area_deg2_s` and `exposure_s` under the rendered measures' names,
//! and `results/unobstructed-parts.csv` (per-part estimates with errors).

use std::path::PathBuf;
use std::time::Instant;

use super::cpu::texel_visibility;
use super::estimator::{PartEstimate, estimate_parts};
use super::geometry::{Obstacles, eye_frames, seconds_per_frame};
use super::placement::{ExactInputs, PlacementWritten, write_placement_frames};
use super::points::surface_samples;
use super::rules::Tracer;
use super::types::{DEG2_PER_SR, MeasureOptions, PartEyeFrames, SurfaceSamples, TexelVisibility};
use crate::error::{CaptureError, Result};
use crate::job::{
    CaptureOptions, CapturedTiles, TileFiles, TileTally, prepare_archive, summarize, write_manifest,
};
use crate::scene::Scene;
use crate::scene::scenario::Scenario;

/// The most samples per texel side (`--texel-samples`).
pub const MAX_TEXEL_SAMPLES: u32 = 16;

/// What [`measure_unobstructed`] did.
pub struct UnobstructedCapture {
    pub analysis: ufcsr::Analysis,
    pub written: ufcsr::output::WrittenFiles,
    pub sampled_texels: u64,
    /// Texels with a footprint on the mesh.
    pub labelled_texels: u64,
    /// Surface samples (K × K per texel, more on edges).
    pub surface_samples: u64,
    pub eye_frames: u64,
    pub seconds: f64,
    /// Seconds of the ray casts alone (samples × eye-frames tests).
    pub visibility_seconds: f64,
    /// Per part: texels, sampled texels, sampled total, estimates and errors.
    pub estimates: Vec<PartEstimate>,
    pub estimates_csv: PathBuf,
    /// The frames measured, in order; eye-frame `i` is frame `frames[i / 2]`,
    /// left eye for even `i`, right for odd.
    pub frames: Vec<u32>,
    /// Seconds one eye-frame stands for.
    pub seconds_per_frame: f64,
    /// Per part and eye-frame, the sampled texels' sums (CPU only).
    pub per_eye_frame: Option<PartEyeFrames>,
    /// With `--placement`: the candidates' table (`placement-frames.csv`).
    pub placement: Option<PlacementWritten>,
}

/// The exact measure's result before it is written.
struct Measured {
    frames: Vec<u32>,
    samples: SurfaceSamples,
    visibility: TexelVisibility,
    eye_frames: usize,
    seconds_per_frame: f64,
    visibility_seconds: f64,
}

fn check_options(measure: &MeasureOptions) -> Result<()> {
    if !(measure.sample > 0.0 && measure.sample <= 1.0) {
        return Err(CaptureError::BadOptions(format!("--sample must be in (0, 1], not {}", measure.sample)));
    }
    if !(1..=MAX_TEXEL_SAMPLES).contains(&measure.texel_samples) {
        return Err(CaptureError::BadOptions(format!(
            "--texel-samples must be 1 to {MAX_TEXEL_SAMPLES}, not {}",
            measure.texel_samples
        )));
    }
    if let Some(placement) = &measure.placement {
        placement.check()?;
    }
    Ok(())
}

/// Measures one scenario (see the module documentation).
pub fn measure_unobstructed(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    scene: &Scene,
    scenario: &Scenario,
    options: &CaptureOptions,
    measure: &MeasureOptions,
) -> Result<UnobstructedCapture> {
    let start = Instant::now();
    check_options(measure)?;
    scene.rig.check()?;
    let prepared = prepare_archive(device, queue, scene, options)?;
    let frames = crate::job::scene_checks::selected_frames(scene, scenario, options)?;
    let warnings = crate::job::scene_checks::scene_warnings(scene, scenario, &frames)?;
    let samples = surface_samples(
        &scene.vehicle,
        &prepared.unwrapped,
        measure.sample,
        measure.seed,
        measure.texel_samples,
    );
    let obstacles = Obstacles::new(scene);
    let (eye_frames, frame_records) = eye_frames(scene, scenario, &frames, &obstacles)?;
    let parts = scene.vehicle.parts.len();
    let casting = Instant::now();
    let visibility = texel_visibility(&samples, &eye_frames, &obstacles, parts, Tracer::Hierarchy);
    let placement_records = measure.placement.map(|_| frame_records.clone());
    let captured = CapturedTiles {
        entries: Vec::new(),
        frame_records,
        tally: TileTally::default(),
        frames: frames.len() as u32,
        tiles: 0,
        warnings,
    };
    let _ = summarize(scene, scenario, options, &prepared, &captured, 0.0);
    write_manifest(scene, scenario, options, &prepared, captured, TileFiles::NotWritten)?;
    let measured = Measured {
        frames: frames.clone(),
        samples,
        visibility,
        eye_frames: eye_frames.len(),
        seconds_per_frame: seconds_per_frame(scene, &frames),
        visibility_seconds: casting.elapsed().as_secs_f64(),
    };
    let mut capture = write_results(scene, options, measure, &measured, prepared.palette_size, start)?;
    if let (Some(placement), Some(frame_records)) = (&measure.placement, placement_records) {
        let inputs = ExactInputs {
            scene,
            samples: &measured.samples,
            eye_frames: &eye_frames,
            frame_records: &frame_records,
            obstacles: &obstacles,
            sample_fraction: measure.sample,
            frame_s: measured.seconds_per_frame,
        };
        let results = ufcsr::output::default_output_dir(&options.out);
        capture.placement = Some(write_placement_frames(&inputs, placement, &results).map_err(|error| {
            // The result set is written by now (and the patch table, if any):
            // a table over the cap fails the run after them.
            let mut written = capture.written.all(&results);
            written.push(capture.estimates_csv.clone());
            written.extend(
                Some(results.join(crate::exact::placement::PLACEMENT_PATCHES_FILE)).filter(|p| p.is_file()),
            );
            CaptureError::AfterWriting { written, error: Box::new(error) }
        })?);
    }
    Ok(capture)
}

/// The analyzer's results for the counts, the measures block and the CSV.
fn write_results(
    scene: &Scene,
    options: &CaptureOptions,
    measure: &MeasureOptions,
    measured: &Measured,
    [width, height]: [u32; 2],
    start: Instant,
) -> Result<UnobstructedCapture> {
    let Measured { samples, visibility, .. } = measured;
    let mut texel_counts = vec![0u32; width as usize * height as usize];
    for (texel, &count) in samples.texels.iter().zip(&visibility.counts) {
        texel_counts[texel.texel as usize] = count;
    }
    let estimates = estimate_parts(&scene.vehicle.parts, samples, visibility, measure.sample);
    let labelled: u64 = samples.texels_per_part.iter().sum();
    let notes = vec![describe(measure, measured, labelled)];
    let analyze_options =
        ufcsr::AnalyzeOptions { archive: options.out.clone(), ..ufcsr::AnalyzeOptions::default() };
    let mut analysis = ufcsr::analyze_texel_counts(
        &analyze_options,
        texel_counts,
        ufcsr::format::CountMeasure::Unobstructed,
        notes,
    )?;
    analysis.result.measures = Some(measures_block(measure, measured, &estimates)?);
    // Its clock is the analyzer's (the smallest gap), and so is the caveat of uneven frames.
    analysis.result.warnings.extend(ufcsr::frame_spacing_warning(&measured.frames, scene.rig.fps));
    let results = ufcsr::output::default_output_dir(&options.out);
    let written = ufcsr::output::write_results(&mut analysis, &results)?;
    let estimates_csv = results.join("unobstructed-parts.csv");
    write_estimates(&estimates_csv, &estimates)?;
    Ok(UnobstructedCapture {
        analysis,
        written,
        sampled_texels: samples.texels.len() as u64,
        labelled_texels: labelled,
        surface_samples: samples.samples.len() as u64,
        eye_frames: measured.eye_frames as u64,
        seconds: start.elapsed().as_secs_f64(),
        visibility_seconds: measured.visibility_seconds,
        estimates,
        estimates_csv,
        frames: measured.frames.clone(),
        seconds_per_frame: measured.seconds_per_frame,
        per_eye_frame: visibility.per_eye_frame.clone(),
        placement: None,
    })
}

/// The result's note on what the counts mean.
fn describe(measure: &MeasureOptions, measured: &Measured, labelled: u64) -> String {
    let MeasureOptions { sample, seed, texel_samples, .. } = *measure;
    format!(
        "measure \"unobstructed\": a count is the number of eye-frames ({}) in which any part of the texel's \
         footprint on the vehicle is visible: in view, beyond the near plane, not edge-on, nothing in between \
         (exact f64 ray casts of {texel_samples}×{texel_samples} samples per texel, {} in all; independent of pixels \
         per degree); {} of {} texels with a footprint sampled (fraction {sample}, seed {seed}), the others are 0 \
         here: divide totals by the fraction to estimate them (per-part estimates with standard errors in \
         unobstructed-parts.csv); computed on the CPU",
        measured.eye_frames,
        measured.samples.samples.len(),
        measured.samples.texels.len(),
        labelled,
    )
}

/// How the exact measures are defined, recorded in the result's `measures`.
pub(crate) const EXACT_DEFINITION: &str = "exact (ray-traced): angular_area_deg2_s = sum over eye-frames and visible \
     surface samples of area * |cos theta| / r^2 (sr, times (180/pi)^2 for deg^2) * seconds_per_frame / eyes, \
     scaled by texels / sampled texels per part under --sample; exposure_s = eye_frames_seen * seconds_per_frame \
     / eyes, eye_frames_seen = eye-frames in which any sampled surface sample of the part is visible; \
     seconds_per_frame = smallest step between the frame numbers / fps; pixels = the part's count summed over \
     its sampled texels (texel-eye-frames; no pixels are rendered)";

/// The `measures` block: the rendered measures' fields, ray-traced.
fn measures_block(
    measure: &MeasureOptions,
    measured: &Measured,
    estimates: &[PartEstimate],
) -> Result<ufcsr::Measures> {
    let eyes = 2.0;
    let seconds = measured.seconds_per_frame;
    let parts: Vec<ufcsr::format::PartMeasure> = estimates
        .iter()
        .enumerate()
        .map(|(part, estimate)| {
            let seen = measured.visibility.part_seen
                [part * measured.eye_frames..(part + 1) * measured.eye_frames]
                .iter()
                .filter(|&&seen| seen)
                .count() as u64;
            ufcsr::format::PartMeasure {
                name: estimate.part.clone(),
                pixels: estimate.sampled_total,
                eye_frames_seen: seen,
                solid_angle_sr: None,
                angular_area_deg2_s: Some(estimate.estimated_solid_angle_sr * DEG2_PER_SR * seconds / eyes),
                exposure_s: Some(seen as f64 * seconds / eyes),
            }
        })
        .collect();
    let mut notes = Vec::new();
    if measure.sample < 1.0 {
        notes.push(format!(
            "--sample {}: angular_area_deg2_s is estimated from the sampled texels (standard errors in \
             unobstructed-parts.csv); exposure_s counts the eye-frames in which a sampled texel is seen, a lower \
             bound; pixels sums the sampled texels' counts",
            measure.sample
        ));
    }
    Ok(ufcsr::Measures {
        definition: EXACT_DEFINITION.into(),
        pixels_per_degree: None,
        seconds_per_frame: Some(seconds),
        eyes: eyes as usize,
        eye_frames: measured.eye_frames as u64,
        parts,
        notes,
    })
}

/// Writes `unobstructed-parts.csv` through the file layer: never through a
/// link planted there, never blocking on a FIFO (issue 41).
fn write_estimates(path: &std::path::Path, estimates: &[PartEstimate]) -> Result<()> {
    let mut table = csv::Writer::from_writer(Vec::new());
    for estimate in estimates {
        table.serialize(estimate).map_err(|e| CaptureError::bad_file(path, format!("writing CSV: {e}")))?;
    }
    let bytes = table.into_inner().map_err(|e| CaptureError::io(path, e.into_error()))?;
    Ok(ufcsr::files::write_bytes_atomically(path, &bytes)?)
}
