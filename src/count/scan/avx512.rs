//! The AVX-512 row kernel (x86-64 only, chosen at run time): skips blocks
//! that repeat the pixel before them, unpacks, classifies and keys 16 RGB or
//! RGBA pixels per instruction, and hands only the texels whose colour
//! differs from their left neighbour's to scalar code.

use std::arch::x86_64::*;

use super::{ClassCounts, WordAccumulator, unpack_table};
use crate::color::{AtomicColorSet, SeenSet};
use crate::count::scan::{Classifier, PixelClass};

/// The vector form of [`crate::color::color_key`].
#[target_feature(enable = "avx512f")]
#[inline]
fn color_keys(colors: __m512i) -> __m512i {
    let low = _mm512_and_si512(colors, _mm512_set1_epi32(0xFF_001F));
    let x_blocks = _mm512_and_si512(_mm512_slli_epi32::<4>(colors), _mm512_set1_epi32(0xFE00));
    let y_rows = _mm512_and_si512(_mm512_srli_epi32::<7>(colors), _mm512_set1_epi32(0x1E0));
    _mm512_or_si512(low, _mm512_or_si512(x_blocks, y_rows))
}

/// One row in progress: what its blocks need and what they add up to.
struct RowScanner<'a, const SINGLE_BACKGROUND: bool> {
    classifier: &'a Classifier<'a>,
    texel_limit: __m512i,
    seen: &'a mut SeenSet,
    strays: &'a AtomicColorSet,
    word: WordAccumulator,
    /// The colours of the last block scanned (an impossible colour, above
    /// 2^24, before the first, so the first pixel always differs).
    previous: __m512i,
    /// The [`PixelClass`] of the last pixel scanned, as an index into
    /// [`ClassCounts`].
    last_class: usize,
    background: u64,
    stray: u64,
}

impl<const SINGLE_BACKGROUND: bool> RowScanner<'_, SINGLE_BACKGROUND> {
    /// Adds a block of `pixels` that all repeat the last pixel scanned: its
    /// class, and nothing new.
    #[inline(always)]
    fn repeat(&mut self, pixels: u64) {
        self.background += pixels * u64::from(self.last_class == PixelClass::Background as usize);
        self.stray += pixels * u64::from(self.last_class == PixelClass::Stray as usize);
    }

    /// Classifies the 16 colours of `colors` (lanes outside `lanes` are
    /// ignored) and records the texels whose colour differs from their left
    /// neighbour's.
    ///
    /// # Safety
    /// The CPU must have the features `scan_row` enables. (A plain
    /// `#[target_feature]` function is not inlined into its caller, and the
    /// call per 16 pixels cost 15 % of the kernel.)
    #[inline(always)]
    unsafe fn block(&mut self, colors: __m512i, lanes: __mmask16) {
        // SAFETY: the caller guarantees the CPU features (see above); the
        // stores below write 64-byte arrays.
        unsafe {
            let backgrounds = self.classifier.backgrounds();
            let mut is_background = _mm512_cmpeq_epi32_mask(colors, _mm512_set1_epi32(backgrounds[0] as i32));
            if !SINGLE_BACKGROUND {
                for &color in &backgrounds[1..] {
                    is_background |= _mm512_cmpeq_epi32_mask(colors, _mm512_set1_epi32(color as i32));
                }
            }
            is_background &= lanes;
            let member = _mm512_cmplt_epu32_mask(colors, self.texel_limit);
            let is_texel = member & !is_background & lanes;
            let is_stray = !member & !is_background & lanes;
            if is_stray != 0 {
                // Rare: damaged or filtered pixels.
                let mut lane_colors = [0u32; 16];
                _mm512_storeu_si512(lane_colors.as_mut_ptr().cast(), colors);
                let mut remaining = is_stray;
                while remaining != 0 {
                    self.strays.insert(lane_colors[remaining.trailing_zeros() as usize]);
                    remaining &= remaining - 1;
                }
            }
            // A pixel with its left neighbour's colour adds nothing new.
            let left = _mm512_alignr_epi32::<15>(colors, self.previous);
            let fresh = _mm512_mask_cmpneq_epi32_mask(is_texel, colors, left);
            if fresh != 0 {
                let mut keys = [0u32; 16];
                let fresh_keys = _mm512_maskz_compress_epi32(fresh, color_keys(colors));
                _mm512_storeu_si512(keys.as_mut_ptr().cast(), fresh_keys);
                for &key in &keys[..fresh.count_ones() as usize] {
                    self.word.add(self.seen, (key >> 6) as usize, 1u64 << (key & 63));
                }
            }
            self.background += u64::from(is_background.count_ones());
            self.stray += u64::from(is_stray.count_ones());
            // Lane 15 (only a row's last, partial block has fewer lanes, and
            // nothing follows it): background 0, texel 1, stray 2.
            let (last_background, last_stray) =
                (usize::from(is_background >> 15), usize::from(is_stray >> 15));
            self.last_class = (1 - last_background) * (1 + last_stray);
            self.previous = colors;
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
    // SAFETY: a 64-byte array.
    let index = unsafe { _mm512_loadu_si512(unpack_table::<BYTES, 64>(16).as_ptr().cast()) };
    // The bytes of `count` pixels (16 of RGB: 48, of RGBA: 64) from pixel
    // `start`, zero beyond; masked-out bytes are neither read nor faulted on.
    let load = |start: usize, count: usize| {
        let bytes = count * BYTES;
        let mask = if bytes >= 64 { !0 } else { (1u64 << bytes) - 1 };
        // SAFETY: callers keep `start + count` pixels inside `row`.
        unsafe { _mm512_maskz_loadu_epi8(mask, row.as_ptr().add(start * BYTES).cast()) }
    };
    let unpack = |raw: __m512i| _mm512_maskz_permutexvar_epi8(0x7777_7777_7777_7777, index, raw);
    let mut scanner = RowScanner::<SINGLE_BACKGROUND> {
        classifier,
        texel_limit: _mm512_set1_epi32(classifier.palette().texel_count() as i32),
        seen,
        strays,
        word: WordAccumulator::new(),
        previous: _mm512_set1_epi32(-1),
        last_class: PixelClass::Background as usize,
        background: 0,
        stray: 0,
    };
    let full_blocks = pixels / 16;
    for block in 0..full_blocks {
        let raw = load(block * 16, 16);
        // A block whose bytes equal the bytes one pixel earlier repeats the
        // last pixel scanned (a run of background or of one magnified texel).
        // As in the portable kernel, equal bytes imply equal colours; RGBA
        // pixels that differ only in alpha take the exact path.
        if block > 0 && _mm512_cmpneq_epi8_mask(raw, load(block * 16 - 1, 16)) == 0 {
            scanner.repeat(16);
            continue;
        }
        // SAFETY: this function has the features `block` needs.
        unsafe { scanner.block(unpack(raw), !0) };
    }
    let rest = pixels - full_blocks * 16;
    if rest > 0 {
        let lanes = ((1u32 << rest) - 1) as __mmask16;
        // SAFETY: as above.
        unsafe { scanner.block(unpack(load(full_blocks * 16, rest)), lanes) };
    }
    scanner.word.flush(scanner.seen);
    super::add_row_classes(by_class, pixels, scanner.background, scanner.stray);
}
