//! Undoing PNG row filters (PNG spec §9) for 8-bit samples, for the tile
//! decoder ([`crate::png::decode`]).
//!
//! Renderers (Unity, Blender, libpng's adaptive filtering) write most rows
//! of a tile with the Paeth filter, whose unfiltering is a chain from pixel
//! to pixel: each output byte needs the one to its left. Decoding one row
//! at a time is therefore bound by that chain's latency (≈ 4 cycles per
//! pixel in the png crate). [`unfilter_rows`] takes several consecutive
//! rows at once and runs their chains side by side, each row two pixels
//! behind the row above it (the pixel above and the pixel above-left are
//! then already done): the chains overlap in the CPU, and the rows come out
//! byte-identical to one-row-at-a-time unfiltering ([`unfilter_row`], the
//! reference the tests hold it to).

use crate::simd::{Kernel, SideBySide};

/// Rows [`unfilter_rows`] takes at once (the decoder hands it this many):
/// eight side by side with AVX-512, two fours with AVX2.
pub(crate) const GROUP: usize = 8;

/// The five PNG filter types.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Filter {
    None = 0,
    Sub = 1,
    Up = 2,
    Average = 3,
    Paeth = 4,
}

impl Filter {
    /// The filter of a row's first byte, if it names one.
    pub(crate) fn from_byte(byte: u8) -> Option<Filter> {
        [Filter::None, Filter::Sub, Filter::Up, Filter::Average, Filter::Paeth]
            .get(usize::from(byte))
            .copied()
    }

    /// Whether each pixel needs the one to its left (Up and None do not).
    fn chained(self) -> bool {
        matches!(self, Filter::Sub | Filter::Average | Filter::Paeth)
    }
}

/// The Paeth predictor (PNG spec §9.4) in the branch-free form of
/// stb_image, which equals the spec's for every `a`, `b`, `c`: it picks
/// `a` (left), `b` (above) or `c` (above-left), whichever is nearest to
/// `a + b − c`, ties in that order.
#[inline(always)]
fn paeth(a: i16, b: i16, c: i16) -> u8 {
    let threshold = c * 3 - (a + b);
    let low = a.min(b);
    let high = a.max(b);
    let t0 = if high <= threshold { low } else { c };
    let t1 = if threshold <= low { high } else { t0 };
    t1 as u8
}

/// Consecutive rows to unfilter, as the decoder holds them.
///
/// `filtered` holds the rows as inflated, each a filter byte followed by
/// its `row_bytes` bytes (`filters` are those bytes, checked). `out` holds
/// `filters.len() + 1` rows `pitch` (≥ `row_bytes`) bytes apart: row 0 is
/// the unfiltered row above the first (zeros above the image), the others
/// receive the rows.
pub(crate) struct RowGroup<'a> {
    pub filters: &'a [Filter],
    /// Bytes per pixel, 1 to 4.
    pub bpp: usize,
    pub row_bytes: usize,
    pub filtered: &'a [u8],
    pub out: &'a mut [u8],
    pub pitch: usize,
}

impl RowGroup<'_> {
    /// The group's rows `first..first + count` (their `out` starts at the
    /// row above them).
    fn part(&mut self, first: usize, count: usize) -> RowGroup<'_> {
        RowGroup {
            filters: &self.filters[first..first + count],
            bpp: self.bpp,
            row_bytes: self.row_bytes,
            filtered: &self.filtered[first * (self.row_bytes + 1)..],
            out: &mut self.out[first * self.pitch..],
            pitch: self.pitch,
        }
    }

    /// These rows (`N` of them) as a side-by-side form takes them.
    ///
    /// # Panics
    /// Unless there are `N` rows.
    fn side_by_side_form<const N: usize>(&mut self) -> SideBySide<'_, N> {
        let filters: &[Filter; N] = self.filters.try_into().expect("a whole group");
        let chained = [Filter::Sub, Filter::Up, Filter::Average, Filter::Paeth];
        SideBySide {
            filters: chained.map(|filter| filters.map(|row| row == filter)),
            bpp: self.bpp,
            row_bytes: self.row_bytes,
            filtered: self.filtered,
            out: &mut *self.out,
            pitch: self.pitch,
        }
    }

    /// Whether `rows` of these rows can go side by side: RGB or RGBA, at
    /// least 16 pixels wide, 4 spare bytes after the filtered rows and in
    /// `pitch`, and `chained` of them with a chained filter (Up and None
    /// alone are faster row by row).
    fn side_by_side(&self, rows: usize, chained: usize) -> bool {
        self.filters.len() == rows
            && matches!(self.bpp, 3 | 4)
            && self.row_bytes >= 16 * self.bpp
            && self.filters.iter().filter(|f| f.chained()).count() >= chained
            && self.filtered.len() >= rows * (self.row_bytes + 1) + 4
            && self.pitch >= self.row_bytes + 4
    }
}

/// Unfilters the rows of `group` (at most [`GROUP`]). A whole group of RGB
/// or RGBA rows with chained filters among them goes side by side (see the
/// module doc): eight at once with the AVX-512 kernels, four at once with
/// the AVX2 ones ([`Kernel::selected`], the process's one choice of vector
/// code; [`SideBySide`] in [`crate::simd`]); otherwise, and for the answers
/// the tests hold those paths to, one row at a time.
pub(crate) fn unfilter_rows(mut group: RowGroup) {
    let kernel = Kernel::selected();
    if kernel == Kernel::Avx512
        && group.side_by_side(GROUP, GROUP / 2)
        && group.side_by_side_form::<GROUP>().unfilter()
    {
        return;
    }
    if kernel >= Kernel::Avx2 {
        for first in (0..group.filters.len()).step_by(FOUR) {
            let count = FOUR.min(group.filters.len() - first);
            let mut four = group.part(first, count);
            if !(four.side_by_side(FOUR, 2) && four.side_by_side_form::<FOUR>().unfilter()) {
                row_by_row(four);
            }
        }
        return;
    }
    row_by_row(group);
}

/// Rows the AVX2 form takes at once.
const FOUR: usize = 4;

/// [`unfilter_rows`] one row at a time.
fn row_by_row(group: RowGroup) {
    let RowGroup { filters, bpp, row_bytes, filtered, out, pitch } = group;
    for (k, &filter) in filters.iter().enumerate() {
        let (above, below) = out.split_at_mut((k + 1) * pitch);
        let from = k * (row_bytes + 1) + 1;
        let previous = &above[k * pitch..k * pitch + row_bytes];
        unfilter_row(filter, bpp, previous, &filtered[from..from + row_bytes], &mut below[..row_bytes]);
    }
}

/// Unfilters one row: `filtered` (without its filter byte) into `out`, with
/// `previous` the unfiltered row above (zeros for the first row). `bpp` is
/// bytes per pixel (1 to 4).
fn unfilter_row(filter: Filter, bpp: usize, previous: &[u8], filtered: &[u8], out: &mut [u8]) {
    debug_assert!(previous.len() == filtered.len() && out.len() == filtered.len());
    match bpp {
        1 => unfilter_pixels::<1>(filter, previous, filtered, out),
        2 => unfilter_pixels::<2>(filter, previous, filtered, out),
        3 => unfilter_pixels::<3>(filter, previous, filtered, out),
        _ => unfilter_pixels::<4>(filter, previous, filtered, out),
    }
}

/// The Up filter: `out = filtered + previous`, byte by byte. Not inlined:
/// inlined into the decoder, the compiler lost sight of the slices being
/// distinct and added one byte at a time; on its own it adds 32 at once.
#[inline(never)]
fn add_up(previous: &[u8], filtered: &[u8], out: &mut [u8]) {
    for ((o, &f), &p) in out.iter_mut().zip(filtered).zip(previous) {
        *o = f.wrapping_add(p);
    }
}

/// [`unfilter_row`] for `BPP`-byte pixels, in place in `out` (a copy of the
/// filtered bytes): a pixel's channels side by side, the png crate's
/// formulation, which compilers keep in registers; Up over whole rows.
#[inline(always)]
fn unfilter_pixels<const BPP: usize>(filter: Filter, previous: &[u8], filtered: &[u8], out: &mut [u8]) {
    match filter {
        Filter::None => return out.copy_from_slice(filtered),
        Filter::Up => return add_up(previous, filtered, out),
        _ => out.copy_from_slice(filtered),
    }
    let pixels = out.chunks_exact_mut(BPP).zip(previous.chunks_exact(BPP));
    match filter {
        Filter::None | Filter::Up => {}
        Filter::Sub => {
            let mut left = [0u8; BPP];
            for (o, _) in pixels {
                let new: [u8; BPP] = std::array::from_fn(|i| o[i].wrapping_add(left[i]));
                *TryInto::<&mut [u8; BPP]>::try_into(o).unwrap() = new;
                left = new;
            }
        }
        Filter::Average => {
            let mut left = [0u8; BPP];
            for (o, p) in pixels {
                let new: [u8; BPP] = std::array::from_fn(|i| {
                    o[i].wrapping_add(((u16::from(left[i]) + u16::from(p[i])) >> 1) as u8)
                });
                *TryInto::<&mut [u8; BPP]>::try_into(o).unwrap() = new;
                left = new;
            }
        }
        Filter::Paeth => {
            let (mut left, mut above_left) = ([0i16; BPP], [0i16; BPP]);
            for (o, p) in pixels {
                for i in 0..BPP {
                    o[i] = o[i].wrapping_add(paeth(left[i], i16::from(p[i]), above_left[i]));
                }
                left = std::array::from_fn(|i| i16::from(o[i]));
                above_left = std::array::from_fn(|i| i16::from(p[i]));
            }
        }
    }
}

/// The checks that hold the side-by-side forms ([`SideBySide`]) to
/// row-by-row unfiltering. `tests/kernels` runs them
/// (`testing::kernel_checks`), and reports one ignored where this
/// CPU lacks its form's kernel.
#[cfg(any(test, feature = "synthetic"))]
pub(crate) mod kernel_checks {
    use super::*;

    /// Holds the form of `rows` rows (`unfilter`) to [`row_by_row`] on RGB
    /// and RGBA rows of several widths, smooth (as renderers give) and
    /// noisy, for each filter mix `mixes` gives (one filter per row).
    fn check_side_by_side(rows: usize, unfilter: fn(RowGroup) -> bool, mixes: &[Vec<Filter>]) {
        let mut byte = xorshift_bytes(0x2545_F491_4F6C_DD1D);
        for bpp in [3usize, 4] {
            for width in [16usize, 17, 23, 64, 101] {
                let row_bytes = width * bpp;
                let pitch = row_bytes + 4 + (width % 3);
                for (m, group) in mixes.iter().enumerate() {
                    assert_eq!(group.len(), rows);
                    let mut filtered = Vec::new();
                    for &filter in group {
                        filtered.push(filter as u8);
                        filtered
                            .extend((0..row_bytes).map(|i| if m % 2 == 0 { byte() } else { (i as u8) / 7 }));
                    }
                    filtered.extend([byte(), byte(), byte(), byte()]);
                    let mut expected: Vec<u8> = (0..(rows + 1) * pitch).map(|_| byte()).collect();
                    let mut side = expected.clone();
                    row_by_row(RowGroup {
                        filters: group,
                        bpp,
                        row_bytes,
                        filtered: &filtered,
                        out: &mut expected,
                        pitch,
                    });
                    let under_test = RowGroup {
                        filters: group,
                        bpp,
                        row_bytes,
                        filtered: &filtered,
                        out: &mut side,
                        pitch,
                    };
                    assert!(unfilter(under_test), "this CPU lacks a feature of the form");
                    for k in 0..=rows {
                        let row = k * pitch..k * pitch + row_bytes;
                        assert_eq!(
                            side[row.clone()],
                            expected[row],
                            "bpp {bpp} width {width} {group:?} row {k}"
                        );
                    }
                }
            }
        }
    }

    /// Pseudo-random bytes (xorshift64) from `state`.
    pub(crate) fn xorshift_bytes(mut state: u64) -> impl FnMut() -> u8 {
        move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 32) as u8
        }
    }

    pub(crate) const FILTERS: [Filter; 5] =
        [Filter::None, Filter::Sub, Filter::Up, Filter::Average, Filter::Paeth];

    /// The AVX2 form against row-by-row unfiltering, every mix of filters.
    pub(crate) fn four_rows_side_by_side_equal_rows_one_at_a_time_for_every_filter_mix() {
        let mixes: Vec<Vec<Filter>> = (0..5usize.pow(4))
            .map(|mix| (0..4).map(|k| FILTERS[mix / 5usize.pow(k) % 5]).collect())
            .collect();
        check_side_by_side(FOUR, |mut group| group.side_by_side_form::<FOUR>().unfilter(), &mixes);
    }

    /// The AVX-512 form against row-by-row unfiltering: every filter in
    /// every row, each filter alone, and random mixes.
    pub(crate) fn eight_rows_side_by_side_equal_rows_one_at_a_time_for_many_filter_mixes() {
        // Every filter in every row (each row's filter from a different
        // digit), each filter alone, and random mixes.
        let mut mixes: Vec<Vec<Filter>> = (0..5usize.pow(4))
            .map(|mix| (0..8).map(|k| FILTERS[mix / 5usize.pow(k % 4) % 5]).collect())
            .collect();
        mixes.extend(FILTERS.map(|filter| vec![filter; 8]));
        let mut byte = xorshift_bytes(7);
        mixes.extend((0..600).map(|_| (0..8).map(|_| FILTERS[usize::from(byte()) % 5]).collect()));
        check_side_by_side(GROUP, |mut group| group.side_by_side_form::<GROUP>().unfilter(), &mixes);
    }
}

#[cfg(test)]
mod tests {
    use super::kernel_checks::{FILTERS, xorshift_bytes};
    use super::*;

    /// The PNG spec's Paeth predictor, written as the spec writes it.
    fn spec_paeth(a: u8, b: u8, c: u8) -> u8 {
        let p = i16::from(a) + i16::from(b) - i16::from(c);
        let (pa, pb, pc) = ((p - i16::from(a)).abs(), (p - i16::from(b)).abs(), (p - i16::from(c)).abs());
        if pa <= pb && pa <= pc {
            a
        } else if pb <= pc {
            b
        } else {
            c
        }
    }

    #[test]
    fn paeth_predictor_equals_the_spec_for_every_input() {
        for a in 0..=255u8 {
            for b in 0..=255u8 {
                for c in (0..=255u8).step_by(3) {
                    assert_eq!(paeth(a.into(), b.into(), c.into()), spec_paeth(a, b, c), "{a} {b} {c}");
                }
            }
        }
    }

    #[test]
    fn groups_of_any_size_equal_rows_one_at_a_time() {
        // The dispatch itself: partial groups (an image's last rows), mixes
        // with few chained rows, grey rows; whichever path this CPU takes.
        let mut byte = xorshift_bytes(11);
        for bpp in 1..=4usize {
            let row_bytes = 40 * bpp;
            let pitch = row_bytes + 4;
            for rows in 1..=GROUP {
                for _ in 0..40 {
                    let filters: Vec<Filter> = (0..rows).map(|_| FILTERS[usize::from(byte()) % 5]).collect();
                    let mut filtered = Vec::new();
                    for &filter in &filters {
                        filtered.push(filter as u8);
                        filtered.extend((0..row_bytes).map(|_| byte()));
                    }
                    filtered.extend([0; 4]);
                    let mut expected: Vec<u8> = (0..(rows + 1) * pitch).map(|_| byte()).collect();
                    let mut chosen = expected.clone();
                    let group =
                        |out| RowGroup { filters: &filters, bpp, row_bytes, filtered: &filtered, out, pitch };
                    row_by_row(group(&mut expected));
                    unfilter_rows(group(&mut chosen));
                    for k in 0..=rows {
                        let row = k * pitch..k * pitch + row_bytes;
                        assert_eq!(chosen[row.clone()], expected[row], "bpp {bpp} {filters:?} row {k}");
                    }
                }
            }
        }
    }

    #[test]
    fn unknown_filter_bytes_name_no_filter() {
        assert_eq!(Filter::from_byte(4), Some(Filter::Paeth));
        assert_eq!(Filter::from_byte(5), None);
        assert_eq!(Filter::from_byte(255), None);
    }
}
