//! `result.json`: the summary of one analysis (its counts' bookkeeping,
//! per-part statistics, settings, diagnostics) followed by the per-texel
//! counts. Written by `ufcsr analyze`, `ufcsr merge` and the
//! capture's `--count` / `--measure unobstructed`; only ufcsr writes it, so
//! every object is closed in the schema (a new field is a format change).
//! The types hold data only; what computes them lives beside the analysis
//! (`crate::result`, `crate::checks`), which re-exports them.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use crate::color::Color;

/// Schema string of `result.json`.
pub const RESULT_SCHEMA: &str = "ufcsr-result/1";

/// What a count of `result.json` is (its `measure` field). "Measure" names several things in
/// ufcsr (docs/architecture.md, Vocabulary); this is the one a per-texel count is of.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum CountMeasure {
    /// The paper's: a texel counts once per image (or eye-frame) whose pixels show it.
    #[default]
    Pixels,
    /// The capture's exact measure: eye-frames in which the texel's point is in view, faces
    /// the eye and nothing is in between.
    Unobstructed,
}

impl CountMeasure {
    /// The name in files and on the command line (`pixels`, `unobstructed`).
    pub fn name(self) -> &'static str {
        match self {
            CountMeasure::Pixels => "pixels",
            CountMeasure::Unobstructed => "unobstructed",
        }
    }
}

impl std::fmt::Display for CountMeasure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// ufcsr result (`ufcsr-result/1`): `result.json` as written by
/// ufcsr analyze, ufcsr merge and ufcsr capture --count /
/// --measure unobstructed: the summary, then the per-texel counts.
/// Field-by-field prose: docs/archive-format.md. Generated from the types in
/// src/format/result.rs.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[schemars(title = "ufcsr result (ufcsr-result/1)", deny_unknown_fields)]
pub struct ResultFile {
    /// Everything but the per-texel counts.
    #[serde(flatten)]
    pub summary: AnalysisResult,
    /// The per-texel counts.
    pub texel_counts: TexelCountsJson,
}

fn is_zero(value: &u64) -> bool {
    *value == 0
}

/// Image bookkeeping: `found = trimmed + decoded + failed`.
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[schemars(deny_unknown_fields)]
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

/// Pixel bookkeeping over the decoded images.
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[schemars(deny_unknown_fields)]
pub struct PixelCounts {
    pub decoded: u64,
    /// Pixels showing a palette texel.
    pub texel: u64,
    pub background: u64,
    /// Neither background nor palette: never counted.
    pub stray: u64,
}

impl PixelCounts {
    /// True when more of the pixels that are not background are stray than
    /// show a palette colour: the images are most likely not palette renders
    /// (issue 44 §5: a folder of ordinary PNGs, or renders that are not
    /// FCSP-textured, lit, antialiased or colour-managed), and nothing counted
    /// from them can be trusted.
    pub fn not_palette_renders(&self) -> bool {
        self.stray > self.texel
    }
}

/// A failed image.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[schemars(deny_unknown_fields)]
pub struct FailedImage {
    pub file: String,
    pub error: String,
}

/// An image with stray pixels.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[schemars(deny_unknown_fields)]
pub struct StrayImage {
    pub file: String,
    pub stray_pixels: u64,
}

/// How trimming was configured and what it found.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[schemars(deny_unknown_fields)]
pub struct TrimReport {
    /// `auto`, `off` or a byte threshold; anything else is refused on
    /// reading (it used to be shown as it came, issue 34).
    #[serde(deserialize_with = "trim_mode")]
    #[schemars(pattern(r"^(auto|off|[0-9]+)$"))]
    pub mode: String,
    /// Candidate empty-file sizes and whether decoding verified them.
    pub empty_tiles: Vec<EmptyTile>,
}

/// A trim mode as `ufcsr analyze --trim` takes it: `auto`, `off` or a
/// byte threshold.
fn trim_mode<'de, D: serde::Deserializer<'de>>(deserializer: D) -> Result<String, D::Error> {
    let mode = String::deserialize(deserializer)?;
    let bytes = !mode.is_empty() && mode.len() <= 20 && mode.bytes().all(|b| b.is_ascii_digit());
    if mode == "auto" || mode == "off" || bytes {
        Ok(mode)
    } else {
        Err(serde::de::Error::custom(format!(
            "settings.trim.mode {:?}: expected auto, off or a byte threshold",
            mode.chars().take(40).collect::<String>()
        )))
    }
}

/// The settings a result was computed with.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[schemars(deny_unknown_fields)]
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
    /// The top of the angular-area heatmap's colour scale, deg²·s per texel
    /// (`--area-max`); absent = the largest texel's.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub heatmap_area_max: Option<f64>,
    /// The shard counted (`ufcsr analyze --shard`); absent for a whole archive.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shard: Option<Shard>,
    /// What the counts depend on (manifest or tile list, palette, PIdT,
    /// legend), digested: `merge` refuses shards whose identities differ.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub archive_identity: Option<String>,
}

/// Unlabelled texels: PIdT colours that no legend entry names.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[schemars(deny_unknown_fields)]
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
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[schemars(deny_unknown_fields)]
pub struct ColorTexels {
    pub color: Color,
    pub texels: u64,
}

/// What eye-frame deduplication changed.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[schemars(deny_unknown_fields)]
pub struct DedupeReport {
    /// Grand total when counting once per image.
    pub grand_total_per_image: u64,
    /// Grand total when counting once per eye-frame (the reported one).
    pub grand_total_per_frame: u64,
    /// `100 * (per_frame - per_image) / per_image` (≤ 0).
    pub change_percent: f64,
}

/// The summary part of `result.json`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct AnalysisResult {
    /// `ufcsr-result/1`.
    #[schemars(extend("const" = "ufcsr-result/1"))]
    pub schema: String,
    /// What a count is: `"pixels"` (the paper's: once per image whose pixels
    /// show the texel) or `"unobstructed"` (eye-frames in which the texel's
    /// point is in view, faces the eye and nothing is in between).
    #[serde(default)]
    pub measure: CountMeasure,
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
    pub resolution: Option<ResolutionReport>,
    /// Resolution-independent measures per part (with frames tallied).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub measures: Option<Measures>,
    /// Signs of colour-management and filtering damage (pixel counts only;
    /// absent in older results). Its warnings are in `warnings` too.
    // The file keeps the name it was published with (British spelling).
    #[serde(rename = "colour_checks", default, skip_serializing_if = "Option::is_none")]
    pub color_checks: Option<ColorChecks>,
}

/// Per-texel counts as stored in `result.json`: only seen texels, texel
/// indices (`y * width + x`) ascending and delta-coded (the first delta is the
/// first index), counts in the same order.
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[schemars(deny_unknown_fields)]
pub struct TexelCountsJson {
    pub encoding: String,
    pub texels: u64,
    pub texel_delta: Vec<u32>,
    /// Only seen texels are listed: every count is 1 or more.
    #[schemars(inner(range(min = 1)))]
    pub count: Vec<u32>,
}

/// Statistics of one part (or of the unlabelled texels).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize, JsonSchema)]
#[schemars(deny_unknown_fields)]
pub struct PartStats {
    pub name: String,
    pub color: Option<Color>,
    /// Texels of this part in the PIdT.
    pub texels: u64,
    /// Sum of the counts of its texels.
    pub total: u64,
    /// Largest count of one of its texels.
    pub peak: u32,
    /// `total / texels`, 0 for a part without texels.
    pub average: f64,
    /// Percentage of the grand total (sum of totals over legend parts).
    pub share: f64,
    /// Percentage of its texels seen at least once.
    pub coverage: f64,
    /// Texels with count ≥ 1.
    pub texels_seen: u64,
}

/// The resolution diagnostics of one result.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[schemars(deny_unknown_fields)]
pub struct ResolutionReport {
    /// Pixels that showed a texel, per count (per-image counts over all
    /// texels). About 1: each count is one pixel. Well above 1: texels covered
    /// by many pixels counted once — the count saturates with resolution.
    pub pixels_per_count: f64,
    /// The counts behind it: per-image counts summed over all texels (kept
    /// so that the results of shards can be merged exactly).
    #[serde(default)]
    pub per_image_counts: u64,
    /// The pixels behind it: pixels that showed a texel.
    #[serde(default)]
    pub texel_pixels: u64,
    pub pixels_per_degree: Option<f64>,
    pub texel_size_mm: Option<f64>,
    /// Beyond this distance a texel is smaller than a pixel.
    pub sub_pixel_distance_m: Option<f64>,
    /// Share of captured frames with the vehicle beyond that distance (0–1).
    pub sub_pixel_frame_share: Option<f64>,
}

/// The measures of one part.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[schemars(deny_unknown_fields)]
pub struct PartMeasure {
    pub name: String,
    /// Pixels showing the part, summed over all eye-frames (both eyes).
    pub pixels: u64,
    /// Eye-frames with at least one pixel of the part (both eyes).
    pub eye_frames_seen: u64,
    /// The solid angle of its pixels summed over all eye-frames (both
    /// eyes), sr; absent without the eyes' projection.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub solid_angle_sr: Option<f64>,
    /// Visible angular area summed over time, deg²·s (per eye).
    pub angular_area_deg2_s: Option<f64>,
    /// Seconds the part is seen (per eye).
    pub exposure_s: Option<f64>,
}

/// The measures of every part (see the module documentation).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[schemars(deny_unknown_fields)]
pub struct Measures {
    pub definition: String,
    pub pixels_per_degree: Option<f64>,
    pub seconds_per_frame: Option<f64>,
    pub eyes: usize,
    /// Eye-frames (or images) tallied.
    pub eye_frames: u64,
    pub parts: Vec<PartMeasure>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub notes: Vec<String>,
}

/// What the checks measured and what they warn about (`result.json`'s
/// `colour_checks`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[schemars(deny_unknown_fields)]
pub struct ColorChecks {
    /// Counts on unlabelled texels / all counts (legend parts and
    /// unlabelled); absent without a PIdT or without counts.
    pub unlabelled_count_share: Option<f64>,
    /// Background pixels / decoded pixels; absent when nothing was decoded.
    pub background_pixel_share: Option<f64>,
    /// Tiles trimmed as all background or listed empty by the manifest.
    pub background_tiles: u64,
    /// The neighbour sample; absent for image palettes (no layout).
    pub neighbours: Option<NeighbourSample>,
    /// `neighbours.jumps / neighbours.varying`, when anything varied.
    pub jump_share: Option<f64>,
    /// One per failed check, in the order above.
    pub warnings: Vec<ColorWarning>,
}

/// One failed check.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[schemars(deny_unknown_fields)]
pub struct ColorWarning {
    /// `unlabelled-counts`, `no-background` or `texel-jumps`.
    pub check: String,
    /// The measured share, in percent.
    pub percent: f64,
    /// The threshold it crossed, in percent.
    pub threshold_percent: f64,
    /// What was measured, with its number and the threshold.
    pub message: String,
    /// What usually causes it.
    pub causes: String,
    /// How to render the palette unchanged.
    pub fix: String,
}

/// What the sample found: triples of adjacent texel pixels.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[schemars(deny_unknown_fields)]
pub struct NeighbourSample {
    /// Triples of adjacent pixels (in a row or a column) that all show texels.
    pub triples: u64,
    /// Of those, the triples whose three texels are not all the same.
    pub varying: u64,
    /// Of the varying ones, those whose middle texel is far from both
    /// neighbours while they are close to each other.
    pub jumps: u64,
}

/// One candidate empty file: a tile size and a file size.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[schemars(deny_unknown_fields)]
pub struct EmptyTile {
    pub width: u32,
    pub height: u32,
    /// File size in bytes.
    pub bytes: u64,
    /// The file that was decoded to verify it.
    pub reference: String,
    /// True when the reference decoded as pure background.
    pub verified: bool,
    /// Files of this size (the reference included).
    pub candidates: u64,
}

/// The palette as `result.json`'s `settings.palette` records it
/// ([`Fcsp::describe`]).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[schemars(deny_unknown_fields)]
pub struct PaletteSetting {
    /// `"canonical"` or `"image"`.
    pub kind: String,
    pub width: u32,
    pub height: u32,
    /// The palette image, for `"image"` palettes.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub file: Option<String>,
}

/// Shard `index` of `count`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[schemars(deny_unknown_fields)]
pub struct Shard {
    pub index: u32,
    pub count: u32,
}

/// What one count means.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum Dedupe {
    /// A texel counts once per image (tile) that shows it.
    #[default]
    Image,
    /// A texel counts once per eye-frame, however many of its tiles show it
    /// (each eye counts separately).
    Frame,
    /// A texel counts once per frame, over both eyes and all their tiles.
    #[serde(rename = "eye-pair")]
    EyePair,
}

/// How counts map onto the colormap.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum Scale {
    /// `count / max`.
    #[default]
    Linear,
    /// `ln(1 + count) / ln(1 + max)`: shows rarely seen texels too.
    Log,
}

#[cfg(test)]
mod tests {
    use super::TrimReport;

    #[test]
    fn a_trim_mode_other_than_auto_off_or_bytes_is_refused_naming_the_field() {
        for good in ["auto", "off", "4096"] {
            let json = format!(r#"{{"mode": "{good}", "empty_tiles": []}}"#);
            assert_eq!(serde_json::from_str::<TrimReport>(&json).unwrap().mode, good);
        }
        for bad in ["", "<script>", "-1", "4096 bytes", "AUTO"] {
            let json = format!(r#"{{"mode": "{bad}", "empty_tiles": []}}"#);
            let error = serde_json::from_str::<TrimReport>(&json).unwrap_err().to_string();
            assert!(error.contains("settings.trim.mode"), "{bad}: {error}");
        }
    }
}
