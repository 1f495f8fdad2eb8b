//! Counting rendered tiles that never become files (the capture's `--count`).
//!
//! A renderer that already holds a tile's pixels in memory need not encode a
//! PNG only for the analyzer to decode it again. [`TileCounter`] takes the
//! readback buffer (tightly packed RGBA8 rows) and runs the same row kernels
//! into the same tables as [`crate::analyze()`] does for a decoded PNG, with
//! the same once-per-image (and, with `--dedupe frame`, once-per-eye-frame)
//! rule; [`crate::analyze_counted`] then joins the counts exactly as the PNG
//! path would, so both give the same `result.json`.

use std::collections::BTreeMap;

use crate::color::Color;
use crate::color::{AtomicColorSet, SeenSet};
use crate::count::counts::Counts;
use crate::count::scan::row_scan;
use crate::count::scan::{Classifier, ImageTally, PixelClass};
use crate::error::{Error, Result};
use crate::input::options::Dedupe;
use crate::input::palette::Fcsp;
use crate::input::png_rows::PixelLayout;

/// Counts RGBA8 tiles handed over one at a time, in capture order (all tiles
/// of one eye-frame together).
pub struct TileCounter<'a> {
    classifier: Classifier<'a>,
    pub(crate) image_counts: Counts,
    pub(crate) frame_counts: Option<Counts>,
    pub(crate) strays: AtomicColorSet,
    seen: SeenSet,
    frame_seen: Option<SeenSet>,
    /// The eye-frame whose tiles `frame_seen` holds.
    current_eye_frame: Option<(u32, String)>,
    /// With `EyePair` the set is committed per frame, not per eye-frame.
    dedupe: Dedupe,
    /// Per tile name (`tiles/fNNNN_EYE_rR_cC.png`): its pixel tally.
    pub(crate) tallies: BTreeMap<String, ImageTally>,
}

impl<'a> TileCounter<'a> {
    /// A counter for tiles drawn with `palette` over `backgrounds`.
    pub fn new(palette: &'a Fcsp, backgrounds: &[Color], dedupe: Dedupe) -> Result<TileCounter<'a>> {
        let backgrounds: Vec<u32> = backgrounds.iter().map(|c| c.packed()).collect();
        Ok(TileCounter {
            classifier: Classifier::new(palette, &backgrounds)?,
            image_counts: Counts::new(),
            frame_counts: dedupe.per_frame().then(Counts::new),
            strays: AtomicColorSet::new(),
            seen: SeenSet::new(),
            frame_seen: dedupe.per_frame().then(SeenSet::new),
            dedupe,
            current_eye_frame: None,
            tallies: BTreeMap::new(),
        })
    }

    /// Counts one tile: `rgba` holds `width × height` pixels, row 0 at the
    /// top, no row padding. `name` is the file the tile would have been.
    pub fn count_rgba(
        &mut self,
        name: &str,
        frame: u32,
        eye: &str,
        width: u32,
        height: u32,
        rgba: &[u8],
    ) -> Result<ImageTally> {
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
        let scan = row_scan(PixelLayout::Rgba, &self.classifier);
        let mut by_class = [0u64; 3];
        for row in rgba.chunks_exact(row_bytes.max(1)) {
            scan.scan(row, &self.classifier, &mut self.seen, &self.strays, &mut by_class);
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
        self.tallies.insert(name.to_string(), tally);
        Ok(tally)
    }

    /// Commits the eye-frame set (frame mode) once its last tile is in.
    pub(crate) fn commit_eye_frame(&mut self) {
        if let (Some(counts), Some(frame_seen)) = (&self.frame_counts, self.frame_seen.as_mut()) {
            counts.add_set(frame_seen);
        }
    }

    /// Tiles counted so far.
    pub fn tiles(&self) -> usize {
        self.tallies.len()
    }
}
