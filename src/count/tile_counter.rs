//! Counting rendered tiles that never become files (the capture's `--count`).
//!
//! A renderer that already holds a tile's pixels in memory need not encode a
//! PNG only for the analyzer to decode it again. [`TileCounter`] takes the
//! readback buffer (tightly packed RGBA8 rows) and runs the same row kernels
//! into the same tables as [`crate::analyze()`] does for a decoded PNG, with
//! the same once-per-image (and, with `--dedupe frame`, once-per-eye-frame)
//! rule; [`crate::analyze_counted`] then joins the counts exactly as the PNG
//! path would, so both give the same `result.json`. With
//! [`TileCounter::tally_parts`] it also tallies pixels, their solid angles and
//! texels by part per eye-frame, as the PNG path does for `frames.csv` and
//! the measures, and, with the eyes' projection, the per-texel solid angles
//! behind `texel-area.f32` from the same kernel pass ([`crate::count::texel_area`]),
//! the same integers as the PNG path's. A palette of more than 2^24 texels
//! (32-bit texel ids, an `rgba32` archive) is counted by the `rgba32` path's
//! row scan instead ([`crate::count::rgba32`]), as its PNG tiles would be.

use std::collections::BTreeMap;

use crate::archive::options::Dedupe;
use crate::archive::palette::Fcsp;
use crate::checks::neighbours::{NeighbourSampler, TexelGrid};
use crate::color::Color;
use crate::color::{AtomicColorSet, SeenSet};
use crate::count::counts::Counts;
use crate::count::part_lookup::{PartLookup, PartPixels, TiledEyeFrame, TiledParts};
use crate::count::rgba32::Rgba32Tiles;
use crate::count::scan::{Classifier, ImageTally, PixelClass};
use crate::count::scan::{PartRows, row_scan};
use crate::count::texel_area::{PendingRuns, TexelSolidAngles};
use crate::error::{Error, Result};
use crate::optics::solid_angle::{EyeProjection, TileView};
use crate::png::rows::PixelLayout;

/// One tile handed to [`TileCounter::count_tile`].
#[derive(Debug, Clone, Copy)]
pub struct CountedTile<'n> {
    /// The file the tile would have been (`tiles/fNNNN_EYE_rR_cC.png`).
    pub name: &'n str,
    pub frame: u32,
    pub eye: &'n str,
    /// `[width, height]` in pixels.
    pub size: [u32; 2],
    /// Its top-left pixel in the eye image (for the pixels' solid angles).
    pub origin: [u32; 2],
}

/// The per-part tallies of [`TileCounter::tally_parts`] (24-bit colours).
pub(crate) struct PartTallies {
    pub lookup: PartLookup,
    pub projection: Option<EyeProjection>,
    /// The eye-frame being tallied, its pixels and its texels.
    current: Option<(u32, String)>,
    pixels: PartPixels,
    seen: SeenSet,
    /// Finished eye-frames.
    records: Vec<TiledEyeFrame>,
}

impl PartTallies {
    fn finish_eye_frame(&mut self) {
        if let Some((frame, eye)) = self.current.take() {
            let mut texels = self.lookup.tally();
            self.lookup.add_texels(&self.seen, &mut texels);
            texels.pop();
            self.seen.clear();
            let pixels = std::mem::replace(&mut self.pixels, PartPixels::new(&self.lookup));
            self.records.push(TiledEyeFrame { frame, eye, pixels, texels });
        }
    }

    /// The finished eye-frames' tallies.
    pub(crate) fn into_parts(self) -> TiledParts {
        let weighted = self.projection.is_some();
        TiledParts { names: self.lookup.names, weighted, records: self.records }
    }
}

/// Counts RGBA8 tiles handed over one at a time, in capture order (all tiles
/// of one eye-frame together): as 24-bit colours, or as 32-bit texel ids
/// when the palette has more than 2^24 texels (an `rgba32` archive).
pub struct TileCounter<'a> {
    pub(crate) ids: TileIds<'a>,
    /// The dedupe unit (eye-frame, or frame with `EyePair`) being counted.
    current_eye_frame: Option<(u32, String)>,
    /// With `EyePair` the set is committed per frame, not per eye-frame.
    dedupe: Dedupe,
    /// Per tile name (`tiles/fNNNN_EYE_rR_cC.png`): its pixel tally.
    pub(crate) tallies: BTreeMap<String, ImageTally>,
}

/// What a [`TileCounter`] counts its tiles' pixels as.
pub(crate) enum TileIds<'a> {
    /// 24-bit colours, by the analyzer's row kernels.
    Rgb24(Box<Rgb24Tiles<'a>>),
    /// 32-bit texel ids, by the `rgba32` path's row scan ([`crate::count::rgba32`]).
    Rgba32(Box<Rgba32Tiles>),
}

/// The tables tiles of 24-bit colours are counted into.
pub(crate) struct Rgb24Tiles<'a> {
    classifier: Classifier<'a>,
    pub(crate) image_counts: Counts,
    pub(crate) frame_counts: Option<Counts>,
    pub(crate) strays: AtomicColorSet,
    seen: SeenSet,
    frame_seen: Option<SeenSet>,
    /// Per eye-frame and part, when asked for ([`TileCounter::tally_parts`]).
    pub(crate) parts: Option<PartTallies>,
    /// The colour checks' neighbour sample (canonical palettes).
    pub(crate) neighbours: Option<NeighbourSampler>,
    /// Per-texel solid angles, when parts are tallied with the projection.
    pub(crate) texel_area: Option<(TexelSolidAngles, PendingRuns)>,
}

impl<'a> TileCounter<'a> {
    /// A counter for tiles drawn with `palette` over `backgrounds`; a
    /// palette of more than 2^24 texels takes 32-bit texel ids.
    pub fn new(palette: &'a Fcsp, backgrounds: &[Color], dedupe: Dedupe) -> Result<TileCounter<'a>> {
        let backgrounds: Vec<u32> = backgrounds.iter().map(|c| c.packed()).collect();
        let ids = if palette.needs_rgba32() {
            // The classifier checks the backgrounds as for 24-bit colours.
            Classifier::new(palette, &backgrounds)?;
            TileIds::Rgba32(Box::new(Rgba32Tiles::new(palette, backgrounds, dedupe)))
        } else {
            TileIds::Rgb24(Box::new(Rgb24Tiles::new(palette, &backgrounds, dedupe)?))
        };
        Ok(TileCounter { ids, dedupe, current_eye_frame: None, tallies: BTreeMap::new() })
    }

    /// Whether tiles are counted as 32-bit texel ids (the palette has more
    /// than 2^24 texels).
    pub fn counts_rgba32(&self) -> bool {
        matches!(self.ids, TileIds::Rgba32(_))
    }

    /// Also tallies pixels and texels by `lookup`'s parts per eye-frame and,
    /// with the eyes' `projection`, the solid angle of those pixels — what
    /// `frames.csv` and the measures of [`crate::analyze_counted`] need; with
    /// the projection also each texel's solid angle (`texel-area.f32`).
    pub fn tally_parts(&mut self, lookup: PartLookup, projection: Option<EyeProjection>) {
        match &mut self.ids {
            TileIds::Rgb24(tiles) => tiles.tally_parts(lookup, projection),
            TileIds::Rgba32(tiles) => tiles.tally_parts(lookup, projection),
        }
    }

    /// Counts one tile, placed in its eye: `rgba` holds the tile's pixels, row 0 at the top,
    /// no row padding. `tile.name` is the file the tile would have been.
    pub fn count_tile(&mut self, tile: &CountedTile, rgba: &[u8]) -> Result<ImageTally> {
        let CountedTile { name, frame, eye, size: [width, height], origin } = *tile;
        let row_bytes = width as usize * 4;
        if rgba.len() != row_bytes * height as usize {
            return Err(Error::BadOptions(format!(
                "tile {name}: {} bytes of RGBA for {width}×{height} pixels",
                rgba.len()
            )));
        }
        if self.tallies.contains_key(name) {
            return Err(Error::BadOptions(format!("tile {name} was counted twice")));
        }
        // Eye-pair dedupe commits when the frame changes (the capture sends
        // a frame's eyes one after the other).
        let eye_changes = |e: &String| self.dedupe != Dedupe::EyePair && e != eye;
        if self.current_eye_frame.as_ref().is_none_or(|(f, e)| *f != frame || eye_changes(e)) {
            self.commit_eye_frame();
            self.current_eye_frame = Some((frame, eye.to_string()));
        }
        let tally = match &mut self.ids {
            TileIds::Rgb24(tiles) => tiles.count(tile, rgba),
            TileIds::Rgba32(tiles) => {
                tiles.start_eye_frame(frame, eye);
                tiles.count(name, origin, tile.size, rgba)?
            }
        };
        self.tallies.insert(name.to_string(), tally);
        Ok(tally)
    }

    /// Commits the dedupe unit's texels (frame mode) once its last tile is in.
    pub(crate) fn commit_eye_frame(&mut self) {
        match &mut self.ids {
            TileIds::Rgb24(tiles) => tiles.commit_eye_frame(),
            TileIds::Rgba32(tiles) => tiles.end_unit(),
        }
    }

    /// Tiles counted so far.
    pub fn tiles(&self) -> usize {
        self.tallies.len()
    }
}

impl<'a> Rgb24Tiles<'a> {
    fn new(palette: &'a Fcsp, backgrounds: &[u32], dedupe: Dedupe) -> Result<Rgb24Tiles<'a>> {
        let neighbours = TexelGrid::new(palette, backgrounds).map(NeighbourSampler::new);
        Ok(Rgb24Tiles {
            classifier: Classifier::new(palette, backgrounds)?,
            image_counts: Counts::new(),
            frame_counts: dedupe.per_frame().then(Counts::new),
            strays: AtomicColorSet::new(),
            seen: SeenSet::new(),
            frame_seen: dedupe.per_frame().then(SeenSet::new),
            parts: None,
            neighbours,
            texel_area: None,
        })
    }

    /// [`TileCounter::tally_parts`].
    fn tally_parts(&mut self, lookup: PartLookup, projection: Option<EyeProjection>) {
        let pixels = PartPixels::new(&lookup);
        self.texel_area = projection.map(|_| {
            let sums = TexelSolidAngles::new(self.classifier.palette(), self.classifier.backgrounds());
            (sums, PendingRuns::default())
        });
        self.parts = Some(PartTallies {
            lookup,
            projection,
            current: None,
            pixels,
            seen: SeenSet::new(),
            records: Vec::new(),
        });
    }

    /// Counts one tile (its size checked) with the row kernels.
    fn count(&mut self, tile: &CountedTile, rgba: &[u8]) -> ImageTally {
        let CountedTile { frame, eye, size: [width, height], origin, .. } = *tile;
        let row_bytes = width as usize * 4;
        debug_assert_eq!(rgba.len(), row_bytes * height as usize);
        let scan = row_scan(PixelLayout::Rgba, &self.classifier);
        let mut by_class = [0u64; 3];
        if let Some(parts) = self.parts.as_mut() {
            if parts.current.as_ref().is_none_or(|(f, e)| *f != frame || e != eye) {
                parts.finish_eye_frame();
                parts.current = Some((frame, eye.to_string()));
            }
            parts.pixels.view = parts.projection.map(|projection| TileView { projection, origin });
        }
        let projection = self.parts.as_ref().and_then(|parts| parts.projection);
        let mut part_rows = self.parts.as_mut().map(|parts| {
            PartRows::new(scan, PixelLayout::Rgba, &self.classifier, &parts.lookup, &mut parts.pixels)
        });
        let mut neighbours = self.neighbours.as_mut();
        if let Some(sampler) = neighbours.as_mut() {
            sampler.start_image();
        }
        let mut area = self.texel_area.as_mut().zip(projection).and_then(|((sums, pending), projection)| {
            let table = sums.pixel_prefix(&TileView { projection, origin }, [width, height])?;
            Some((&*sums, table, pending))
        });
        for (y, row) in rgba.chunks_exact(row_bytes.max(1)).enumerate() {
            let (y, counts) = (y as u32, (&mut self.seen, &self.strays, &mut by_class));
            match (part_rows.as_mut(), area.as_mut()) {
                (Some(parts), Some((sums, table, pending))) => {
                    let mut runs = sums.row_runs(table.row(y), pending);
                    parts.scan_runs(row, y, counts, &mut runs);
                    runs.finish(width as usize);
                    sums.flush_if_full(pending);
                }
                (Some(parts), None) => parts.scan_runs(row, y, counts, ()),
                (None, _) => scan.scan(row, &self.classifier, counts.0, counts.1, counts.2),
            }
            if let Some(sampler) = neighbours.as_mut() {
                sampler.row(y, row, PixelLayout::Rgba);
            }
        }
        if let Some((sums, _, pending)) = area {
            sums.flush(pending);
        }
        if let Some(parts) = self.parts.as_mut() {
            self.seen.merge_into(&mut parts.seen);
        }
        let tally = ImageTally {
            width,
            height,
            background_pixels: by_class[PixelClass::Background as usize],
            texel_pixels: by_class[PixelClass::Texel as usize],
            stray_pixels: by_class[PixelClass::Stray as usize],
        };
        if let Some(frame_seen) = self.frame_seen.as_mut() {
            self.seen.merge_into(frame_seen);
        }
        self.image_counts.add_set(&mut self.seen);
        tally
    }

    /// Commits the eye-frame set (frame mode) once its last tile is in.
    fn commit_eye_frame(&mut self) {
        if let (Some(counts), Some(frame_seen)) = (&self.frame_counts, self.frame_seen.as_mut()) {
            counts.add_set(frame_seen);
        }
    }

    /// The per-texel solid angles (units, row-major over the palette), when
    /// measured ([`TileCounter::tally_parts`] with a projection).
    pub(crate) fn take_texel_solid_angles(&mut self) -> Option<Vec<u64>> {
        self.texel_area.take().map(|(sums, _)| sums.into_units())
    }

    /// Ends the last eye-frame's part tallies (once every tile is in).
    pub(crate) fn finish_parts(&mut self) {
        if let Some(parts) = self.parts.as_mut() {
            parts.finish_eye_frame();
        }
    }
}
