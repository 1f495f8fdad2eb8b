//! Row kernels: classify the pixels of one decoded row and record the
//! palette texels they show.
//!
//! The hot loop of the whole tool, in two forms that give identical results:
//!
//! * a portable kernel for every sample layout and palette kind, which scans
//!   blocks of 16 pixels without branches and skips a block equal to the block
//!   one pixel earlier (a run of background, or of one magnified texel) with
//!   one comparison;
//! * an AVX-512 kernel for RGB and RGBA rows against the canonical palette
//!   (the layout every capture writes), picked at run time when the CPU has
//!   AVX-512 VBMI: it classifies 16 pixels per instruction and leaves only
//!   the pixels whose colour differs from their left neighbour to scalar
//!   code.
//!
//! Both accumulate the bits of one 64-bit word of the [`SeenSet`] in a
//! register and write it back only when a pixel needs another word:
//! neighbouring pixels nearly always share a word (see
//! [`crate::bitset::color_key`]), so memory sees one update per run of
//! nearby texels, not one per pixel.

use crate::bitset::{AtomicColorSet, SeenSet, color_key};
use crate::count::{Classifier, PixelClass};
use crate::decode::PixelLayout;
use crate::palette::Fcsp;

/// Pixel counts by [`PixelClass`] (indexed by its discriminant).
pub(crate) type ClassCounts = [u64; 3];

/// A row kernel: classifies `row`, adds its palette texels (as
/// [`color_key`]s) to the set, its stray colours to the stray set, and its
/// pixels to the per-class counts.
pub(crate) type RowScan = fn(&[u8], &Classifier, &mut SeenSet, &AtomicColorSet, &mut ClassCounts);

/// Set to `1` to use the portable kernels even where AVX-512 is available
/// (for comparisons, or to rule the vector code out when debugging).
pub const PORTABLE_ENV: &str = "UFCSR_PORTABLE";

/// True when this CPU has the AVX-512 subset the vector kernels use and
/// [`PORTABLE_ENV`] does not ask for the portable ones.
pub fn avx512_enabled() -> bool {
    static ENABLED: std::sync::OnceLock<bool> = std::sync::OnceLock::new();
    *ENABLED.get_or_init(|| {
        let requested = std::env::var_os(PORTABLE_ENV).is_none_or(|value| value.is_empty() || value == "0");
        #[cfg(target_arch = "x86_64")]
        let available = std::arch::is_x86_feature_detected!("avx512f")
            && std::arch::is_x86_feature_detected!("avx512bw")
            && std::arch::is_x86_feature_detected!("avx512vbmi")
            && std::arch::is_x86_feature_detected!("popcnt")
            && std::arch::is_x86_feature_detected!("bmi1")
            && std::arch::is_x86_feature_detected!("bmi2");
        #[cfg(not(target_arch = "x86_64"))]
        let available = false;
        requested && available
    })
}

/// The fastest kernel for `layout` and the classifier's palette.
pub(crate) fn row_scan(layout: PixelLayout, classifier: &Classifier) -> RowScan {
    #[cfg(target_arch = "x86_64")]
    if let Some(scan) = vector::row_scan(layout, classifier) {
        return scan;
    }
    portable_row_scan(layout, classifier)
}

/// The portable kernel for `layout` and the classifier's palette.
pub(crate) fn portable_row_scan(layout: PixelLayout, classifier: &Classifier) -> RowScan {
    let canonical = matches!(classifier.palette(), Fcsp::Canonical { .. });
    let single = classifier.backgrounds().len() == 1;
    match (layout, canonical, single) {
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

#[inline(always)]
fn pack<const BYTES: usize, const GRAY: bool>(row: &[u8], pixel: usize) -> u32 {
    let at = pixel * BYTES;
    if GRAY {
        u32::from(row[at]) * 0x01_0101
    } else {
        (u32::from(row[at]) << 16) | (u32::from(row[at + 1]) << 8) | u32::from(row[at + 2])
    }
}

/// Accumulates the bits of one [`SeenSet`] word at a time.
///
/// Writing each pixel's bit to memory would chain neighbouring pixels through
/// store-to-load forwarding on the same word; holding the word in a register
/// and flushing it when the word changes keeps the loop free of that chain
/// (measured 1.85 → 1.53 ns per pixel when it was introduced).
struct WordAccumulator {
    index: usize,
    bits: u64,
}

impl WordAccumulator {
    fn new() -> WordAccumulator {
        WordAccumulator { index: 0, bits: 0 }
    }

    /// Adds `bits` (possibly none) at word `index`.
    #[inline(always)]
    fn add(&mut self, seen: &mut SeenSet, index: usize, bits: u64) {
        if index != self.index {
            self.flush(seen);
            self.index = index;
        }
        self.bits |= bits;
    }

    #[inline(always)]
    fn flush(&mut self, seen: &mut SeenSet) {
        if self.bits != 0 {
            seen.or_word(self.index, self.bits);
            self.bits = 0;
        }
    }
}

/// Pixels per block of the portable kernel (a power of two).
const BLOCK: usize = 16;

/// The portable kernel.
#[inline(always)]
fn scan_row<const BYTES: usize, const GRAY: bool, const CANONICAL: bool, const SINGLE_BACKGROUND: bool>(
    row: &[u8],
    classifier: &Classifier,
    seen: &mut SeenSet,
    strays: &AtomicColorSet,
    by_class: &mut ClassCounts,
) {
    let pixels = row.len() / BYTES;
    let texels = classifier.palette().texel_count() as u32;
    let background_0 = classifier.backgrounds()[0];
    let block_bytes = BLOCK * BYTES;
    let mut previous_class = PixelClass::Background as usize;
    let mut word = WordAccumulator::new();
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
        let (mut background, mut stray) = (0u64, 0u64);
        for pixel in start..end {
            let color = pack::<BYTES, GRAY>(row, pixel);
            let is_background =
                if SINGLE_BACKGROUND { color == background_0 } else { classifier.is_background(color) };
            let member = if CANONICAL { color < texels } else { classifier.palette().contains(color) };
            let is_texel = member & !is_background;
            let is_stray = !member & !is_background;
            let key = color_key(color);
            // Non-texels add no bit.
            word.add(seen, (key >> 6) as usize, u64::from(is_texel) << (key & 63));
            background += u64::from(is_background);
            stray += u64::from(is_stray);
            if is_stray {
                strays.insert(color); // rare: damaged or filtered pixels
            }
            previous_class = usize::from(is_texel) + 2 * usize::from(is_stray);
        }
        by_class[PixelClass::Background as usize] += background;
        by_class[PixelClass::Stray as usize] += stray;
        by_class[PixelClass::Texel as usize] += (end - start) as u64 - background - stray;
        start = end;
    }
    word.flush(seen);
}

#[cfg(target_arch = "x86_64")]
mod vector {
    //! The AVX-512 kernel (x86-64 only, chosen at run time).

    use std::arch::x86_64::*;

    use super::{ClassCounts, RowScan, WordAccumulator};
    use crate::bitset::{AtomicColorSet, SeenSet};
    use crate::count::{Classifier, PixelClass};
    use crate::decode::PixelLayout;
    use crate::palette::Fcsp;

    /// The AVX-512 kernel for `layout`, when it is enabled and the palette
    /// is canonical (membership is then one comparison).
    pub(super) fn row_scan(layout: PixelLayout, classifier: &Classifier) -> Option<RowScan> {
        if !super::avx512_enabled() || !matches!(classifier.palette(), Fcsp::Canonical { .. }) {
            return None;
        }
        match layout {
            PixelLayout::Rgb => Some(scan_rgb),
            PixelLayout::Rgba => Some(scan_rgba),
            PixelLayout::Gray | PixelLayout::GrayAlpha => None,
        }
    }

    fn scan_rgb(
        row: &[u8],
        classifier: &Classifier,
        seen: &mut SeenSet,
        strays: &AtomicColorSet,
        by_class: &mut ClassCounts,
    ) {
        // SAFETY: `row_scan` hands out this function only after
        // `avx512_enabled` checked that the CPU has the features it enables.
        unsafe { scan_row::<3>(row, classifier, seen, strays, by_class) }
    }

    fn scan_rgba(
        row: &[u8],
        classifier: &Classifier,
        seen: &mut SeenSet,
        strays: &AtomicColorSet,
        by_class: &mut ClassCounts,
    ) {
        // SAFETY: as for `scan_rgb`.
        unsafe { scan_row::<4>(row, classifier, seen, strays, by_class) }
    }

    /// Byte shuffle that turns 16 pixels of `BYTES` samples into 16 lanes of
    /// `0x00RRGGBB` (lane byte 0 = B, 1 = G, 2 = R; byte 3 is zeroed by the
    /// mask in [`scan_row`]).
    const fn unpack_index<const BYTES: usize>() -> [u8; 64] {
        let mut index = [0u8; 64];
        let mut lane = 0;
        while lane < 16 {
            index[lane * 4] = (lane * BYTES + 2) as u8;
            index[lane * 4 + 1] = (lane * BYTES + 1) as u8;
            index[lane * 4 + 2] = (lane * BYTES) as u8;
            lane += 1;
        }
        index
    }

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
            BlockTally { background: is_background.count_ones(), stray: is_stray.count_ones() }
        }
    }

    #[target_feature(enable = "avx512f,avx512bw,avx512vbmi,popcnt,bmi1,bmi2")]
    fn scan_row<const BYTES: usize>(
        row: &[u8],
        classifier: &Classifier,
        seen: &mut SeenSet,
        strays: &AtomicColorSet,
        by_class: &mut ClassCounts,
    ) {
        if classifier.backgrounds().len() == 1 {
            scan_row_with::<BYTES, true>(row, classifier, seen, strays, by_class)
        } else {
            scan_row_with::<BYTES, false>(row, classifier, seen, strays, by_class)
        }
    }

    #[target_feature(enable = "avx512f,avx512bw,avx512vbmi,popcnt,bmi1,bmi2")]
    fn scan_row_with<const BYTES: usize, const SINGLE_BACKGROUND: bool>(
        row: &[u8],
        classifier: &Classifier,
        seen: &mut SeenSet,
        strays: &AtomicColorSet,
        by_class: &mut ClassCounts,
    ) {
        let pixels = row.len() / BYTES;
        let texel_limit = _mm512_set1_epi32(classifier.palette().texel_count() as i32);
        // SAFETY: a 64-byte array.
        let index = unsafe { _mm512_loadu_si512(unpack_index::<BYTES>().as_ptr().cast()) };
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
        let full_blocks = pixels / 16;
        for block in 0..full_blocks {
            let colors = unpack(block * 16, 16);
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
        by_class[PixelClass::Background as usize] += background;
        by_class[PixelClass::Stray as usize] += stray;
        by_class[PixelClass::Texel as usize] += pixels as u64 - background - stray;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Per-class counts and texel keys of one row; strays go to `strays`.
    fn scan_with(
        scan: RowScan,
        classifier: &Classifier,
        row: &[u8],
        strays: &AtomicColorSet,
    ) -> (ClassCounts, Vec<u32>) {
        // A 2 MiB set per call would make the test slow unoptimised.
        thread_local! {
            static SEEN: std::cell::RefCell<SeenSet> = std::cell::RefCell::new(SeenSet::new());
        }
        SEEN.with_borrow_mut(|seen| {
            let mut by_class = [0; 3];
            scan(row, classifier, seen, strays, &mut by_class);
            let keys = seen.keys();
            seen.clear();
            (by_class, keys)
        })
    }

    fn rgb(colors: &[u32]) -> Vec<u8> {
        colors.iter().flat_map(|&c| [(c >> 16) as u8, (c >> 8) as u8, c as u8]).collect()
    }

    #[test]
    fn runs_of_every_length_are_counted_exactly() {
        let palette = Fcsp::canonical(16, 16).unwrap();
        let classifier = Classifier::new(&palette, &[0x000FFF]).unwrap();
        for scan in
            [portable_row_scan(PixelLayout::Rgb, &classifier), row_scan(PixelLayout::Rgb, &classifier)]
        {
            let strays = AtomicColorSet::new();
            for length in 0..60 {
                let mut colors = vec![0x000FFF; length];
                colors.extend([5, 5, 7, 0xFFFFFF, 5]);
                colors.extend(vec![9; length]);
                colors.push(0x000FFF);
                let (by_class, seen) = scan_with(scan, &classifier, &rgb(&colors), &strays);
                let seen: Vec<u32> = seen.into_iter().map(crate::bitset::key_color).collect();
                assert_eq!(by_class, [length as u64 + 1, 4 + length as u64, 1], "length {length}");
                let mut expected = vec![5, 7];
                if length > 0 {
                    expected.push(9);
                }
                assert_eq!(seen, expected);
                assert_eq!(strays.first(10), vec![0xFFFFFF]);
            }
        }
    }

    /// A deterministic pseudo-random row mixing background runs, texel
    /// gradients, repeats, strays and (for RGBA) arbitrary alpha.
    fn random_row(seed: u64, pixels: usize, bytes: usize, backgrounds: &[u32]) -> Vec<u8> {
        let mut state = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
        let mut next = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        let mut row = Vec::with_capacity(pixels * bytes);
        let mut color = 0u32;
        while row.len() < pixels * bytes {
            let run = (next() % 40) as usize + 1;
            let kind = next() % 10;
            for step in 0..run {
                color = match kind {
                    0..=2 => backgrounds[(next() as usize) % backgrounds.len()],
                    3..=7 => ((next() as u32) & 0xFF_FFFF) / 2 + (step as u32 / 3), // texels, magnified
                    8 => (next() as u32) & 0xFF_FFFF,                               // anything, often stray
                    _ => color,                                                     // repeat
                };
                row.extend_from_slice(
                    &[(color >> 16) as u8, (color >> 8) as u8, color as u8, next() as u8][..bytes],
                );
            }
        }
        row.truncate(pixels * bytes);
        row
    }

    #[test]
    fn vector_kernel_equals_portable_kernel() {
        #[cfg(target_arch = "x86_64")]
        {
            if !avx512_enabled() {
                eprintln!("skipped: the AVX-512 kernel is not in use on this CPU (or {PORTABLE_ENV} is set)");
                return;
            }
            // 4096 × 3000 texels: colours from 12,288,000 up are strays.
            let palette = Fcsp::canonical(4096, 3000).unwrap();
            for backgrounds in [vec![0x000FFF], vec![0x000FFF, 0x000010, 0xFFFFFF]] {
                let classifier = Classifier::new(&palette, &backgrounds).unwrap();
                for (layout, bytes) in [(PixelLayout::Rgb, 3), (PixelLayout::Rgba, 4)] {
                    let vector = row_scan(layout, &classifier);
                    let portable = portable_row_scan(layout, &classifier);
                    let (vector_strays, portable_strays) = (AtomicColorSet::new(), AtomicColorSet::new());
                    for seed in 0..300u64 {
                        let pixels = (seed as usize * 7) % 200 + (seed as usize % 3) * 1284;
                        let row = random_row(seed, pixels, bytes, &backgrounds);
                        assert_eq!(
                            scan_with(vector, &classifier, &row, &vector_strays),
                            scan_with(portable, &classifier, &row, &portable_strays),
                            "seed {seed}, {pixels} pixels, {bytes} bytes per pixel"
                        );
                    }
                    let all = usize::MAX;
                    assert!(vector_strays.len() > 1000, "the rows must exercise strays");
                    assert_eq!(vector_strays.first(all), portable_strays.first(all));
                }
            }
        }
    }
}
