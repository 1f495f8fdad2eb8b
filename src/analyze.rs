//! The analysis job: archive in, counts and per-part statistics out.
//!
//! [`analyze`] is the whole pipeline in four stages, each in its folder:
//! resolve the options against the archive's manifest and load every input
//! once ([`crate::archive`]), count the images in parallel ([`crate::count`]),
//! summarize the counts into the result ([`crate::result`]); the caller then
//! writes the result set ([`crate::output::write_results`], [`crate::output`]).

use std::time::Instant;

use crate::archive::capture_facts::EyeFrame;
use crate::archive::manifest::MANIFEST_FILE;
use crate::archive::options::{AnalyzeOptions, Progress, Timings};
use crate::archive::resolve::{Images, Inputs, resolve_inputs, resolve_inputs_with};
use crate::count::part_lookup::{FrameLabel, FrameRecord, TiledParts};
use crate::count::rgba32::{Rgba32Counts, background_ids, count_rgba32_images, verify_empty};
use crate::count::scan::{Classifier, Kernel};
use crate::count::tile_counter::{Rgb24Tiles, TileCounter, TileIds};
use crate::count::trim::TrimPlan;
use crate::count::work::{CountJob, CountedImages, Outcome, count_images};
use crate::count::work::{FrameTallies, eye_frame_label};
use crate::error::{Error, Result};
use crate::format::manifest::TexelIds;
use crate::format::result::CountMeasure;
use crate::result::frames::FrameTable;
use crate::result::measures::Measures;
use crate::result::model::Analysis;
use crate::result::summarize::{
    Summary, TexelCounts, frame_table, summarize, summarize_counted_texels, summarize_texel_counts,
};
use crate::result::texel_area_file::TexelAreaUnits;

/// Runs the analysis.
pub fn analyze(options: &AnalyzeOptions, progress: Option<&dyn Progress>) -> Result<Analysis> {
    let started = Instant::now();
    let mut timings = Timings {
        threads: rayon::current_num_threads(),
        kernel: Kernel::selected().name().to_string(),
        ..Timings::default()
    };
    options.check_area_max()?;
    let inputs = resolve_inputs(options)?;
    if !inputs.tiles_written {
        return Err(Error::bad_file(
            &options.archive.join(MANIFEST_FILE),
            "this capture was counted while rendering (--count) and its tiles were never written; \
             its results are in results/ beside the manifest",
        ));
    }
    if inputs.texel_ids == TexelIds::Rgba32 {
        timings.load_seconds = started.elapsed().as_secs_f64();
        return analyze_rgba32(options, &inputs, timings, started, progress);
    }
    let classifier =
        Classifier::new(&inputs.palette, &inputs.backgrounds.iter().map(|c| c.packed()).collect::<Vec<_>>())?;
    timings.load_seconds = started.elapsed().as_secs_f64();

    let stage = Instant::now();
    let plan = TrimPlan::build(options.trim, &inputs.archive.images, &classifier);
    timings.trim_seconds = stage.elapsed().as_secs_f64();

    let stage = Instant::now();
    let job = CountJob { options, inputs: &inputs, plan: &plan, classifier: &classifier, progress };
    let (counted, mut frame_tallies) = count_images(&job);
    let texel_units = frame_tallies.as_mut().and_then(|tallies| tallies.texel_solid_angle_units.take());
    let frames = frame_tallies.map(|tallies| frame_table(tallies, &inputs, options.shard));
    timings.count_seconds = stage.elapsed().as_secs_f64();

    let summary =
        Summary { options, inputs: &inputs, empty_tiles: plan.empty_tiles.clone(), timings, started };
    let mut analysis = summarize(summary, counted)?;
    if let Some(frames) = &frames {
        analysis.result.measures = Some(Measures::from_frames(frames, &inputs.clock));
    }
    analysis.frames = frames;
    set_texel_area(&mut analysis, texel_units, &inputs.clock, options);
    Ok(analysis)
}

/// [`analyze`] for an archive of 32-bit texel ids ([`crate::count::rgba32`]):
/// empty tiles trimmed as in 24-bit archives (verified by their ids);
/// `frames.csv`, the measures and the per-texel angular area are summed as
/// the 24-bit path sums them.
fn analyze_rgba32(
    options: &AnalyzeOptions,
    inputs: &Inputs,
    timings: Timings,
    started: Instant,
    progress: Option<&dyn Progress>,
) -> Result<Analysis> {
    let mut timings = timings;
    let stage = Instant::now();
    let backgrounds = background_ids(inputs);
    let plan = TrimPlan::build_verified(options.trim, &inputs.archive.images, |image| {
        verify_empty(image, &backgrounds)
    });
    timings.trim_seconds = stage.elapsed().as_secs_f64();
    let stage = Instant::now();
    let mut counted = count_rgba32_images(options, inputs, &plan, progress);
    timings.count_seconds = stage.elapsed().as_secs_f64();
    let frames = counted.frames.take().map(|tallies| frame_table(tallies, inputs, options.shard));
    let summary = Summary { options, inputs, empty_tiles: plan.empty_tiles.clone(), timings, started };
    summarize_rgba32(summary, counted, frames)
}

/// The result of counted 32-bit texel ids (from PNG tiles or from memory):
/// the counts summarized with the note every such result has, the measures
/// from the eye-frames' tallies and the per-texel angular area.
fn summarize_rgba32(summary: Summary, counted: Rgba32Counts, frames: Option<FrameTable>) -> Result<Analysis> {
    let (options, clock) = (summary.options, &summary.inputs.clock);
    let counts = TexelCounts { image: counted.image_counts, frame: counted.frame_counts };
    let mut analysis = summarize_counted_texels(summary, counted.outcomes, counts, None, &counted.strays)?;
    analysis.result.notes.push(RGBA32_NOTE.to_string());
    set_texel_area(&mut analysis, counted.texel_solid_angle_units, clock, options);
    if let Some(frames) = &frames {
        analysis.result.measures = Some(Measures::from_frames(frames, clock));
    }
    analysis.frames = frames;
    Ok(analysis)
}

/// The note of every result of a 32-bit texel-id archive.
pub(crate) const RGBA32_NOTE: &str = "32-bit texel ids (texel_ids \"rgba32\"): counted on the portable path; \
    stray colours are told apart by their RGB";

/// The per-texel angular area from the kernels' integer sums; a shard
/// keeps the sums too (`texel-area.units`, which `merge` adds exactly).
fn set_texel_area(
    analysis: &mut Analysis,
    units: Option<Vec<u64>>,
    clock: &crate::archive::capture_facts::FrameClock,
    options: &AnalyzeOptions,
) {
    let factor = Measures::texel_area_factor(clock);
    let units = units.zip(factor).map(|(units, deg2_s_per_sr)| TexelAreaUnits { units, deg2_s_per_sr });
    analysis.texel_angular_area = units.as_ref().map(TexelAreaUnits::areas);
    analysis.texel_area_units = units.filter(|_| options.shard.is_some());
}

/// Joins tiles counted from memory ([`TileCounter`], the capture's `--count`)
/// with the archive folder `options.archive`, whose `manifest.json` lists
/// those tiles by name, exactly as [`analyze`] would have after decoding them
/// as PNGs: the same `result.json`, except that nothing was trimmed (the
/// renderer knew which tiles were empty and listed them so). Tiles of 32-bit
/// texel ids (an `rgba32` archive) are joined as [`analyze`] joins those.
pub fn analyze_counted(options: &AnalyzeOptions, mut counter: TileCounter) -> Result<Analysis> {
    let started = Instant::now();
    let timings = Timings { threads: 1, kernel: Kernel::selected().name().to_string(), ..Timings::default() };
    counter.commit_eye_frame();
    let inputs = resolve_inputs(options)?;
    if (inputs.texel_ids == TexelIds::Rgba32) != counter.counts_rgba32() {
        let (said, counted) = match inputs.texel_ids {
            TexelIds::Rgba32 => ("32-bit texel ids (texel_ids \"rgba32\")", "24-bit colours"),
            TexelIds::Rgb24 => ("24-bit colours", "32-bit texel ids"),
        };
        return Err(Error::bad_file(
            &options.archive.join(MANIFEST_FILE),
            format!("the manifest says its tiles hold {said}, but they were counted as {counted}"),
        ));
    }
    let outcomes = counted_outcomes(options, &inputs, &mut counter)?;
    let summary = Summary { options, inputs: &inputs, empty_tiles: Vec::new(), timings, started };
    match counter.ids {
        TileIds::Rgb24(tiles) => summarize_counted_rgb24(summary, *tiles, outcomes),
        TileIds::Rgba32(tiles) => {
            let (mut counted, parts) = tiles.into_counts(outcomes);
            counted.texel_solid_angle_units = counted.texel_solid_angle_units.filter(|_| options.texel_area);
            let frames = parts.map(|parts| counted_frame_table(parts, &inputs));
            summarize_rgba32(summary, counted, frames)
        }
    }
}

/// One outcome per image of the manifest: its tile's tally, or a failure
/// where it was never counted; a tile counted but not listed is refused.
fn counted_outcomes(
    options: &AnalyzeOptions,
    inputs: &Inputs,
    counter: &mut TileCounter,
) -> Result<Vec<Outcome>> {
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
            options.archive.join(MANIFEST_FILE).display()
        )));
    }
    Ok(outcomes)
}

/// [`analyze_counted`] of tiles counted as 24-bit colours.
fn summarize_counted_rgb24(summary: Summary, tiles: Rgb24Tiles, outcomes: Vec<Outcome>) -> Result<Analysis> {
    let mut tiles = tiles;
    tiles.finish_parts();
    let (options, inputs) = (summary.options, summary.inputs);
    let texel_units = tiles.take_texel_solid_angles().filter(|_| options.texel_area);
    let part_tallies = tiles.parts.take();
    let counted = CountedImages {
        outcomes,
        image_counts: tiles.image_counts,
        frame_counts: tiles.frame_counts,
        strays: tiles.strays,
        neighbours: tiles.neighbours.map(|sampler| sampler.sample),
    };
    let frames = part_tallies.map(|tallies| counted_frame_table(tallies.into_parts(), inputs));
    let mut analysis = summarize(summary, counted)?;
    if let Some(frames) = &frames {
        analysis.result.measures = Some(Measures::from_frames(frames, &inputs.clock));
    }
    analysis.frames = frames;
    set_texel_area(&mut analysis, texel_units, &inputs.clock, options);
    Ok(analysis)
}

/// The `frames.csv` table of a [`TileCounter`]'s part tallies, labelled by
/// the manifest's eye-frames as the PNG path labels them.
fn counted_frame_table(tallies: TiledParts, inputs: &Inputs) -> FrameTable {
    let weighted = tallies.weighted;
    let records = tallies
        .records
        .into_iter()
        .map(|tiled| {
            let (frame, eye) = (tiled.frame, tiled.eye);
            let group = inputs.eye_frames.iter().position(|e| e.frame == frame && e.eye == eye);
            let label = match group {
                Some(group) => eye_frame_label(&inputs.eye_frames, group),
                None => FrameLabel::EyeFrame(EyeFrame { frame, eye, time_s: None, distance_m: None }),
            };
            FrameRecord::from_parts(label, tiled.pixels, tiled.texels, weighted)
        })
        .collect();
    frame_table(FrameTallies { parts: tallies.names, records, texel_solid_angle_units: None }, inputs, None)
}

/// A result for per-texel counts measured some other way than by counting
/// pixels (e.g. the capture's exact "unobstructed" measure, `measure` names
/// it), joined with the archive's PIdT and legend exactly as an analysis
/// would: same parts table, heatmap and files. `options.archive` is an
/// archive folder with a manifest (its tiles need not exist).
pub fn analyze_texel_counts(
    options: &AnalyzeOptions,
    texel_counts: Vec<u32>,
    measure: CountMeasure,
    notes: Vec<String>,
) -> Result<Analysis> {
    let started = Instant::now();
    let inputs = resolve_inputs_with(options, Images::Optional)?;
    if texel_counts.len() != inputs.palette.texel_count() {
        return Err(Error::BadOptions(format!(
            "{} per-texel counts for a palette of {} texels",
            texel_counts.len(),
            inputs.palette.texel_count()
        )));
    }
    let summary =
        Summary { options, inputs: &inputs, empty_tiles: Vec::new(), timings: Timings::default(), started };
    let mut analysis = summarize_texel_counts(summary, texel_counts, measure)?;
    analysis.result.notes.extend(notes);
    Ok(analysis)
}
