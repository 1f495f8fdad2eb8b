//! The AVX-512 row kernel (x86-64 only, chosen at run time): skips blocks
//! that repeat the pixel before them, unpacks, classifies and keys 16 RGB or
//! RGBA pixels per instruction, and hands only the texels whose colour
//! differs from their left neighbour's to scalar code.

use std::arch::x86_64::*;

use super::{ClassCounts, WordAccumulator, unpack_table};
use crate::bitset::{AtomicColorSet, SeenSet};
use crate::count::{Classifier, PixelClass};

/// The vector form of [`crate::bitset::color_key`].
#[target_feature(enable = "avx512f")]
#[inline]
fn color_keys(colors: __m512i) -> __m512i {
    let low = _mm512_and_si512(colors, _mm512_set1_epi32(0xFF_001F));
    let x_blocks = _mm512_and_si512(_mm512_slli_epi32::<4>(colors), _mm512_set1_epi32(0xFE00));
    let y_rows = _mm512_and_si512(_mm512_srli_epi32::<7>(colors), _mm512_set1_epi32(0x1E0));
    _mm512_or_si512(low, _mm512_or_si512(x_blocks, y_rows))
}

/// What one block of up to 16 pixels contributed.
struct BlockTally {
    background: u32,
    stray: u32,
    /// The [`PixelClass`] of lane 15 (as its index into [`ClassCounts`]).
    last_class: usize,
}

/// Classifies the 16 colours of `colors` (lanes outside `lanes` are
/// ignored) and records the texels whose colour differs from their left
/// neighbour's (`previous` holds the block before).
///
/// # Safety
/// The CPU must have the features `scan_row` enables. (A plain
/// `#[target_feature]` function is not inlined into its caller, and the
/// call per 16 pixels cost 15 % of the kernel.)
#[inline(always)]
#[allow(clippy::too_many_arguments)]
unsafe fn scan_block<const SINGLE_BACKGROUND: bool>(
    colors: __m512i,
    previous: __m512i,
    lanes: __mmask16,
    classifier: &Classifier,
    texel_limit: __m512i,
    seen: &mut SeenSet,
    word: &mut WordAccumulator,
    strays: &AtomicColorSet,
) -> BlockTally {
    // SAFETY: the caller guarantees the CPU features (see above); the
    // stores below write 64-byte arrays.
    unsafe {
        let backgrounds = classifier.backgrounds();
        let mut is_background = _mm512_cmpeq_epi32_mask(colors, _mm512_set1_epi32(backgrounds[0] as i32));
        if !SINGLE_BACKGROUND {
            for &color in &backgrounds[1..] {
                is_background |= _mm512_cmpeq_epi32_mask(colors, _mm512_set1_epi32(color as i32));
            }
        }
        is_background &= lanes;
        let member = _mm512_cmplt_epu32_mask(colors, texel_limit);
        let is_texel = member & !is_background & lanes;
        let is_stray = !member & !is_background & lanes;
        if is_stray != 0 {
            // Rare: damaged or filtered pixels.
            let mut lane_colors = [0u32; 16];
            _mm512_storeu_si512(lane_colors.as_mut_ptr().cast(), colors);
            let mut remaining = is_stray;
            while remaining != 0 {
                strays.insert(lane_colors[remaining.trailing_zeros() as usize]);
                remaining &= remaining - 1;
            }
        }
        // A pixel with its left neighbour's colour adds nothing new.
        let left = _mm512_alignr_epi32::<15>(colors, previous);
        let fresh = _mm512_mask_cmpneq_epi32_mask(is_texel, colors, left);
        if fresh != 0 {
            let mut keys = [0u32; 16];
            let fresh_keys = _mm512_maskz_compress_epi32(fresh, color_keys(colors));
            _mm512_storeu_si512(keys.as_mut_ptr().cast(), fresh_keys);
            for &key in &keys[..fresh.count_ones() as usize] {
                word.add(seen, (key >> 6) as usize, 1u64 << (key & 63));
            }
        }
        let (last_background, last_stray) = (usize::from(is_background >> 15), usize::from(is_stray >> 15));
        BlockTally {
            background: is_background.count_ones(),
            stray: is_stray.count_ones(),
            // Background 0, texel 1, stray 2 (the two flags never both hold).
            last_class: (1 - last_background) * (1 + last_stray),
        }
    }
}

/// The AVX-512 kernel for rows of `BYTES`-byte pixels (3: RGB, 4: RGBA)
/// against a canonical palette with one background colour or (when
/// `SINGLE_BACKGROUND` is false) several; for CPUs where
/// [`super::Kernel::supported`] is at least [`super::Kernel::Avx512`].
#[target_feature(enable = "avx512f,avx512bw,avx512vbmi,popcnt,bmi1,bmi2")]
pub(super) fn scan_row<const BYTES: usize, const SINGLE_BACKGROUND: bool>(
    row: &[u8],
    classifier: &Classifier,
    seen: &mut SeenSet,
    strays: &AtomicColorSet,
    by_class: &mut ClassCounts,
) {
    let pixels = row.len() / BYTES;
    let texel_limit = _mm512_set1_epi32(classifier.palette().texel_count() as i32);
    // SAFETY: a 64-byte array.
    let index = unsafe { _mm512_loadu_si512(unpack_table::<BYTES, 64>(16).as_ptr().cast()) };
    // 16 pixels' bytes: 48 of RGB, 64 of RGBA.
    const fn bytes_mask(bytes: usize) -> u64 {
        if bytes >= 64 { !0 } else { (1u64 << bytes) - 1 }
    }
    let unpack = |start: usize, lanes: usize| {
        // SAFETY: the mask covers only bytes of `row` (masked-out bytes
        // are neither read nor faulted on).
        let raw = unsafe {
            _mm512_maskz_loadu_epi8(bytes_mask(lanes * BYTES), row.as_ptr().add(start * BYTES).cast())
        };
        _mm512_maskz_permutexvar_epi8(0x7777_7777_7777_7777, index, raw)
    };
    // An impossible colour (above 2^24), so the first pixel always differs.
    let mut previous = _mm512_set1_epi32(-1);
    let mut word = WordAccumulator::new();
    let (mut background, mut stray) = (0u64, 0u64);
    // Two explicit calls rather than one closure: rustc keeps such a closure
    // out of line, which cost 5 % of the whole count (measured).
    let full_blocks = pixels / 16;
    let block_bytes = 16 * BYTES;
    let block_mask = bytes_mask(block_bytes);
    let mut last_class = PixelClass::Background as usize;
    for block in 0..full_blocks {
        let at = block * block_bytes;
        // SAFETY: a full block lies inside `row`.
        let raw = unsafe { _mm512_maskz_loadu_epi8(block_mask, row.as_ptr().add(at).cast()) };
        if block > 0 {
            // SAFETY: `at - BYTES` is at least 0 for every block after the
            // first, and the block one pixel earlier ends inside `row`.
            let before = unsafe { _mm512_maskz_loadu_epi8(block_mask, row.as_ptr().add(at - BYTES).cast()) };
            if _mm512_cmpneq_epi8_mask(raw, before) == 0 {
                // Each pixel repeats the one before it (a run of background
                // or of one magnified texel): the class of the last pixel
                // scanned, and nothing new. As in the portable kernel, equal
                // bytes imply equal colours (RGBA alpha may differ: exact path).
                background += 16 * u64::from(last_class == PixelClass::Background as usize);
                stray += 16 * u64::from(last_class == PixelClass::Stray as usize);
                continue;
            }
        }
        let colors = _mm512_maskz_permutexvar_epi8(0x7777_7777_7777_7777, index, raw);
        // SAFETY: this function has the features `scan_block` needs.
        let tally = unsafe {
            scan_block::<SINGLE_BACKGROUND>(
                colors,
                previous,
                !0,
                classifier,
                texel_limit,
                seen,
                &mut word,
                strays,
            )
        };
        background += u64::from(tally.background);
        stray += u64::from(tally.stray);
        last_class = tally.last_class;
        previous = colors;
    }
    let rest = pixels - full_blocks * 16;
    if rest > 0 {
        let colors = unpack(full_blocks * 16, rest);
        let lanes = ((1u32 << rest) - 1) as __mmask16;
        // SAFETY: this function has the features `scan_block` needs.
        let tally = unsafe {
            scan_block::<SINGLE_BACKGROUND>(
                colors,
                previous,
                lanes,
                classifier,
                texel_limit,
                seen,
                &mut word,
                strays,
            )
        };
        background += u64::from(tally.background);
        stray += u64::from(tally.stray);
    }
    word.flush(seen);
    super::add_row_classes(by_class, pixels, background, stray);
}
