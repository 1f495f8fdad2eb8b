//! The AVX2 row kernel (x86-64 only, chosen at run time on CPUs without
//! AVX-512, such as most Intel desktop parts since Alder Lake): the AVX-512
//! kernel's method on 8 pixels per instruction. AVX2 has neither masked
//! loads of bytes nor a compress instruction, so whole 32-byte loads cover
//! the row up to its last full block, the portable kernel finishes the row,
//! and new texels are picked from a bit mask.

use std::arch::x86_64::*;

use super::{BACKGROUND, Classes, ColorRuns, MarkAccumulator, RowTally, STRAY, unpack_table};
use crate::color::{AtomicColorSet, SeenSet, color_key};

/// One row in progress: what its blocks need and what they add up to.
struct RowScanner<'a, const BYTES: usize, const SINGLE_BACKGROUND: bool, R: ColorRuns> {
    backgrounds: &'a [u32],
    texel_limit: __m256i,
    first_background: __m256i,
    /// In-lane shuffle: each 128-bit half unpacks 4 pixels.
    shuffle: __m256i,
    /// RGB: moves bytes 12..24 (pixels 4..8) to the upper 128-bit half.
    spread: __m256i,
    /// Lane i takes lane i − 1 (lane 0 takes lane 7).
    rotate: __m256i,
    seen: &'a mut SeenSet,
    strays: &'a AtomicColorSet,
    marks: MarkAccumulator,
    /// The colours of the last block scanned (an impossible colour, above
    /// 2^24, before the first, so the first pixel always differs).
    previous: __m256i,
    /// The class of the last pixel scanned ([`BACKGROUND`], texel or
    /// [`STRAY`]).
    last_class: usize,
    background: u64,
    stray: u64,
    /// Where the runs of equal colour go (as the AVX-512 kernel's).
    runs: R,
}

impl<const BYTES: usize, const SINGLE_BACKGROUND: bool, R: ColorRuns>
    RowScanner<'_, BYTES, SINGLE_BACKGROUND, R>
{
    /// Adds a block of `pixels` that all repeat the last pixel scanned: its
    /// class, and nothing new.
    #[inline(always)]
    fn repeat(&mut self, pixels: u64) {
        self.background += pixels * u64::from(self.last_class == BACKGROUND);
        self.stray += pixels * u64::from(self.last_class == STRAY);
    }

    /// Classifies the 8 pixels of the 32 bytes `raw` (pixels `first` on) and
    /// records the texels whose colour differs from their left neighbour's.
    ///
    /// # Safety
    /// The CPU must have the features `scan_row` enables (as in the AVX-512
    /// kernel, a `#[target_feature]` function here would not be inlined), so
    /// each intrinsic below is called in an `unsafe` block of its own.
    #[inline(always)]
    unsafe fn block(&mut self, first: usize, raw: __m256i) {
        let raw = if BYTES == 3 {
            // SAFETY: the caller guarantees the CPU features (as for every
            // intrinsic of this function).
            unsafe { _mm256_permutevar8x32_epi32(raw, self.spread) }
        } else {
            raw
        };
        // SAFETY: CPU features as above.
        let colors = unsafe { _mm256_shuffle_epi8(raw, self.shuffle) };
        // SAFETY: CPU features as above.
        let mut is_background = unsafe { _mm256_cmpeq_epi32(colors, self.first_background) };
        if !SINGLE_BACKGROUND {
            for &color in &self.backgrounds[1..] {
                // SAFETY: CPU features as above.
                let color = unsafe { _mm256_set1_epi32(color as i32) };
                // SAFETY: CPU features as above.
                let equal = unsafe { _mm256_cmpeq_epi32(colors, color) };
                // SAFETY: CPU features as above.
                is_background = unsafe { _mm256_or_si256(is_background, equal) };
            }
        }
        // SAFETY: CPU features as above.
        let member = unsafe { _mm256_cmpgt_epi32(self.texel_limit, colors) };
        // SAFETY: CPU features as above.
        let is_background = unsafe { _mm256_castsi256_ps(is_background) };
        // SAFETY: CPU features as above.
        let is_background = unsafe { _mm256_movemask_ps(is_background) } as u32;
        // SAFETY: CPU features as above.
        let member = unsafe { _mm256_castsi256_ps(member) };
        // SAFETY: CPU features as above.
        let member = unsafe { _mm256_movemask_ps(member) } as u32;
        let is_texel = member & !is_background;
        let is_stray = !member & !is_background & 0xFF;
        self.background += u64::from(is_background.count_ones());
        self.stray += u64::from(is_stray.count_ones());
        // Lane 0 of `left` is the last pixel of the previous block.
        // SAFETY: CPU features as above.
        let rotated = unsafe { _mm256_permutevar8x32_epi32(colors, self.rotate) };
        // SAFETY: CPU features as above.
        let previous = unsafe { _mm256_permutevar8x32_epi32(self.previous, self.rotate) };
        // SAFETY: CPU features as above.
        let left = unsafe { _mm256_blend_epi32::<1>(rotated, previous) };
        // SAFETY: CPU features as above.
        let equal = unsafe { _mm256_cmpeq_epi32(colors, left) };
        // SAFETY: CPU features as above.
        let equal = unsafe { _mm256_castsi256_ps(equal) };
        // SAFETY: CPU features as above.
        let same = unsafe { _mm256_movemask_ps(equal) } as u32;
        let fresh = is_texel & !same;
        self.previous = colors;
        let starts = if R::ACTIVE { !same & 0xFF } else { 0 };
        // Background 0, texel 1, stray 2 (the two flags never both hold).
        self.last_class = (1 - (is_background >> 7) as usize) * (1 + (is_stray >> 7) as usize);
        if fresh | is_stray | starts != 0 {
            let mut lane_values = [0u32; 8];
            // SAFETY: CPU features as above; the store writes the 32 bytes
            // of `lane_values`.
            unsafe { _mm256_storeu_si256(lane_values.as_mut_ptr().cast(), colors) };
            let mut remaining = starts;
            while remaining != 0 {
                let lane = remaining.trailing_zeros() as usize;
                self.runs.start(first + lane, lane_values[lane], is_texel >> lane & 1 != 0);
                remaining &= remaining - 1;
            }
            let mut remaining = fresh;
            while remaining != 0 {
                let key = color_key(lane_values[remaining.trailing_zeros() as usize]);
                self.marks.add(self.seen, key);
                remaining &= remaining - 1;
            }
            // Rare: damaged or filtered pixels.
            let mut remaining = is_stray;
            while remaining != 0 {
                self.strays.insert(lane_values[remaining.trailing_zeros() as usize]);
                remaining &= remaining - 1;
            }
        }
    }
}

/// The AVX2 kernel for rows of `BYTES`-byte pixels (3: RGB, 4: RGBA)
/// against a canonical palette with one background colour or (when
/// `SINGLE_BACKGROUND` is false) several, over the pixels of whole 32-byte
/// loads; the caller's portable kernel does the rest of the row (a few
/// pixels: it does not know the last block's colours, so it may set a bit
/// that is already set, which changes nothing). For CPUs where
/// [`crate::simd::Kernel::supported`] is at least AVX2.
#[target_feature(enable = "avx2,popcnt,bmi1,bmi2")]
pub(super) fn scan_row<const BYTES: usize, const SINGLE_BACKGROUND: bool, R: ColorRuns>(
    row: &[u8],
    classes: Classes,
    seen: &mut SeenSet,
    strays: &AtomicColorSet,
    runs: R,
) -> RowTally {
    let pixels = row.len() / BYTES;
    let backgrounds = classes.backgrounds;
    // Every colour and the limit are below 2^31, so signed comparison works.
    let mut scanner = RowScanner::<BYTES, SINGLE_BACKGROUND, R> {
        backgrounds,
        texel_limit: _mm256_set1_epi32(classes.texels as i32),
        first_background: _mm256_set1_epi32(backgrounds[0] as i32),
        // SAFETY: the load reads the 32 bytes of the table.
        shuffle: unsafe { _mm256_loadu_si256(unpack_table::<BYTES, 32>(4).as_ptr().cast()) },
        spread: _mm256_setr_epi32(0, 1, 2, 0, 3, 4, 5, 0),
        rotate: _mm256_setr_epi32(7, 0, 1, 2, 3, 4, 5, 6),
        seen,
        strays,
        marks: MarkAccumulator::new(),
        previous: _mm256_set1_epi32(-1),
        last_class: BACKGROUND,
        background: 0,
        stray: 0,
        runs,
    };
    // Blocks of 8 pixels whose 32-byte load stays inside the row.
    let blocks = if row.len() >= 32 { ((row.len() - 32) / (8 * BYTES) + 1).min(pixels / 8) } else { 0 };
    // The bytes of 8 pixels within a 32-byte load.
    let block_bytes_mask = if BYTES == 4 { u32::MAX } else { (1u32 << (8 * BYTES)) - 1 };
    for block in 0..blocks {
        let at = block * 8 * BYTES;
        // SAFETY: `blocks` keeps the 32 bytes from `at` inside `row`.
        let raw = unsafe { _mm256_loadu_si256(row.as_ptr().wrapping_add(at).cast()) };
        if block > 0 {
            // SAFETY: `at - BYTES` is at least 0 for every block after the
            // first, and the 32 bytes from it end before `at + 32`.
            let before = unsafe { _mm256_loadu_si256(row.as_ptr().wrapping_add(at - BYTES).cast()) };
            let equal = _mm256_movemask_epi8(_mm256_cmpeq_epi8(raw, before)) as u32;
            if equal & block_bytes_mask == block_bytes_mask {
                // Each pixel repeats the one before it: see the AVX-512 kernel.
                scanner.repeat(8);
                continue;
            }
        }
        // SAFETY: this function has the features `block` needs.
        unsafe { scanner.block(block * 8, raw) };
    }
    scanner.marks.flush(scanner.seen);
    RowTally { pixels: blocks * 8, background: scanner.background, stray: scanner.stray }
}
