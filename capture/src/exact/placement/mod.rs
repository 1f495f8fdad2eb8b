//! Candidate eHMI placements measured by the exact ray tracer (issue 18):
//! per candidate and eye-frame, the visible solid angle, the visible share
//! of its area, the mean angle between line of sight and surface normal and
//! the visible angular height, written as `results/placement-frames.csv`
//! for `ufcsr placement` (`docs/placement.md`).
//!
//! Candidates are a [`labels::LabelSet`] over the exact measure's surface
//! samples: the parts (each sample in its texel's part) and, with
//! `--display WxH`, display patches of that size ([`patches`]), where a
//! sample may belong to several overlapping patches. The same per-label
//! loop ([`frames`]) measures both.
//!
//! The folder: [`labels`] the label set, [`patches`] where patches go,
//! which samples they hold and their footprints (`placement-patches.csv`),
//! [`surface`] the mesh queries the layout is made of (so it does not
//! depend on the texel sample), [`frames`] the per-eye-frame numbers and the
//! CSV.

mod frames;
mod labels;
mod patches;
mod surface;
#[cfg(test)]
mod tests;

use std::path::{Path, PathBuf};
use std::time::Instant;

use super::geometry::Obstacles;
use super::types::{EyeFrame, PlacementCandidates, SurfaceSamples};
use crate::error::{CaptureError, Result};
use crate::scene::Scene;

/// The file written into the results folder (the analyzer's, which reads it).
pub use ufcsr::placement::PLACEMENT_FRAMES_FILE;

pub use patches::{PLACEMENT_PATCHES_COLUMNS, PLACEMENT_PATCHES_FILE};

/// `WxH` in metres, e.g. `0.40x0.15`.
pub fn parse_display(text: &str) -> Result<[f64; 2]> {
    let bad =
        || CaptureError::BadOptions(format!("--display {text:?}: expected WxH in metres, e.g. 0.40x0.15"));
    let (w, h) = text.split_once(['x', 'X', '×']).ok_or_else(bad)?;
    let [w, h]: [f64; 2] = [w.trim().parse().map_err(|_| bad())?, h.trim().parse().map_err(|_| bad())?];
    if !(w.is_finite() && h.is_finite() && w > 0.0 && h > 0.0 && w <= 20.0 && h <= 20.0) {
        return Err(CaptureError::BadOptions(format!(
            "--display {text:?}: width and height must be more than 0 and at most 20 m"
        )));
    }
    Ok([w, h])
}

/// What the exact measure hands over: its samples and eye-frames.
pub(crate) struct ExactInputs<'a> {
    pub scene: &'a Scene,
    pub samples: &'a SurfaceSamples,
    /// Both eyes per frame, in frame order (left, right).
    pub eye_frames: &'a [EyeFrame],
    /// Per frame: its record as in the manifest (frame, time, distance).
    pub frame_records: &'a [ufcsr::format::FrameEntry],
    pub obstacles: &'a Obstacles,
    /// `--sample`: the share of texels measured.
    pub sample_fraction: f64,
    /// Seconds one frame stands for.
    pub frame_s: f64,
}

/// What [`write_placement_frames`] did.
#[derive(Debug, Clone)]
pub struct PlacementWritten {
    pub csv: PathBuf,
    /// With `--display`: the patches' footprints (`placement-patches.csv`).
    pub patches_csv: Option<PathBuf>,
    pub parts: usize,
    pub patches: usize,
    pub rows: u64,
    pub seconds: f64,
}

/// Measures every candidate in every eye-frame and writes the table into
/// `results_dir`.
pub(crate) fn write_placement_frames(
    inputs: &ExactInputs,
    options: &PlacementCandidates,
    results_dir: &Path,
) -> Result<PlacementWritten> {
    let start = Instant::now();
    options.check()?;
    let mut labels = labels::LabelSet::parts(&inputs.scene.vehicle.parts, inputs.samples);
    let parts = labels.count();
    // A link at results/ is replaced by a real folder, never written through.
    ufcsr::files::real_dir(results_dir)?;
    let mut patches_csv = None;
    if let Some(display) = options.display_m {
        let placed = patches::place_patches(inputs, display, options.spacing_m);
        labels.add_patches(&placed, inputs.samples);
        let path = results_dir.join(PLACEMENT_PATCHES_FILE);
        patches::write_patch_table(&path, &placed, display)?;
        patches_csv = Some(path);
    }
    let patches = labels.count() - parts;
    let csv = results_dir.join(PLACEMENT_FRAMES_FILE);
    let rows = frames::write_table(inputs, &labels, &csv)?;
    Ok(PlacementWritten { csv, patches_csv, parts, patches, rows, seconds: start.elapsed().as_secs_f64() })
}
