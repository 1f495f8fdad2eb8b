//! Reports: `result.json`, `parts.csv`, `timings.json` and the console table.
//!
//! `result.json` holds everything needed to regenerate the heatmap or redo
//! statistics without touching the archive: the summary (pretty-printed, for
//! people) followed by the per-texel counts (compact, for programs). It holds
//! no timings or thread counts, so the same input always gives the same bytes.

use std::io::Write;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::color::Color;
use crate::error::{Error, Result};
use crate::heatmap::Scale;
use crate::options::{Dedupe, Timings};
use crate::output::write_atomically;
use crate::palette::PaletteDescription;
use crate::parts::{PartStats, PartTable, Pidt, ratio};
use crate::trim::EmptyTile;

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
    pub palette: PaletteDescription,
    pub background: Vec<Color>,
    pub pidt: Option<String>,
    pub parts: Option<String>,
    pub dedupe: Dedupe,
    pub trim: TrimReport,
    pub heatmap_scale: Scale,
    pub heatmap_max: Option<u32>,
    /// The shard counted (`ufcsr-analyze --shard`); absent for a whole archive.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shard: Option<crate::shard::Shard>,
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
    pub resolution: Option<crate::resolution::ResolutionReport>,
    /// Resolution-independent measures per part (with frames tallied).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub measures: Option<crate::measures::Measures>,
}

fn default_measure() -> String {
    crate::options::MEASURE_PIXELS.to_string()
}

/// Per-texel counts as stored in `result.json`: only seen texels, texel
/// indices (`y * width + x`) ascending and delta-coded (the first delta is the
/// first index), counts in the same order.
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct TexelCountsJson {
    pub encoding: String,
    pub texels: u64,
    pub texel_delta: Vec<u32>,
    pub count: Vec<u32>,
}

impl TexelCountsJson {
    /// Expands into dense per-texel counts of `texel_count` texels.
    pub fn to_dense(&self, texel_count: usize, path: &Path) -> Result<Vec<u32>> {
        if self.encoding != "delta" || self.texel_delta.len() != self.count.len() {
            return Err(Error::bad_file(
                path,
                "texel_counts: expected delta encoding with arrays of equal length",
            ));
        }
        if self.texels != self.count.len() as u64 {
            return Err(Error::bad_file(
                path,
                format!(
                    "texel_counts: \"texels\" says {} but {} counts follow (edited or truncated?)",
                    self.texels,
                    self.count.len()
                ),
            ));
        }
        let mut dense = vec![0u32; texel_count];
        let mut texel = 0u64;
        for (position, (&delta, &count)) in self.texel_delta.iter().zip(&self.count).enumerate() {
            // Indices ascend strictly: only the first delta may be 0.
            if delta == 0 && position > 0 {
                return Err(Error::bad_file(
                    path,
                    format!("texel_counts: texel {texel} is listed twice (entry {position})"),
                ));
            }
            if count == 0 {
                return Err(Error::bad_file(
                    path,
                    format!("texel_counts: entry {position} has count 0 (only seen texels are listed)"),
                ));
            }
            texel += u64::from(delta);
            let slot = dense.get_mut(texel as usize).ok_or_else(|| {
                Error::bad_file(path, format!("texel_counts: texel {texel} is outside the palette"))
            })?;
            *slot = count;
        }
        Ok(dense)
    }
}

/// Writes `result.json`: the pretty summary, then the compact per-texel counts.
pub fn write_result_json(path: &Path, result: &AnalysisResult, texel_counts: &[u32]) -> Result<()> {
    let mut summary = serde_json::to_vec_pretty(result).map_err(|e| Error::bad_file(path, e.to_string()))?;
    // Re-open the top-level object to append the large arrays without
    // building them as JSON values in memory.
    while summary.last().is_some_and(|b| b.is_ascii_whitespace()) {
        summary.pop();
    }
    summary.pop(); // the closing '}'
    let seen = texel_counts.iter().filter(|&&c| c > 0).count();
    write_atomically(path, |writer| {
        writer.write_all(&summary)?;
        write!(writer, ",\n  \"texel_counts\": {{\n    \"encoding\": \"delta\",\n    \"texels\": {seen},\n")?;
        let mut buffer = itoa::Buffer::new();
        writer.write_all(b"    \"texel_delta\": [")?;
        let mut previous = 0usize;
        let mut first = true;
        for (texel, _) in texel_counts.iter().enumerate().filter(|(_, c)| **c > 0) {
            if !first {
                writer.write_all(b",")?;
            }
            let delta = if first { texel } else { texel - previous };
            writer.write_all(buffer.format(delta).as_bytes())?;
            previous = texel;
            first = false;
        }
        writer.write_all(b"],\n    \"count\": [")?;
        let mut first = true;
        for &count in texel_counts.iter().filter(|c| **c > 0) {
            if !first {
                writer.write_all(b",")?;
            }
            writer.write_all(buffer.format(count).as_bytes())?;
            first = false;
        }
        writer.write_all(b"]\n  }\n}\n")
    })
}

/// The parts of `result.json` that the heatmap needs.
#[derive(Deserialize)]
struct HeatmapSource {
    schema: String,
    #[serde(default = "default_measure")]
    measure: String,
    settings: HeatmapSettings,
    texel_counts: TexelCountsJson,
}

#[derive(Deserialize)]
struct HeatmapSettings {
    archive: String,
    palette: PaletteDescription,
    heatmap_scale: Scale,
    heatmap_max: Option<u32>,
}

/// Counts read back from `result.json`.
pub struct StoredCounts {
    pub width: u32,
    pub height: u32,
    pub texel_counts: Vec<u32>,
    pub scale: Scale,
    pub max: Option<u32>,
    /// What the counts are (`result.json`'s `measure`) and of which archive.
    pub measure: String,
    pub archive: String,
}

/// Reads the per-texel counts of a `result.json` (without the summary).
pub fn read_texel_counts(path: &Path) -> Result<StoredCounts> {
    let file = crate::input_file::open_regular(path)?;
    let source: HeatmapSource = serde_json::from_reader(std::io::BufReader::new(file))
        .map_err(|e| Error::bad_file(path, format!("not a ufcsr result.json: {e}")))?;
    stored_counts(path, source)
}

/// [`read_texel_counts`] of a result.json's bytes (`path` names it in messages).
pub fn parse_texel_counts(path: &Path, bytes: &[u8]) -> Result<StoredCounts> {
    let source: HeatmapSource = serde_json::from_slice(bytes)
        .map_err(|e| Error::bad_file(path, format!("not a ufcsr result.json: {e}")))?;
    stored_counts(path, source)
}

fn stored_counts(path: &Path, source: HeatmapSource) -> Result<StoredCounts> {
    if !source.schema.starts_with("ufcsr-result/") {
        return Err(Error::bad_file(path, format!("unknown result schema {:?}", source.schema)));
    }
    let palette = source.settings.palette;
    if palette.kind != "canonical" && palette.kind != "image" {
        return Err(Error::bad_file(
            path,
            format!("settings.palette.kind is {:?}: not \"canonical\" or \"image\"", palette.kind),
        ));
    }
    let texel_count = palette.width as usize * palette.height as usize;
    if palette.width == 0 || palette.height == 0 || texel_count > crate::color::COLOR_COUNT {
        return Err(Error::bad_file(
            path,
            format!("settings.palette is {}×{}: not a palette size", palette.width, palette.height),
        ));
    }
    let texel_counts = source.texel_counts.to_dense(texel_count, path)?;
    Ok(StoredCounts {
        width: palette.width,
        height: palette.height,
        texel_counts,
        scale: source.settings.heatmap_scale,
        max: source.settings.heatmap_max,
        measure: source.measure,
        archive: source.settings.archive,
    })
}

/// Reads the summary of a `result.json` (the per-texel arrays are skipped).
pub fn read_result_summary(path: &Path) -> Result<AnalysisResult> {
    let file = crate::input_file::open_regular(path)?;
    serde_json::from_reader(std::io::BufReader::new(file))
        .map_err(|e| Error::bad_file(path, format!("not a ufcsr result.json: {e}")))
}

/// Writes `timings.json`.
pub fn write_timings_json(path: &Path, timings: &Timings) -> Result<()> {
    write_atomically(path, |writer| {
        serde_json::to_writer_pretty(&mut *writer, timings).map_err(std::io::Error::other)?;
        writer.write_all(b"\n")
    })
}

/// Writes `parts.csv` with the original tool's columns plus `coverage`.
pub fn write_parts_csv(path: &Path, parts: &[PartStats]) -> Result<()> {
    write_atomically(path, |writer| {
        writeln!(
            writer,
            "part_name,pixel_count,part_total_value,highest_value,average_value,total_percentage,coverage"
        )?;
        for part in parts {
            writeln!(
                writer,
                "{},{},{},{},{},{},{}",
                csv_field(&part.name),
                part.texels,
                part.total,
                part.peak,
                part.average,
                part.share,
                part.coverage
            )?;
        }
        Ok(())
    })
}

/// `text` as one CSV field, quoted when it holds a comma, quote or newline.
pub fn csv_field(text: &str) -> String {
    // CR too: an unquoted CR would end the record for any CSV reader.
    if text.contains([',', '"', '\n', '\r']) || text.trim() != text {
        format!("\"{}\"", text.replace('"', "\"\""))
    } else {
        text.to_string()
    }
}

/// The parts shown in the console table: the union of the five highest by
/// total, by peak and by average (the paper's way), ordered by total.
pub fn headline_parts(parts: &[PartStats]) -> Vec<usize> {
    let top = |key: &dyn Fn(&PartStats) -> f64| {
        let mut order: Vec<usize> = (0..parts.len()).collect();
        order.sort_by(|&a, &b| key(&parts[b]).total_cmp(&key(&parts[a])).then(a.cmp(&b)));
        order.truncate(5);
        order
    };
    let mut chosen: Vec<usize> = top(&|p| p.total as f64);
    chosen.extend(top(&|p| f64::from(p.peak)));
    chosen.extend(top(&|p| p.average));
    chosen.sort_by(|&a, &b| parts[b].total.cmp(&parts[a].total).then(a.cmp(&b)));
    chosen.dedup();
    chosen
}

/// The console report: image bookkeeping and the headline part table.
pub fn format_table(result: &AnalysisResult) -> String {
    let mut out = String::new();
    let images = &result.images;
    out.push_str(&format!(
        "images: {} found, {} trimmed (empty), {} decoded, {} failed\n",
        images.found, images.trimmed, images.decoded, images.failed
    ));
    out.push_str(&format!(
        "pixels: {} decoded, {} background, {} stray ({} distinct stray colours)\n",
        result.pixels.decoded, result.background_pixels, result.stray_pixels, result.stray_colors
    ));
    out.push_str(&format!("texels seen: {}, max count: {}\n", result.texels_seen, result.max_count));
    if let Some(dedupe) = &result.dedupe {
        out.push_str(&format!(
            "dedupe per eye-frame: grand total {} vs {} per image ({:+.2}%)\n",
            dedupe.grand_total_per_frame, dedupe.grand_total_per_image, dedupe.change_percent
        ));
    }
    if result.parts.is_empty() {
        out.push_str(&format!("grand total (all texels): {}\n", result.grand_total));
        return out;
    }
    let header = format!(
        "\n{:<28} {:>10} {:>12} {:>7} {:>10} {:>8} {:>9}\n",
        "part", "texels", "total", "peak", "average", "share %", "covered %"
    );
    out.push_str(&header);
    out.push_str(&format!("{}\n", "-".repeat(header.trim().len())));
    let row = |name: &str, texels: u64, total: u64, peak: u32, seen: u64| {
        format!(
            "{:<28} {:>10} {:>12} {:>7} {:>10.3} {:>8.3} {:>9.2}\n",
            truncate(name, 28),
            texels,
            total,
            peak,
            ratio(total, texels),
            100.0 * ratio(total, result.grand_total),
            100.0 * ratio(seen, texels)
        )
    };
    let chosen = headline_parts(&result.parts);
    for &index in &chosen {
        let part = &result.parts[index];
        out.push_str(&row(&part.name, part.texels, part.total, part.peak, part.texels_seen));
    }
    let others: Vec<&PartStats> =
        result.parts.iter().enumerate().filter(|(i, _)| !chosen.contains(i)).map(|(_, p)| p).collect();
    if !others.is_empty() {
        let sum = |f: &dyn Fn(&PartStats) -> u64| others.iter().map(|p| f(p)).sum::<u64>();
        out.push_str(&row(
            &format!("(other {} parts)", others.len()),
            sum(&|p| p.texels),
            sum(&|p| p.total),
            others.iter().map(|p| p.peak).max().unwrap_or(0),
            sum(&|p| p.texels_seen),
        ));
    }
    out.push_str(&format!("{:<28} {:>10} {:>12}\n", "grand total", "", result.grand_total));
    if let Some(unlabelled) = &result.unlabelled {
        out.push_str(&format!(
            "unlabelled texels: {} (total {}, not in the grand total)\n",
            unlabelled.texels, unlabelled.total
        ));
    }
    out
}

fn truncate(text: &str, width: usize) -> String {
    if text.chars().count() <= width {
        text.to_string()
    } else {
        let mut short: String = text.chars().take(width - 1).collect();
        short.push('…');
        short
    }
}

/// The files [`crate::write_results`] wrote.
#[derive(Debug, Clone)]
pub struct WrittenFiles {
    pub result_json: PathBuf,
    pub parts_csv: Option<PathBuf>,
    pub heatmap_png: PathBuf,
    pub timings_json: PathBuf,
    /// The vehicle with the heatmap on it, when the analysis had a vehicle model.
    pub heatmap_glb: Option<PathBuf>,
    /// The page that shows it all.
    pub report_html: PathBuf,
    /// `views.png`, the contact sheet of the eight views (with a vehicle model).
    pub views_png: Option<PathBuf>,
    /// `frames.csv`, when frames were tallied.
    pub frames_csv: Option<PathBuf>,
    /// The plots written under `plots/`.
    pub plots: Vec<crate::plots::Plot>,
}
