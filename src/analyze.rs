//! The analysis job: archive in, counts and per-part statistics out.
//!
//! [`analyze`] resolves the options against the archive's manifest once,
//! builds every read-only object the workers need (palette, classifier,
//! trimming plan), then counts the images in parallel with rayon and joins
//! the counts with the PIdT. Per-image outcomes are kept in archive order, so
//! the result is identical whatever the number of threads.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Mutex, PoisonError};
use std::time::Instant;

use rayon::prelude::*;

use crate::archive::Archive;
use crate::bitset::{AtomicColorSet, SeenSet};
use crate::color::Color;
use crate::count::Counts;
use crate::decode::read_file;
use crate::error::{Error, Result};
use crate::frames::{EyeFrame, FrameClock, FrameLabel, FrameRecord, FrameTable, PartLookup};
use crate::heatmap::HeatmapOptions;
use crate::manifest::{Manifest, PaletteSpec};
use crate::measures::Measures;
pub use crate::options::{AnalyzeOptions, Dedupe, MEASURE_PIXELS, PaletteChoice, Progress, Timings};
use crate::palette::{DEFAULT_PALETTE_SIDE, Fcsp};
use crate::parts::{Legend, Pidt, join_parts};
pub use crate::report::WrittenFiles;
use crate::report::{
    AnalysisResult, DedupeReport, FailedImage, ImageCounts, Settings, StrayImage, TrimReport,
    UnlabelledReport,
};
use crate::resolution::{CaptureGeometry, ResolutionReport};
use crate::scan::{Classifier, ImageTally, scan_image_by_part};
use crate::shard::Shard;
use crate::tile_counter::TileCounter;
use crate::trim::TrimPlan;

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
}

impl Analysis {
    /// True when every image was read (exit code 0 material).
    pub fn is_complete(&self) -> bool {
        self.result.images.failed == 0
    }
}

/// What happened to one image.
enum Outcome {
    Trimmed,
    Decoded(ImageTally),
    Failed(Error),
    /// Not looked at because `--strict` stopped the run.
    Skipped,
}

/// Options resolved against the manifest: the fully built inputs.
struct Inputs {
    palette: Fcsp,
    backgrounds: Vec<Color>,
    parts: Option<(PathBuf, Legend, PathBuf, Pidt)>,
    archive: Archive,
    dedupe: Dedupe,
    /// The palette image, when the palette is not the canonical one.
    palette_file: Option<PathBuf>,
    /// `--mesh`, or the manifest's `vehicle` when it is there.
    vehicle_model: Option<PathBuf>,
    /// What resolving found wrong but not fatal (a missing vehicle model).
    warnings: Vec<String>,
    /// Resolution and texel size from the capture's manifest.
    geometry: CaptureGeometry,
    /// False for a capture counted while rendering (`--count`): its manifest
    /// names tiles that were never written.
    tiles_written: bool,
    /// The manifest's eye-frames, by eye-frame group (empty without one).
    eye_frames: Vec<EyeFrame>,
    /// Seconds per captured frame, eyes and pixels per degree.
    clock: FrameClock,
}

/// Runs the analysis.
pub fn analyze(options: &AnalyzeOptions, progress: Option<&dyn Progress>) -> Result<Analysis> {
    let started = Instant::now();
    let mut timings = Timings {
        threads: rayon::current_num_threads(),
        kernel: crate::scan::Kernel::selected().name().to_string(),
        ..Timings::default()
    };
    let inputs = resolve_inputs(options)?;
    if !inputs.tiles_written {
        return Err(Error::bad_file(
            &options.archive.join(crate::manifest::MANIFEST_FILE),
            "this capture was counted while rendering (--count) and its tiles were never written; \
             its results are in results/ beside the manifest",
        ));
    }
    let classifier =
        Classifier::new(&inputs.palette, &inputs.backgrounds.iter().map(|c| c.packed()).collect::<Vec<_>>())?;
    timings.load_seconds = started.elapsed().as_secs_f64();

    let stage = Instant::now();
    let images = &inputs.archive.images;
    let plan = TrimPlan::build(options.trim, images, &classifier);
    timings.trim_seconds = stage.elapsed().as_secs_f64();

    let stage = Instant::now();
    let image_counts = Counts::new();
    let frame_counts = inputs.dedupe.per_frame().then(Counts::new);
    let strays = AtomicColorSet::new();
    let stop = AtomicBool::new(false);
    let selected: Vec<usize> =
        (0..images.len()).filter(|&index| in_shard(options.shard, index, &images[index])).collect();
    let lookup = options.frames.then(|| {
        PartLookup::new(
            &inputs.palette,
            inputs.parts.as_ref().map(|p| (&p.1, &p.3)),
            classifier.backgrounds(),
        )
    });
    // Work units, each a list of eye-frames (lists of images), so that what
    // is deduplicated together stays in one thread: one image; one eye-frame
    // (frame dedupe, and frames.csv, which tallies whole eye-frames); both
    // eye-frames of a frame (eye-pair dedupe). With a shard, only its images.
    let by_eye_frame = inputs.archive.frame_groups > 0 && (lookup.is_some() || inputs.dedupe.per_frame());
    let units: Vec<Vec<Vec<usize>>> = match inputs.dedupe {
        Dedupe::EyePair => eye_pair_units(&inputs.archive, &inputs.eye_frames, &selected),
        _ if by_eye_frame => {
            eye_frame_units(&inputs.archive, &selected).into_iter().map(|g| vec![g]).collect()
        }
        _ => selected.iter().map(|&i| vec![vec![i]]).collect(),
    };
    if let Some(progress) = progress {
        progress.start(selected.len() as u64);
    }
    // Per worker thread a 2 MiB set for the image, one for the eye-frame
    // (frame dedupe or frames.csv) and one for the frame (eye-pair dedupe),
    // reused for every unit: fresh sets per rayon split would pay their page
    // faults again and again.
    let worker_sets: Vec<Mutex<WorkerSets>> = (0..rayon::current_num_threads())
        .map(|_| {
            Mutex::new(WorkerSets {
                image: SeenSet::new(),
                eye_frame: (frame_counts.is_some() || lookup.is_some()).then(SeenSet::new),
                pair: (inputs.dedupe == Dedupe::EyePair).then(SeenSet::new),
            })
        })
        .collect();
    let unit_results: Vec<UnitResult> = units
        .par_iter()
        .map(|unit| {
            let slot = rayon::current_thread_index().unwrap_or(0) % worker_sets.len();
            // Only this thread uses its slot, and nothing below yields to rayon,
            // so the lock is never contended.
            let mut sets = worker_sets[slot].lock().unwrap_or_else(PoisonError::into_inner);
            let WorkerSets { image: seen, eye_frame: frame_seen, pair: pair_seen } = &mut *sets;
            let mut unit_outcomes = Vec::new();
            let mut records = Vec::new();
            for eye_frame in unit {
                let mut image_pixels = lookup.as_ref().map(PartLookup::tally);
                let mut frame_pixels = lookup.as_ref().map(PartLookup::tally);
                for &index in eye_frame {
                    if options.strict && stop.load(Ordering::Relaxed) {
                        unit_outcomes.push((index, Outcome::Skipped));
                        continue;
                    }
                    let parts = lookup.as_ref().zip(image_pixels.as_deref_mut());
                    let outcome = count_one(index, &inputs.archive, &plan, &classifier, seen, &strays, parts);
                    if let (Some(image), Some(sum)) = (image_pixels.as_mut(), frame_pixels.as_mut()) {
                        // A failed image's partial tally is dropped with it.
                        if let Outcome::Decoded(_) = outcome {
                            sum.iter_mut().zip(image.iter()).for_each(|(sum, pixels)| *sum += pixels);
                        }
                        image.fill(0);
                    }
                    if let Outcome::Decoded(_) = outcome {
                        if let Some(frame_seen) = frame_seen.as_mut() {
                            seen.merge_into(frame_seen);
                        }
                        image_counts.add_set(seen);
                    }
                    // add_set drained it; a failed image was cleared by scan_image.
                    debug_assert!(seen.is_empty());
                    if let Outcome::Failed(_) = outcome {
                        stop.store(true, Ordering::Relaxed);
                    }
                    unit_outcomes.push((index, outcome));
                    if let Some(progress) = progress {
                        progress.advance(1);
                    }
                }
                if let (Some(lookup), Some(mut pixels), Some(frame_seen), Some(&first)) =
                    (&lookup, frame_pixels, frame_seen.as_mut(), eye_frame.first())
                {
                    let mut texels = lookup.tally();
                    lookup.add_texels(frame_seen, &mut texels);
                    // Drop the non-texel slot.
                    pixels.pop();
                    texels.pop();
                    let label = match images[first].frame_group {
                        Some(group) if by_eye_frame => eye_frame_label(&inputs.eye_frames, group),
                        _ => FrameLabel::Image(first),
                    };
                    records.push(FrameRecord { label, pixels, texels });
                }
                if let Some(frame_seen) = frame_seen.as_mut() {
                    match (&frame_counts, pair_seen.as_mut()) {
                        (_, Some(pair_seen)) => {
                            frame_seen.merge_into(pair_seen);
                            frame_seen.clear();
                        }
                        (Some(counts), None) => counts.add_set(frame_seen),
                        (None, None) => frame_seen.clear(),
                    }
                }
            }
            if let (Some(counts), Some(pair_seen)) = (&frame_counts, pair_seen.as_mut()) {
                counts.add_set(pair_seen);
            }
            (unit_outcomes, records)
        })
        .collect();
    let mut outcomes = Vec::with_capacity(images.len());
    let mut records = Vec::new();
    for (unit_outcomes, unit_records) in unit_results {
        outcomes.extend(unit_outcomes);
        records.extend(unit_records);
    }
    let frames = lookup.map(|lookup| frame_table(lookup, records, &inputs, options.shard));
    if let Some(progress) = progress {
        progress.finish();
    }
    timings.count_seconds = stage.elapsed().as_secs_f64();
    // One outcome per archive image, in order; images of other shards are Skipped.
    let mut by_image: Vec<Outcome> = (0..images.len()).map(|_| Outcome::Skipped).collect();
    for (index, outcome) in outcomes.drain(..) {
        by_image[index] = outcome;
    }
    let counted = CountedImages { outcomes: by_image, image_counts, frame_counts, strays };
    let mut analysis = summarize(options, &inputs, plan.empty_tiles.clone(), counted, timings, started)?;
    if let Some(frames) = &frames {
        analysis.result.measures = Some(Measures::from_frames(frames, &inputs.clock));
    }
    analysis.frames = frames;
    Ok(analysis)
}

/// What counting one work unit gives: its images' outcomes, and its
/// eye-frame's tallies by part when frames are tallied.
type UnitResult = (Vec<(usize, Outcome)>, Vec<FrameRecord>);

/// A worker thread's sets (see [`analyze`]).
struct WorkerSets {
    image: SeenSet,
    eye_frame: Option<SeenSet>,
    pair: Option<SeenSet>,
}

/// Work units of whole frames: per frame number, its eye-frames (both
/// eyes), each the list of its selected images.
fn eye_pair_units(archive: &Archive, eye_frames: &[EyeFrame], selected: &[usize]) -> Vec<Vec<Vec<usize>>> {
    let mut frames: BTreeMap<u32, Vec<Vec<usize>>> = BTreeMap::new();
    for group in eye_frame_units(archive, selected) {
        let frame_group = archive.images[group[0]].frame_group.unwrap_or(0);
        let frame = eye_frames.get(frame_group).map_or(frame_group as u32, |e| e.frame);
        frames.entry(frame).or_default().push(group);
    }
    frames.into_values().collect()
}

/// Work units of whole eye-frames: the selected images grouped by eye-frame.
fn eye_frame_units(archive: &Archive, selected: &[usize]) -> Vec<Vec<usize>> {
    let mut groups = vec![Vec::new(); archive.frame_groups];
    for &index in selected {
        groups[archive.images[index].frame_group.unwrap_or(0)].push(index);
    }
    groups.retain(|group| !group.is_empty());
    groups
}

/// The label of eye-frame group `group`.
fn eye_frame_label(eye_frames: &[EyeFrame], group: usize) -> FrameLabel {
    match eye_frames.get(group) {
        Some(eye_frame) => FrameLabel::EyeFrame(eye_frame.clone()),
        None => FrameLabel::Image(group),
    }
}

/// The `frames.csv` table: a record per eye-frame of the shard (with a
/// manifest, also those whose tiles were all empty or trimmed: zero rows), or
/// per decoded image without one, in eye-frame (or name) order.
fn frame_table(
    lookup: PartLookup,
    records: Vec<FrameRecord>,
    inputs: &Inputs,
    shard: Option<Shard>,
) -> FrameTable {
    let parts = lookup.names;
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
            })
        })
        .collect();
    FrameTable { parts, records }
}

/// Joins tiles counted from memory ([`TileCounter`], the capture's `--count`)
/// with the archive folder `options.archive`, whose `manifest.json` lists
/// those tiles by name, exactly as [`analyze`] would have after decoding them
/// as PNGs: the same `result.json`, except that nothing was trimmed (the
/// renderer knew which tiles were empty and listed them so).
pub fn analyze_counted(options: &AnalyzeOptions, mut counter: TileCounter) -> Result<Analysis> {
    let started = Instant::now();
    let timings = Timings {
        threads: 1,
        kernel: crate::scan::Kernel::selected().name().to_string(),
        ..Timings::default()
    };
    counter.commit_eye_frame();
    let inputs = resolve_inputs(options)?;
    let mut outcomes = Vec::with_capacity(inputs.archive.images.len());
    for image in &inputs.archive.images {
        outcomes.push(match counter.tallies.remove(&image.name) {
            Some(tally) => Outcome::Decoded(tally),
            None => Outcome::Failed(Error::bad_file(&image.path, "listed in the manifest but never counted")),
        });
    }
    if let Some(name) = counter.tallies.keys().next() {
        return Err(Error::BadOptions(format!(
            "tile {name} was counted but {} does not list it",
            options.archive.join(crate::manifest::MANIFEST_FILE).display()
        )));
    }
    let counted = CountedImages {
        outcomes,
        image_counts: counter.image_counts,
        frame_counts: counter.frame_counts,
        strays: counter.strays,
    };
    summarize(options, &inputs, Vec::new(), counted, timings, started)
}

/// Joins per-texel counts with the PIdT and legend: the parts table, the
/// unlabelled report, and a warning per legend part without texels.
pub(crate) fn join_with_legend(
    texel_counts: &[u32],
    legend_path: &Path,
    legend: &Legend,
    pidt_path: &Path,
    pidt: &Pidt,
    warnings: &mut Vec<String>,
) -> (crate::parts::PartTable, UnlabelledReport) {
    let table = join_parts(texel_counts, pidt, legend);
    warnings.extend(empty_part_warnings(
        &table,
        &legend_path.display().to_string(),
        &pidt_path.display().to_string(),
    ));
    let unlabelled = UnlabelledReport::new(&table, pidt);
    (table, unlabelled)
}

/// Warnings about the inputs (found while resolving them, the same for every
/// shard of an archive): merge carries them over from the first shard.
const SKIPPED_FILES_WARNING: &str = "were left out as not frames";
const MISSING_VEHICLE_WARNING: &str =
    "the vehicle the manifest names is missing, so there is no heatmap.glb and no views";

const UNREADABLE_VEHICLE_WARNING: &str =
    "the vehicle the manifest names cannot be read, so there is no heatmap.glb and no views";

/// What the capture warned about (the manifest's `warnings`), carried into the result.
const CAPTURE_WARNING: &str = "the capture warned: ";

fn capture_warnings(manifest: Option<&Manifest>) -> Vec<String> {
    let listed = manifest.and_then(|m| m.extra.get("warnings")).and_then(serde_json::Value::as_array);
    listed
        .into_iter()
        .flatten()
        .filter_map(serde_json::Value::as_str)
        .map(|warning| format!("{CAPTURE_WARNING}{warning}"))
        .collect()
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
pub(crate) fn empty_part_warnings(table: &crate::parts::PartTable, legend: &str, pidt: &str) -> Vec<String> {
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

/// True when image `position` of the archive belongs to `shard` (whole
/// eye-frames with a manifest, single images without).
fn in_shard(shard: Option<Shard>, position: usize, image: &crate::archive::ImageSource) -> bool {
    shard.is_none_or(|shard| shard.takes(image.frame_group.unwrap_or(position)))
}

/// A result for per-texel counts measured some other way than by counting
/// pixels (e.g. the capture's exact "unobstructed" measure, `measure` names
/// it), joined with the archive's PIdT and legend exactly as an analysis
/// would: same parts table, heatmap and files. `options.archive` is an
/// archive folder with a manifest (its tiles need not exist).
pub fn analyze_texel_counts(
    options: &AnalyzeOptions,
    texel_counts: Vec<u32>,
    measure: &'static str,
    notes: Vec<String>,
) -> Result<Analysis> {
    let started = Instant::now();
    let inputs = resolve_inputs_allowing_no_images(options, true)?;
    if texel_counts.len() != inputs.palette.texel_count() {
        return Err(Error::BadOptions(format!(
            "{} per-texel counts for a palette of {} texels",
            texel_counts.len(),
            inputs.palette.texel_count()
        )));
    }
    let tally = Tally { images: ImageCounts::default(), ..Tally::default() };
    let per_texel = PerTexel { texel_counts, per_image_counts: None, measure, resolution_report: false };
    let strays = AtomicColorSet::new();
    let mut analysis = finish(
        options,
        &inputs,
        Vec::new(),
        tally,
        per_texel,
        &strays,
        Timings::default(),
        started,
        Instant::now(),
    )?;
    analysis.result.notes.extend(notes);
    Ok(analysis)
}

/// What counting produced, in archive image order: the input of [`summarize`].
struct CountedImages {
    /// One outcome per image of the archive, in order.
    outcomes: Vec<Outcome>,
    /// Per-colour counts, one per image that shows the colour.
    image_counts: Counts,
    /// Per-colour counts, one per eye-frame (`--dedupe frame`).
    frame_counts: Option<Counts>,
    strays: AtomicColorSet,
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
        tally.images.skipped = archive.skipped.len() as u64;
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

/// Stages "tally" and "summarize": counted images → per-texel counts, the
/// parts table and everything `result.json` reports.
fn summarize(
    options: &AnalyzeOptions,
    inputs: &Inputs,
    empty_tiles: Vec<crate::trim::EmptyTile>,
    counted: CountedImages,
    mut timings: Timings,
    started: Instant,
) -> Result<Analysis> {
    let CountedImages { outcomes, image_counts, frame_counts, strays } = counted;
    let tally = tally(options, &inputs.archive, outcomes)?;
    let decoded_pixels = tally.background_pixels + tally.stray_pixels + tally.texel_pixels;
    timings.decoded_megapixels_per_second = decoded_pixels as f64 / 1e6 / timings.count_seconds.max(1e-9);

    let stage = Instant::now();
    let texel_counts = texel_counts_of(&inputs.palette, image_counts);
    let frame_texel_counts = frame_counts.map(|counts| texel_counts_of(&inputs.palette, counts));
    let (texel_counts, per_image_counts) = match frame_texel_counts {
        Some(frame) => (frame, Some(texel_counts)),
        None => (texel_counts, None),
    };
    let per_texel =
        PerTexel { texel_counts, per_image_counts, measure: MEASURE_PIXELS, resolution_report: true };
    finish(options, inputs, empty_tiles, tally, per_texel, &strays, timings, started, stage)
}

/// Per-texel counts ready to be joined with the PIdT.
struct PerTexel {
    texel_counts: Vec<u32>,
    /// The once-per-image counts when `texel_counts` are per eye-frame.
    per_image_counts: Option<Vec<u32>>,
    measure: &'static str,
    /// Whether pixel-based resolution diagnostics apply.
    resolution_report: bool,
}

/// Stage "summarize": per-texel counts → parts table and everything
/// `result.json` reports.
#[allow(clippy::too_many_arguments)]
fn finish(
    options: &AnalyzeOptions,
    inputs: &Inputs,
    empty_tiles: Vec<crate::trim::EmptyTile>,
    tally: Tally,
    per_texel: PerTexel,
    strays: &AtomicColorSet,
    mut timings: Timings,
    started: Instant,
    stage: Instant,
) -> Result<Analysis> {
    let PerTexel { texel_counts, per_image_counts, measure, resolution_report } = per_texel;
    let decoded_pixels = tally.background_pixels + tally.stray_pixels + tally.texel_pixels;
    let texels_seen = texel_counts.par_iter().filter(|&&c| c > 0).count() as u64;
    let max_count = texel_counts.par_iter().copied().max().unwrap_or(0);
    let mut warnings = inputs.warnings.clone();
    let mut notes = Vec::new();
    for background in &inputs.backgrounds {
        if inputs.palette.contains(background.packed()) {
            notes.push(format!(
                "background {background} is also a palette colour; that texel is ignored (never counted)"
            ));
        }
    }
    let (table, unlabelled, dedupe_report) = match &inputs.parts {
        Some((legend_path, legend, pidt_path, pidt)) => {
            let (table, unlabelled) =
                join_with_legend(&texel_counts, legend_path, legend, pidt_path, pidt, &mut warnings);
            let dedupe_report = per_image_counts.as_ref().map(|per_image| {
                let per_image_total = join_parts(per_image, pidt, legend).grand_total;
                DedupeReport::new(per_image_total, table.grand_total)
            });
            (Some(table), Some(unlabelled), dedupe_report)
        }
        None => {
            let dedupe_report = per_image_counts.as_ref().map(|per_image| {
                let sum = |counts: &[u32]| counts.par_iter().map(|&c| u64::from(c)).sum::<u64>();
                DedupeReport::new(sum(per_image), sum(&texel_counts))
            });
            (None, None, dedupe_report)
        }
    };
    timings.join_seconds = stage.elapsed().as_secs_f64();
    timings.total_seconds = started.elapsed().as_secs_f64();

    let settings = Settings {
        archive: options.archive.display().to_string(),
        manifest: !options.ignore_manifest && inputs.archive.frame_groups > 0,
        palette: inputs.palette.describe(),
        background: inputs.backgrounds.clone(),
        pidt: inputs.parts.as_ref().map(|p| p.2.display().to_string()),
        parts: inputs.parts.as_ref().map(|p| p.0.display().to_string()),
        dedupe: inputs.dedupe,
        trim: TrimReport { mode: options.trim.to_string(), empty_tiles },
        heatmap_scale: options.heatmap.scale,
        heatmap_max: options.heatmap.max,
        shard: options.shard,
    };
    let grand_total = texel_counts.par_iter().map(|&count| u64::from(count)).sum();
    let per_image_total = match &per_image_counts {
        Some(per_image) => per_image.par_iter().map(|&count| u64::from(count)).sum(),
        None => grand_total,
    };
    warnings.extend(stray_warning(tally.stray_pixels, tally.stray_images.len()));
    warnings.extend(saturation_warning(&texel_counts));
    let resolution = resolution_report
        .then(|| ResolutionReport::new(tally.texel_pixels, per_image_total, &inputs.geometry));
    warnings.extend(resolution.iter().flat_map(ResolutionReport::warnings));
    let result = AnalysisResult {
        schema: crate::report::RESULT_SCHEMA.to_string(),
        measure: measure.to_string(),
        images: tally.images,
        texels_seen,
        pixels: crate::report::PixelCounts {
            decoded: decoded_pixels,
            texel: tally.texel_pixels,
            background: tally.background_pixels,
            stray: tally.stray_pixels,
        },
        stray_pixels: tally.stray_pixels,
        stray_colors: strays.len(),
        stray_color_examples: strays
            .first(crate::report::STRAY_EXAMPLES)
            .into_iter()
            .map(Color::from_packed)
            .collect(),
        background_pixels: tally.background_pixels,
        grand_total: table.as_ref().map_or(grand_total, |t| t.grand_total),
        max_count,
        parts: table.map(|t| t.parts).unwrap_or_default(),
        unlabelled,
        dedupe: dedupe_report,
        settings,
        failures: tally.failures,
        images_with_stray_pixels: tally.stray_images,
        warnings,
        notes,
        resolution,
        measures: None,
    };
    let mut input_files: Vec<PathBuf> =
        inputs.archive.images.iter().map(|image| image.path.clone()).collect();
    input_files.extend(inputs.parts.iter().flat_map(|(legend, _, pidt, _)| [legend.clone(), pidt.clone()]));
    input_files.extend(inputs.palette_file.iter().cloned());
    input_files.push(options.archive.join(crate::manifest::MANIFEST_FILE));
    input_files.extend(inputs.vehicle_model.iter().cloned());
    Ok(Analysis {
        result,
        texel_counts,
        timings,
        input_files,
        vehicle_model: inputs.vehicle_model.clone(),
        frames: None,
    })
}

/// Counts one image into `seen` (left for the caller to commit and clear).
fn count_one(
    index: usize,
    archive: &Archive,
    plan: &TrimPlan,
    classifier: &Classifier,
    seen: &mut SeenSet,
    strays: &AtomicColorSet,
    parts: Option<(&PartLookup, &mut [u64])>,
) -> Outcome {
    let image = &archive.images[index];
    let bytes = match read_file(&image.path) {
        Ok(bytes) => bytes,
        Err(error) => return Outcome::Failed(error),
    };
    if plan.is_trimmable(index, &bytes) {
        return Outcome::Trimmed;
    }
    match scan_image_by_part(&image.path, &bytes, classifier, seen, strays, parts) {
        Ok(tally) => Outcome::Decoded(tally),
        Err(error) => Outcome::Failed(error),
    }
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

/// Resolves options against the manifest and loads every input once.
fn resolve_inputs(options: &AnalyzeOptions) -> Result<Inputs> {
    resolve_inputs_allowing_no_images(options, false)
}

fn resolve_inputs_allowing_no_images(options: &AnalyzeOptions, allow_no_images: bool) -> Result<Inputs> {
    let root = &options.archive;
    if !root.is_dir() {
        return Err(Error::bad_file(root, "not a folder (expected an archive folder of PNG tiles)"));
    }
    let manifest = if options.ignore_manifest { None } else { Manifest::load_from_dir(root)? };
    let from_manifest = |path: &Option<PathBuf>| path.as_ref().map(|p| root.join(p));

    let palette_choice = match (&options.palette, manifest.as_ref().and_then(|m| m.palette.as_ref())) {
        (Some(choice), _) => choice.clone(),
        (None, Some(PaletteSpec::Canonical { canonical: [width, height] })) => {
            PaletteChoice::Canonical { width: *width, height: *height }
        }
        (None, Some(PaletteSpec::File(file))) => PaletteChoice::Image(root.join(file)),
        (None, None) => {
            PaletteChoice::Canonical { width: DEFAULT_PALETTE_SIDE, height: DEFAULT_PALETTE_SIDE }
        }
    };
    let palette = match &palette_choice {
        PaletteChoice::Canonical { width, height } => Fcsp::canonical(*width, *height)?,
        PaletteChoice::Image(path) => Fcsp::from_png(path)?,
    };

    let backgrounds = options
        .background
        .clone()
        .or_else(|| manifest.as_ref().and_then(|m| m.background.clone()))
        .unwrap_or_else(|| vec![Color::DEFAULT_BACKGROUND]);

    let pidt_path = options.pidt.clone().or_else(|| manifest.as_ref().and_then(|m| from_manifest(&m.pidt)));
    let legend_path =
        options.legend.clone().or_else(|| manifest.as_ref().and_then(|m| from_manifest(&m.parts)));
    let parts = match (pidt_path, legend_path) {
        (Some(pidt_path), Some(legend_path)) => {
            let legend = Legend::load(&legend_path)?;
            let pidt = Pidt::load(&pidt_path, &legend, palette.width(), palette.height())?;
            Some((legend_path, legend, pidt_path, pidt))
        }
        (Some(pidt_path), None) => {
            return Err(Error::BadOptions(format!(
                "the PIdT {} needs its legend: add --parts parts.csv",
                pidt_path.display()
            )));
        }
        (None, Some(legend_path)) => {
            return Err(Error::BadOptions(format!(
                "the legend {} needs its PIdT: add --pidt pidt.png",
                legend_path.display()
            )));
        }
        (None, None) => None,
    };

    let archive = match &manifest {
        Some(manifest) => Archive::from_manifest(root, manifest),
        None => {
            let mut exclude = options.exclude.clone();
            exclude.extend(options.pidt.iter().cloned());
            if let PaletteChoice::Image(path) = &palette_choice {
                exclude.push(path.clone());
            }
            Archive::scan_folder(root, &exclude, [palette.width(), palette.height()])?
        }
    };
    if archive.found() == 0 && !allow_no_images {
        return Err(Error::NoImages { path: root.to_path_buf() });
    }
    if options.dedupe.per_frame() && archive.frame_groups == 0 {
        return Err(Error::BadOptions(format!(
            "--dedupe {} needs {}/manifest.json to know which tiles form one eye-frame",
            options.dedupe.name(),
            root.display()
        )));
    }
    if options.dedupe == Dedupe::EyePair && options.shard.is_some() {
        // Shards hold whole eye-frames, and the two eyes of a frame may fall
        // in different shards, where a texel would count once in each.
        return Err(Error::BadOptions(
            "--dedupe eye-pair cannot be sharded yet (a frame's two eyes may fall in different shards)"
                .into(),
        ));
    }
    let tiles_written = manifest
        .as_ref()
        .and_then(|m| m.extra.get("capture"))
        .and_then(|capture| capture.get("tiles_written"))
        .and_then(serde_json::Value::as_bool)
        .unwrap_or(true);
    let geometry = manifest.as_ref().map(CaptureGeometry::from_manifest).unwrap_or_default();
    let eye_frames = manifest.as_ref().map(crate::frames::eye_frames).unwrap_or_default();
    let clock = manifest.as_ref().map(FrameClock::from_manifest).unwrap_or_default();
    let palette_file = match palette_choice {
        PaletteChoice::Image(path) => Some(path),
        PaletteChoice::Canonical { .. } => None,
    };
    let mut warnings = capture_warnings(manifest.as_ref());
    if !archive.skipped.is_empty() {
        warnings.push(format!(
            "{} PNGs in {} {SKIPPED_FILES_WARNING}: palette- or PIdT-sized textures, or the palette/PIdT a \
             manifest below names ({}{}); without a manifest every other PNG is counted",
            archive.skipped.len(),
            root.display(),
            archive.skipped.iter().take(5).cloned().collect::<Vec<_>>().join(", "),
            if archive.skipped.len() > 5 { ", …" } else { "" }
        ));
    }
    let vehicle_model = match &options.mesh {
        // Asked for: missing is an error now, not after counting.
        Some(mesh) => {
            crate::input_file::open_regular(mesh)?;
            Some(mesh.clone())
        }
        // Named by the manifest: only the pictures need it, so counting goes on without.
        None => manifest
            .as_ref()
            .and_then(|m| m.extra.get("vehicle")?.as_str())
            .map(|file| root.join(file))
            .and_then(|path| match crate::input_file::open_regular(&path) {
                Ok(_) => Some(path),
                Err(Error::Io { cause, .. }) if cause.kind() == std::io::ErrorKind::NotFound => {
                    warnings.push(format!(
                        "{}: {MISSING_VEHICLE_WARNING} (give the mesh with --mesh)",
                        path.display()
                    ));
                    None
                }
                // Say what it is (a FIFO, a folder, ...), not that it is missing.
                Err(error) => {
                    warnings
                        .push(format!("{error}: {UNREADABLE_VEHICLE_WARNING} (give the mesh with --mesh)"));
                    None
                }
            }),
    };
    Ok(Inputs {
        palette,
        backgrounds,
        parts,
        archive,
        dedupe: options.dedupe,
        tiles_written,
        geometry,
        palette_file,
        vehicle_model,
        warnings,
        eye_frames,
        clock,
    })
}

/// The default output folder for an archive: `<archive>/results` (excluded
/// from the images when the archive has no manifest).
pub fn default_output_dir(archive: &Path) -> PathBuf {
    archive.join("results")
}

/// Errors when writing `files` would replace one of the analysis's inputs
/// (e.g. `--out` pointing at the archive, whose legend is `parts.csv`).
fn refuse_to_overwrite_inputs(inputs: &[PathBuf], files: &WrittenFiles) -> Result<()> {
    let outputs = [
        Some(&files.result_json),
        files.parts_csv.as_ref(),
        Some(&files.heatmap_png),
        Some(&files.timings_json),
        files.heatmap_glb.as_ref(),
        Some(&files.report_html),
        files.views_png.as_ref(),
        files.frames_csv.as_ref(),
    ];
    for output in outputs.into_iter().flatten() {
        let Ok(output_real) = output.canonicalize() else { continue };
        for input in inputs.iter().filter(|input| input.file_name() == output.file_name()) {
            if input.canonicalize().is_ok_and(|input_real| input_real == output_real) {
                return Err(Error::BadOptions(format!(
                    "writing {} would overwrite the input {}: choose another --out folder",
                    output.display(),
                    input.display()
                )));
            }
        }
    }
    Ok(())
}

/// Writes `result.json`, `parts.csv` (with a PIdT), `heatmap.png` and
/// `timings.json` into `out_dir` (created if needed), each atomically. The
/// heatmap uses the scale recorded in the result's settings.
///
/// The set is written into a staging folder inside `out_dir` and moved into
/// place only when every file was written: a failure (a full disk, a bad
/// vehicle model) or an interruption leaves the previous result set whole.
pub fn write_results(analysis: &mut Analysis, out_dir: &Path) -> Result<WrittenFiles> {
    std::fs::create_dir_all(out_dir).map_err(|e| Error::io(out_dir, e))?;
    let mut files = planned_files(analysis, out_dir);
    refuse_to_overwrite_inputs(&analysis.input_files, &files)?;
    let staging = crate::output::Staging::new(out_dir)?;
    // Plot paths are relative to the output folder: the same after the move.
    files.plots = write_results_into(analysis, staging.path())?;
    staging.commit(out_dir, &RESULT_SET)?;
    Ok(files)
}

/// Every name a result set can have in its folder: a run that writes fewer
/// (no vehicle model, `--frames-csv off`) removes the rest of an earlier run.
const RESULT_SET: [&str; 10] = [
    "result.json",
    "parts.csv",
    "heatmap.png",
    "timings.json",
    "heatmap.glb",
    "report.html",
    "views.png",
    "views",
    crate::frames::FRAMES_FILE,
    crate::plots::PLOTS_DIR,
];

/// The files [`write_results`] writes into `out_dir`.
fn planned_files(analysis: &Analysis, out_dir: &Path) -> WrittenFiles {
    WrittenFiles {
        result_json: out_dir.join("result.json"),
        parts_csv: (!analysis.result.parts.is_empty()).then(|| out_dir.join("parts.csv")),
        heatmap_png: out_dir.join("heatmap.png"),
        timings_json: out_dir.join("timings.json"),
        heatmap_glb: analysis.vehicle_model.as_ref().map(|_| out_dir.join("heatmap.glb")),
        report_html: out_dir.join("report.html"),
        views_png: analysis.vehicle_model.as_ref().map(|_| out_dir.join("views.png")),
        frames_csv: analysis.frames.as_ref().map(|_| out_dir.join(crate::frames::FRAMES_FILE)),
        plots: Vec::new(),
    }
}

/// Writes the whole result set into `out_dir` (a staging folder); returns
/// the plots written there.
fn write_results_into(analysis: &mut Analysis, out_dir: &Path) -> Result<Vec<crate::plots::Plot>> {
    let files = planned_files(analysis, out_dir);
    let palette = &analysis.result.settings.palette;
    let (width, height) = (palette.width, palette.height);
    let settings = &analysis.result.settings;
    let heatmap = HeatmapOptions { scale: settings.heatmap_scale, max: settings.heatmap_max };
    let stage = Instant::now();
    crate::heatmap::write_heatmap(&files.heatmap_png, &analysis.texel_counts, width, height, heatmap)?;
    analysis.timings.heatmap_seconds = stage.elapsed().as_secs_f64();
    let stage = Instant::now();
    crate::report::write_result_json(&files.result_json, &analysis.result, &analysis.texel_counts)?;
    if let Some(path) = &files.parts_csv {
        match &analysis.result.measures {
            Some(measures) => crate::measures::write_parts_csv(path, &analysis.result.parts, measures)?,
            None => crate::report::write_parts_csv(path, &analysis.result.parts)?,
        }
    }
    if let (Some(frames), Some(path)) = (&analysis.frames, &files.frames_csv) {
        frames.write_csv(path)?;
    }
    analysis.timings.write_seconds = stage.elapsed().as_secs_f64();
    analysis.timings.total_seconds += analysis.timings.heatmap_seconds + analysis.timings.write_seconds;
    crate::report::write_timings_json(&files.timings_json, &analysis.timings)?;
    if let (Some(model), Some(glb)) = (&analysis.vehicle_model, &files.heatmap_glb) {
        let png = crate::input_file::read_limited(&files.heatmap_png, crate::input_file::IMAGE_LIMIT)?;
        let model = crate::vehicle_model::VehicleModel::read(model)?;
        model.write_glb(glb, Some(&png))?;
        let texture = crate::heatmap_views::ViewTexture {
            counts: &analysis.texel_counts,
            width,
            height,
            options: heatmap,
            caption: crate::heatmap_views::views_caption(
                &analysis.result.measure,
                &analysis.result.settings.archive,
            ),
        };
        crate::heatmap_views::write_views(&model, &texture, out_dir)?;
    }
    let mut files = files;
    files.plots = crate::plots::write_plots(out_dir, &analysis.result.parts, analysis.frames.as_ref())?;
    crate::html_report::write_report(&files.report_html, &analysis.result, &files)?;
    Ok(files.plots)
}
