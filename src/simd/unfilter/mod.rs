//! The side-by-side forms of the tile decoder's unfilter
//! (`png::unfilter`, which holds the method and the row-by-row
//! reference they are held to): eight rows at once with AVX-512
//! ([`avx512`]), four with AVX2 ([`avx2`]), for RGB and RGBA rows.
//!
//! [`SideBySide::unfilter`] is their safe door: it runs a form only where
//! [`Kernel::supported`] found every feature it is compiled for, and each
//! form asserts the sizes its pointers rely on ([`checked_width`]) before
//! it reads or writes a byte.

use crate::simd::Kernel;

#[cfg(target_arch = "x86_64")]
mod avx2;
#[cfg(target_arch = "x86_64")]
mod avx512;

/// `N` consecutive rows to unfilter side by side, as the decoder holds them
/// (`png::unfilter::RowGroup`): `filtered` holds the rows as inflated, each
/// a filter byte followed by its `row_bytes` bytes, and at least 4 bytes
/// after the last; `out` holds `N + 1` rows `pitch` (≥ `row_bytes + 4`)
/// bytes apart, row 0 the unfiltered row above the first.
pub(crate) struct SideBySide<'a, const N: usize> {
    /// For the filters Sub, Up, Average and Paeth, in this order: which of
    /// the rows have it (a row with none of them has None).
    pub filters: [[bool; N]; 4],
    /// Bytes per pixel: 3 or 4.
    pub bpp: usize,
    pub row_bytes: usize,
    pub filtered: &'a [u8],
    pub out: &'a mut [u8],
    pub pitch: usize,
}

/// A side-by-side form for RGB or RGBA: the rows' filters, `row_bytes`, the
/// filtered rows, `out` and `pitch`, as [`SideBySide`] holds them.
#[cfg(target_arch = "x86_64")]
type Form<const N: usize> = unsafe fn(&[[bool; N]; 4], usize, &[u8], &mut [u8], usize);

impl SideBySide<'_, 8> {
    /// Unfilters the rows with the AVX-512 form and returns true, or
    /// returns false and leaves them (this CPU lacks a feature of it, or the
    /// pixels are neither RGB nor RGBA).
    ///
    /// # Panics
    /// When the slices are smaller than [`SideBySide`] says, or the rows
    /// are narrower than 15 pixels.
    pub(crate) fn unfilter(self) -> bool {
        #[cfg(target_arch = "x86_64")]
        {
            if Kernel::supported() >= Kernel::Avx512 && matches!(self.bpp, 3 | 4) {
                let form: Form<8> =
                    if self.bpp == 3 { avx512::unfilter_rows::<3> } else { avx512::unfilter_rows::<4> };
                // SAFETY: the CPU has every feature of the AVX-512 kernel
                // (checked just above); the form asserts the slices' sizes.
                unsafe { form(&self.filters, self.row_bytes, self.filtered, self.out, self.pitch) };
                return true;
            }
        }
        #[cfg(not(target_arch = "x86_64"))]
        let _ = self;
        false
    }
}

impl SideBySide<'_, 4> {
    /// [`SideBySide::<8>::unfilter`] with the AVX2 form (rows of at least 7
    /// pixels).
    pub(crate) fn unfilter(self) -> bool {
        #[cfg(target_arch = "x86_64")]
        {
            if Kernel::supported() >= Kernel::Avx2 && matches!(self.bpp, 3 | 4) {
                let form: Form<4> =
                    if self.bpp == 3 { avx2::unfilter_rows::<3> } else { avx2::unfilter_rows::<4> };
                // SAFETY: the CPU has every feature of the AVX2 kernel (checked
                // just above); the form asserts the slices' sizes.
                unsafe { form(&self.filters, self.row_bytes, self.filtered, self.out, self.pitch) };
                return true;
            }
        }
        #[cfg(not(target_arch = "x86_64"))]
        let _ = self;
        false
    }
}

/// The rows of a side-by-side form in progress ([`avx2`], [`avx512`]): row
/// `k` is `2k` pixels behind row 0, so at step `t` each row `k` takes its
/// pixel `t − 2k`.
#[cfg(target_arch = "x86_64")]
trait Steps {
    /// Rows side by side.
    const ROWS: usize;

    /// Step `t`: pixel t − 2k of each row k. With `EVERY` every row has
    /// that pixel; without, rows before their first or past their last
    /// pixel read and write nothing and hold zeros.
    ///
    /// # Safety
    /// The CPU features of the form, and slices [`checked_width`] checked.
    unsafe fn step<const BPP: usize, const EVERY: bool>(&mut self, t: usize);
}

/// Asserts what a side-by-side form of `S::ROWS` rows of `BPP`-byte pixels
/// needs: `filtered` holds the rows as inflated (a filter byte, then
/// `row_bytes`) and at least 4 bytes after the last; `out_len` covers
/// `S::ROWS + 1` rows `pitch ≥ row_bytes + 4` bytes apart; each row is
/// longer than the last row's lag. Returns the width in pixels.
#[cfg(target_arch = "x86_64")]
fn checked_width<S: Steps, const BPP: usize>(
    row_bytes: usize,
    filtered: usize,
    out: usize,
    pitch: usize,
) -> usize {
    let (rows, width) = (S::ROWS, row_bytes / BPP);
    assert!(filtered >= rows * (row_bytes + 1) + 4 && out >= (rows + 1) * pitch && pitch >= row_bytes + 4);
    assert!(width > 2 * (rows - 1));
    width
}

/// Runs every step of `rows`, `width` pixels wide (from
/// [`checked_width`]): the last row's lag with some rows outside their
/// pixels, then every row inside, then the lag again.
///
/// # Safety
/// The CPU features of the form; `width` from [`checked_width`] on the
/// slices `rows` points into.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
unsafe fn run_steps<S: Steps, const BPP: usize>(rows: &mut S, width: usize) {
    let lag = 2 * (S::ROWS - 1);
    for t in 0..lag {
        // SAFETY: the caller's CPU features; `step` touches pixel t − 2k of
        // row k only where that is inside the row, 4 bytes at a time, which
        // the sizes `checked_width` asserted allow.
        unsafe { rows.step::<BPP, false>(t) };
    }
    for t in lag..width {
        // SAFETY: as above; in these steps every row is inside.
        unsafe { rows.step::<BPP, true>(t) };
    }
    for t in width..width + lag {
        // SAFETY: as the first loop.
        unsafe { rows.step::<BPP, false>(t) };
    }
}
