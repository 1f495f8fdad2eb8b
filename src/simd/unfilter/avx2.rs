//! The AVX2 form of the tile decoder's unfilter ([`super::SideBySide`]) (x86-64 only, chosen at run
//! time): four rows side by side, one 64-bit lane of a register each (a
//! pixel's 3 or 4 channels as 16-bit numbers), row `k` two pixels behind
//! row `k − 1`. A row's left neighbour is its own lane one step earlier;
//! the pixel above comes from the lane below two steps earlier, so the
//! cross-lane shuffle that fetches it is off the step-to-step chain, which
//! is then only the left neighbour's (≈ 8 dependent instructions per four
//! pixels, where one row alone costs ≈ 5 per pixel).
//!
//! Every row computes all five predictors and keeps its own filter's with
//! a per-lane mask, so any mix of filters shares the loop. With 3-byte
//! pixels each lane carries a fourth, meaningless channel (the next
//! pixel's first byte): channels never mix, and its byte is stored where
//! the next step (or the row's padding) overwrites it.

use std::arch::x86_64::*;

use super::{Steps, checked_width, run_steps};

/// Rows unfiltered together.
pub(super) const ROWS: usize = 4;

/// All ones in the lanes of the rows `rows` marks.
#[target_feature(enable = "avx2")]
fn lanes_of(rows: &[bool; ROWS]) -> __m256i {
    let lane = |k: usize| if rows[k] { -1i64 } else { 0 };
    _mm256_set_epi64x(lane(3), lane(2), lane(1), lane(0))
}

/// Unfilters [`ROWS`] rows of `BPP`-byte pixels (3 or 4) whose filters
/// are Sub, Up, Average and Paeth where `filters` says (else None):
/// `filtered` as inflated, `out` with the row above the group first; the
/// slices as [`super::checked_width`] asserts them.
#[target_feature(enable = "avx2")]
pub(super) fn unfilter_rows<const BPP: usize>(
    filters: &[[bool; ROWS]; 4],
    row_bytes: usize,
    filtered: &[u8],
    out: &mut [u8],
    pitch: usize,
) {
    let width = checked_width::<Rows, BPP>(row_bytes, filtered.len(), out.len(), pitch);
    let stride = row_bytes + 1;
    let mut rows = Rows {
        masks: filters.map(|rows| lanes_of(&rows)),
        // Pixel t − 2k of row k is at `inputs[k] + BPP·t` (and likewise in
        // `outputs`); wrapping, as the sum is formed before t is large
        // enough to bring it inside the slice.
        inputs: std::array::from_fn(|k| {
            filtered.as_ptr().wrapping_add(k * stride + 1).wrapping_sub(2 * k * BPP)
        }),
        outputs: std::array::from_fn(|k| {
            out.as_mut_ptr().wrapping_add((k + 1) * pitch).wrapping_sub(2 * k * BPP)
        }),
        above: out.as_ptr(),
        width,
        left: _mm256_setzero_si256(),
        two_back: _mm256_setzero_si256(),
        above_before: _mm256_setzero_si256(),
    };
    // SAFETY: this function has AVX2; `width` is `checked_width`'s.
    unsafe { run_steps::<Rows, BPP>(&mut rows, width) };
}

/// The four rows in progress.
struct Rows {
    /// Sub, Up, Average, Paeth lanes.
    masks: [__m256i; 4],
    inputs: [*const u8; ROWS],
    outputs: [*mut u8; ROWS],
    /// Row 0 of `out`: the row above the group.
    above: *const u8,
    width: usize,
    /// The outputs one and two steps back, and the last step's "above".
    left: __m256i,
    two_back: __m256i,
    above_before: __m256i,
}

impl Rows {
    /// Pixel t − 2k of each row k (zero where `inside` says the row has
    /// none), its 3 or 4 channels (and a spare one) as 16-bit numbers.
    ///
    /// # Safety
    /// AVX2, and the rows of `inside` have that pixel (as `Steps::step`).
    #[inline(always)]
    unsafe fn read<const BPP: usize>(&self, t: usize, inside: impl Fn(usize) -> bool) -> __m256i {
        let read = |k: usize| {
            if inside(k) {
                // SAFETY: pixel t − 2k of row k is inside `filtered`, which
                // `checked_width` asserted has 4 bytes after the last pixel.
                unsafe { self.inputs[k].wrapping_add(BPP * t).cast::<u32>().read_unaligned() }
            } else {
                0
            }
        };
        let pixels = [read(0), read(1), read(2), read(3)].map(|pixel| pixel as i32);
        // SAFETY: the caller guarantees the CPU features (as for every
        // intrinsic of this function).
        let pixels = unsafe { _mm_set_epi32(pixels[3], pixels[2], pixels[1], pixels[0]) };
        // SAFETY: CPU features as above.
        unsafe { _mm256_cvtepu8_epi16(pixels) }
    }

    /// The pixels above those of step `t`: row 0's from the row before the
    /// group, the others' the lane below's output two steps back.
    ///
    /// # Safety
    /// As [`Rows::read`].
    #[inline(always)]
    unsafe fn above<const BPP: usize, const EVERY: bool>(&self, t: usize) -> __m256i {
        let first_above = if EVERY || t < self.width {
            // SAFETY: pixel t of the row above the group is inside `out`,
            // with 4 bytes of the row's padding after it.
            unsafe { self.above.wrapping_add(BPP * t).cast::<u32>().read_unaligned() }
        } else {
            0
        };
        // SAFETY: the caller guarantees the CPU features (as for every
        // intrinsic of this function).
        let from_below = unsafe { _mm256_permute4x64_epi64::<0b10_01_00_00>(self.two_back) };
        // SAFETY: CPU features as above.
        let first_above = unsafe { _mm_cvtsi32_si128(first_above as i32) };
        // SAFETY: CPU features as above.
        let first_above = unsafe { _mm256_cvtepu8_epi16(first_above) };
        // SAFETY: CPU features as above.
        unsafe { _mm256_blend_epi32::<0b0000_0011>(from_below, first_above) }
    }

    /// Writes each row's pixel of step `t` from `result` (its channels' low
    /// bytes) where `inside` says the row has one.
    ///
    /// # Safety
    /// As [`Rows::read`].
    #[inline(always)]
    unsafe fn write<const BPP: usize>(&self, t: usize, result: __m256i, inside: impl Fn(usize) -> bool) {
        // The low byte of each channel (a byte shuffle: a pack would let the
        // compiler move the addition after it, onto the chain).
        // SAFETY: the caller guarantees the CPU features (as for every
        // intrinsic of this function).
        let low_bytes = unsafe {
            _mm256_setr_epi8(
                0, 2, 4, 6, 8, 10, 12, 14, -1, -1, -1, -1, -1, -1, -1, -1, 0, 2, 4, 6, 8, 10, 12, 14, -1, -1,
                -1, -1, -1, -1, -1, -1,
            )
        };
        // SAFETY: CPU features as above.
        let packed = unsafe { _mm256_shuffle_epi8(result, low_bytes) };
        // SAFETY: CPU features as above.
        let lower = unsafe { _mm256_castsi256_si128(packed) };
        // SAFETY: CPU features as above.
        let upper = unsafe { _mm256_extracti128_si256::<1>(packed) };
        let values = [
            // SAFETY: CPU features as above.
            unsafe { _mm_cvtsi128_si32(lower) },
            // SAFETY: CPU features as above.
            unsafe { _mm_extract_epi32::<1>(lower) },
            // SAFETY: CPU features as above.
            unsafe { _mm_cvtsi128_si32(upper) },
            // SAFETY: CPU features as above.
            unsafe { _mm_extract_epi32::<1>(upper) },
        ];
        for (k, value) in values.into_iter().enumerate() {
            if inside(k) {
                // The spare fourth byte lands where the next step or the
                // row's padding overwrites it.
                // SAFETY: pixel t − 2k of row k is inside `out`, with 4
                // bytes of padding after the row (`checked_width`).
                unsafe { self.outputs[k].wrapping_add(BPP * t).cast::<u32>().write_unaligned(value as u32) };
            }
        }
    }
}

impl Steps for Rows {
    const ROWS: usize = ROWS;

    /// [`Steps::step`] for AVX2, on the pointers of [`unfilter_rows`].
    #[inline(always)]
    unsafe fn step<const BPP: usize, const EVERY: bool>(&mut self, t: usize) {
        let inside = |k: usize| EVERY || (t >= 2 * k && t - 2 * k < self.width);
        // SAFETY: the caller's CPU features and slices are `read`'s.
        let x = unsafe { self.read::<BPP>(t, inside) };
        // SAFETY: as above.
        let above = unsafe { self.above::<BPP, EVERY>(t) };
        // SAFETY: the caller guarantees the CPU features.
        let mut result = unsafe { predict_and_add(x, [self.left, above, self.above_before], self.masks) };
        if !EVERY {
            let lane = |k: usize| if inside(k) { -1i64 } else { 0 };
            // SAFETY: CPU features as above.
            let lanes = unsafe { _mm256_set_epi64x(lane(3), lane(2), lane(1), lane(0)) };
            // SAFETY: CPU features as above.
            result = unsafe { _mm256_and_si256(result, lanes) };
        }
        // SAFETY: the caller's CPU features and slices are `write`'s.
        unsafe { self.write::<BPP>(t, result, inside) };
        self.two_back = self.left;
        self.left = result;
        self.above_before = above;
    }
}

/// `(x + predictor) mod 256` per channel from the left, above and
/// above-left pixels, each lane with its row's filter (`masks`: Sub, Up,
/// Average, Paeth; None is what no mask keeps, 0).
#[target_feature(enable = "avx2")]
#[inline]
fn predict_and_add(x: __m256i, [a, b, c]: [__m256i; 3], [sub, up, average, paeth]: [__m256i; 4]) -> __m256i {
    let sum = _mm256_add_epi16(a, b);
    let mean = _mm256_srli_epi16::<1>(sum);
    // Paeth as `super::paeth` computes it (stb_image's form).
    let threshold = _mm256_sub_epi16(_mm256_add_epi16(c, _mm256_add_epi16(c, c)), sum);
    let (low, high) = (_mm256_min_epi16(a, b), _mm256_max_epi16(a, b));
    let t0 = _mm256_blendv_epi8(low, c, _mm256_cmpgt_epi16(high, threshold));
    let nearest = _mm256_blendv_epi8(high, t0, _mm256_cmpgt_epi16(threshold, low));
    let predicted = _mm256_or_si256(
        _mm256_or_si256(_mm256_and_si256(a, sub), _mm256_and_si256(b, up)),
        _mm256_or_si256(_mm256_and_si256(mean, average), _mm256_and_si256(nearest, paeth)),
    );
    // Every channel's high byte is zero in both: 8-bit lanes wrap exactly.
    _mm256_add_epi8(x, predicted)
}
