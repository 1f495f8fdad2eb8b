//! The AVX-512 form of [`super::unfilter_rows`] (x86-64 only, chosen at
//! run time): [`super::avx2`]'s scheme with eight rows side by side instead
//! of four, one 64-bit lane of a 512-bit register each, row `k` two pixels
//! behind row `k − 1`.
//!
//! Why a second form: the AVX2 loop is bound by its instruction count, not
//! by the pixel-to-pixel chain it hides, so twice the rows per instruction
//! is the gain. The eight rows' pixels are gathered and their results
//! narrowed back to bytes in one instruction each, the filters are kept
//! per lane with mask registers, and the addition wraps in 8-bit lanes (a
//! channel's high byte is zero on both sides), so no mask is needed to
//! keep the sums below 256.

use std::arch::x86_64::*;

use super::{Filter, Steps, checked_width, run_steps};

/// Rows unfiltered together.
pub(super) const ROWS: usize = 8;

/// The lanes of the rows whose filter is `filter`.
fn lanes_of(filters: &[Filter; ROWS], filter: Filter) -> __mmask8 {
    filters.iter().enumerate().filter(|(_, f)| **f == filter).fold(0, |mask, (k, _)| mask | 1 << k)
}

/// This form for [`super::unfilter_rows`]: RGB, RGBA.
pub(super) const FORM: super::SideBySideForm<ROWS> = [unfilter_rows::<3>, unfilter_rows::<4>];

/// Unfilters [`ROWS`] rows of `BPP`-byte pixels (3 or 4), as
/// [`super::avx2::unfilter_rows`] does four; the slices as
/// [`super::checked_width`] asserts them.
///
/// # Safety
/// The CPU must have AVX-512 F and BW. (The slice sizes are asserted.)
#[target_feature(enable = "avx512f,avx512bw")]
unsafe fn unfilter_rows<const BPP: usize>(
    filters: &[Filter; ROWS],
    row_bytes: usize,
    filtered: &[u8],
    out: &mut [u8],
    pitch: usize,
) {
    let width = checked_width::<Rows, BPP>(row_bytes, filtered.len(), out.len(), pitch);
    let stride = row_bytes + 1;
    // Pixel t − 2k of row k is `filtered[from[k] + BPP·t]` and
    // `out[to[k] + BPP·t]`; the offsets are signed, as they are formed
    // before t is large enough to bring them inside the slices.
    let from: [i64; ROWS] = std::array::from_fn(|k| (k * stride + 1) as i64 - (2 * k * BPP) as i64);
    let to: [i64; ROWS] = std::array::from_fn(|k| ((k + 1) * pitch) as i64 - (2 * k * BPP) as i64);
    let mut rows = Rows {
        masks: [Filter::Sub, Filter::Up, Filter::Average, Filter::Paeth].map(|f| lanes_of(filters, f)),
        from: _mm512_set_epi64(from[7], from[6], from[5], from[4], from[3], from[2], from[1], from[0]),
        to,
        filtered: filtered.as_ptr(),
        out: out.as_mut_ptr(),
        width,
        left: _mm512_setzero_si512(),
        two_back: _mm512_setzero_si512(),
        above_before: _mm512_setzero_si512(),
    };
    // SAFETY: this function has AVX-512 F and BW; `width` is `checked_width`'s.
    unsafe { run_steps::<Rows, BPP>(&mut rows, width) };
}

/// The eight rows in progress.
struct Rows {
    /// Sub, Up, Average, Paeth lanes.
    masks: [__mmask8; 4],
    /// Each row's pixel 0 − 2k in `filtered`, as byte offsets.
    from: __m512i,
    /// Each row's pixel 0 − 2k in `out`, as byte offsets.
    to: [i64; ROWS],
    filtered: *const u8,
    out: *mut u8,
    width: usize,
    /// The outputs one and two steps back, and the last step's "above".
    left: __m512i,
    two_back: __m512i,
    above_before: __m512i,
}

impl Rows {
    /// The lanes whose row has pixel t − 2k at step `t`.
    #[inline(always)]
    fn inside(&self, t: usize) -> __mmask8 {
        (0..ROWS).filter(|&k| t >= 2 * k && t - 2 * k < self.width).fold(0, |mask, k| mask | 1 << k)
    }
}

impl Steps for Rows {
    const ROWS: usize = ROWS;

    /// [`Steps::step`] for AVX-512 F and BW, on the slices of
    /// [`unfilter_rows`].
    #[inline(always)]
    unsafe fn step<const BPP: usize, const EVERY: bool>(&mut self, t: usize) {
        unsafe {
            let inside = if EVERY { 0xFF } else { self.inside(t) };
            let at = _mm512_add_epi64(self.from, _mm512_set1_epi64((BPP * t) as i64));
            let gathered =
                _mm512_mask_i64gather_epi32::<1>(_mm256_setzero_si256(), inside, at, self.filtered.cast());
            let x = _mm512_cvtepu8_epi16(gathered);
            // Row 0's "above" is the row before the group, the others' the
            // lane below's output two steps back.
            let first_above = if EVERY || t < self.width {
                self.out.add(BPP * t).cast::<u32>().read_unaligned()
            } else {
                0
            };
            let from_below =
                _mm512_permutexvar_epi64(_mm512_set_epi64(6, 5, 4, 3, 2, 1, 0, 0), self.two_back);
            let row_above = _mm512_castsi128_si512(_mm_cvtepu8_epi16(_mm_cvtsi32_si128(first_above as i32)));
            let above = _mm512_mask_mov_epi64(from_below, 1, row_above);
            let mut result = predict_and_add(x, [self.left, above, self.above_before], self.masks);
            if !EVERY {
                result = _mm512_maskz_mov_epi64(inside, result);
            }
            let mut values = [0u32; ROWS];
            _mm256_storeu_si256(values.as_mut_ptr().cast(), _mm512_cvtepi16_epi8(result));
            for (k, value) in values.into_iter().enumerate() {
                if inside & (1 << k) != 0 {
                    // The spare fourth byte lands where the next step or
                    // the row's padding overwrites it.
                    let at = (self.to[k] + (BPP * t) as i64) as usize;
                    self.out.add(at).cast::<u32>().write_unaligned(value);
                }
            }
            self.two_back = self.left;
            self.left = result;
            self.above_before = above;
        }
    }
}

/// `(x + predictor) mod 256` per channel from the left, above and
/// above-left pixels, each lane with its row's filter (`masks`: Sub, Up,
/// Average, Paeth; None is what no mask keeps, 0).
#[target_feature(enable = "avx512f,avx512bw")]
#[inline]
fn predict_and_add(x: __m512i, [a, b, c]: [__m512i; 3], [sub, up, average, paeth]: [__mmask8; 4]) -> __m512i {
    let sum = _mm512_add_epi16(a, b);
    let mean = _mm512_srli_epi16::<1>(sum);
    // Paeth as `super::paeth` computes it (stb_image's form).
    let threshold = _mm512_sub_epi16(_mm512_add_epi16(c, _mm512_add_epi16(c, c)), sum);
    let (low, high) = (_mm512_min_epi16(a, b), _mm512_max_epi16(a, b));
    let t0 = _mm512_mask_blend_epi16(_mm512_cmpgt_epi16_mask(high, threshold), low, c);
    let nearest = _mm512_mask_blend_epi16(_mm512_cmpgt_epi16_mask(threshold, low), high, t0);
    let predicted = _mm512_maskz_mov_epi64(sub, a);
    let predicted = _mm512_mask_mov_epi64(predicted, up, b);
    let predicted = _mm512_mask_mov_epi64(predicted, average, mean);
    let predicted = _mm512_mask_mov_epi64(predicted, paeth, nearest);
    // Every channel's high byte is zero in both: 8-bit lanes wrap exactly.
    _mm512_add_epi8(x, predicted)
}
