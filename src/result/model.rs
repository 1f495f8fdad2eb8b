//! The result model: [`AnalysisResult`], everything `result.json` reports
//! beside the per-texel counts, and [`Analysis`], a result with its counts
//! and what it was made from. [`crate::result::result_json`] stores it.

use std::path::PathBuf;

use serde::{Deserialize, Serialize};

use crate::archive::options::Scale;
use crate::archive::options::{Dedupe, Timings};
use crate::archive::palette::PaletteSetting;
use crate::color::Color;
use crate::count::trim::EmptyTile;
use crate::result::frames::FrameTable;
use crate::{
    archive::labels::Pidt,
    result::part_stats::{PartStats, PartTable, ratio},
};

/// Schema string of `result.json`.
pub const RESULT_SCHEMA: &str = "ufcsr-result/1";

/// How many example stray colours and unlabelled PIdT colours to list.
pub(crate) const STRAY_EXAMPLES: usize = 10;

/// Image bookkeeping: `found = trimmed + decoded + failed`.
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct ImageCounts {
    /// Tiles found: image files plus tiles the manifest lists as empty.
    pub found: u64,
    /// Skipped as all-background (verified), including `listed_empty`.
    pub trimmed: u64,
    pub decoded: u64,
    /// Unreadable images (see `failures`); they contribute nothing.
    pub failed: u64,
    /// Tiles the manifest lists as empty (never written by the capture).
    pub listed_empty: u64,
    /// PNGs of a folder without a manifest left out as not frames (palette-
    /// or PIdT-sized textures; see `warnings`). Not part of `found`.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub skipped: u64,
}

fn is_zero(value: &u64) -> bool {
    *value == 0
}

/// Pixel bookkeeping over the decoded images.
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct PixelCounts {
    pub decoded: u64,
    /// Pixels showing a palette texel.
    pub texel: u64,
    pub background: u64,
    /// Neither background nor palette: never counted.
    pub stray: u64,
}

/// A failed image.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct FailedImage {
    pub file: String,
    pub error: String,
}

/// An image with stray pixels.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct StrayImage {
    pub file: String,
    pub stray_pixels: u64,
}

/// How trimming was configured and what it found.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct TrimReport {
    /// `auto`, `off` or a byte threshold.
    pub mode: String,
    /// Candidate empty-file sizes and whether decoding verified them.
    pub empty_tiles: Vec<EmptyTile>,
}

/// The settings a result was computed with.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Settings {
    pub archive: String,
    /// True when the archive's manifest was used.
    pub manifest: bool,
    pub palette: PaletteSetting,
    pub background: Vec<Color>,
    pub pidt: Option<String>,
    pub parts: Option<String>,
    pub dedupe: Dedupe,
    pub trim: TrimReport,
    pub heatmap_scale: Scale,
    pub heatmap_max: Option<u32>,
    /// The shard counted (`ufcsr-analyze --shard`); absent for a whole archive.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shard: Option<crate::archive::shard::Shard>,
    /// What the counts depend on (manifest or tile list, palette, PIdT,
    /// legend), digested: `merge` refuses shards whose identities differ.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub archive_identity: Option<String>,
}

/// Unlabelled texels: PIdT colours that no legend entry names.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct UnlabelledReport {
    pub texels: u64,
    pub total: u64,
    pub peak: u32,
    pub texels_seen: u64,
    /// Distinct unlabelled PIdT colours.
    pub distinct_colors: u64,
    /// The most common unlabelled colours and their texel counts.
    pub colors: Vec<ColorTexels>,
}

/// A colour and how many texels carry it.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct ColorTexels {
    pub color: Color,
    pub texels: u64,
}

impl UnlabelledReport {
    /// Summarises the unlabelled row of a table.
    pub fn new(table: &PartTable, pidt: &Pidt) -> UnlabelledReport {
        let mut colors: Vec<ColorTexels> =
            pidt.unlabelled_colors.iter().map(|(&color, &texels)| ColorTexels { color, texels }).collect();
        colors.sort_by(|a, b| b.texels.cmp(&a.texels).then(a.color.cmp(&b.color)));
        let distinct_colors = colors.len() as u64;
        colors.truncate(STRAY_EXAMPLES);
        let row = &table.unlabelled;
        UnlabelledReport {
            texels: row.texels,
            total: row.total,
            peak: row.peak,
            texels_seen: row.texels_seen,
            distinct_colors,
            colors,
        }
    }
}

/// What eye-frame deduplication changed.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DedupeReport {
    /// Grand total when counting once per image.
    pub grand_total_per_image: u64,
    /// Grand total when counting once per eye-frame (the reported one).
    pub grand_total_per_frame: u64,
    /// `100 * (per_frame - per_image) / per_image` (≤ 0).
    pub change_percent: f64,
}

impl DedupeReport {
    /// Compares the two grand totals.
    pub fn new(per_image: u64, per_frame: u64) -> DedupeReport {
        DedupeReport {
            grand_total_per_image: per_image,
            grand_total_per_frame: per_frame,
            change_percent: if per_image == 0 { 0.0 } else { 100.0 * (ratio(per_frame, per_image) - 1.0) },
        }
    }
}

/// The summary part of `result.json`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct AnalysisResult {
    pub schema: String,
    /// What a count is: `"pixels"` (the paper's: once per image whose pixels
    /// show the texel) or `"unobstructed"` (eye-frames in which the texel's
    /// point is in view, faces the eye and nothing is in between).
    #[serde(default = "default_measure")]
    pub measure: String,
    pub images: ImageCounts,
    /// Texels with count ≥ 1.
    pub texels_seen: u64,
    pub pixels: PixelCounts,
    pub stray_pixels: u64,
    pub stray_colors: u64,
    pub stray_color_examples: Vec<Color>,
    pub background_pixels: u64,
    /// Sum of part totals over legend parts; without a PIdT, over all texels.
    pub grand_total: u64,
    /// Largest count of any texel.
    pub max_count: u32,
    /// Per legend part, in legend order.
    pub parts: Vec<PartStats>,
    pub unlabelled: Option<UnlabelledReport>,
    /// Present with `--dedupe frame`.
    pub dedupe: Option<DedupeReport>,
    pub settings: Settings,
    pub failures: Vec<FailedImage>,
    pub images_with_stray_pixels: Vec<StrayImage>,
    /// Problems a researcher should look at (e.g. a legend part with no texels).
    pub warnings: Vec<String>,
    /// Facts worth knowing that need no action.
    pub notes: Vec<String>,
    /// Whether the counts depend on resolution (absent in older results).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub resolution: Option<crate::result::resolution::ResolutionReport>,
    /// Resolution-independent measures per part (with frames tallied).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub measures: Option<crate::result::measures::Measures>,
    /// Signs of colour-management and filtering damage (pixel counts only;
    /// absent in older results). Its warnings are in `warnings` too.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub colour_checks: Option<crate::checks::ColourChecks>,
}

pub(crate) fn default_measure() -> String {
    crate::archive::options::MEASURE_PIXELS.to_string()
}

/// The outcome of an analysis.
pub struct Analysis {
    /// Everything that goes into `result.json` except the per-texel counts.
    pub result: AnalysisResult,
    /// Count per texel, row-major over the palette (`width * height`).
    pub texel_counts: Vec<u32>,
    pub timings: Timings,
    /// Every file the analysis read (legend, PIdT, palette, manifest, images):
    /// [`write_results`] refuses to write over any of them.
    pub input_files: Vec<PathBuf>,
    /// The vehicle model `heatmap.glb` is made from, when there is one.
    pub vehicle_model: Option<PathBuf>,
    /// Per-eye-frame tallies by part (`frames.csv`), with
    /// [`AnalyzeOptions::frames`].
    pub frames: Option<FrameTable>,
    /// The legend and PIdT the counts were joined with, for the figures
    /// drawn after (the frame strip), so they are not read again; `None`
    /// without labels, or for a merge, which reads them when it needs them.
    pub labels: Option<crate::archive::labels::LoadedLabels>,
}

impl Analysis {
    /// True when every image was read (exit code 0 material).
    pub fn is_complete(&self) -> bool {
        self.result.images.failed == 0
    }
}
