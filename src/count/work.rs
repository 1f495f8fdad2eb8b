//! Counting in parallel: the work units (what is deduplicated together stays
//! in one thread), the per-worker sets, and one image's count.
//!
//! Per-image outcomes are kept in archive order, so the result is identical
//! whatever the number of threads.

use std::collections::BTreeMap;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Mutex, PoisonError};

use rayon::prelude::*;

use crate::archive::archive_reader::{Archive, ImageSource};
use crate::archive::capture_facts::EyeFrame;
use crate::archive::options::{AnalyzeOptions, Dedupe, Progress};
use crate::archive::resolve::Inputs;
use crate::archive::shard::Shard;
use crate::checks::neighbours::{NeighbourSample, NeighbourSampler, TexelGrid};
use crate::color::sets::{AtomicColorSet, SeenSet};
use crate::count::counts::Counts;
use crate::count::part_lookup::{FrameLabel, FrameRecord, PartLookup, PartPixels};
use crate::count::scan::{Classifier, ImageTally, RowPasses, scan_image_with};
use crate::count::texel_area::TexelSolidAngles;
use crate::count::trim::TrimPlan;
use crate::error::Error;
use crate::png::rows::read_file;

/// What [`count_images`] needs: the options, the resolved inputs, and the
/// read-only objects built from them.
pub(crate) struct CountJob<'a> {
    pub options: &'a AnalyzeOptions,
    pub inputs: &'a Inputs,
    pub plan: &'a TrimPlan,
    pub classifier: &'a Classifier<'a>,
    pub progress: Option<&'a dyn Progress>,
}

/// Per-eye-frame tallies by part (`frames.csv`), in counting order.
pub(crate) struct FrameTallies {
    /// Part names ([`PartLookup::names`]).
    pub parts: Vec<String>,
    pub records: Vec<FrameRecord>,
    /// Per texel, the solid angle its pixels subtended, summed over the
    /// images counted, in units of [`crate::count::texel_area::TEXEL_SOLID_ANGLE_UNITS_PER_SR`],
    /// when the eyes' projection is known. A failed image's
    /// rows read before the failure stay in it (the result is incomplete
    /// then anyway, and says so).
    pub texel_solid_angle_units: Option<Vec<u64>>,
}

/// Everything the workers share while counting: the job, and the counts and
/// flags they add to.
struct Workers<'a> {
    job: &'a CountJob<'a>,
    lookup: Option<PartLookup>,
    /// Whether work units are whole eye-frames.
    by_eye_frame: bool,
    image_counts: Counts,
    frame_counts: Option<Counts>,
    strays: AtomicColorSet,
    /// Per-texel solid angles, when frames are tallied and the projection known.
    texel_area: Option<TexelSolidAngles>,
    /// Set by the first failure (`--strict` skips the rest).
    stop: AtomicBool,
}

/// Counts the images of `job`'s archive in parallel (only its shard's), and
/// tallies frames by part with [`AnalyzeOptions::frames`].
pub(crate) fn count_images(job: &CountJob) -> (CountedImages, Option<FrameTallies>) {
    let (options, inputs) = (job.options, job.inputs);
    let images = &inputs.archive.images;
    let selected: Vec<usize> =
        (0..images.len()).filter(|&index| in_shard(options.shard, index, &images[index])).collect();
    let lookup = options.frames.then(|| {
        PartLookup::new(
            &inputs.palette,
            inputs.parts.as_ref().map(|p| (&p.legend, &*p.pidt)),
            job.classifier.backgrounds(),
        )
    });
    let by_eye_frame = inputs.archive.frame_groups > 0 && (lookup.is_some() || inputs.dedupe.per_frame());
    let units = work_units(inputs, &selected, by_eye_frame);
    if let Some(progress) = job.progress {
        progress.start(selected.len() as u64);
    }
    let workers = Workers {
        job,
        lookup,
        by_eye_frame,
        image_counts: Counts::new(),
        frame_counts: inputs.dedupe.per_frame().then(Counts::new),
        strays: AtomicColorSet::new(),
        texel_area: (options.texel_area && options.frames && inputs.optics.is_some())
            .then(|| TexelSolidAngles::new(&inputs.palette, job.classifier.backgrounds())),
        stop: AtomicBool::new(false),
    };
    // Per worker thread a 2 MiB set for the image, one for the eye-frame
    // (frame dedupe or frames.csv) and one for the frame (eye-pair dedupe),
    // reused for every unit: fresh sets per rayon split would pay their page
    // faults again and again.
    let grid = TexelGrid::new(&inputs.palette, job.classifier.backgrounds());
    let worker_sets: Vec<Mutex<WorkerSets>> = (0..rayon::current_num_threads())
        .map(|_| {
            Mutex::new(WorkerSets {
                image: SeenSet::new(),
                eye_frame: (workers.frame_counts.is_some() || workers.lookup.is_some()).then(SeenSet::new),
                pair: (inputs.dedupe == Dedupe::EyePair).then(SeenSet::new),
                neighbours: grid.clone().map(NeighbourSampler::new),
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
            workers.count_unit(unit, &mut sets)
        })
        .collect();
    let mut outcomes = Vec::with_capacity(images.len());
    let mut records = Vec::new();
    for (unit_outcomes, unit_records) in unit_results {
        outcomes.extend(unit_outcomes);
        records.extend(unit_records);
    }
    if let Some(progress) = job.progress {
        progress.finish();
    }
    // One outcome per archive image, in order; images of other shards are Skipped.
    let mut by_image: Vec<Outcome> = (0..images.len()).map(|_| Outcome::Skipped).collect();
    for (index, outcome) in outcomes.drain(..) {
        by_image[index] = outcome;
    }
    let neighbours = grid.map(|_| {
        let mut sum = NeighbourSample::default();
        for sets in worker_sets {
            let sets = sets.into_inner().unwrap_or_else(PoisonError::into_inner);
            sum.add(&sets.neighbours.map(|n| n.sample).unwrap_or_default());
        }
        sum
    });
    let Workers { lookup, image_counts, frame_counts, strays, texel_area, .. } = workers;
    let texel_solid_angle_units = texel_area.map(TexelSolidAngles::into_units);
    let frames = lookup.map(|lookup| FrameTallies { parts: lookup.names, records, texel_solid_angle_units });
    (CountedImages { outcomes: by_image, image_counts, frame_counts, strays, neighbours }, frames)
}

/// Work units, each a list of eye-frames (lists of images), so that what
/// is deduplicated together stays in one thread: one image; one eye-frame
/// (frame dedupe, and frames.csv, which tallies whole eye-frames); both
/// eye-frames of a frame (eye-pair dedupe). With a shard, only its images.
pub(crate) fn work_units(inputs: &Inputs, selected: &[usize], by_eye_frame: bool) -> Vec<Vec<Vec<usize>>> {
    match inputs.dedupe {
        Dedupe::EyePair => eye_pair_units(&inputs.archive, &inputs.eye_frames, selected),
        _ if by_eye_frame => {
            eye_frame_units(&inputs.archive, selected).into_iter().map(|g| vec![g]).collect()
        }
        _ => selected.iter().map(|&i| vec![vec![i]]).collect(),
    }
}

impl Workers<'_> {
    /// Counts one work unit with this thread's `sets`.
    fn count_unit(&self, unit: &[Vec<usize>], sets: &mut WorkerSets) -> UnitResult {
        let mut unit_outcomes = Vec::new();
        let mut records = Vec::new();
        for eye_frame in unit {
            records.extend(self.count_eye_frame(eye_frame, sets, &mut unit_outcomes));
            let WorkerSets { eye_frame: frame_seen, pair: pair_seen, .. } = sets;
            if let Some(frame_seen) = frame_seen.as_mut() {
                match (&self.frame_counts, pair_seen.as_mut()) {
                    (_, Some(pair_seen)) => {
                        frame_seen.merge_into(pair_seen);
                        frame_seen.clear();
                    }
                    (Some(counts), None) => counts.add_set(frame_seen),
                    (None, None) => frame_seen.clear(),
                }
            }
        }
        if let (Some(counts), Some(pair_seen)) = (&self.frame_counts, sets.pair.as_mut()) {
            counts.add_set(pair_seen);
        }
        (unit_outcomes, records)
    }

    /// Counts the images of one eye-frame into `outcomes`; returns its tallies
    /// by part when frames are tallied. Its texels stay in the eye-frame set.
    fn count_eye_frame(
        &self,
        eye_frame: &[usize],
        sets: &mut WorkerSets,
        outcomes: &mut Vec<(usize, Outcome)>,
    ) -> Option<FrameRecord> {
        let (job, lookup) = (self.job, self.lookup.as_ref());
        let WorkerSets { image: seen, eye_frame: frame_seen, neighbours, .. } = sets;
        let optics = job.inputs.optics;
        let mut image_pixels = lookup.map(PartPixels::new);
        let mut frame_pixels = lookup.map(PartPixels::new);
        for &index in eye_frame {
            if job.options.strict && self.stop.load(Ordering::Relaxed) {
                outcomes.push((index, Outcome::Skipped));
                continue;
            }
            let view = optics.zip(job.inputs.archive.images[index].tile).map(|(o, tile)| o.view(tile));
            if let Some(image) = image_pixels.as_mut() {
                image.view = view;
            }
            let parts = lookup.zip(image_pixels.as_mut());
            let sampled = neighbours.as_ref().map(|n| n.sample);
            let texel_area = self.texel_area.as_ref().zip(view);
            let passes = RowPasses { parts, neighbours: neighbours.as_mut(), texel_area };
            let outcome =
                count_one(index, &job.inputs.archive, job.plan, job.classifier, seen, &self.strays, passes);
            if let (Some(sampler), Some(sampled), Outcome::Failed(_)) =
                (neighbours.as_mut(), sampled, &outcome)
            {
                // A failed image's partial sample is dropped with it.
                sampler.sample = sampled;
            }
            if let (Some(image), Some(sum)) = (image_pixels.as_mut(), frame_pixels.as_mut()) {
                // A failed image's partial tally is dropped with it.
                if let Outcome::Decoded(_) = outcome {
                    sum.add(image);
                }
                image.clear();
            }
            if let Outcome::Decoded(_) = outcome {
                if let Some(frame_seen) = frame_seen.as_mut() {
                    seen.merge_into(frame_seen);
                }
                self.image_counts.add_set(seen);
            }
            // add_set drained it; a failed image was cleared by scan_image.
            debug_assert!(seen.is_empty());
            if let Outcome::Failed(_) = outcome {
                self.stop.store(true, Ordering::Relaxed);
            }
            outcomes.push((index, outcome));
            if let Some(progress) = job.progress {
                progress.advance(1);
            }
        }
        let (lookup, tally, frame_seen, &first) =
            (lookup?, frame_pixels?, frame_seen.as_mut()?, eye_frame.first()?);
        let label = match job.inputs.archive.images[first].frame_group {
            Some(group) if self.by_eye_frame => eye_frame_label(&job.inputs.eye_frames, group),
            _ => FrameLabel::Image(first),
        };
        Some(FrameRecord::from_tally(label, lookup, tally, frame_seen, optics.is_some()))
    }
}

/// What happened to one image.
pub(crate) enum Outcome {
    Trimmed,
    Decoded(ImageTally),
    Failed(Error),
    /// Not looked at because `--strict` stopped the run.
    Skipped,
}

/// What counting one work unit gives: its images' outcomes, and its
/// eye-frame's tallies by part when frames are tallied.
pub(crate) type UnitResult = (Vec<(usize, Outcome)>, Vec<FrameRecord>);

/// A worker thread's sets (see [`count_images`]).
struct WorkerSets {
    image: SeenSet,
    eye_frame: Option<SeenSet>,
    pair: Option<SeenSet>,
    /// The neighbour sample of the colour checks (canonical palettes).
    neighbours: Option<NeighbourSampler>,
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
pub(crate) fn eye_frame_label(eye_frames: &[EyeFrame], group: usize) -> FrameLabel {
    match eye_frames.get(group) {
        Some(eye_frame) => FrameLabel::EyeFrame(eye_frame.clone()),
        None => FrameLabel::Image(group),
    }
}

/// Counts one image into `seen` (left for the caller to commit and clear).
fn count_one(
    index: usize,
    archive: &Archive,
    plan: &TrimPlan,
    classifier: &Classifier,
    seen: &mut SeenSet,
    strays: &AtomicColorSet,
    passes: RowPasses,
) -> Outcome {
    let image = &archive.images[index];
    let bytes = match read_file(&image.path) {
        Ok(bytes) => bytes,
        Err(error) => return Outcome::Failed(error),
    };
    if plan.is_trimmable(index, &bytes) {
        return Outcome::Trimmed;
    }
    match scan_image_with(&image.path, &bytes, classifier, seen, strays, passes) {
        Ok(tally) => Outcome::Decoded(tally),
        Err(error) => Outcome::Failed(error),
    }
}

/// True when image `position` of the archive belongs to `shard` (whole
/// eye-frames with a manifest, single images without).
pub(crate) fn in_shard(shard: Option<Shard>, position: usize, image: &ImageSource) -> bool {
    shard.is_none_or(|shard| shard.takes(image.frame_group.unwrap_or(position)))
}

/// What counting produced, in archive image order: the input of
/// [`crate::result::summarize`].
pub(crate) struct CountedImages {
    /// One outcome per image of the archive, in order.
    pub outcomes: Vec<Outcome>,
    /// Per-colour counts, one per image that shows the colour.
    pub image_counts: Counts,
    /// Per-colour counts, one per eye-frame (`--dedupe frame`).
    pub frame_counts: Option<Counts>,
    pub strays: AtomicColorSet,
    /// The colour checks' neighbour sample (canonical palettes only).
    pub neighbours: Option<NeighbourSample>,
}
