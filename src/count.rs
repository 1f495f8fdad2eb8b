//! Counting: how many images show each colour, once per image.
//!
//! The hot loop of the whole tool. Rows come straight from the PNG decoder
//! and are scanned in blocks of 16 pixels: a block equal to the block one
//! pixel earlier (a run of background, or of one magnified texel) is skipped
//! with one comparison; any other block is classified without branches, so
//! the unpredictable colour changes inside a vehicle cost no mispredictions.
//! New palette colours land in a per-thread [`TouchedSet`]; when the image is
//! complete they are added to the shared [`Counts`] in ascending order. A
//! failed image is forgotten whole, so a truncated file never leaves half its
//! counts behind.

use std::path::Path;
use std::sync::{Mutex, MutexGuard, PoisonError};

use crate::bitset::{AtomicColorSet, TouchedSet, color_key};
use crate::color::COLOR_COUNT;
use crate::decode::{PixelLayout, RowReader};
use crate::error::{Error, Result};
use crate::palette::Fcsp;

/// Colours per shard of [`Counts`] (2^16 counts = 256 KiB).
const SHARD_BITS: u32 = 16;
const SHARD_SIZE: usize = 1 << SHARD_BITS;
const SHARDS: usize = COLOR_COUNT / SHARD_SIZE;

/// For each of the 2^24 colours, the number of images (or eye-frames) that
/// showed it. Shared by all workers. Indexed by [`color_key`], like the
/// [`TouchedSet`]s that feed it.
///
/// Images add their colours in ascending order, so the array is split into
/// shards, each behind a lock: a worker takes a shard once and then adds
/// plainly to a few thousand neighbouring counts. That is ~5× faster than one
/// atomic add per colour (measured: 2.3 ms vs 5.4 ms per 1284×1620 tile with
/// 244 k distinct texels), and exact.
pub struct Counts {
    shards: Box<[Mutex<Box<[u32]>>]>,
}

impl Default for Counts {
    fn default() -> Self {
        Counts::new()
    }
}

impl Counts {
    /// All counts zero (64 MiB).
    pub fn new() -> Counts {
        Counts {
            shards: (0..SHARDS).map(|_| Mutex::new(vec![0u32; SHARD_SIZE].into_boxed_slice())).collect(),
        }
    }

    /// A writer that adds to counts in (mostly) ascending colour order.
    pub fn writer(&self) -> CountsWriter<'_> {
        CountsWriter { counts: self, shard: usize::MAX, guard: None }
    }

    /// Adds one to every key of `seen` (keys from [`color_key`]) and empties it.
    ///
    /// The sweep starts at a point chosen by the calling rayon thread, so
    /// workers that commit at the same moment work on different shards
    /// instead of queueing behind each other's locks.
    pub fn add_set(&self, seen: &mut TouchedSet) {
        let threads = rayon::current_num_threads().max(1);
        let slot = rayon::current_thread_index().unwrap_or(0) % threads;
        let start = (slot * (COLOR_COUNT / threads)) as u32;
        let mut writer = self.writer();
        seen.drain_sorted_from(start, |key| writer.add(key));
    }

    /// The counts as plain integers, indexed by colour (`0xRRGGBB`).
    pub fn into_vec(self) -> Vec<u32> {
        let mut by_key = Vec::with_capacity(COLOR_COUNT);
        for shard in self.shards.into_vec() {
            by_key.extend_from_slice(&shard.into_inner().unwrap_or_else(PoisonError::into_inner));
        }
        use rayon::prelude::*;
        (0..COLOR_COUNT as u32).into_par_iter().map(|color| by_key[color_key(color) as usize]).collect()
    }
}

/// Adds to [`Counts`], holding one shard's lock at a time.
pub struct CountsWriter<'a> {
    counts: &'a Counts,
    shard: usize,
    guard: Option<MutexGuard<'a, Box<[u32]>>>,
}

impl CountsWriter<'_> {
    /// Adds one to the count at `key` (see [`color_key`]).
    #[inline]
    pub fn add(&mut self, key: u32) {
        let shard = (key as usize >> SHARD_BITS) & (SHARDS - 1);
        if shard != self.shard || self.guard.is_none() {
            self.guard = None; // release before taking the next shard
            let lock = &self.counts.shards[shard];
            self.guard = Some(lock.lock().unwrap_or_else(PoisonError::into_inner));
            self.shard = shard;
        }
        if let Some(guard) = self.guard.as_mut() {
            let slot = &mut guard[key as usize & (SHARD_SIZE - 1)];
            *slot = slot.saturating_add(1);
        }
    }
}

/// At most this many background colours (checked without branches).
pub const MAX_BACKGROUNDS: usize = 8;

/// Decides, for each pixel colour, whether it is background, a palette
/// texel or a stray. Built once from validated options; shared read-only.
pub struct Classifier<'a> {
    palette: &'a Fcsp,
    /// Background colours, padded by repeating the first.
    backgrounds: [u32; MAX_BACKGROUNDS],
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
    /// A classifier for `palette` ignoring `backgrounds` (1 to
    /// [`MAX_BACKGROUNDS`] packed colours).
    pub fn new(palette: &'a Fcsp, backgrounds: &[u32]) -> Result<Classifier<'a>> {
        let Some(&first) = backgrounds.first() else {
            return Err(Error::BadOptions("at least one background colour is needed".into()));
        };
        if backgrounds.len() > MAX_BACKGROUNDS {
            return Err(Error::BadOptions(format!(
                "at most {MAX_BACKGROUNDS} background colours are supported, {} were given",
                backgrounds.len()
            )));
        }
        let mut padded = [first; MAX_BACKGROUNDS];
        padded[..backgrounds.len()].copy_from_slice(backgrounds);
        Ok(Classifier { palette, backgrounds: padded })
    }

    #[inline(always)]
    fn is_background(&self, color: u32) -> bool {
        self.backgrounds.iter().fold(false, |hit, &background| hit | (color == background))
    }

    /// True when there is exactly one background colour (the usual case,
    /// which the scanner checks with a single comparison).
    fn single_background(&self) -> bool {
        self.backgrounds.iter().all(|&b| b == self.backgrounds[0])
    }

    /// Background wins over palette membership: a background colour is
    /// ignored even when it also names a texel.
    #[inline(always)]
    pub fn classify(&self, color: u32) -> PixelClass {
        if self.is_background(color) {
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
/// as [`color_key`]s (`seen` must be empty on entry; [`crate::bitset::key_color`] turns
/// them back into colours). Stray colours go to `strays`.
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

/// The row scanner for one sample layout and palette kind.
type RowScan = fn(&[u8], &Classifier, &mut TouchedSet, &AtomicColorSet, &mut [u64; 3]);

fn row_scan(layout: PixelLayout, classifier: &Classifier) -> RowScan {
    let canonical = matches!(classifier.palette, Fcsp::Canonical { .. });
    match (layout, canonical, classifier.single_background()) {
        (PixelLayout::Rgb, true, true) => scan_row::<3, false, true, true>,
        (PixelLayout::Rgb, true, false) => scan_row::<3, false, true, false>,
        (PixelLayout::Rgb, false, true) => scan_row::<3, false, false, true>,
        (PixelLayout::Rgb, false, false) => scan_row::<3, false, false, false>,
        (PixelLayout::Rgba, true, true) => scan_row::<4, false, true, true>,
        (PixelLayout::Rgba, true, false) => scan_row::<4, false, true, false>,
        (PixelLayout::Rgba, false, true) => scan_row::<4, false, false, true>,
        (PixelLayout::Rgba, false, false) => scan_row::<4, false, false, false>,
        (PixelLayout::Gray, true, _) => scan_row::<1, true, true, false>,
        (PixelLayout::Gray, false, _) => scan_row::<1, true, false, false>,
        (PixelLayout::GrayAlpha, true, _) => scan_row::<2, true, true, false>,
        (PixelLayout::GrayAlpha, false, _) => scan_row::<2, true, false, false>,
    }
}

fn scan_rows(
    path: &Path,
    bytes: &[u8],
    classifier: &Classifier,
    seen: &mut TouchedSet,
    strays: &AtomicColorSet,
) -> Result<ImageTally> {
    let mut reader = RowReader::new(path, bytes)?;
    let scan = row_scan(reader.layout(), classifier);
    let mut by_class = [0u64; 3];
    while let Some(row) = reader.next_row()? {
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

/// Pixels per block (a power of two).
const BLOCK: usize = 16;

/// Classifies one row and records its new palette colours in `seen`.
#[inline(always)]
fn scan_row<const BYTES: usize, const GRAY: bool, const CANONICAL: bool, const SINGLE_BACKGROUND: bool>(
    row: &[u8],
    classifier: &Classifier,
    seen: &mut TouchedSet,
    strays: &AtomicColorSet,
    by_class: &mut [u64; 3],
) {
    let pixels = row.len() / BYTES;
    let texels = classifier.palette.texel_count() as u32;
    let words_mask = seen.words.len() - 1;
    let block_bytes = BLOCK * BYTES;
    let mut previous_class = PixelClass::Background as usize;
    // The bit-set word of the last texel lives in a register and goes back to
    // memory only when another word is needed: neighbouring pixels nearly
    // always share a word, and a load after a store to the same word would
    // chain every pixel through store forwarding (measured 1.85 → 1.53 ns/px).
    let mut word_index = usize::MAX;
    let mut word = 0u64;
    let mut start = 0;
    while start < pixels {
        // A block equal to the block one pixel earlier repeats the previous
        // pixel throughout (byte equality implies colour equality; differing
        // alpha merely sends the block down the exact path below).
        if start > 0
            && start + BLOCK <= pixels
            && row[start * BYTES..start * BYTES + block_bytes]
                == row[(start - 1) * BYTES..(start - 1) * BYTES + block_bytes]
        {
            by_class[previous_class] += BLOCK as u64;
            start += BLOCK;
            continue;
        }
        let end = (start + BLOCK).min(pixels);
        let mut fresh = [0u32; BLOCK];
        let mut fresh_count = 0usize;
        let (mut background, mut stray) = (0u64, 0u64);
        for pixel in start..end {
            let color = pack::<BYTES, GRAY>(row, pixel);
            let is_background = if SINGLE_BACKGROUND {
                color == classifier.backgrounds[0]
            } else {
                classifier.is_background(color)
            };
            let member = if CANONICAL { color < texels } else { classifier.palette.contains(color) };
            let is_texel = member & !is_background;
            let is_stray = !member & !is_background;
            let key = color_key(color);
            let index = (key >> 6) as usize & words_mask;
            if index != word_index {
                if word_index != usize::MAX {
                    seen.words[word_index] = word;
                }
                word_index = index;
                word = seen.words[index];
            }
            // Test-and-set without a branch: non-texels carry no bit.
            let bit = u64::from(is_texel) << (key & 63);
            fresh[fresh_count & (BLOCK - 1)] = key;
            fresh_count += usize::from(!word & bit != 0);
            word |= bit;
            background += u64::from(is_background);
            stray += u64::from(is_stray);
            if is_stray {
                strays.insert(color); // rare: damaged or filtered pixels
            }
            previous_class = usize::from(is_texel) + 2 * usize::from(is_stray);
        }
        seen.touched.extend_from_slice(&fresh[..fresh_count]);
        by_class[PixelClass::Background as usize] += background;
        by_class[PixelClass::Stray as usize] += stray;
        by_class[PixelClass::Texel as usize] += (end - start) as u64 - background - stray;
        start = end;
    }
    if word_index != usize::MAX {
        seen.words[word_index] = word;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn classify_row(row: &[u8]) -> ([u64; 3], Vec<u32>, u64) {
        let palette = Fcsp::canonical(16, 16).unwrap();
        let classifier = Classifier::new(&palette, &[0x000FFF]).unwrap();
        let mut seen = TouchedSet::new();
        let strays = AtomicColorSet::new();
        let mut by_class = [0; 3];
        scan_row::<3, false, true, true>(row, &classifier, &mut seen, &strays, &mut by_class);
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
            let seen: Vec<u32> = seen.into_iter().map(crate::bitset::key_color).collect();
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

#[cfg(test)]
mod counts_tests {
    use super::*;

    #[test]
    fn sharded_counts_add_and_flatten() {
        let counts = Counts::new();
        let mut seen = TouchedSet::new();
        for color in [70_000, 3, 0xFF_FFFF] {
            seen.insert(color_key(color));
        }
        counts.add_set(&mut seen);
        seen.insert(color_key(3));
        seen.insert(color_key(65_536));
        counts.add_set(&mut seen);
        assert!(seen.is_empty());
        let flat = counts.into_vec();
        assert_eq!(flat.len(), COLOR_COUNT);
        assert_eq!((flat[3], flat[70_000], flat[65_536], flat[0xFF_FFFF], flat[4]), (2, 1, 1, 1, 0));
    }
}
