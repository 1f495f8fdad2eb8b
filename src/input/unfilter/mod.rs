//! Undoing PNG row filters (PNG spec §9) for 8-bit samples, for the tile
//! decoder ([`crate::input::png_decode`]).
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

#[cfg(target_arch = "x86_64")]
mod avx2;

/// Rows [`unfilter_rows`] takes at once (the decoder hands it this many).
pub(crate) const GROUP: usize = 4;

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
    pub fn from_byte(byte: u8) -> Option<Filter> {
        [Filter::None, Filter::Sub, Filter::Up, Filter::Average, Filter::Paeth]
            .get(usize::from(byte))
            .copied()
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

/// Unfilters `filters.len()` (at most [`GROUP`]) consecutive rows of
/// `row_bytes` bytes, `bpp` bytes per pixel.
///
/// `filtered` holds the rows as inflated, each a filter byte followed by
/// its bytes (`filters` are those bytes, checked). `out` holds
/// `filters.len() + 1` rows `pitch` (≥ `row_bytes`) bytes apart: row 0 is
/// the unfiltered row above the first (zeros above the image), the others
/// receive the rows. A whole group of RGB or RGBA rows with a chained
/// filter among them goes side by side (see the module doc) when the CPU
/// has AVX2 and `filtered` and `pitch` leave 4 spare bytes; otherwise, and
/// for the answers the tests hold that path to, one row at a time.
pub(crate) fn unfilter_rows(
    filters: &[Filter],
    bpp: usize,
    row_bytes: usize,
    filtered: &[u8],
    out: &mut [u8],
    pitch: usize,
) {
    #[cfg(target_arch = "x86_64")]
    if side_by_side(filters, bpp, row_bytes, filtered.len(), pitch) {
        let group: &[Filter; GROUP] = filters.try_into().expect("a whole group");
        // SAFETY: `side_by_side` checked AVX2; the sizes are asserted inside.
        unsafe {
            match bpp {
                3 => avx2::unfilter_rows::<3>(group, row_bytes, filtered, out, pitch),
                _ => avx2::unfilter_rows::<4>(group, row_bytes, filtered, out, pitch),
            }
        }
        return;
    }
    row_by_row(filters, bpp, row_bytes, filtered, out, pitch);
}

/// [`unfilter_rows`] one row at a time.
fn row_by_row(
    filters: &[Filter],
    bpp: usize,
    row_bytes: usize,
    filtered: &[u8],
    out: &mut [u8],
    pitch: usize,
) {
    for (k, &filter) in filters.iter().enumerate() {
        let (above, below) = out.split_at_mut((k + 1) * pitch);
        let from = k * (row_bytes + 1) + 1;
        let previous = &above[k * pitch..k * pitch + row_bytes];
        unfilter_row(filter, bpp, previous, &filtered[from..from + row_bytes], &mut below[..row_bytes]);
    }
}

/// Whether [`unfilter_rows`] takes the side-by-side path: a whole group of
/// RGB or RGBA rows, at least 16 pixels wide, two of them with a chained
/// filter (Up and None alone are faster row by row), 4 spare bytes, AVX2.
#[cfg(target_arch = "x86_64")]
fn side_by_side(filters: &[Filter], bpp: usize, row_bytes: usize, filtered: usize, pitch: usize) -> bool {
    static AVX2: std::sync::OnceLock<bool> = std::sync::OnceLock::new();
    let chained =
        filters.iter().filter(|f| matches!(f, Filter::Sub | Filter::Average | Filter::Paeth)).count();
    filters.len() == GROUP
        && matches!(bpp, 3 | 4)
        && row_bytes >= 16 * bpp
        && chained >= 2
        && filtered >= GROUP * (row_bytes + 1) + 4
        && pitch >= row_bytes + 4
        && *AVX2.get_or_init(|| std::arch::is_x86_feature_detected!("avx2") && side_by_side_allowed())
}

/// `UFCSR_KERNEL=portable` (the counting kernels' switch,
/// `crate::count::KERNEL_ENV`) rules the vector code out here too.
#[cfg(target_arch = "x86_64")]
fn side_by_side_allowed() -> bool {
    std::env::var("UFCSR_KERNEL").map_or(true, |kernel| kernel != "portable")
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

#[cfg(test)]
mod tests {
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

    #[cfg(target_arch = "x86_64")]
    #[test]
    fn rows_side_by_side_equal_rows_one_at_a_time_for_every_filter_mix() {
        if !std::arch::is_x86_feature_detected!("avx2") {
            eprintln!("skipped: this CPU has no AVX2");
            return;
        }
        let filters = [Filter::None, Filter::Sub, Filter::Up, Filter::Average, Filter::Paeth];
        let mut state = 0x2545_F491_4F6C_DD1Du64;
        let mut byte = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 32) as u8
        };
        for bpp in [3usize, 4] {
            for width in [16usize, 17, 23, 64, 101] {
                let row_bytes = width * bpp;
                let pitch = row_bytes + 4 + (width % 3);
                for mix in 0..5usize.pow(4) {
                    let group: [Filter; GROUP] =
                        std::array::from_fn(|k| filters[mix / 5usize.pow(k as u32) % 5]);
                    let mut filtered = Vec::new();
                    for filter in group {
                        filtered.push(filter as u8);
                        // Smooth rows (as renderers give) and noisy ones.
                        filtered.extend(
                            (0..row_bytes).map(|i| if mix % 2 == 0 { byte() } else { (i as u8) / 7 }),
                        );
                    }
                    filtered.extend([byte(), byte(), byte(), byte()]);
                    let mut expected: Vec<u8> = (0..(GROUP + 1) * pitch).map(|_| byte()).collect();
                    let mut side = expected.clone();
                    row_by_row(&group, bpp, row_bytes, &filtered, &mut expected, pitch);
                    // SAFETY: AVX2 was checked above.
                    unsafe {
                        match bpp {
                            3 => avx2::unfilter_rows::<3>(&group, row_bytes, &filtered, &mut side, pitch),
                            _ => avx2::unfilter_rows::<4>(&group, row_bytes, &filtered, &mut side, pitch),
                        }
                    }
                    for k in 0..=GROUP {
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

    #[test]
    fn unknown_filter_bytes_name_no_filter() {
        assert_eq!(Filter::from_byte(4), Some(Filter::Paeth));
        assert_eq!(Filter::from_byte(5), None);
        assert_eq!(Filter::from_byte(255), None);
    }
}
