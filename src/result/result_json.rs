//! `result.json` and `timings.json`: writing them, and reading them back.
//!
//! `result.json` holds everything needed to regenerate the heatmap or redo
//! statistics without touching the archive: the summary (pretty-printed, for
//! people) followed by the per-texel counts (compact, for programs). It holds
//! no timings or thread counts, so the same input always gives the same bytes.

use std::io::Write;
use std::path::Path;

use serde::Deserialize;

use crate::archive::options::{Scale, Timings};
use crate::archive::palette::PaletteSetting;
use crate::error::{Error, Result};
use crate::files::write_atomically;
use crate::format::result::CountMeasure;
use crate::result::model::AnalysisResult;

pub(crate) use crate::format::result::TexelCountsJson;

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
    #[serde(default)]
    measure: CountMeasure,
    settings: HeatmapSettings,
    texel_counts: TexelCountsJson,
}

#[derive(Deserialize)]
struct HeatmapSettings {
    archive: String,
    palette: PaletteSetting,
    heatmap_scale: Scale,
    heatmap_max: Option<u32>,
    #[serde(default)]
    heatmap_area_max: Option<f64>,
}

/// Counts read back from `result.json`.
pub struct StoredCounts {
    pub width: u32,
    pub height: u32,
    pub texel_counts: Vec<u32>,
    pub scale: Scale,
    pub max: Option<u32>,
    /// The top of the angular-area heatmap's scale (`--area-max`, deg²·s
    /// per texel), when it was given.
    pub area_max: Option<f64>,
    /// What the counts are (`result.json`'s `measure`) and of which archive.
    pub measure: CountMeasure,
    pub archive: String,
}

/// Reads the per-texel counts of a `result.json` (without the summary).
pub fn read_texel_counts(path: &Path) -> Result<StoredCounts> {
    refuse_half_written(path)?;
    let file = crate::files::open_regular(path)?;
    let source: HeatmapSource = serde_json::from_reader(std::io::BufReader::new(file))
        .map_err(|e| Error::bad_file(path, format!("not a ufcsr result.json: {e}")))?;
    stored_counts(path, source)
}

/// [`read_texel_counts`] of a result.json's bytes (`path` names it in messages).
pub(crate) fn parse_texel_counts(path: &Path, bytes: &[u8]) -> Result<StoredCounts> {
    let source: HeatmapSource = serde_json::from_slice(bytes)
        .map_err(|e| Error::bad_file(path, format!("not a ufcsr result.json: {e}")))?;
    stored_counts(path, source)
}

fn stored_counts(path: &Path, source: HeatmapSource) -> Result<StoredCounts> {
    check_result_schema(path, &source.schema)?;
    let palette = source.settings.palette;
    if palette.kind != "canonical" && palette.kind != "image" {
        return Err(Error::bad_file(
            path,
            format!("settings.palette.kind is {:?}: not \"canonical\" or \"image\"", palette.kind),
        ));
    }
    let texel_count = palette.width as usize * palette.height as usize;
    if palette.width == 0
        || palette.height == 0
        || texel_count as u64 > crate::archive::palette::MAX_RGBA32_TEXELS
    {
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
        area_max: source.settings.heatmap_area_max,
        measure: source.measure,
        archive: source.settings.archive,
    })
}

/// Only the current schema is read: a newer version (or a foreign file)
/// could mean something else by the same fields, as for manifests.
fn check_result_schema(path: &Path, schema: &str) -> Result<()> {
    if schema == crate::result::model::RESULT_SCHEMA {
        return Ok(());
    }
    let hint = if schema.starts_with("ufcsr-result/") {
        format!(
            "a version this ufcsr does not know (it reads {}); update ufcsr",
            crate::result::model::RESULT_SCHEMA
        )
    } else {
        format!("not a ufcsr result (expected {})", crate::result::model::RESULT_SCHEMA)
    };
    Err(Error::bad_file(path, format!("schema {schema:?}: {hint}")))
}

/// A result set whose commit a killed run left unfinished is part old,
/// part new: refused until a run into its folder finishes it.
fn refuse_half_written(path: &Path) -> Result<()> {
    let folder = path.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
    match crate::files::interrupted_commit(folder)? {
        Some(journal) => Err(Error::bad_file(
            path,
            format!(
                "its run was killed while it moved a new result set into place ({} is left): the set is \
                 part old, part new; analyse again into this folder (that finishes the move first)",
                journal.display()
            ),
        )),
        None => Ok(()),
    }
}

/// Reads the summary of a `result.json` (the per-texel arrays are skipped).
pub fn read_result_summary(path: &Path) -> Result<AnalysisResult> {
    refuse_half_written(path)?;
    let file = crate::files::open_regular(path)?;
    let result: AnalysisResult = serde_json::from_reader(std::io::BufReader::new(file))
        .map_err(|e| Error::bad_file(path, format!("not a ufcsr result.json: {e}")))?;
    check_result_schema(path, &result.schema)?;
    Ok(result)
}

/// Writes `timings.json`.
pub fn write_timings_json(path: &Path, timings: &Timings) -> Result<()> {
    write_atomically(path, |writer| {
        let file = crate::format::timings::TimingsFile::new(timings.clone());
        serde_json::to_writer_pretty(&mut *writer, &file).map_err(std::io::Error::other)?;
        writer.write_all(b"\n")
    })
}
