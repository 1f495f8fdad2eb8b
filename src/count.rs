//! Counting: how many images show each colour, once per image.
//!
//! The hot loop of the whole tool. Rows come straight from the PNG decoder;
//! runs of identical pixels (background, or one texel magnified over several
//! pixels) are skipped by comparing whole blocks of bytes, so per-pixel work
//! is paid only where the colour changes. Each new palette colour is recorded
//! in a per-thread [`TouchedSet`]; when the image is complete, its touched
//! colours are added to the shared dense [`Counts`]. A failed image is
//! forgotten whole, so a truncated file never leaves half its counts behind.

use std::path::Path;
use std::sync::atomic::{AtomicU32, Ordering};

use crate::bitset::{AtomicColorSet, TouchedSet};
use crate::color::COLOR_COUNT;
use crate::decode::{PixelLayout, RowReader};
use crate::error::Result;
use crate::palette::Fcsp;

/// For each of the 2^24 colours, the number of images (or eye-frames) that
/// showed it. Shared by all workers; relaxed atomic adds are exact for sums.
pub struct Counts {
    per_color: Box<[AtomicU32]>,
}

impl Default for Counts {
    fn default() -> Self {
        Counts::new()
    }
}

impl Counts {
    /// All counts zero (64 MiB).
    pub fn new() -> Counts {
        Counts { per_color: (0..COLOR_COUNT).map(|_| AtomicU32::new(0)).collect() }
    }

    /// Adds one to every colour in `colors` (each colour at most once per call).
    #[inline]
    pub fn add_once(&self, colors: &[u32]) {
        for &color in colors {
            self.per_color[color as usize & (COLOR_COUNT - 1)].fetch_add(1, Ordering::Relaxed);
        }
    }

    /// The count of one colour.
    pub fn get(&self, color: u32) -> u32 {
        self.per_color[color as usize & (COLOR_COUNT - 1)].load(Ordering::Relaxed)
    }

    /// The counts as plain integers, indexed by colour (no copy).
    pub fn into_vec(self) -> Vec<u32> {
        self.per_color.into_vec().into_iter().map(AtomicU32::into_inner).collect()
    }
}

/// Decides, for each pixel colour, whether it is background, a palette
/// texel or a stray. Built once from validated options; shared read-only.
pub struct Classifier<'a> {
    palette: &'a Fcsp,
    backgrounds: Vec<u32>,
}

/// What a pixel colour is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(usize)]
pub enum PixelClass {
    Background = 0,
    Texel = 1,
    Stray = 2,
}

impl<'a> Classifier<'a> {
    /// A classifier for `palette` ignoring `backgrounds` (packed colours).
    pub fn new(palette: &'a Fcsp, backgrounds: &[u32]) -> Classifier<'a> {
        let mut backgrounds = backgrounds.to_vec();
        backgrounds.sort_unstable();
        backgrounds.dedup();
        Classifier { palette, backgrounds }
    }

    /// Background wins over palette membership: a background colour is
    /// ignored even when it also names a texel.
    #[inline(always)]
    pub fn classify(&self, color: u32) -> PixelClass {
        if self.backgrounds.contains(&color) {
            PixelClass::Background
        } else if self.palette.contains(color) {
            PixelClass::Texel
        } else {
            PixelClass::Stray
        }
    }
}

/// Pixel statistics of one decoded image.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct ImageTally {
    pub width: u32,
    pub height: u32,
    /// Pixels of palette colours.
    pub texel_pixels: u64,
    pub background_pixels: u64,
    pub stray_pixels: u64,
    /// Distinct palette colours in the image.
    pub distinct_texels: u64,
}

impl ImageTally {
    /// True when every pixel is background.
    pub fn is_pure_background(&self) -> bool {
        self.texel_pixels == 0 && self.stray_pixels == 0
    }
}

/// Decodes one PNG and records its distinct palette colours in `seen`
/// (which must be empty on entry). Stray colours go to `strays`.
///
/// On error `seen` is cleared again, so nothing of a failed image is counted.
pub fn scan_image(
    path: &Path,
    bytes: &[u8],
    classifier: &Classifier,
    seen: &mut TouchedSet,
    strays: &AtomicColorSet,
) -> Result<ImageTally> {
    debug_assert!(seen.is_empty());
    let outcome = scan_rows(path, bytes, classifier, seen, strays);
    if outcome.is_err() {
        seen.clear();
    }
    outcome
}

fn scan_rows(
    path: &Path,
    bytes: &[u8],
    classifier: &Classifier,
    seen: &mut TouchedSet,
    strays: &AtomicColorSet,
) -> Result<ImageTally> {
    let mut reader = RowReader::new(path, bytes)?;
    let layout = reader.layout();
    let mut by_class = [0u64; 3];
    while let Some(row) = reader.next_row()? {
        let scan = match layout {
            PixelLayout::Rgb => scan_row::<3, false>,
            PixelLayout::Rgba => scan_row::<4, false>,
            PixelLayout::Gray => scan_row::<1, true>,
            PixelLayout::GrayAlpha => scan_row::<2, true>,
        };
        scan(row, classifier, seen, strays, &mut by_class);
    }
    Ok(ImageTally {
        width: reader.width(),
        height: reader.height(),
        background_pixels: by_class[PixelClass::Background as usize],
        texel_pixels: by_class[PixelClass::Texel as usize],
        stray_pixels: by_class[PixelClass::Stray as usize],
        distinct_texels: seen.len() as u64,
    })
}

#[inline(always)]
fn pack<const BYTES: usize, const GRAY: bool>(row: &[u8], pixel: usize) -> u32 {
    let at = pixel * BYTES;
    if GRAY {
        u32::from(row[at]) * 0x01_0101
    } else {
        (u32::from(row[at]) << 16) | (u32::from(row[at + 1]) << 8) | u32::from(row[at + 2])
    }
}

/// Pixels compared at once while skipping a long run.
const BLOCK_PIXELS: usize = 16;
/// A run this long switches from per-pixel to block comparison.
const LONG_RUN: usize = 4;

/// Classifies one row, skipping runs of equal pixels.
#[inline(always)]
fn scan_row<const BYTES: usize, const GRAY: bool>(
    row: &[u8],
    classifier: &Classifier,
    seen: &mut TouchedSet,
    strays: &AtomicColorSet,
    by_class: &mut [u64; 3],
) {
    let pixels = row.len() / BYTES;
    let block = BLOCK_PIXELS * BYTES;
    let mut start = 0;
    while start < pixels {
        let color = pack::<BYTES, GRAY>(row, start);
        let class = classifier.classify(color);
        match class {
            PixelClass::Texel => {
                seen.insert(color);
            }
            PixelClass::Stray => strays.insert(color),
            PixelClass::Background => {}
        }
        // Extend the run of pixels equal to this one.
        let mut end = start + 1;
        while end < pixels && end - start < LONG_RUN && pack::<BYTES, GRAY>(row, end) == color {
            end += 1;
        }
        if end - start == LONG_RUN {
            // Long run: each block of pixels equal to the block one pixel
            // earlier continues it (byte equality implies colour equality;
            // differing alpha only sends us back to the per-pixel check).
            while end + BLOCK_PIXELS <= pixels
                && row[end * BYTES..end * BYTES + block] == row[(end - 1) * BYTES..(end - 1) * BYTES + block]
            {
                end += BLOCK_PIXELS;
            }
            while end < pixels && pack::<BYTES, GRAY>(row, end) == color {
                end += 1;
            }
        }
        by_class[class as usize] += (end - start) as u64;
        start = end;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn classify_row(row: &[u8]) -> ([u64; 3], Vec<u32>, u64) {
        let palette = Fcsp::canonical(16, 16).unwrap();
        let classifier = Classifier::new(&palette, &[0x000FFF]);
        let mut seen = TouchedSet::new();
        let strays = AtomicColorSet::new();
        let mut by_class = [0; 3];
        scan_row::<3, false>(row, &classifier, &mut seen, &strays, &mut by_class);
        (by_class, seen.touched().to_vec(), strays.len())
    }

    fn rgb(colors: &[u32]) -> Vec<u8> {
        colors.iter().flat_map(|&c| [(c >> 16) as u8, (c >> 8) as u8, c as u8]).collect()
    }

    #[test]
    fn runs_of_every_length_are_counted_exactly() {
        for length in 0..60 {
            let mut colors = vec![0x000FFF; length];
            colors.extend([5, 5, 7, 0xFFFFFF, 5]);
            colors.extend(vec![9; length]);
            colors.push(0x000FFF);
            let (by_class, seen, strays) = classify_row(&rgb(&colors));
            assert_eq!(by_class, [length as u64 + 1, 4 + length as u64, 1], "length {length}");
            let mut expected = vec![5, 7];
            if length > 0 {
                expected.push(9);
            }
            assert_eq!(seen, expected);
            assert_eq!(strays, 1);
        }
    }
}
