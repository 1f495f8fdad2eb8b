//! The result model: [`AnalysisResult`], everything `result.json` reports
//! beside the per-texel counts, and [`Analysis`], a result with its counts
//! and what it was made from. [`crate::result::result_json`] stores it.

use std::path::PathBuf;

use crate::archive::labels::Pidt;
use crate::archive::options::Timings;
use crate::result::frames::FrameTable;
use crate::result::part_stats::{PartTable, ratio};

pub use crate::format::result::RESULT_SCHEMA;

/// How many example stray colours and unlabelled PIdT colours to list.
pub(crate) const STRAY_EXAMPLES: usize = 10;

pub(crate) use crate::format::result::ImageCounts;

pub(crate) use crate::format::result::PixelCounts;

pub(crate) use crate::format::result::FailedImage;

pub(crate) use crate::format::result::StrayImage;

pub(crate) use crate::format::result::TrimReport;

pub(crate) use crate::format::result::Settings;

pub(crate) use crate::format::result::UnlabelledReport;

pub(crate) use crate::format::result::ColorTexels;

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

pub(crate) use crate::format::result::DedupeReport;

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

pub use crate::format::result::AnalysisResult;

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
    /// Per texel, row-major like `texel_counts`: the visible angular area
    /// over time, deg²·s — the part measure `angular_area_deg2_s` texel by
    /// texel (its pixels' solid angles × seconds per frame / eyes), so the
    /// texels of a part add up to the part's. The default heatmap
    /// (`heatmap.png`) and the views show it; `None` without the eyes'
    /// projection or fps, without [`AnalyzeOptions::frames`] and for a merge
    /// (not kept in the result set). Tiles counted in memory (the capture's
    /// `--count`, [`crate::analyze_counted`]) give the PNG path's bits.
    pub texel_angular_area: Option<Vec<f32>>,
    /// The integer sums `texel_angular_area` was made from, kept by a shard
    /// (written as `texel-area.units`) so that `merge` adds them exactly.
    pub texel_area_units: Option<crate::result::texel_area_file::TexelAreaUnits>,
    /// The legend and PIdT the counts were joined with, for the figures
    /// drawn after (the frame strip), so they are not read again; `None`
    /// without labels, or for a merge, which reads them when it needs them.
    pub labels: Option<crate::archive::labels::LoadedLabels>,
}

impl Analysis {
    /// True when every image was read and the images are palette renders
    /// (exit code 0 material; see [`crate::format::result::PixelCounts::not_palette_renders`]).
    pub fn is_complete(&self) -> bool {
        self.result.images.failed == 0 && !self.result.pixels.not_palette_renders()
    }
}
