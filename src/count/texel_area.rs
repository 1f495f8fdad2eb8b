//! The solid angle each texel subtends, summed over every image: the
//! per-texel form of the rendered angular-area measure (issue 35), the
//! default heatmap's and views' measure (deg²·s) rather than the paper's
//! per-texel count.
//!
//! Each pixel is weighted by the solid angle it subtends in its eye. The
//! weights are not computed per run (two `atan` each, ≈ 44 ns, twenty times
//! the count's ≈ 2 ns per pixel) but once per tile position and size: a
//! table ([`PixelPrefix`]) built the first time a tile there is counted and
//! shared by every later image there, from one `atan` per pixel corner (each
//! pixel is the difference of its four corners' `F`, [`crate::optics`]). The
//! table holds each row's prefix sums of its pixels' solid angles as integers
//! in [`TEXEL_SOLID_ANGLE_UNITS_PER_SR`] (each pixel rounded once), so a run
//! of pixels `[a, b)` weighs `prefix[b] − prefix[a]` — two loads, and exact:
//! a run split anywhere adds the same to its texel, so every counting kernel
//! (portable, AVX2, AVX-512, with or without the part tally), the capture's
//! `--count` and the order the images are counted in give the same integers.
//!
//! The runs are found by the counting kernel itself as it classifies each
//! row ([`crate::simd::ColorRuns`]: the pixels whose colour differs from their
//! left neighbour's, which it compares anyway), and each texel run's sum goes
//! to the worker's [`PendingRuns`], added to the shared sums in batches under
//! one lock (an atomic add per run into the 128 MiB array missed the cache
//! each time without overlapping). The sums are indexed by the texel's
//! [`color_key`] (32 × 16-texel tiles of the palette in 4 KiB), so the runs
//! of neighbouring pixels, which show neighbouring texels whichever way the
//! surface runs through the texture, land in the same page and often the same
//! cache line. [`reference_add_row`] is the second pass this replaced, kept as
//! the reference the kernels are held to. Its cost:
//! docs/performance.md#per-texel-angular-area.
//!
//! Memory: one `u64` per texel (128 MiB for a 4096² palette, 2 MiB at
//! 512²) and one `u64` per pixel of each tile position that showed texels
//! (at most the eye image: 416 MiB at 6420×8100, 4 MiB at the example's
//! 640×810), allocated only when angular area is measured (frames tallied
//! and the eyes' projection known).

use std::collections::HashMap;
use std::sync::{Arc, Mutex, PoisonError};

use crate::archive::palette::Fcsp;
use crate::color::color_key;
use crate::optics::solid_angle::TileView;
use crate::simd::ColorRuns;

/// Units of [`TexelSolidAngles`]: 2⁻⁴⁸ sr. A pixel at 480 px/° (≈ 1.3e-9
/// sr) is ≈ 3.7e5 units (rounding it costs ≤ 1.4e-6 of it); a texel may sum
/// to 2¹⁶ sr (10⁴ frames of a texel covering a sixth of the eye's view).
pub const TEXEL_SOLID_ANGLE_UNITS_PER_SR: f64 = (1u64 << 48) as f64;

/// Colour → texel, for the texels of a palette.
enum TexelOf {
    /// Texel index == colour, below the texel count.
    Canonical(u32),
    /// A palette image: its colours' texels.
    Map(HashMap<u32, u32>),
}

impl TexelOf {
    /// The texel `color` names (no background check).
    #[inline(always)]
    fn texel(&self, color: u32) -> Option<u32> {
        match self {
            TexelOf::Canonical(count) => (color < *count).then_some(color),
            TexelOf::Map(map) => map.get(&color).copied(),
        }
    }
}

/// Per-texel solid angle summed over the images counted (shared by the
/// workers).
pub struct TexelSolidAngles {
    /// Per texel at its [`color_key`], units of [`TEXEL_SOLID_ANGLE_UNITS_PER_SR`].
    units: Mutex<Vec<u64>>,
    texels: usize,
    texel_of: TexelOf,
    /// Packed background colours: no texel even where they name one (the
    /// kernels decide it themselves; the reference pass here).
    #[cfg_attr(not(any(test, feature = "synthetic")), allow(dead_code))]
    backgrounds: Vec<u32>,
    /// Per tile position and size, its pixels' prefix sums.
    tables: Mutex<HashMap<TilePlace, Arc<PixelPrefix>>>,
}

/// A worker's texel runs not yet added to [`TexelSolidAngles`]: texel key
/// and its run's solid angle in units (at most [`PendingRuns::BATCH`],
/// 384 KiB).
#[derive(Default)]
pub struct PendingRuns(Vec<(u32, u64)>);

impl PendingRuns {
    /// Runs added under one lock.
    const BATCH: usize = 1 << 15;
}

/// A tile position in its eye and its size in pixels: what a table of
/// pixel solid angles is for.
/// A tile's place: its eye (image size and the field of view's bits) as well as
/// its origin and size, since one sum is shared by captures of several eyes
/// (the observers' coarser re-capture shares the fine one's set-up: a table
/// keyed by origin and size alone gave it the fine eye's solid angles).
type TilePlace = ([u32; 2], u64, [u32; 2], [u32; 2]);

/// Every row's prefix sums of its pixels' solid angles, in
/// [`TEXEL_SOLID_ANGLE_UNITS_PER_SR`]: row `y` is `width + 1` values, the
/// first 0, value `x` the sum of the row's pixels before `x`.
pub struct PixelPrefix {
    width: usize,
    prefix: Vec<u64>,
}

/// `F(u, v)`, the solid angle of the image-plane rectangle `[0, u] × [0, v]`
/// (signed: odd in `u` and in `v`).
fn corner(u: f64, v: f64) -> f64 {
    (u * v / (1.0 + u * u + v * v).sqrt()).atan()
}

impl PixelPrefix {
    /// The table of an image of `size` pixels at `view`: `F` at each pixel
    /// corner once (a row of corners kept from the row above), each pixel the
    /// difference of its four corners, rounded to units once.
    pub fn new(view: &TileView, [width, height]: [u32; 2]) -> PixelPrefix {
        let p = view.projection;
        let (width, x0, y0) = (width as usize, f64::from(view.origin[0]), f64::from(view.origin[1]));
        let us: Vec<f64> = (0..=width).map(|x| p.u(x0 + x as f64)).collect();
        let corners = |y: u32| -> Vec<f64> {
            let v = p.v(y0 + f64::from(y));
            us.iter().map(|&u| corner(u, v)).collect()
        };
        let mut prefix = Vec::with_capacity((width + 1) * height as usize);
        let mut above = corners(0);
        for y in 0..height {
            let below = corners(y + 1);
            let mut sum = 0u64;
            prefix.push(0);
            for x in 0..width {
                let sr = (below[x + 1] - below[x] - above[x + 1] + above[x]).abs();
                sum += (sr * TEXEL_SOLID_ANGLE_UNITS_PER_SR).round() as u64;
                prefix.push(sum);
            }
            above = below;
        }
        PixelPrefix { width, prefix }
    }

    /// Row `y`'s `width + 1` prefix sums (empty past the last row).
    #[inline]
    pub fn row(&self, y: u32) -> &[u64] {
        let start = y as usize * (self.width + 1);
        self.prefix.get(start..start + self.width + 1).unwrap_or(&[])
    }
}

impl TexelSolidAngles {
    /// Zero for every texel of `palette`.
    pub fn new(palette: &Fcsp, backgrounds: &[u32]) -> TexelSolidAngles {
        let texels = palette.texel_count();
        let texel_of = match palette {
            Fcsp::Canonical { .. } => TexelOf::Canonical(texels as u32),
            Fcsp::Image { colors, .. } => {
                TexelOf::Map(colors.iter().enumerate().map(|(texel, &color)| (color, texel as u32)).collect())
            }
        };
        // Below 2^k (k ≥ 16) a key stays below 2^k; below 2^16 it may use
        // all 16 bits.
        let keys = texels.next_power_of_two().clamp(1 << 16, 1 << 24);
        TexelSolidAngles {
            units: Mutex::new(vec![0; keys]),
            texels,
            texel_of,
            backgrounds: backgrounds.to_vec(),
            tables: Mutex::new(HashMap::new()),
        }
    }

    /// The pixel prefix sums of an image of `size` at `view`: built once per
    /// tile position and size, then shared. `None` for an image that does
    /// not fit inside its eye (a tile of another size than the manifest
    /// says: its texels get no solid angle, and no table the size a damaged
    /// header claims is allocated).
    pub fn pixel_prefix(&self, view: &TileView, size: [u32; 2]) -> Option<Arc<PixelPrefix>> {
        let eye = [view.projection.width, view.projection.height];
        let fits =
            (0..2).all(|axis| u64::from(view.origin[axis]) + u64::from(size[axis]) <= u64::from(eye[axis]));
        if !fits {
            return None;
        }
        let mut tables = self.tables.lock().unwrap_or_else(PoisonError::into_inner);
        let table = tables
            .entry((eye, view.projection.tan_half_x.to_bits(), view.origin, size))
            .or_insert_with(|| Arc::new(PixelPrefix::new(view, size)));
        Some(Arc::clone(table))
    }

    /// The key a run of `color` adds to (`texel`: the kernel's verdict,
    /// palette member and no background), or `None`.
    #[inline(always)]
    fn key(&self, color: u32, texel: bool) -> Option<u32> {
        if !texel {
            return None;
        }
        self.texel_of.texel(color).map(color_key)
    }

    /// A row's runs as a counting kernel reports them: `prefix` is the row
    /// of [`PixelPrefix::row`]; each texel run's units go to `pending`.
    pub fn row_runs<'r>(&'r self, prefix: &'r [u64], pending: &'r mut PendingRuns) -> RowRuns<'r> {
        RowRuns { sums: self, prefix, pending, start: 0, open: None }
    }

    /// Adds the runs in `pending` to the sums and empties it.
    pub fn flush(&self, pending: &mut PendingRuns) {
        let mut units = self.units.lock().unwrap_or_else(PoisonError::into_inner);
        for &(key, run) in &pending.0 {
            if let Some(sum) = units.get_mut(key as usize) {
                *sum += run;
            }
        }
        pending.0.clear();
    }

    /// [`TexelSolidAngles::flush`] once `pending` holds a batch.
    #[inline]
    pub fn flush_if_full(&self, pending: &mut PendingRuns) {
        if pending.0.len() >= PendingRuns::BATCH {
            self.flush(pending);
        }
    }

    /// Per-texel sums in units (row-major over the palette).
    pub fn into_units(self) -> Vec<u64> {
        let units = self.units.into_inner().unwrap_or_else(PoisonError::into_inner);
        (0..self.texels as u32).map(|texel| units[color_key(texel) as usize]).collect()
    }

    /// Per-texel sums, sr (row-major over the palette).
    #[cfg(test)]
    pub fn into_sr(self) -> Vec<f64> {
        self.into_units().into_iter().map(|u| u as f64 / TEXEL_SOLID_ANGLE_UNITS_PER_SR).collect()
    }
}

/// One row's runs, as a counting kernel reports them ([`ColorRuns`]): each
/// start closes the open run, whose texel (if it is one) gets the row's
/// prefix-sum difference over it. [`RowRuns::finish`] closes the last.
pub struct RowRuns<'r> {
    sums: &'r TexelSolidAngles,
    prefix: &'r [u64],
    pending: &'r mut PendingRuns,
    /// The open run's first pixel and texel key.
    start: usize,
    open: Option<u32>,
}

impl RowRuns<'_> {
    #[inline(always)]
    fn close(&mut self, end: usize) {
        if let Some(key) = self.open {
            let (Some(&to), Some(&from)) = (self.prefix.get(end), self.prefix.get(self.start)) else {
                return;
            };
            self.pending.0.push((key, to - from));
        }
    }

    /// The row ends at pixel `end` (its width).
    pub fn finish(mut self, end: usize) {
        self.close(end);
    }
}

impl ColorRuns for RowRuns<'_> {
    const ACTIVE: bool = true;

    #[inline(always)]
    fn start(&mut self, at: usize, color: u32, texel: bool) {
        self.close(at);
        self.start = at;
        self.open = self.sums.key(color, texel);
    }
}

/// A kernel's runs reported from pixel `by` of the row on (the portable
/// kernel finishing a row a vector kernel began).
pub(crate) struct Shifted<R> {
    pub runs: R,
    pub by: usize,
}

impl<R: ColorRuns> ColorRuns for Shifted<R> {
    const ACTIVE: bool = R::ACTIVE;

    #[inline(always)]
    fn start(&mut self, at: usize, color: u32, texel: bool) {
        self.runs.start(at + self.by, color, texel);
    }
}

/// The reference the kernels are held to: the second pass over a decoded
/// row that the per-texel area was before it moved into the kernels — each
/// run of one colour (found pixel by pixel-block, [`crate::count::part_lookup::Runs`])
/// whose colour is a texel and no background adds its pixels' prefix-sum
/// difference.
#[cfg(any(test, feature = "synthetic"))]
pub(crate) fn reference_add_row(
    sums: &TexelSolidAngles,
    row: &[u8],
    layout: crate::png::rows::PixelLayout,
    prefix: &[u64],
    pending: &mut PendingRuns,
) {
    use crate::count::part_lookup::Runs;
    use crate::png::rows::PixelLayout;
    let runs: Vec<(usize, usize, u32)> = match layout {
        PixelLayout::Rgb => Runs::<3, false>::new(row).collect(),
        PixelLayout::Rgba => Runs::<4, false>::new(row).collect(),
        PixelLayout::Gray => Runs::<1, true>::new(row).collect(),
        PixelLayout::GrayAlpha => Runs::<2, true>::new(row).collect(),
    };
    for (start, end, color) in runs {
        let texel = !sums.backgrounds.contains(&color) && sums.texel_of.texel(color).is_some();
        if let (Some(key), Some(&to), Some(&from)) =
            (sums.key(color, texel), prefix.get(end), prefix.get(start))
        {
            pending.0.push((key, to - from));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::optics::solid_angle::{EyeProjection, RowWeights};
    use crate::png::rows::PixelLayout;

    #[test]
    fn the_reference_pass_adds_each_texels_pixels_solid_angles_and_skips_background_and_strays() {
        let palette = Fcsp::canonical([4, 4]).unwrap();
        let sums = TexelSolidAngles::new(&palette, &[3]);
        let projection = EyeProjection::new(90.0, [8, 2]).unwrap();
        let view = TileView { projection, origin: [0, 0] };
        // Texels 1,1,5 then background 3, a stray, texel 5, texel 1.
        let row: Vec<u8> = [1u32, 1, 5, 3, 0xFFFFFF, 5, 1, 1]
            .iter()
            .flat_map(|&c| [(c >> 16) as u8, (c >> 8) as u8, c as u8])
            .collect();
        let table = sums.pixel_prefix(&view, [8, 2]).unwrap();
        assert!(
            Arc::ptr_eq(&table, &sums.pixel_prefix(&view, [8, 2]).unwrap()),
            "one table per tile position"
        );
        assert!(sums.pixel_prefix(&view, [9, 2]).is_none(), "wider than the eye: no table");
        let mut pending = PendingRuns::default();
        reference_add_row(&sums, &row, PixelLayout::Rgb, table.row(0), &mut pending);
        sums.flush(&mut pending);
        let sr = sums.into_sr();
        let pixel = |x: u32| projection.pixel_sr(x, 0);
        // Each pixel rounded to 2^-48 sr: within 1e-9 of the exact solid angles.
        let close = |a: f64, b: f64| (a - b).abs() < 1e-9 * b;
        assert!(close(sr[1], pixel(0) + pixel(1) + pixel(6) + pixel(7)), "{}", sr[1]);
        assert!(close(sr[5], pixel(2) + pixel(5)), "{}", sr[5]);
        assert_eq!(sr[3], 0.0, "background is no texel");
        assert_eq!(sr.iter().filter(|&&s| s > 0.0).count(), 2);
    }

    /// The table from one `atan` per corner against the pass's old weights
    /// (two `atan` per pixel edge, each row's edges apart): the same solid
    /// angles to rounding, and a whole eye's pixels sum to its frustum.
    #[test]
    fn pixel_prefix_sums_from_corners_match_the_per_edge_weights_and_the_frustum() {
        let projection = EyeProjection::new(107.0, [214, 270]).unwrap();
        let view = TileView { projection, origin: [40, 30] };
        let table = PixelPrefix::new(&view, [100, 50]);
        for y in [0u32, 17, 49] {
            let row = RowWeights::new(&view, y);
            let prefix = table.row(y);
            assert_eq!(prefix.len(), 101);
            for x in [1usize, 37, 100] {
                let edges = (row.edge(x) - row.edge(0)).abs();
                let units = prefix[x] as f64 / TEXEL_SOLID_ANGLE_UNITS_PER_SR;
                assert!((units - edges).abs() < 1e-9 * edges, "row {y}, pixel {x}: {units} vs {edges}");
            }
        }
        let whole = PixelPrefix::new(&TileView { projection, origin: [0, 0] }, [214, 270]);
        let total: u64 = (0..270).map(|y| whole.row(y)[214]).sum();
        let sr = total as f64 / TEXEL_SOLID_ANGLE_UNITS_PER_SR;
        assert!((sr - projection.image_sr()).abs() < 1e-9 * sr, "{sr} vs {}", projection.image_sr());
        assert!(whole.row(270).is_empty());
    }

    /// One sum shared by captures of two eyes (the observers' fine and
    /// coarser captures): a tile at the same origin and of the same size in
    /// an eye of half the pixels gets that eye's solid angles, not the first's.
    #[test]
    fn a_tile_of_the_same_place_in_another_eye_gets_that_eyes_solid_angles() {
        let palette = Fcsp::canonical([16, 16]).unwrap();
        let sums = TexelSolidAngles::new(&palette, &[255]);
        let fine = EyeProjection::new(107.0, [128, 64]).unwrap();
        let coarse = EyeProjection::new(107.0, [64, 32]).unwrap();
        let tile = |projection| TileView { projection, origin: [0, 0] };
        let first = sums.pixel_prefix(&tile(fine), [32, 16]).unwrap();
        let second = sums.pixel_prefix(&tile(coarse), [32, 16]).unwrap();
        let alone = PixelPrefix::new(&tile(coarse), [32, 16]);
        assert_eq!(second.row(5), alone.row(5));
        assert!(second.row(5)[32] > 3 * first.row(5)[32], "a coarse pixel is about 4 fine ones");
    }

    #[test]
    fn a_run_split_anywhere_adds_the_same_integers_to_its_texel() {
        let palette = Fcsp::canonical([16, 16]).unwrap();
        let projection = EyeProjection::new(107.0, [64, 8]).unwrap();
        let view = TileView { projection, origin: [0, 0] };
        let (whole, split) =
            (TexelSolidAngles::new(&palette, &[255]), TexelSolidAngles::new(&palette, &[255]));
        let table = whole.pixel_prefix(&view, [64, 8]).unwrap();
        let mut pending = PendingRuns::default();
        let mut runs = whole.row_runs(table.row(3), &mut pending);
        runs.start(0, 7, true);
        runs.start(40, 255, false);
        runs.finish(64);
        whole.flush(&mut pending);
        let mut runs = split.row_runs(table.row(3), &mut pending);
        for at in [0, 3, 17, 39] {
            runs.start(at, 7, true);
        }
        runs.start(40, 255, false);
        runs.finish(64);
        split.flush(&mut pending);
        let (whole, split) = (whole.into_units(), split.into_units());
        assert_eq!(whole, split);
        assert_eq!(whole[7], table.row(3)[40]);
    }
}
