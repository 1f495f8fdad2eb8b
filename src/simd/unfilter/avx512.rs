//! The AVX-512 form of the tile decoder's unfilter ([`super::SideBySide`]) (x86-64 only, chosen at
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

use super::{Steps, checked_width, run_steps};

/// Rows unfiltered together.
pub(super) const ROWS: usize = 8;

/// The lanes of the rows `rows` marks.
fn lanes_of(rows: &[bool; ROWS]) -> __mmask8 {
    rows.iter().enumerate().filter(|(_, row)| **row).fold(0, |mask, (k, _)| mask | 1 << k)
}

/// Unfilters [`ROWS`] rows of `BPP`-byte pixels (3 or 4), as
/// [`super::avx2::unfilter_rows`] does four; the slices as
/// [`super::checked_width`] asserts them.
///
#[target_feature(enable = "avx512f,avx512bw")]
pub(super) fn unfilter_rows<const BPP: usize>(
    filters: &[[bool; ROWS]; 4],
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
        masks: filters.map(|rows| lanes_of(&rows)),
        from: _mm512_set_epi64(from[7], from[6], from[5], from[4], from[3], from[2], from[1], from[0]),
        to,
        filtered: filtered.as_ptr(),
        out: out.as_mut_ptr(),
        width,
        left: _mm512_setzero_si512(),
        two_back: _mm512_setzero_si512(),
        above_before: _mm512_setzero_si512(),
    };
    // SAFETY: this function has AVX-512 F and BW; `width` is
    // `checked_width`'s.
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
        let inside = if EVERY { 0xFF } else { self.inside(t) };
        // SAFETY: the caller's CPU features and slices are `read`'s.
        let x = unsafe { self.read::<BPP>(t, inside) };
        // SAFETY: as above.
        let above = unsafe { self.above::<BPP, EVERY>(t) };
        // SAFETY: the caller guarantees the CPU features.
        let mut result = unsafe { predict_and_add(x, [self.left, above, self.above_before], self.masks) };
        if !EVERY {
            // SAFETY: CPU features as above.
            result = unsafe { _mm512_maskz_mov_epi64(inside, result) };
        }
        // SAFETY: the caller's CPU features and slices are `write`'s.
        unsafe { self.write::<BPP>(t, result, inside) };
        self.two_back = self.left;
        self.left = result;
        self.above_before = above;
    }
}

impl Rows {
    /// Pixel t − 2k of each row k of `inside` (zero elsewhere), its 3 or 4
    /// channels (and a spare one) as 16-bit numbers.
    ///
    /// # Safety
    /// AVX-512 F and BW, and the rows of `inside` have that pixel (as
    /// `Steps::step`).
    #[inline(always)]
    unsafe fn read<const BPP: usize>(&self, t: usize, inside: __mmask8) -> __m512i {
        // SAFETY: the caller guarantees the CPU features (as for every
        // intrinsic of this function).
        let step = unsafe { _mm512_set1_epi64((BPP * t) as i64) };
        // SAFETY: CPU features as above.
        let at = unsafe { _mm512_add_epi64(self.from, step) };
        // SAFETY: CPU features as above.
        let zero = unsafe { _mm256_setzero_si256() };
        // SAFETY: CPU features as above; each gathered lane (`inside`)
        // reads 4 bytes at a pixel inside `filtered`, which
        // `checked_width` asserted has 4 bytes after the last pixel.
        let gathered = unsafe { _mm512_mask_i64gather_epi32::<1>(zero, inside, at, self.filtered.cast()) };
        // SAFETY: CPU features as above.
        unsafe { _mm512_cvtepu8_epi16(gathered) }
    }

    /// The pixels above those of step `t`: row 0's from the row before the
    /// group, the others' the lane below's output two steps back.
    ///
    /// # Safety
    /// As [`Rows::read`].
    #[inline(always)]
    unsafe fn above<const BPP: usize, const EVERY: bool>(&self, t: usize) -> __m512i {
        let first_above = if EVERY || t < self.width {
            // SAFETY: pixel t of the row above the group is inside `out`,
            // with 4 bytes of the row's padding after it.
            unsafe { self.out.wrapping_add(BPP * t).cast::<u32>().read_unaligned() }
        } else {
            0
        };
        // SAFETY: the caller guarantees the CPU features (as for every
        // intrinsic of this function).
        let lane_below = unsafe { _mm512_set_epi64(6, 5, 4, 3, 2, 1, 0, 0) };
        // SAFETY: CPU features as above.
        let from_below = unsafe { _mm512_permutexvar_epi64(lane_below, self.two_back) };
        // SAFETY: CPU features as above.
        let row_above = unsafe { _mm_cvtsi32_si128(first_above as i32) };
        // SAFETY: CPU features as above.
        let row_above = unsafe { _mm_cvtepu8_epi16(row_above) };
        // SAFETY: CPU features as above.
        let row_above = unsafe { _mm512_castsi128_si512(row_above) };
        // SAFETY: CPU features as above.
        unsafe { _mm512_mask_mov_epi64(from_below, 1, row_above) }
    }

    /// Writes each row's pixel of step `t` from `result` (its channels' low
    /// bytes) for the rows of `inside`.
    ///
    /// # Safety
    /// As [`Rows::read`].
    #[inline(always)]
    unsafe fn write<const BPP: usize>(&self, t: usize, result: __m512i, inside: __mmask8) {
        let mut values = [0u32; ROWS];
        // SAFETY: the caller guarantees the CPU features (as for every
        // intrinsic of this function).
        let narrow = unsafe { _mm512_cvtepi16_epi8(result) };
        // SAFETY: CPU features as above; the store writes the 32 bytes of
        // `values`.
        unsafe { _mm256_storeu_si256(values.as_mut_ptr().cast(), narrow) };
        for (k, value) in values.into_iter().enumerate() {
            if inside & (1 << k) != 0 {
                // The spare fourth byte lands where the next step or the
                // row's padding overwrites it.
                let at = (self.to[k] + (BPP * t) as i64) as usize;
                // SAFETY: pixel t − 2k of row k is inside `out`, with 4
                // bytes of padding after the row (`checked_width`).
                unsafe { self.out.wrapping_add(at).cast::<u32>().write_unaligned(value) };
            }
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
