//! Counting archives of 32-bit texel ids (`"texel_ids": "rgba32"`): the
//! palettes above 2^24 texels that one 24-bit colour per texel cannot name
//! (a bus or an articulated truck at the paper's texel density).
//!
//! Why a path of its own beside [`crate::count::scan`]: the 24-bit path's
//! tables (the count table, the seen sets, the stray set, the kernels'
//! colour keys) span the 2^24 colours, and its vector kernels are tuned for
//! 3-byte pixels. This one is portable and sized to the palette: the shared
//! counts hold one `u32` per texel of the palette, and an image's texels are
//! collected as a sorted list of its distinct ids (no per-texel set per
//! thread), so a palette of N texels costs 4·N bytes however many ids the
//! 32 bits could name. A pixel's id is [`rgba32_id`] of its RGBA samples
//! (an RGB tile is opaque: its ids are its 24-bit colours). The outcomes are
//! the 24-bit path's ([`Outcome`], [`ImageTally`]), so everything after
//! counting is shared.

use std::path::Path;
use std::sync::atomic::{AtomicBool, AtomicU32, AtomicU64, Ordering};

use rayon::prelude::*;

use crate::archive::options::{AnalyzeOptions, Progress};
use crate::archive::palette::rgba32_id;
use crate::archive::resolve::Inputs;
use crate::color::AtomicColorSet;
use crate::count::part_lookup::{FrameLabel, FrameRecord, PartLookup, PartPixels, RowSpans};
use crate::count::scan::ImageTally;
use crate::count::texel_area::EyeTables;
use crate::count::work::{FrameTallies, Outcome, UnitResult, eye_frame_label, in_shard, work_units};
use crate::error::{Error, Result};
use crate::optics::TileView;
use crate::png::PixelLayout;
use crate::png::rows::{RowReader, read_file};

/// What counting an `rgba32` archive gives: the 24-bit path's outcomes and
/// per-texel counts in palette layout.
pub(crate) struct Rgba32Counts {
    /// One outcome per image of the archive, in order.
    pub outcomes: Vec<Outcome>,
    /// Per texel, the images that showed it.
    pub image_counts: Vec<u32>,
    /// Per texel, the eye-frames (`--dedupe frame`) or frames (`eye-pair`)
    /// that showed it.
    pub frame_counts: Option<Vec<u32>>,
    /// Stray pixels' colours, by their RGB samples (their 24 low id bits).
    pub strays: AtomicColorSet,
    /// Per texel, the solid angle its pixels subtended over the images, in
    /// [`crate::count::texel_area::TEXEL_SOLID_ANGLE_UNITS_PER_SR`] (each
    /// pixel rounded once, as the 24-bit path sums them), with
    /// `--texel-area` and the eyes' projection.
    pub texel_solid_angle_units: Option<Vec<u64>>,
    /// Per-eye-frame tallies by part (`frames.csv`), with [`AnalyzeOptions::frames`].
    pub frames: Option<FrameTallies>,
}

/// Counts the images of an `rgba32` archive (only `options.shard`'s) in
/// parallel; the result does not depend on the number of threads.
pub(crate) fn count_rgba32_images(
    options: &AnalyzeOptions,
    inputs: &Inputs,
    progress: Option<&dyn Progress>,
) -> Rgba32Counts {
    let images = &inputs.archive.images;
    let selected: Vec<usize> =
        (0..images.len()).filter(|&index| in_shard(options.shard, index, &images[index])).collect();
    let deduped = inputs.archive.frame_groups > 0 && inputs.dedupe.per_frame();
    let backgrounds: Vec<u32> = inputs.backgrounds.iter().map(|c| c.packed()).collect();
    let labels = inputs.parts.as_ref().map(|p| (&p.legend, &*p.pidt));
    let lookup = options.frames.then(|| PartLookup::new(&inputs.palette, labels, &backgrounds));
    let by_eye_frame = inputs.archive.frame_groups > 0 && (lookup.is_some() || deduped);
    // A unit is an image, an eye-frame (frame dedupe, frames.csv) or a frame (eye-pair).
    let units = work_units(inputs, &selected, by_eye_frame);
    if let Some(progress) = progress {
        progress.start(selected.len() as u64);
    }
    let texels = inputs.palette.texel_count();
    let counter = Counter {
        texels: texels as u64,
        backgrounds: &backgrounds,
        image_counts: zeroed_counts(texels),
        frame_counts: deduped.then(|| zeroed_counts(texels)),
        strays: AtomicColorSet::new(),
        area: (options.texel_area && inputs.optics.is_some())
            .then(|| (0..texels).into_par_iter().map(|_| AtomicU64::new(0)).collect()),
        eye_tables: EyeTables::default(),
        stop: AtomicBool::new(false),
        strict: options.strict,
        lookup,
        by_eye_frame,
    };
    let unit_results: Vec<UnitResult> = units
        .par_iter()
        .map(|unit| {
            let counted = counter.count_unit(inputs, unit);
            if let Some(progress) = progress {
                progress.advance(counted.0.len() as u64);
            }
            counted
        })
        .collect();
    if let Some(progress) = progress {
        progress.finish();
    }
    let mut outcomes: Vec<Outcome> = (0..images.len()).map(|_| Outcome::Skipped).collect();
    let mut records = Vec::new();
    for (unit_outcomes, unit_records) in unit_results {
        for (index, outcome) in unit_outcomes {
            outcomes[index] = outcome;
        }
        records.extend(unit_records);
    }
    let plain = |counts: Vec<AtomicU32>| counts.into_iter().map(AtomicU32::into_inner).collect::<Vec<u32>>();
    Rgba32Counts {
        outcomes,
        image_counts: plain(counter.image_counts),
        frame_counts: counter.frame_counts.map(plain),
        strays: counter.strays,
        texel_solid_angle_units: counter
            .area
            .map(|area| area.into_iter().map(AtomicU64::into_inner).collect()),
        frames: counter.lookup.map(|lookup| FrameTallies {
            parts: lookup.names,
            records,
            texel_solid_angle_units: None,
        }),
    }
}

/// The tables the workers share while counting.
struct Counter<'a> {
    texels: u64,
    backgrounds: &'a [u32],
    image_counts: Vec<AtomicU32>,
    frame_counts: Option<Vec<AtomicU32>>,
    strays: AtomicColorSet,
    /// Per texel, solid-angle units (see [`Rgba32Counts`]).
    area: Option<Vec<AtomicU64>>,
    /// The eyes' pixel prefix tables, shared by every image (one per eye).
    eye_tables: EyeTables,
    /// Set by the first failure (`--strict` skips the rest).
    stop: AtomicBool,
    strict: bool,
    /// Texel → part slot, when eye-frames are tallied by part.
    lookup: Option<PartLookup>,
    /// Whether work units are whole eye-frames.
    by_eye_frame: bool,
}

/// One eye-frame's texels and part tallies while its images are counted.
struct EyeFrameTally {
    /// Texel ids of its decoded images (one list per image, appended).
    ids: Vec<u32>,
    /// The image being counted, by part (with its view).
    image: Option<PartPixels>,
    /// The sum of its decoded images, by part.
    sum: Option<PartPixels>,
}

impl Counter<'_> {
    /// Counts one work unit: each image once, each eye-frame's tallies by
    /// part, and the unit's distinct texels once more into the frame counts
    /// (the unit is the eye-frame or frame those count).
    fn count_unit(&self, inputs: &Inputs, unit: &[Vec<usize>]) -> UnitResult {
        let (mut outcomes, mut records, mut unit_ids) = (Vec::new(), Vec::new(), Vec::new());
        for eye_frame in unit {
            let tally = || self.lookup.as_ref().map(PartPixels::new);
            let mut frame = EyeFrameTally { ids: Vec::new(), image: tally(), sum: tally() };
            for &index in eye_frame {
                if self.strict && self.stop.load(Ordering::Relaxed) {
                    outcomes.push((index, Outcome::Skipped));
                    continue;
                }
                let outcome = self.count_one(inputs, index, &mut frame);
                if !matches!(outcome, Outcome::Decoded(_)) {
                    self.stop.store(true, Ordering::Relaxed);
                }
                outcomes.push((index, outcome));
            }
            records.extend(self.record(inputs, eye_frame, &mut frame));
            if self.frame_counts.is_some() {
                unit_ids.append(&mut frame.ids);
            }
        }
        if let Some(frame_counts) = &self.frame_counts {
            unit_ids.sort_unstable();
            unit_ids.dedup();
            add_ids(frame_counts, &unit_ids);
        }
        (outcomes, records)
    }

    /// Counts image `index` of an eye-frame into the shared counts and the
    /// eye-frame's tallies (a failed image leaves none of either).
    fn count_one(&self, inputs: &Inputs, index: usize, frame: &mut EyeFrameTally) -> Outcome {
        let image = &inputs.archive.images[index];
        let view = inputs.optics.zip(image.tile).map(|(optics, tile)| optics.view(tile));
        if let Some(parts) = frame.image.as_mut() {
            parts.clear();
            parts.view = view;
        }
        let mut ids = Vec::new();
        let area_view = view.filter(|_| self.area.is_some());
        let outcome = self.count_image(&image.path, area_view.as_ref(), &mut ids, frame.image.as_mut());
        if let Outcome::Decoded(_) = outcome {
            add_ids(&self.image_counts, &ids);
            frame.ids.extend_from_slice(&ids);
            if let (Some(image), Some(sum)) = (frame.image.as_ref(), frame.sum.as_mut()) {
                sum.add(image);
            }
        }
        outcome
    }

    /// The `frames.csv` record of an eye-frame (when tallied by part): its
    /// pixels and solid angles by part, and its distinct texels by part.
    fn record(&self, inputs: &Inputs, eye_frame: &[usize], frame: &mut EyeFrameTally) -> Option<FrameRecord> {
        let (lookup, sum, &first) = (self.lookup.as_ref()?, frame.sum.take()?, eye_frame.first()?);
        frame.ids.sort_unstable();
        frame.ids.dedup();
        let mut texels = vec![0u64; lookup.parts()];
        for &id in &frame.ids {
            if let Some(count) = texels.get_mut(usize::from(lookup.slot_table().get(id))) {
                *count += 1;
            }
        }
        let label = match inputs.archive.images[first].frame_group {
            Some(group) if self.by_eye_frame => eye_frame_label(&inputs.eye_frames, group),
            _ => FrameLabel::Image(first),
        };
        Some(FrameRecord::from_parts(label, sum, texels, inputs.optics.is_some()))
    }

    /// Reads and counts one image: its distinct texel ids into `ids`
    /// (ascending), its stray colours and (at `view`) its texels' solid
    /// angles into the shared tables once it is whole.
    fn count_image(
        &self,
        path: &Path,
        view: Option<&TileView>,
        ids: &mut Vec<u32>,
        parts: Option<&mut PartPixels>,
    ) -> Outcome {
        let bytes = match read_file(path) {
            Ok(bytes) => bytes,
            Err(error) => return Outcome::Failed(error),
        };
        let mut found = Found { ids, strays: Vec::new(), runs: Vec::new() };
        match self.scan(path, &bytes, view, &mut found, parts) {
            Ok(tally) => {
                for stray in found.strays {
                    self.strays.insert(stray & 0xFF_FFFF);
                }
                if let Some(area) = &self.area {
                    for (id, units) in found.runs {
                        area[id as usize].fetch_add(units, Ordering::Relaxed);
                    }
                }
                Outcome::Decoded(tally)
            }
            Err(error) => {
                found.ids.clear();
                Outcome::Failed(error)
            }
        }
    }

    /// Classifies every pixel of one PNG: background (an opaque background
    /// colour), a texel of the palette (its id below the palette's texel
    /// count) or stray; a run of one id is classified once. At `view`, each
    /// texel pixel's solid angle goes to its id's run in `found.runs`; with
    /// `parts`, each row's spans of one part slot go to its tally.
    fn scan(
        &self,
        path: &Path,
        bytes: &[u8],
        view: Option<&TileView>,
        found: &mut Found,
        mut parts: Option<&mut PartPixels>,
    ) -> Result<ImageTally> {
        let mut reader = RowReader::new(path, bytes)?;
        let step = pixel_step(path, reader.layout())?;
        let size = [reader.width(), reader.height()];
        let weighted_parts = parts.as_ref().is_some_and(|parts| parts.view.is_some());
        if (view.is_some() || weighted_parts) && reader.interlaced() {
            return Err(Error::bad_file(
                path,
                "an interlaced PNG: the per-texel angular area needs its rows in order (write the tiles \
                 without interlacing, or analyse with --texel-area off)",
            ));
        }
        let prefix = view.and_then(|view| self.eye_tables.pixel_prefix(view, size));
        let mut tally = ImageTally { width: size[0], height: size[1], ..ImageTally::default() };
        let mut last: Option<(u32, PixelKind, usize)> = None;
        let mut y = 0;
        while let Some(row) = reader.next_row()? {
            let weights = prefix.as_ref().map(|prefix| prefix.row(y));
            let mut spans = parts.as_deref_mut().map(|tally| RowSpans::new(tally, y));
            let mut span_slot = None;
            for (x, pixel) in row.chunks_exact(step).enumerate() {
                let id = pixel_id(pixel);
                let (kind, slot) = match last {
                    Some((previous, kind, slot)) if previous == id => (kind, slot),
                    _ => {
                        let kind = self.classify(id);
                        found.first_of_run(id, kind);
                        let slot = self.slot(id, kind);
                        last = Some((id, kind, slot));
                        (kind, slot)
                    }
                };
                if let Some(spans) = spans.as_mut().filter(|_| span_slot != Some(slot)) {
                    spans.change(x, slot);
                    span_slot = Some(slot);
                }
                match kind {
                    PixelKind::Texel => tally.texel_pixels += 1,
                    PixelKind::Background => tally.background_pixels += 1,
                    PixelKind::Stray => tally.stray_pixels += 1,
                }
                if let (PixelKind::Texel, Some(row)) = (kind, weights.as_ref())
                    && let (Some(after), Some(before)) = (row.at(x + 1), row.at(x))
                {
                    found.add_units(id, after - before);
                }
            }
            if let Some(spans) = spans {
                spans.finish(row.len() / step);
            }
            y += 1;
        }
        reader.finish()?;
        found.ids.sort_unstable();
        found.ids.dedup();
        Ok(tally)
    }

    /// The part slot of a pixel of `id` (the slot after the parts' for a
    /// background or stray pixel; 0 when parts are not tallied).
    #[inline]
    fn slot(&self, id: u32, kind: PixelKind) -> usize {
        match (&self.lookup, kind) {
            (Some(lookup), PixelKind::Texel) => usize::from(lookup.slot_table().get(id)),
            (Some(lookup), _) => lookup.parts(),
            (None, _) => 0,
        }
    }

    /// What pixel id `id` is.
    #[inline]
    fn classify(&self, id: u32) -> PixelKind {
        if self.backgrounds.contains(&id) {
            PixelKind::Background
        } else if u64::from(id) < self.texels {
            PixelKind::Texel
        } else {
            PixelKind::Stray
        }
    }
}

/// What scanning one image found, kept apart until the image is whole.
struct Found<'a> {
    /// Texel ids, one per run (sorted and deduplicated at the end).
    ids: &'a mut Vec<u32>,
    /// Stray ids, one per run.
    strays: Vec<u32>,
    /// `(texel id, solid-angle units)` per run of one texel.
    runs: Vec<(u32, u64)>,
}

impl Found<'_> {
    /// A run of `id` starts.
    fn first_of_run(&mut self, id: u32, kind: PixelKind) {
        match kind {
            PixelKind::Texel => self.ids.push(id),
            PixelKind::Stray => self.strays.push(id),
            PixelKind::Background => {}
        }
    }

    /// A texel pixel of `id` subtends `units`.
    fn add_units(&mut self, id: u32, units: u64) {
        match self.runs.last_mut() {
            Some((last, sum)) if *last == id => *sum += units,
            _ => self.runs.push((id, units)),
        }
    }
}

/// Bytes per pixel of an `rgba32` tile: RGBA, or RGB (opaque); any other
/// layout is refused naming the file.
fn pixel_step(path: &Path, layout: PixelLayout) -> Result<usize> {
    match layout {
        PixelLayout::Rgba => Ok(4),
        PixelLayout::Rgb => Ok(3),
        other => Err(Error::bad_file(
            path,
            format!(
                "a {other:?} PNG: the tiles of a 32-bit texel-id archive (texel_ids \"rgba32\") are RGBA \
                 (or RGB, opaque)"
            ),
        )),
    }
}

/// The texel id of one RGBA or RGB (opaque) pixel.
#[inline(always)]
fn pixel_id(pixel: &[u8]) -> u32 {
    let alpha = pixel.get(3).copied().unwrap_or(255);
    rgba32_id([pixel[0], pixel[1], pixel[2], alpha])
}

/// Every pixel's 32-bit texel id of an `rgba32` tile, with its size: what
/// the capture's `verify` checks such tiles with. In decoding order (raster
/// order unless the PNG is interlaced).
pub fn read_rgba32_ids(path: &Path) -> Result<([u32; 2], Vec<u32>)> {
    let bytes = read_file(path)?;
    let mut reader = RowReader::new(path, &bytes)?;
    let step = pixel_step(path, reader.layout())?;
    let mut ids = Vec::new();
    while let Some(row) = reader.next_row()? {
        ids.extend(row.chunks_exact(step).map(pixel_id));
    }
    reader.finish()?;
    Ok(([reader.width(), reader.height()], ids))
}

/// The three kinds of pixel.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum PixelKind {
    Background,
    Texel,
    Stray,
}

/// One count per texel of the palette, all zero.
fn zeroed_counts(texels: usize) -> Vec<AtomicU32> {
    (0..texels).into_par_iter().map(|_| AtomicU32::new(0)).collect()
}

/// Adds one to the count of each id (distinct, inside the palette),
/// saturating at the `u32` maximum as the 24-bit path does.
fn add_ids(counts: &[AtomicU32], ids: &[u32]) {
    for &id in ids {
        // Err means saturated: the count stays at the maximum.
        let _ = counts[id as usize].fetch_update(Ordering::Relaxed, Ordering::Relaxed, |c| c.checked_add(1));
    }
}
