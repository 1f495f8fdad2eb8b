//! Summarizing: counted images (or per-texel counts measured another way) →
//! the image and pixel bookkeeping, the parts table, the warnings and
//! everything else `result.json` reports ([`crate::result::model`]).

use std::path::PathBuf;
use std::time::Instant;

use rayon::prelude::*;

use crate::archive::archive_reader::Archive;
use crate::archive::manifest::MANIFEST_FILE;
use crate::archive::options::{AnalyzeOptions, Timings};
use crate::archive::palette::Fcsp;
use crate::archive::resolve::{
    CAPTURE_WARNING, Inputs, LabelFiles, MISSING_VEHICLE_WARNING, SKIPPED_FILES_WARNING,
    UNREADABLE_VEHICLE_WARNING,
};
use crate::archive::shard::Shard;
use crate::checks::color_damage::{ColorFacts, UNLABELLED_CHECK};
use crate::checks::{ColorChecks, ColorWarning, NeighbourSample};
use crate::color::Color;
use crate::color::sets::AtomicColorSet;
use crate::count::counts::Counts;
use crate::count::part_lookup::{FrameLabel, FrameRecord};
use crate::count::trim::EmptyTile;
use crate::count::work::{CountedImages, FrameTallies, Outcome, eye_frame_label, in_shard};
use crate::error::{Error, Result};
use crate::format::result::CountMeasure;
use crate::result::frames::FrameTable;
use crate::result::model::{
    Analysis, AnalysisResult, DedupeReport, FailedImage, ImageCounts, PixelCounts, RESULT_SCHEMA,
    STRAY_EXAMPLES, Settings, StrayImage, TrimReport, UnlabelledReport,
};
use crate::result::part_stats::{PartTable, join_parts};
use crate::result::resolution::ResolutionReport;

/// What every summary needs beside the counts: the job and its inputs, what
/// trimming found, and the clock.
pub(crate) struct Summary<'a> {
    pub options: &'a AnalyzeOptions,
    pub inputs: &'a Inputs,
    pub empty_tiles: Vec<EmptyTile>,
    pub timings: Timings,
    /// When the analysis began.
    pub started: Instant,
}

/// Stages "tally" and "summarize": counted images → per-texel counts, the
/// parts table and everything `result.json` reports.
pub(crate) fn summarize(summary: Summary, counted: CountedImages) -> Result<Analysis> {
    let CountedImages { outcomes, image_counts, frame_counts, strays, neighbours } = counted;
    let palette = &summary.inputs.palette;
    let counts = TexelCounts {
        image: texel_counts_of(palette, image_counts),
        frame: frame_counts.map(|counts| texel_counts_of(palette, counts)),
    };
    summarize_counted_texels(summary, outcomes, counts, neighbours, &strays)
}

/// Per-texel counts in palette layout: once per image, and once per
/// eye-frame or frame when deduplicated.
pub(crate) struct TexelCounts {
    pub image: Vec<u32>,
    pub frame: Option<Vec<u32>>,
}

/// Stages "tally" and "summarize" for images already counted into per-texel
/// counts ([`summarize`]'s, and the 32-bit texel-id path's,
/// [`crate::count::rgba32`]).
pub(crate) fn summarize_counted_texels(
    summary: Summary,
    outcomes: Vec<Outcome>,
    counts: TexelCounts,
    neighbours: Option<NeighbourSample>,
    strays: &AtomicColorSet,
) -> Result<Analysis> {
    let mut summary = summary;
    let mut tally = tally(summary.options, &summary.inputs.archive, outcomes)?;
    tally.neighbours = neighbours;
    let decoded_pixels = tally.background_pixels + tally.stray_pixels + tally.texel_pixels;
    summary.timings.decoded_megapixels_per_second =
        decoded_pixels as f64 / 1e6 / summary.timings.count_seconds.max(1e-9);

    let stage = Instant::now();
    let (texel_counts, per_image_counts) = match counts.frame {
        Some(frame) => (frame, Some(counts.image)),
        None => (counts.image, None),
    };
    let per_texel =
        PerTexel { texel_counts, per_image_counts, measure: CountMeasure::Pixels, resolution_report: true };
    finish(summary, tally, per_texel, strays, stage)
}

/// Stage "summarize" for per-texel counts measured some other way than by
/// counting pixels (`measure` names it): no images, no pixels.
pub(crate) fn summarize_texel_counts(
    summary: Summary,
    texel_counts: Vec<u32>,
    measure: CountMeasure,
) -> Result<Analysis> {
    let tally = Tally { images: ImageCounts::default(), ..Tally::default() };
    let per_texel = PerTexel { texel_counts, per_image_counts: None, measure, resolution_report: false };
    finish(summary, tally, per_texel, &AtomicColorSet::new(), Instant::now())
}

/// The parts table, the unlabelled report and the dedupe report: the
/// per-texel counts joined with the PIdT (when there is one).
struct Joined {
    table: Option<PartTable>,
    unlabelled: Option<UnlabelledReport>,
    dedupe: Option<DedupeReport>,
}

/// Joins `per_texel`'s counts with the labels (when there are any); warns
/// about legend parts without texels.
fn join(labels: Option<&LabelFiles>, per_texel: &PerTexel, warnings: &mut Vec<String>) -> Joined {
    let PerTexel { texel_counts, per_image_counts, .. } = per_texel;
    match labels {
        Some(labels) => {
            let (table, unlabelled) = join_with_legend(texel_counts, labels, warnings);
            let dedupe = per_image_counts.as_ref().map(|per_image| {
                let per_image_total = join_parts(per_image, &labels.pidt, &labels.legend).grand_total;
                DedupeReport::new(per_image_total, table.grand_total)
            });
            Joined { table: Some(table), unlabelled: Some(unlabelled), dedupe }
        }
        None => {
            let dedupe = per_image_counts.as_ref().map(|per_image| {
                let sum = |counts: &[u32]| counts.par_iter().map(|&c| u64::from(c)).sum::<u64>();
                DedupeReport::new(sum(per_image), sum(texel_counts))
            });
            Joined { table: None, unlabelled: None, dedupe }
        }
    }
}

/// The settings `result.json` records.
fn settings(summary: &Summary, empty_tiles: Vec<EmptyTile>) -> Settings {
    let (options, inputs) = (summary.options, summary.inputs);
    Settings {
        archive: options.archive.display().to_string(),
        manifest: !options.ignore_manifest && inputs.archive.frame_groups > 0,
        palette: inputs.palette.describe(),
        background: inputs.backgrounds.clone(),
        pidt: inputs.parts.as_ref().map(|p| p.pidt_path.display().to_string()),
        parts: inputs.parts.as_ref().map(|p| p.legend_path.display().to_string()),
        dedupe: inputs.dedupe,
        trim: TrimReport { mode: options.trim.to_string(), empty_tiles },
        heatmap_scale: options.heatmap.scale,
        heatmap_max: options.heatmap.max,
        heatmap_area_max: options.area_max,
        shard: options.shard,
        archive_identity: Some(inputs.identity.clone()),
    }
}

/// A note per background colour that is also a palette colour.
fn background_notes(inputs: &Inputs) -> Vec<String> {
    let mut notes = Vec::new();
    for background in &inputs.backgrounds {
        if inputs.palette.contains(background.packed()) {
            notes.push(format!(
                "background {background} is also a palette colour; that texel is ignored (never counted)"
            ));
        }
    }
    notes
}

/// Every file the analysis read: [`crate::output::write_results`] refuses to write over them.
fn input_files(summary: &Summary) -> Vec<PathBuf> {
    let inputs = summary.inputs;
    let mut input_files: Vec<PathBuf> =
        inputs.archive.images.iter().map(|image| image.path.clone()).collect();
    input_files.extend(
        inputs.parts.iter().flat_map(|labels| [labels.legend_path.clone(), labels.pidt_path.clone()]),
    );
    input_files.extend(inputs.palette_file.iter().cloned());
    input_files.push(summary.options.archive.join(MANIFEST_FILE));
    input_files.extend(inputs.vehicle_model.iter().cloned());
    input_files
}

/// Stage "summarize": per-texel counts → parts table and everything
/// `result.json` reports.
fn finish(
    summary: Summary,
    tally: Tally,
    per_texel: PerTexel,
    strays: &AtomicColorSet,
    stage: Instant,
) -> Result<Analysis> {
    let inputs = summary.inputs;
    let decoded_pixels = tally.background_pixels + tally.stray_pixels + tally.texel_pixels;
    let texel_counts = &per_texel.texel_counts;
    let texels_seen = texel_counts.par_iter().filter(|&&c| c > 0).count() as u64;
    let max_count = texel_counts.par_iter().copied().max().unwrap_or(0);
    let mut warnings = inputs.warnings.clone();
    let notes = background_notes(inputs);
    let Joined { table, unlabelled, dedupe } = join(inputs.parts.as_ref(), &per_texel, &mut warnings);
    let mut summary = summary;
    let mut timings = std::mem::take(&mut summary.timings);
    timings.join_seconds = stage.elapsed().as_secs_f64();
    timings.total_seconds = summary.started.elapsed().as_secs_f64();

    let grand_total = texel_counts.par_iter().map(|&count| u64::from(count)).sum();
    let per_image_total = match &per_texel.per_image_counts {
        Some(per_image) => per_image.par_iter().map(|&count| u64::from(count)).sum(),
        None => grand_total,
    };
    // Leading the list: nothing after it matters when the images are not palette renders.
    if let Some(warning) = not_palette_renders_warning(tally.stray_pixels, tally.texel_pixels) {
        warnings.insert(0, warning);
    }
    warnings.extend(stray_warning(tally.stray_pixels, tally.stray_images.len()));
    warnings.extend(saturation_warning(texel_counts));
    let resolution = per_texel
        .resolution_report
        .then(|| ResolutionReport::new(tally.texel_pixels, per_image_total, &inputs.geometry));
    warnings.extend(resolution.iter().flat_map(ResolutionReport::warnings));
    let color_facts = ColorFacts {
        unlabelled_counts: unlabelled.as_ref().map(|u| u.total),
        labelled_counts: table.as_ref().map_or(grand_total, |t| t.grand_total),
        decoded_pixels,
        background_pixels: tally.background_pixels,
        background_tiles: tally.images.trimmed,
        neighbours: tally.neighbours,
    };
    let color_checks = per_texel.resolution_report.then(|| color_checks(&color_facts, &mut warnings));
    let result = AnalysisResult {
        schema: RESULT_SCHEMA.to_string(),
        measure: per_texel.measure,
        images: tally.images,
        texels_seen,
        pixels: PixelCounts {
            decoded: decoded_pixels,
            texel: tally.texel_pixels,
            background: tally.background_pixels,
            stray: tally.stray_pixels,
        },
        stray_pixels: tally.stray_pixels,
        stray_colors: strays.len(),
        stray_color_examples: strays.first(STRAY_EXAMPLES).into_iter().map(Color::from_packed).collect(),
        background_pixels: tally.background_pixels,
        grand_total: table.as_ref().map_or(grand_total, |t| t.grand_total),
        max_count,
        parts: table.map(|t| t.parts).unwrap_or_default(),
        unlabelled,
        dedupe,
        settings: settings(&summary, summary.empty_tiles.clone()),
        failures: tally.failures,
        images_with_stray_pixels: tally.stray_images,
        warnings,
        notes,
        resolution,
        measures: None,
        color_checks,
    };
    Ok(Analysis {
        result,
        texel_counts: per_texel.texel_counts,
        timings,
        input_files: input_files(&summary),
        vehicle_model: inputs.vehicle_model.clone(),
        frames: None,
        texel_angular_area: None,
        texel_area_units: None,
        labels: inputs.parts.as_ref().map(crate::archive::resolve::LabelFiles::loaded),
    })
}

/// The `frames.csv` table: a record per eye-frame of the shard (with a
/// manifest, also those whose tiles were all empty or trimmed: zero rows), or
/// per decoded image without one, in eye-frame (or name) order.
pub(crate) fn frame_table(tallies: FrameTallies, inputs: &Inputs, shard: Option<Shard>) -> FrameTable {
    let FrameTallies { parts, records, .. } = tallies;
    if inputs.archive.frame_groups == 0 || inputs.eye_frames.len() != inputs.archive.frame_groups {
        let mut records = records;
        records.sort_by_key(|record| match record.label {
            FrameLabel::Image(position) => position,
            FrameLabel::EyeFrame(_) => usize::MAX,
        });
        return FrameTable { parts, records };
    }
    let mut by_label: Vec<Option<FrameRecord>> = vec![None; inputs.eye_frames.len()];
    for record in records {
        if let FrameLabel::EyeFrame(eye_frame) = &record.label {
            let group =
                inputs.eye_frames.iter().position(|e| e.frame == eye_frame.frame && e.eye == eye_frame.eye);
            if let Some(group) = group {
                by_label[group] = Some(record);
            }
        }
    }
    let records = by_label
        .into_iter()
        .enumerate()
        .filter(|(group, _)| shard.is_none_or(|shard| shard.takes(*group)))
        .map(|(group, record)| {
            record.unwrap_or_else(|| FrameRecord {
                label: eye_frame_label(&inputs.eye_frames, group),
                pixels: vec![0; parts.len()],
                texels: vec![0; parts.len()],
                solid_angle_sr: inputs.optics.map(|_| vec![0.0; parts.len()]),
            })
        })
        .collect();
    FrameTable { parts, records }
}

/// Joins per-texel counts with the PIdT and legend: the parts table, the
/// unlabelled report, and a warning per legend part without texels.
pub(crate) fn join_with_legend(
    texel_counts: &[u32],
    labels: &LabelFiles,
    warnings: &mut Vec<String>,
) -> (PartTable, UnlabelledReport) {
    let table = join_parts(texel_counts, &labels.pidt, &labels.legend);
    warnings.extend(empty_part_warnings(
        &table,
        &labels.legend_path.display().to_string(),
        &labels.pidt_path.display().to_string(),
    ));
    let unlabelled = UnlabelledReport::new(&table, &labels.pidt);
    (table, unlabelled)
}

/// True for a warning about the inputs rather than the counts (see above).
pub(crate) fn is_input_warning(warning: &str) -> bool {
    warning.contains(SKIPPED_FILES_WARNING)
        || warning.contains(MISSING_VEHICLE_WARNING)
        || warning.contains(UNREADABLE_VEHICLE_WARNING)
        || warning.starts_with(CAPTURE_WARNING)
}

/// The warning for texels whose count reached the most a `u32` holds
/// (4,294,967,295: a texel in every image of a 10⁶-frame run at 5×5 tiles
/// and two eyes is far below it, but merged shards of many runs may get
/// there). Counting saturates instead of wrapping, so such counts, and the
/// totals, peaks and shares they enter, are lower bounds.
pub(crate) fn saturation_warning(texel_counts: &[u32]) -> Option<String> {
    let saturated = texel_counts.iter().filter(|&&count| count == u32::MAX).count();
    (saturated > 0).then(|| {
        format!(
            "{saturated} texels reached {}, the most a count holds: their counts (and the totals, peaks and \
             shares they enter) are lower bounds",
            u32::MAX
        )
    })
}

/// Judges the colour checks and adds their warnings to `warnings`, with,
/// when no check warned about them, the plain fact of counts on unlabelled
/// texels (a PIdT that misses a part, perhaps).
pub(crate) fn color_checks(facts: &ColorFacts, warnings: &mut Vec<String>) -> ColorChecks {
    let checks = ColorChecks::judge(facts);
    warnings.extend(checks.warnings.iter().map(ColorWarning::line));
    let unlabelled_warned = checks.warnings.iter().any(|w| w.check == UNLABELLED_CHECK);
    if let (Some(total), Some(share)) = (facts.unlabelled_counts, checks.unlabelled_count_share)
        && total > 0
        && !unlabelled_warned
    {
        warnings.push(format!(
            "{total} counts ({:.2} % of all counts) fell on texels the PIdT does not label (not in the grand \
             total; see unlabelled)",
            100.0 * share
        ));
    }
    checks
}

/// The plain warning when most pixels that are not background show no
/// palette colour ([`crate::format::result::PixelCounts::not_palette_renders`]):
/// what the images likely are and what to check. The analysis then ends
/// with failures (exit 1).
pub(crate) fn not_palette_renders_warning(stray_pixels: u64, texel_pixels: u64) -> Option<String> {
    (stray_pixels > texel_pixels).then(|| {
        format!(
            "these images are not palette renders: {stray_pixels} of the {} pixels that are not background show \
             no palette colour (only {texel_pixels} do), so the counts mean nothing. Likely the vehicle is not \
             textured with the FCSP palette, or it was rendered lit or shaded, antialiased (MSAA, FXAA, TAA), \
             filtered (mipmaps, bilinear), or colour-managed (sRGB conversion, tone mapping, a lossy format); \
             see docs/guide.md#colour-damage",
            stray_pixels + texel_pixels
        )
    })
}

/// The warning for stray pixels, in result.json as well as on stderr (on
/// stderr alone it was lost to anyone reading only the results).
pub(crate) fn stray_warning(stray_pixels: u64, images: usize) -> Option<String> {
    (stray_pixels > 0).then(|| {
        format!(
            "{stray_pixels} stray pixels (neither background nor a palette colour) in {images} images were not \
             counted (see images_with_stray_pixels)"
        )
    })
}

/// One warning per legend part without texels in the PIdT.
pub(crate) fn empty_part_warnings(
    table: &crate::result::part_stats::PartTable,
    legend: &str,
    pidt: &str,
) -> Vec<String> {
    table
        .parts
        .iter()
        .filter(|p| p.texels == 0)
        .map(|part| {
            format!(
                "{legend}: part {:?} ({}) has no texels in {pidt}",
                part.name,
                part.color.map(|c| c.to_string()).unwrap_or_default(),
            )
        })
        .collect()
}

/// Pixel and image bookkeeping of the outcomes.
#[derive(Default)]
struct Tally {
    images: ImageCounts,
    failures: Vec<FailedImage>,
    stray_images: Vec<StrayImage>,
    background_pixels: u64,
    stray_pixels: u64,
    texel_pixels: u64,
    /// The colour checks' neighbour sample.
    neighbours: Option<NeighbourSample>,
}

/// Stage "tally": outcomes → image and pixel bookkeeping (failures reported
/// in archive order; under `--strict` the first failure is the error).
fn tally(options: &AnalyzeOptions, archive: &Archive, outcomes: Vec<Outcome>) -> Result<Tally> {
    let mut tally = Tally::default();
    let (images_here, listed_empty) = match options.shard {
        None => (archive.images.len() as u64, archive.listed_empty),
        Some(shard) => (
            archive.images.iter().enumerate().filter(|(i, image)| in_shard(Some(shard), *i, image)).count()
                as u64,
            archive.listed_empty_groups.iter().filter(|&&group| shard.takes(group)).count() as u64,
        ),
    };
    tally.images.found = images_here + listed_empty;
    tally.images.listed_empty = listed_empty;
    // Shards of one folder all see the same skipped files: the first reports them.
    if options.shard.is_none_or(|s| s.index == 0) {
        tally.images.skipped =
            (archive.skipped.len() + archive.aliases.len() + archive.result_folder_pngs) as u64;
    }
    tally.images.trimmed = listed_empty;
    for (image, outcome) in archive.images.iter().zip(outcomes) {
        let name = &image.name;
        match outcome {
            Outcome::Trimmed => tally.images.trimmed += 1,
            Outcome::Decoded(image_tally) => {
                tally.images.decoded += 1;
                tally.background_pixels += image_tally.background_pixels;
                tally.stray_pixels += image_tally.stray_pixels;
                tally.texel_pixels += image_tally.texel_pixels;
                if image_tally.stray_pixels > 0 {
                    tally
                        .stray_images
                        .push(StrayImage { file: name.clone(), stray_pixels: image_tally.stray_pixels });
                }
            }
            Outcome::Failed(error) => {
                if options.strict {
                    return Err(Error::Strict(Box::new(error)));
                }
                tally.images.failed += 1;
                tally.failures.push(FailedImage { file: name.clone(), error: error.to_string() });
            }
            // Only under --strict, which returned above when anything failed.
            Outcome::Skipped => {}
        }
    }
    Ok(tally)
}

/// Per-texel counts ready to be joined with the PIdT.
struct PerTexel {
    texel_counts: Vec<u32>,
    /// The once-per-image counts when `texel_counts` are per eye-frame.
    per_image_counts: Option<Vec<u32>>,
    measure: CountMeasure,
    /// Whether pixel-based resolution diagnostics apply.
    resolution_report: bool,
}

/// Per-colour counts → per-texel counts in palette layout.
fn texel_counts_of(palette: &Fcsp, counts: Counts) -> Vec<u32> {
    match palette {
        Fcsp::Canonical { .. } => {
            // Texel index == colour: reuse the allocation.
            let mut per_color = counts.into_vec();
            per_color.truncate(palette.texel_count());
            per_color
        }
        Fcsp::Image { colors, .. } => {
            let per_color = counts.into_vec();
            colors.par_iter().map(|&color| per_color[color as usize]).collect()
        }
    }
}
