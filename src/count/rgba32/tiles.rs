//! The capture's `--count` for palettes of 32-bit texel ids: rendered RGBA
//! tiles counted from memory, one after the other, by the `rgba32` path's
//! own [`Counter`] and row scan ([`Counter::count_one`]), so a tile counted
//! here gives what its PNG gives to [`super::count_rgba32_images`]: the
//! same texels once per image and per eye-frame (or frame, `eye-pair`), the
//! same strays, part tallies and per-texel solid angles, to the bit.
//! [`crate::TileCounter`] hands tiles here when its palette needs 32-bit ids.

use std::path::Path;

use crate::archive::options::Dedupe;
use crate::archive::palette::Fcsp;
use crate::count::part_lookup::{PartLookup, TiledEyeFrame, TiledParts};
use crate::count::scan::ImageTally;
use crate::count::work::Outcome;
use crate::error::{Error, Result};
use crate::optics::solid_angle::{EyeProjection, TileView};

use super::{Counter, EyeFrameTally, IdRows, Rgba32Counts};

/// Counts rendered tiles of 32-bit texel ids in capture order (all tiles of
/// one eye-frame together, a frame's eyes one after the other).
pub(crate) struct Rgba32Tiles {
    counter: Counter,
    /// The eyes' projection, when pixels are weighted by solid angle.
    projection: Option<EyeProjection>,
    /// The eye-frame being counted: its frame, eye and tally.
    current: Option<(u32, String, EyeFrameTally)>,
    /// Texels of the dedupe unit being counted (an eye-frame, or a frame
    /// with `eye-pair`), when counted per frame.
    unit_ids: Vec<u32>,
    /// Finished eye-frames' tallies by part, when tallied.
    records: Vec<TiledEyeFrame>,
}

impl Rgba32Tiles {
    /// A counter for tiles drawn with `palette` over `backgrounds` (packed).
    pub(crate) fn new(palette: &Fcsp, backgrounds: Vec<u32>, dedupe: Dedupe) -> Rgba32Tiles {
        Rgba32Tiles {
            counter: Counter::new(palette.texel_count(), backgrounds, dedupe.per_frame()),
            projection: None,
            current: None,
            unit_ids: Vec::new(),
            records: Vec::new(),
        }
    }

    /// Tallies eye-frames by `lookup`'s parts and, with the eyes'
    /// `projection`, their pixels' and each texel's solid angles.
    pub(crate) fn tally_parts(&mut self, lookup: PartLookup, projection: Option<EyeProjection>) {
        self.counter.set_parts(Some(lookup), projection.is_some());
        self.projection = projection;
    }

    /// The next tile is of `frame`'s `eye`: a new eye-frame unless it is the
    /// current one.
    pub(crate) fn start_eye_frame(&mut self, frame: u32, eye: &str) {
        if self.current.as_ref().is_none_or(|(f, e, _)| *f != frame || e != eye) {
            self.finish_eye_frame();
            self.current = Some((frame, eye.to_string(), self.counter.eye_frame()));
        }
    }

    /// Counts one tile of the current eye-frame (`name` for errors): `rgba`
    /// holds its `size` pixels, rows top to bottom without padding, and it
    /// lies at `origin` in its eye.
    pub(crate) fn count(
        &mut self,
        name: &str,
        origin: [u32; 2],
        size: [u32; 2],
        rgba: &[u8],
    ) -> Result<ImageTally> {
        let view = self.projection.map(|projection| TileView { projection, origin });
        let Some((_, _, frame)) = self.current.as_mut() else {
            return Err(Error::BadOptions(format!("tile {name} was counted outside an eye-frame")));
        };
        let rows = TileRows { rows: rgba.chunks_exact((size[0] as usize * 4).max(1)), size };
        match self.counter.count_one(Path::new(name), rows, view, frame) {
            Outcome::Decoded(tally) => Ok(tally),
            Outcome::Failed(error) => Err(error),
            Outcome::Trimmed | Outcome::Skipped => {
                Err(Error::BadOptions(format!("tile {name} was neither counted nor refused")))
            }
        }
    }

    /// Ends the current eye-frame: its tallies by part become a record, its
    /// texels join the unit's.
    pub(crate) fn finish_eye_frame(&mut self) {
        if let Some((frame, eye, mut tally)) = self.current.take() {
            if let Some((pixels, texels)) = self.counter.part_texels(&mut tally) {
                self.records.push(TiledEyeFrame { frame, eye, pixels, texels });
            }
            self.counter.end_eye_frame(&mut tally, &mut self.unit_ids);
        }
    }

    /// Ends the dedupe unit (an eye-frame, or a frame with `eye-pair`): its
    /// distinct texels go to the frame counts once each.
    pub(crate) fn end_unit(&mut self) {
        self.finish_eye_frame();
        self.counter.end_unit(&mut self.unit_ids);
    }

    /// The counts, with one outcome per image of the archive, and the
    /// eye-frames' tallies by part (when tallied). Ends the last unit.
    pub(crate) fn into_counts(mut self, outcomes: Vec<Outcome>) -> (Rgba32Counts, Option<TiledParts>) {
        self.end_unit();
        let weighted = self.projection.is_some();
        let records = std::mem::take(&mut self.records);
        let mut counts = self.counter.into_counts(outcomes, Vec::new());
        let parts =
            counts.frames.take().map(|tallies| TiledParts { names: tallies.parts, weighted, records });
        (counts, parts)
    }
}

/// A rendered tile's rows: RGBA, tightly packed, top to bottom.
struct TileRows<'a> {
    rows: std::slice::ChunksExact<'a, u8>,
    size: [u32; 2],
}

impl IdRows for TileRows<'_> {
    fn size(&self) -> [u32; 2] {
        self.size
    }

    fn step(&self) -> usize {
        4
    }

    fn interlaced(&self) -> bool {
        false
    }

    fn next_row(&mut self) -> Result<Option<&[u8]>> {
        Ok(self.rows.next())
    }

    fn finish(&mut self) -> Result<()> {
        Ok(())
    }
}
