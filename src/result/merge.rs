//! Merging the results of shards: `ufcsr merge RESULT... --out DIR`.
//!
//! Shards of one archive ([`crate::archive::shard`]) count disjoint sets of
//! eye-frames with the same settings, and every shard builds the same
//! trimming plan over the whole archive. So their per-texel counts add (with
//! saturation, like counting does), their image and pixel bookkeeping adds,
//! and everything else is recomputed from the summed counts with the same
//! PIdT and legend: the merged `result.json` is byte-identical to analysing
//! the archive whole (tested). Results whose settings disagree (palette,
//! background, PIdT, legend, dedupe, trimming, heatmap scale) are refused,
//! naming the file.

use std::path::{Path, PathBuf};

use crate::archive::labels::{Legend, Pidt};
use crate::archive::options::Timings;
use crate::archive::resolve::LabelFiles;
use crate::archive::shard::Shard;
use crate::color::Color;
use crate::error::{Error, Result};
use crate::result::model::Analysis;
use crate::result::resolution::ResolutionReport;
use crate::result::summarize::{
    color_checks, is_input_warning, join_with_legend, saturation_warning, stray_warning,
};
use crate::{
    result::model::{AnalysisResult, DedupeReport, ImageCounts, PixelCounts, RESULT_SCHEMA},
    result::result_json::{read_result_summary, read_texel_counts},
};

/// Stray colour examples kept in a result.
const EXAMPLES: usize = crate::result::model::STRAY_EXAMPLES;

/// Merges shard results into one analysis (write it with [`crate::output::write_results`]).
pub fn merge_results(paths: &[PathBuf]) -> Result<Analysis> {
    let first_path =
        paths.first().ok_or_else(|| Error::BadOptions("merge needs at least one result.json".into()))?;
    let (summaries, texel_counts) = read_and_sum(paths)?;
    check_agreement(paths, &summaries)?;
    let first = &summaries[0];
    let mut settings = first.settings.clone();
    settings.shard = None;
    let parts = load_labels(first_path, &settings)?;
    let all_texels_total: u64 = texel_counts.iter().map(|&c| u64::from(c)).sum();
    // Warnings about the inputs are the same in every shard; the rest are recomputed.
    let mut warnings: Vec<String> = first.warnings.iter().filter(|w| is_input_warning(w)).cloned().collect();
    let (table, unlabelled) = match &parts {
        Some(labels) => {
            let (table, unlabelled) = join_with_legend(&texel_counts, labels, &mut warnings);
            (Some(table), Some(unlabelled))
        }
        None => (None, None),
    };
    let grand_total = table.as_ref().map_or(all_texels_total, |t| t.grand_total);
    let dedupe = merged_dedupe(paths, &summaries, grand_total)?;
    let stray_pixels = checked_sum(paths, &summaries, "stray_pixels", |s| s.stray_pixels)?;
    let stray_images = summaries.iter().map(|s| s.images_with_stray_pixels.len()).sum::<usize>();
    warnings.extend(stray_warning(stray_pixels, stray_images));
    warnings.extend(saturation_warning(&texel_counts));
    let resolution =
        ResolutionReport::merged(&summaries.iter().filter_map(|s| s.resolution.as_ref()).collect::<Vec<_>>());
    if let Some(resolution) = &resolution {
        warnings.extend(resolution.warnings());
    }
    let (images, pixels) = summed_images_and_pixels(paths, &summaries)?;
    let color_checks = merged_color_checks(&summaries, &images, &pixels, &table, &unlabelled, &mut warnings);
    let mut notes = first.notes.clone();
    notes.extend(stray_colors_note(&summaries));
    let sum = |what: &str, field: fn(&AnalysisResult) -> u64| checked_sum(paths, &summaries, what, field);
    let mut result = AnalysisResult {
        schema: RESULT_SCHEMA.to_string(),
        measure: first.measure,
        images,
        texels_seen: texel_counts.iter().filter(|&&c| c > 0).count() as u64,
        pixels,
        stray_pixels,
        stray_colors: sum("stray_colors", |s| s.stray_colors)?,
        stray_color_examples: stray_color_examples(&summaries),
        background_pixels: sum("background_pixels", |s| s.background_pixels)?,
        grand_total,
        max_count: texel_counts.iter().copied().max().unwrap_or(0),
        parts: table.map(|t| t.parts).unwrap_or_default(),
        unlabelled,
        dedupe,
        settings,
        failures: sorted_by_file(summaries.iter().flat_map(|s| s.failures.iter().cloned()), |f| &f.file),
        images_with_stray_pixels: sorted_by_file(
            summaries.iter().flat_map(|s| s.images_with_stray_pixels.iter().cloned()),
            |s| &s.file,
        ),
        warnings,
        notes,
        resolution,
        measures: None,
        color_checks,
    };
    let frames = merged_frames(paths)?;
    let vehicle_model = archive_vehicle(&result.settings);
    result.measures = merged_measures(&summaries, frames.as_ref());
    let input_files = merge_input_files(paths, parts.as_ref(), vehicle_model.as_ref());
    let timings = Timings::default();
    let texel_angular_area = merged_texel_area(paths, &result.settings.palette)?;
    Ok(Analysis {
        result,
        texel_counts,
        timings,
        input_files,
        vehicle_model,
        frames,
        texel_angular_area,
        texel_area_units: None,
        labels: None,
    })
}

/// The shards' per-texel angular area, from their integer sums
/// (`texel-area.units`) added exactly, so it equals the whole analysis'
/// bits; `None` unless every shard kept them. Shards of different eyes or
/// fps (another deg²·s per sr) or sums past a `u64` are refused.
fn merged_texel_area(
    paths: &[PathBuf],
    palette: &crate::format::result::PaletteSetting,
) -> Result<Option<Vec<f32>>> {
    use crate::result::texel_area_file::TexelAreaUnits;
    let mut sum: Option<TexelAreaUnits> = None;
    for path in paths {
        let dir = path.parent().unwrap_or(Path::new("."));
        let Some(shard) = TexelAreaUnits::read_in(dir, palette.width, palette.height)? else {
            return Ok(None);
        };
        let units_file = || dir.join(crate::result::texel_area_file::TEXEL_AREA_UNITS_FILE);
        match &mut sum {
            None => sum = Some(shard),
            Some(sum) => {
                if sum.deg2_s_per_sr.to_bits() != shard.deg2_s_per_sr.to_bits() {
                    return Err(Error::bad_file(
                        &units_file(),
                        "another deg²·s per sr than the other shards' (eyes or fps differ)",
                    ));
                }
                for (total, units) in sum.units.iter_mut().zip(&shard.units) {
                    *total = total.checked_add(*units).ok_or_else(|| {
                        Error::bad_file(&units_file(), "the per-texel sums overflow when added")
                    })?;
                }
            }
        }
    }
    Ok(sum.map(|sum| sum.areas()))
}

/// Every result's summary, and their per-texel counts added (saturating, as
/// counting does); results of different palette sizes are refused.
fn read_and_sum(paths: &[PathBuf]) -> Result<(Vec<AnalysisResult>, Vec<u32>)> {
    let mut summaries = Vec::with_capacity(paths.len());
    let mut counts: Option<(Vec<u32>, u32, u32)> = None;
    for path in paths {
        let summary = read_result_summary(path)?;
        let stored = read_texel_counts(path)?;
        match &mut counts {
            None => counts = Some((stored.texel_counts, stored.width, stored.height)),
            Some((sum, width, height)) => {
                if (stored.width, stored.height) != (*width, *height) {
                    return Err(Error::bad_file(path, "its palette size differs from the other results'"));
                }
                for (total, count) in sum.iter_mut().zip(stored.texel_counts) {
                    *total = total.saturating_add(count);
                }
            }
        }
        summaries.push(summary);
    }
    match counts {
        Some((texel_counts, _, _)) => Ok((summaries, texel_counts)),
        None => Err(Error::bad_file(&paths[0], "no per-texel counts were read")),
    }
}

/// The legend and PIdT the results name, loaded again (errors name the
/// first result); none when the results have no labels.
fn load_labels(first_path: &Path, settings: &crate::result::model::Settings) -> Result<Option<LabelFiles>> {
    let (Some(legend_path), Some(pidt_path)) = (&settings.parts, &settings.pidt) else { return Ok(None) };
    let (legend_path, pidt_path) = (PathBuf::from(legend_path), PathBuf::from(pidt_path));
    let legend = Legend::load(&legend_path).map_err(|e| named_in(first_path, e))?;
    let pidt = Pidt::load(&pidt_path, &legend, [settings.palette.width, settings.palette.height])
        .map_err(|e| named_in(first_path, e))?;
    Ok(Some(LabelFiles { legend_path, legend, pidt_path, pidt: pidt.into() }))
}

/// The dedupe report of the whole: the shards' per-image totals added, and
/// the merged grand total (none when the results were not deduplicated).
fn merged_dedupe(
    paths: &[PathBuf],
    summaries: &[AnalysisResult],
    grand_total: u64,
) -> Result<Option<DedupeReport>> {
    if summaries[0].dedupe.is_none() {
        return Ok(None);
    }
    let per_image = checked_sum(paths, summaries, "dedupe.grand_total_per_image", |s| {
        s.dedupe.as_ref().map_or(0, |d| d.grand_total_per_image)
    })?;
    Ok(Some(DedupeReport::new(per_image, grand_total)))
}

/// The shards' image and pixel counts added.
fn summed_images_and_pixels(
    paths: &[PathBuf],
    summaries: &[AnalysisResult],
) -> Result<(ImageCounts, PixelCounts)> {
    let sum = |what: &str, field: fn(&AnalysisResult) -> u64| checked_sum(paths, summaries, what, field);
    let images = ImageCounts {
        found: sum("images.found", |s| s.images.found)?,
        trimmed: sum("images.trimmed", |s| s.images.trimmed)?,
        decoded: sum("images.decoded", |s| s.images.decoded)?,
        failed: sum("images.failed", |s| s.images.failed)?,
        listed_empty: sum("images.listed_empty", |s| s.images.listed_empty)?,
        skipped: sum("images.skipped", |s| s.images.skipped)?,
    };
    let pixels = PixelCounts {
        decoded: sum("pixels.decoded", |s| s.pixels.decoded)?,
        texel: sum("pixels.texel", |s| s.pixels.texel)?,
        background: sum("pixels.background", |s| s.pixels.background)?,
        stray: sum("pixels.stray", |s| s.pixels.stray)?,
    };
    Ok((images, pixels))
}

/// Why `stray_colors` is an upper bound, when more than one shard saw strays.
fn stray_colors_note(summaries: &[AnalysisResult]) -> Option<String> {
    let shards_with_strays = summaries.iter().filter(|s| s.stray_colors > 0).count();
    (shards_with_strays > 1).then(|| {
        format!(
            "stray_colors adds the distinct stray colours of {shards_with_strays} shards: a colour seen in several \
             counts once per shard, so it is an upper bound"
        )
    })
}

/// The shards' stray colour examples, sorted, without repeats, at most
/// [`EXAMPLES`].
fn stray_color_examples(summaries: &[AnalysisResult]) -> Vec<Color> {
    let mut examples: Vec<Color> =
        summaries.iter().flat_map(|s| s.stray_color_examples.iter().copied()).collect();
    examples.sort_by_key(|c| c.packed());
    examples.dedup();
    examples.truncate(EXAMPLES);
    examples
}

/// The shards' entries together, sorted by file (a stable sort, as before).
fn sorted_by_file<T>(entries: impl Iterator<Item = T>, file: impl Fn(&T) -> &String) -> Vec<T> {
    let mut entries: Vec<T> = entries.collect();
    entries.sort_by(|a, b| file(a).cmp(file(b)));
    entries
}

/// The files the merge read: the results, their frames.csv, the labels and
/// the vehicle model (writing the results refuses to overwrite any of them).
fn merge_input_files(
    paths: &[PathBuf],
    labels: Option<&LabelFiles>,
    vehicle_model: Option<&PathBuf>,
) -> Vec<PathBuf> {
    let mut input_files = paths.to_vec();
    input_files.extend(paths.iter().map(|p| p.with_file_name(crate::result::frames::FRAMES_FILE)));
    input_files
        .extend(labels.iter().flat_map(|labels| [labels.legend_path.clone(), labels.pidt_path.clone()]));
    input_files.extend(vehicle_model.cloned());
    input_files
}

/// The colour checks of the shards together: judged again from their summed
/// pixels, trimmed tiles and neighbour samples and the merged counts (absent
/// when a shard has none, e.g. an older result or an exact measure).
fn merged_color_checks(
    summaries: &[AnalysisResult],
    images: &ImageCounts,
    pixels: &PixelCounts,
    table: &Option<crate::result::part_stats::PartTable>,
    unlabelled: &Option<crate::result::model::UnlabelledReport>,
    warnings: &mut Vec<String>,
) -> Option<crate::checks::ColorChecks> {
    let shards: Vec<&crate::checks::ColorChecks> =
        summaries.iter().map(|s| s.color_checks.as_ref()).collect::<Option<_>>()?;
    let neighbours = shards.iter().try_fold(crate::checks::NeighbourSample::default(), |mut sum, c| {
        sum.add(c.neighbours.as_ref()?);
        Some(sum)
    });
    let facts = crate::checks::color_damage::ColorFacts {
        unlabelled_counts: unlabelled.as_ref().map(|u| u.total),
        labelled_counts: table.as_ref().map_or(0, |t| t.grand_total),
        decoded_pixels: pixels.decoded,
        background_pixels: pixels.background,
        background_tiles: images.trimmed,
        neighbours,
    };
    Some(color_checks(&facts, warnings))
}

/// The vehicle model the archive's manifest names (as the whole analysis
/// found it), so the merged result has `heatmap.glb` and the views too.
fn archive_vehicle(settings: &crate::result::model::Settings) -> Option<PathBuf> {
    if !settings.manifest {
        return None;
    }
    let root = PathBuf::from(&settings.archive);
    let manifest = crate::archive::manifest::Manifest::load_from_dir(&root).ok()??;
    let path = root.join(manifest.vehicle?);
    crate::files::open_regular(&path).ok().map(|_| path)
}

/// `field` added over every shard, or an error naming the shard where the
/// sum overflows (a hand-edited or damaged result).
fn checked_sum(
    paths: &[PathBuf],
    summaries: &[AnalysisResult],
    what: &str,
    field: fn(&AnalysisResult) -> u64,
) -> Result<u64> {
    let mut total = 0u64;
    for (path, summary) in paths.iter().zip(summaries) {
        total = total.checked_add(field(summary)).ok_or_else(|| {
            Error::bad_file(
                path,
                format!("{what} overflows when added to the other shards': a damaged result"),
            )
        })?;
    }
    Ok(total)
}

/// The shards' measures, when every shard has them: from their merged
/// `frames.csv` when there is one (the same rows, summed in the same order,
/// as the whole archive's: the same bits), else their sums added.
fn merged_measures(
    summaries: &[AnalysisResult],
    frames: Option<&crate::result::frames::FrameTable>,
) -> Option<crate::result::measures::Measures> {
    let measures: Option<Vec<_>> = summaries.iter().map(|s| s.measures.as_ref()).collect();
    let measures = measures?;
    match (frames, measures.first()) {
        (Some(frames), Some(first)) => {
            let clock = crate::archive::capture_facts::FrameClock {
                seconds_per_frame: first.seconds_per_frame,
                eyes: first.eyes,
                pixels_per_degree: first.pixels_per_degree,
            };
            Some(crate::result::measures::Measures::from_frames(frames, &clock))
        }
        _ => crate::result::measures::Measures::merged(&measures),
    }
}

/// The shards' `frames.csv` (beside each `result.json`) as one table, when
/// every shard wrote one.
fn merged_frames(paths: &[PathBuf]) -> Result<Option<crate::result::frames::FrameTable>> {
    let files: Vec<PathBuf> =
        paths.iter().map(|path| path.with_file_name(crate::result::frames::FRAMES_FILE)).collect();
    if !files.iter().all(|file| file.is_file()) {
        return Ok(None);
    }
    let tables = files
        .iter()
        .map(|file| crate::result::frames::FrameTable::read_csv(file))
        .collect::<Result<Vec<_>>>()?;
    Ok(crate::result::frames::FrameTable::merged(tables))
}

/// Prefixes an error with the result that named the file.
fn named_in(result: &Path, error: Error) -> Error {
    Error::BadOptions(format!("{} (named in {})", error, result.display()))
}

/// Each result's shard, checked (a hand-edited `index >= count` or `count`
/// 0 is an error naming the file, not a panic).
fn valid_shards(paths: &[PathBuf], summaries: &[AnalysisResult]) -> Result<Vec<Option<Shard>>> {
    let shards: Vec<Option<Shard>> = summaries.iter().map(|s| s.settings.shard).collect();
    for (path, shard) in paths.iter().zip(&shards) {
        if let Some(shard) = shard {
            Shard::new(shard.index, shard.count).map_err(|e| Error::bad_file(path, e.to_string()))?;
        }
    }
    Ok(shards)
}

/// Every result must come from the same analysis settings, and shards must
/// be of one split, each once.
fn check_agreement(paths: &[PathBuf], summaries: &[AnalysisResult]) -> Result<()> {
    let first = &summaries[0];
    let mut reference = first.settings.clone();
    reference.shard = None;
    for (path, summary) in paths.iter().zip(summaries).skip(1) {
        let mut settings = summary.settings.clone();
        settings.shard = None;
        if summary.schema != first.schema {
            return Err(Error::bad_file(
                path,
                format!("schema {} differs from {}", summary.schema, first.schema),
            ));
        }
        if summary.measure != first.measure {
            return Err(Error::bad_file(
                path,
                format!(
                    "its measure {:?} differs from {:?}: counts of different measures do not add",
                    summary.measure, first.measure
                ),
            ));
        }
        if settings != reference {
            let field = [
                ("archive", settings.archive != reference.archive),
                ("palette", settings.palette != reference.palette),
                ("background", settings.background != reference.background),
                ("pidt", settings.pidt != reference.pidt),
                ("parts (legend)", settings.parts != reference.parts),
                ("dedupe", settings.dedupe != reference.dedupe),
                ("trim", settings.trim != reference.trim),
                (
                    "archive identity (its manifest, tiles, palette, PIdT or legend)",
                    settings.archive_identity != reference.archive_identity,
                ),
                (
                    "heatmap scale",
                    settings.heatmap_scale != reference.heatmap_scale
                        || settings.heatmap_max != reference.heatmap_max,
                ),
            ]
            .into_iter()
            .find(|(_, differs)| *differs)
            .map_or("settings", |(name, _)| name);
            return Err(Error::bad_file(
                path,
                format!("its {field} differs from {}: only shards of one analysis merge", paths[0].display()),
            ));
        }
    }
    let shards = valid_shards(paths, summaries)?;
    if shards.iter().all(Option::is_some) {
        let count = shards[0].map_or(0, |s| s.count);
        let mut seen = vec![false; count as usize];
        for (path, shard) in paths.iter().zip(shards.iter().flatten()) {
            if shard.count != count {
                return Err(Error::bad_file(
                    path,
                    format!("is shard {shard}, but the first result is of {count} shards"),
                ));
            }
            if std::mem::replace(&mut seen[shard.index as usize], true) {
                return Err(Error::bad_file(path, format!("shard {shard} is given twice")));
            }
        }
        if let Some(missing) = seen.iter().position(|&s| !s) {
            return Err(Error::BadOptions(format!("shard {missing}/{count} is missing from the merge")));
        }
    } else if shards.iter().any(Option::is_some) || summaries.len() > 1 {
        let whole = paths.iter().zip(&shards).find(|(_, s)| s.is_none()).map(|(p, _)| p);
        if let Some(path) = whole {
            return Err(Error::bad_file(
                path,
                "is the result of a whole archive, not a shard: nothing to merge it with",
            ));
        }
    }
    Ok(())
}
