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
use crate::count::part_lookup::{FrameLabel, FrameRecord};
use crate::count::rgba32::count_rgba32_images;
use crate::count::scan::{Classifier, Kernel};
use crate::count::tile_counter::{PartTallies, TileCounter};
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
/// nothing to trim (every tile is decoded; a note says so); `frames.csv`,
/// the measures and the per-texel angular area are summed as the 24-bit
/// path sums them.
fn analyze_rgba32(
    options: &AnalyzeOptions,
    inputs: &Inputs,
    timings: Timings,
    started: Instant,
    progress: Option<&dyn Progress>,
) -> Result<Analysis> {
    let mut timings = timings;
    let stage = Instant::now();
    let counted = count_rgba32_images(options, inputs, progress);
    timings.count_seconds = stage.elapsed().as_secs_f64();
    let counts = TexelCounts { image: counted.image_counts, frame: counted.frame_counts };
    let frames = counted.frames.map(|tallies| frame_table(tallies, inputs, options.shard));
    let summary = Summary { options, inputs, empty_tiles: Vec::new(), timings, started };
    let mut analysis = summarize_counted_texels(summary, counted.outcomes, counts, None, &counted.strays)?;
    analysis.result.notes.push(RGBA32_NOTE.to_string());
    set_texel_area(&mut analysis, counted.texel_solid_angle_units, &inputs.clock, options);
    if let Some(frames) = &frames {
        analysis.result.measures = Some(Measures::from_frames(frames, &inputs.clock));
    }
    analysis.frames = frames;
    Ok(analysis)
}

/// The note of every result of a 32-bit texel-id archive.
pub(crate) const RGBA32_NOTE: &str = "32-bit texel ids (texel_ids \"rgba32\"): counted on the portable path, \
    every written tile decoded (no empty-tile trimming); stray colours are told apart by their RGB";

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
/// renderer knew which tiles were empty and listed them so).
pub fn analyze_counted(options: &AnalyzeOptions, mut counter: TileCounter) -> Result<Analysis> {
    let started = Instant::now();
    let timings = Timings { threads: 1, kernel: Kernel::selected().name().to_string(), ..Timings::default() };
    counter.commit_eye_frame();
    counter.finish_parts();
    let texel_units = counter.take_texel_solid_angles().filter(|_| options.texel_area);
    let inputs = resolve_inputs(options)?;
    if inputs.texel_ids == TexelIds::Rgba32 {
        return Err(Error::bad_file(
            &options.archive.join(MANIFEST_FILE),
            "texel_ids \"rgba32\": tiles counted while rendering (--count) are counted as 24-bit colours; \
             write this capture's tiles and analyse them",
        ));
    }
    let part_tallies = counter.parts.take();
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
    let counted = CountedImages {
        outcomes,
        image_counts: counter.image_counts,
        frame_counts: counter.frame_counts,
        strays: counter.strays,
        neighbours: counter.neighbours.map(|sampler| sampler.sample),
    };
    let frames = part_tallies.map(|tallies| counted_frame_table(tallies, &inputs));
    let mut analysis =
        summarize(Summary { options, inputs: &inputs, empty_tiles: Vec::new(), timings, started }, counted)?;
    if let Some(frames) = &frames {
        analysis.result.measures = Some(Measures::from_frames(frames, &inputs.clock));
    }
    analysis.frames = frames;
    set_texel_area(&mut analysis, texel_units, &inputs.clock, options);
    Ok(analysis)
}

/// The `frames.csv` table of a [`TileCounter`]'s part tallies, labelled by
/// the manifest's eye-frames as the PNG path labels them.
fn counted_frame_table(tallies: PartTallies, inputs: &crate::archive::resolve::Inputs) -> FrameTable {
    let weighted = tallies.projection.is_some();
    let records = tallies
        .records
        .into_iter()
        .map(|(frame, eye, pixels, mut texels)| {
            let group = inputs.eye_frames.iter().position(|e| e.frame == frame && e.eye == eye);
            let label = match group {
                Some(group) => eye_frame_label(&inputs.eye_frames, group),
                None => FrameLabel::EyeFrame(EyeFrame { frame, eye, time_s: None, distance_m: None }),
            };
            texels.pop();
            FrameRecord::from_parts(label, pixels, texels, weighted)
        })
        .collect();
    frame_table(
        FrameTallies { parts: tallies.lookup.names, records, texel_solid_angle_units: None },
        inputs,
        None,
    )
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
