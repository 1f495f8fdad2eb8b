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

use crate::archive::archive_reader::ImageSource;
use crate::archive::options::{AnalyzeOptions, Progress};
use crate::archive::palette::rgba32_id;
use crate::archive::resolve::Inputs;
use crate::color::AtomicColorSet;
use crate::count::part_lookup::{FrameLabel, FrameRecord, PartLookup, PartPixels, RowSpans};
use crate::count::scan::ImageTally;
use crate::count::texel_area::EyeTables;
use crate::count::trim::TrimPlan;
use crate::count::work::{FrameTallies, Outcome, UnitResult, eye_frame_label, in_shard, work_units};
use crate::error::{Error, Result};
use crate::optics::TileView;
use crate::png::PixelLayout;
use crate::png::rows::{FileBytes, RowReader, read_file};

mod tiles;

pub(crate) use tiles::Rgba32Tiles;

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
/// parallel, leaving out those `plan` trims; the result does not depend on
/// the number of threads.
pub(crate) fn count_rgba32_images(
    options: &AnalyzeOptions,
    inputs: &Inputs,
    plan: &TrimPlan,
    progress: Option<&dyn Progress>,
) -> Rgba32Counts {
    let images = &inputs.archive.images;
    let selected: Vec<usize> =
        (0..images.len()).filter(|&index| in_shard(options.shard, index, &images[index])).collect();
    let deduped = inputs.archive.frame_groups > 0 && inputs.dedupe.per_frame();
    let backgrounds = background_ids(inputs);
    let labels = inputs.parts.as_ref().map(|p| (&p.legend, &*p.pidt));
    let lookup = options.frames.then(|| PartLookup::new(&inputs.palette, labels, &backgrounds));
    let by_eye_frame = inputs.archive.frame_groups > 0 && (lookup.is_some() || deduped);
    // A unit is an image, an eye-frame (frame dedupe, frames.csv) or a frame (eye-pair).
    let units = work_units(inputs, &selected, by_eye_frame);
    if let Some(progress) = progress {
        progress.start(selected.len() as u64);
    }
    let mut counter = Counter::new(inputs.palette.texel_count(), backgrounds, deduped);
    counter.set_parts(lookup, options.texel_area && inputs.optics.is_some());
    counter.strict = options.strict;
    let unit_results: Vec<UnitResult> = units
        .par_iter()
        .map(|unit| {
            let counted = counter.count_unit(inputs, plan, unit, by_eye_frame);
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
    counter.into_counts(outcomes, records)
}

/// The packed background colours of an archive: its background ids (an
/// opaque pixel's id is its 24-bit colour).
pub(crate) fn background_ids(inputs: &Inputs) -> Vec<u32> {
    inputs.backgrounds.iter().map(|c| c.packed()).collect()
}

/// Whether `image` is an empty tile of an `rgba32` archive: read whole, and
/// every pixel's id one of `backgrounds`. Its bytes when it is (what
/// [`TrimPlan`] trims the tiles identical to); `None` when it shows anything
/// else or cannot be read (decoding reports that).
pub(crate) fn verify_empty(image: &ImageSource, backgrounds: &[u32]) -> Option<FileBytes> {
    let bytes = read_file(&image.path).ok()?;
    let (_, ids) = png_ids(&image.path, &bytes).ok()?;
    ids.iter().all(|id| backgrounds.contains(id)).then_some(bytes)
}

/// The tables the workers share while counting (or the capture's
/// [`Rgba32Tiles`] fills, one tile after the other).
struct Counter {
    texels: u64,
    backgrounds: Vec<u32>,
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

impl Counter {
    /// Zeroed counts for a palette of `texels` texels over `backgrounds`
    /// (packed), per frame too when `deduped`; no part tallies, no solid
    /// angles, not strict.
    fn new(texels: usize, backgrounds: Vec<u32>, deduped: bool) -> Counter {
        Counter {
            texels: texels as u64,
            backgrounds,
            image_counts: zeroed_counts(texels),
            frame_counts: deduped.then(|| zeroed_counts(texels)),
            strays: AtomicColorSet::new(),
            area: None,
            eye_tables: EyeTables::default(),
            stop: AtomicBool::new(false),
            strict: false,
            lookup: None,
        }
    }

    /// Tallies eye-frames by `lookup`'s parts, and with `area` each texel's
    /// solid angle (where images have a view).
    fn set_parts(&mut self, lookup: Option<PartLookup>, area: bool) {
        self.lookup = lookup;
        self.area = area.then(|| (0..self.texels).into_par_iter().map(|_| AtomicU64::new(0)).collect());
    }

    /// The counts, with the images' `outcomes` and the eye-frames' `records`.
    fn into_counts(self, outcomes: Vec<Outcome>, records: Vec<FrameRecord>) -> Rgba32Counts {
        let plain =
            |counts: Vec<AtomicU32>| counts.into_iter().map(AtomicU32::into_inner).collect::<Vec<u32>>();
        Rgba32Counts {
            outcomes,
            image_counts: plain(self.image_counts),
            frame_counts: self.frame_counts.map(plain),
            strays: self.strays,
            texel_solid_angle_units: self
                .area
                .map(|area| area.into_iter().map(AtomicU64::into_inner).collect()),
            frames: self.lookup.map(|lookup| FrameTallies {
                parts: lookup.names,
                records,
                texel_solid_angle_units: None,
            }),
        }
    }

    /// A new eye-frame's tally.
    fn eye_frame(&self) -> EyeFrameTally {
        let tally = || self.lookup.as_ref().map(PartPixels::new);
        EyeFrameTally { ids: Vec::new(), image: tally(), sum: tally() }
    }

    /// Counts one work unit: each image once (unless `plan` trims it), each
    /// eye-frame's tallies by part, and the unit's distinct texels once more
    /// into the frame counts (the unit is the eye-frame or frame those
    /// count); `by_eye_frame` when its eye-frames are the manifest's.
    fn count_unit(
        &self,
        inputs: &Inputs,
        plan: &TrimPlan,
        unit: &[Vec<usize>],
        by_eye_frame: bool,
    ) -> UnitResult {
        let (mut outcomes, mut records, mut unit_ids) = (Vec::new(), Vec::new(), Vec::new());
        for eye_frame in unit {
            let mut frame = self.eye_frame();
            for &index in eye_frame {
                if self.strict && self.stop.load(Ordering::Relaxed) {
                    outcomes.push((index, Outcome::Skipped));
                    continue;
                }
                let outcome = self.count_file(inputs, plan, index, &mut frame);
                if let Outcome::Failed(_) = outcome {
                    self.stop.store(true, Ordering::Relaxed);
                }
                outcomes.push((index, outcome));
            }
            let label = |first: usize| match inputs.archive.images[first].frame_group {
                Some(group) if by_eye_frame => eye_frame_label(&inputs.eye_frames, group),
                _ => FrameLabel::Image(first),
            };
            if let (Some((sum, texels)), Some(&first)) = (self.part_texels(&mut frame), eye_frame.first()) {
                records.push(FrameRecord::from_parts(label(first), sum, texels, inputs.optics.is_some()));
            }
            self.end_eye_frame(&mut frame, &mut unit_ids);
        }
        self.end_unit(&mut unit_ids);
        (outcomes, records)
    }

    /// Moves an eye-frame's texels into its unit's (when counted per frame).
    fn end_eye_frame(&self, frame: &mut EyeFrameTally, unit_ids: &mut Vec<u32>) {
        if self.frame_counts.is_some() {
            unit_ids.append(&mut frame.ids);
        }
    }

    /// Adds a unit's distinct texels (an eye-frame's, or a frame's with
    /// `eye-pair`) to the frame counts once each, and empties them.
    fn end_unit(&self, unit_ids: &mut Vec<u32>) {
        if let Some(frame_counts) = &self.frame_counts {
            unit_ids.sort_unstable();
            unit_ids.dedup();
            add_ids(frame_counts, unit_ids);
        }
        unit_ids.clear();
    }

    /// Reads image `index` of the archive and counts it into the shared
    /// counts and its eye-frame's tallies, unless `plan` trims it (bytes
    /// identical to a verified empty tile).
    fn count_file(
        &self,
        inputs: &Inputs,
        plan: &TrimPlan,
        index: usize,
        frame: &mut EyeFrameTally,
    ) -> Outcome {
        let image = &inputs.archive.images[index];
        let view = inputs.optics.zip(image.tile).map(|(optics, tile)| optics.view(tile));
        let bytes = match read_file(&image.path) {
            Ok(bytes) => bytes,
            Err(error) => return Outcome::Failed(error),
        };
        if plan.is_trimmable(index, &bytes) {
            return Outcome::Trimmed;
        }
        match PngRows::new(&image.path, &bytes) {
            Ok(rows) => self.count_one(&image.path, rows, view, frame),
            Err(error) => Outcome::Failed(error),
        }
    }

    /// Counts one image's `rows` (a PNG's, or a rendered tile's) at `view`
    /// into the shared counts and the eye-frame's tallies (a failed image
    /// leaves none of either).
    fn count_one(
        &self,
        path: &Path,
        rows: impl IdRows,
        view: Option<TileView>,
        frame: &mut EyeFrameTally,
    ) -> Outcome {
        if let Some(parts) = frame.image.as_mut() {
            parts.clear();
            parts.view = view;
        }
        let mut ids = Vec::new();
        let area_view = view.filter(|_| self.area.is_some());
        let outcome = self.count_image(path, rows, area_view.as_ref(), &mut ids, frame.image.as_mut());
        if let Outcome::Decoded(_) = outcome {
            add_ids(&self.image_counts, &ids);
            frame.ids.extend_from_slice(&ids);
            if let (Some(image), Some(sum)) = (frame.image.as_ref(), frame.sum.as_mut()) {
                sum.add(image);
            }
        }
        outcome
    }

    /// An eye-frame's tallies by part (when tallied): its pixels and solid
    /// angles by part, and its distinct texels by part (a
    /// [`PartLookup::tally`], the non-texel slot last). Its texels are left
    /// sorted and distinct.
    fn part_texels(&self, frame: &mut EyeFrameTally) -> Option<(PartPixels, Vec<u64>)> {
        let (lookup, sum) = (self.lookup.as_ref()?, frame.sum.take()?);
        frame.ids.sort_unstable();
        frame.ids.dedup();
        let mut texels = lookup.tally();
        for &id in &frame.ids {
            if let Some(count) = texels.get_mut(usize::from(lookup.slot_table().get(id))) {
                *count += 1;
            }
        }
        texels.pop();
        Some((sum, texels))
    }

    /// Counts one image's rows: its distinct texel ids into `ids`
    /// (ascending), its stray colours and (at `view`) its texels' solid
    /// angles into the shared tables once it is whole.
    fn count_image(
        &self,
        path: &Path,
        rows: impl IdRows,
        view: Option<&TileView>,
        ids: &mut Vec<u32>,
        parts: Option<&mut PartPixels>,
    ) -> Outcome {
        let mut found = Found { ids, strays: Vec::new(), runs: Vec::new() };
        match self.scan(path, rows, view, &mut found, parts) {
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

    /// Classifies every pixel of one image (`path` names it): background
    /// (an opaque background colour), a texel of the palette (its id below
    /// the palette's texel count) or stray; a run of one id is classified
    /// once. At `view`, each texel pixel's solid angle goes to its id's run
    /// in `found.runs`; with `parts`, each row's spans of one part slot go
    /// to its tally.
    fn scan(
        &self,
        path: &Path,
        mut rows: impl IdRows,
        view: Option<&TileView>,
        found: &mut Found,
        mut parts: Option<&mut PartPixels>,
    ) -> Result<ImageTally> {
        let (step, size) = (rows.step(), rows.size());
        let weighted_parts = parts.as_ref().is_some_and(|parts| parts.view.is_some());
        if (view.is_some() || weighted_parts) && rows.interlaced() {
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
        while let Some(row) = rows.next_row()? {
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
        rows.finish()?;
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
    png_ids(path, &read_file(path)?)
}

/// [`read_rgba32_ids`] of a PNG's `bytes`.
fn png_ids(path: &Path, bytes: &[u8]) -> Result<([u32; 2], Vec<u32>)> {
    let mut rows = PngRows::new(path, bytes)?;
    let (step, mut ids) = (rows.step, Vec::new());
    while let Some(row) = rows.next_row()? {
        ids.extend(row.chunks_exact(step).map(pixel_id));
    }
    rows.finish()?;
    Ok((rows.size(), ids))
}

/// The rows of one image of texel ids, whatever holds them: a PNG being
/// decoded ([`PngRows`]) or a rendered tile in memory (the capture's
/// `--count`, [`tiles`]), so both are counted by one [`Counter::scan`].
trait IdRows {
    /// `[width, height]` in pixels.
    fn size(&self) -> [u32; 2];
    /// Bytes per pixel: 4 (RGBA) or 3 (RGB, opaque).
    fn step(&self) -> usize;
    /// Whether the rows come out of order (an interlaced PNG).
    fn interlaced(&self) -> bool;
    /// The next row, top to bottom; `None` after the last.
    fn next_row(&mut self) -> Result<Option<&[u8]>>;
    /// Checks what follows the last row (a PNG's trailer).
    fn finish(&mut self) -> Result<()>;
}

/// The rows of an `rgba32` tile's PNG, RGBA or RGB.
struct PngRows<'a> {
    reader: RowReader<'a>,
    step: usize,
}

impl<'a> PngRows<'a> {
    /// Reads the header of the PNG `bytes` (the file `path`); refuses a
    /// pixel layout other than RGBA and RGB naming the file.
    fn new(path: &'a Path, bytes: &'a [u8]) -> Result<PngRows<'a>> {
        let reader = RowReader::new(path, bytes)?;
        let step = pixel_step(path, reader.layout())?;
        Ok(PngRows { reader, step })
    }
}

impl IdRows for PngRows<'_> {
    fn size(&self) -> [u32; 2] {
        [self.reader.width(), self.reader.height()]
    }

    fn step(&self) -> usize {
        self.step
    }

    fn interlaced(&self) -> bool {
        self.reader.interlaced()
    }

    fn next_row(&mut self) -> Result<Option<&[u8]>> {
        self.reader.next_row()
    }

    fn finish(&mut self) -> Result<()> {
        self.reader.finish()
    }
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
