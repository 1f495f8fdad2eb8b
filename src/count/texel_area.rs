//! The solid angle each texel subtends, summed over every image: the
//! per-texel form of the rendered angular-area measure (issue 35), the
//! default heatmap's and views' measure (deg²·s) rather than the paper's
//! per-texel count.
//!
//! Each pixel is weighted by the solid angle it subtends in its eye. The
//! weights are not computed per run (two `atan` each, ≈ 44 ns, twenty times
//! the count's ≈ 2 ns per pixel) but once per eye: a table ([`EyePrefix`],
//! seen by a tile as its [`PixelPrefix`]) whose rows are built the first time
//! a tile reaches them and shared by every later image, from one `atan` per
//! pixel corner of a quarter of the eye (each pixel is the difference of its
//! four corners' `F`, [`crate::optics`]; the other quarters are its mirror
//! images). The table holds each row's prefix sums of its pixels' solid angles as integers
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
//! each time without overlapping), a batch found the lock taken going on
//! counting instead of waiting. The sums are indexed by the texel's
//! [`color_key`] (32 × 16-texel tiles of the palette in 4 KiB), so the runs
//! of neighbouring pixels, which show neighbouring texels whichever way the
//! surface runs through the texture, land in the same page and often the same
//! cache line. [`reference_add_row`] is the second pass this replaced, kept as
//! the reference the kernels are held to. Its cost:
//! docs/performance.md#per-texel-angular-area.
//!
//! Memory: one `u64` per texel (128 MiB for a 4096² palette, 2 MiB at
//! 512²) and one `u64` per pixel of a quarter of each eye, in bands of rows
//! that tiles reached (at most 104 MiB at 6420×8100, 1 MiB at the example's
//! 640×810), allocated only when angular area is measured (frames tallied
//! and the eyes' projection known).

use std::collections::HashMap;
use std::sync::{Arc, Mutex, OnceLock, PoisonError};

use crate::archive::palette::Fcsp;
use crate::color::color_key;
use crate::optics::solid_angle::TileView;
use crate::simd::ColorRuns;

/// Units of [`TexelSolidAngles`]: 2⁻⁴⁸ sr. A pixel at 480 px/° (≈ 1.3e-9
/// sr) is ≈ 3.7e5 units (rounding it costs ≤ 1.4e-6 of it); a texel may sum
/// to 2¹⁶ sr (10⁴ frames of a texel covering a sixth of the eye's view).
pub(crate) const TEXEL_SOLID_ANGLE_UNITS_PER_SR: f64 = (1u64 << 48) as f64;

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
pub(crate) struct TexelSolidAngles {
    /// Per texel at its [`color_key`], units of [`TEXEL_SOLID_ANGLE_UNITS_PER_SR`].
    units: Mutex<Vec<u64>>,
    texels: usize,
    texel_of: TexelOf,
    /// Packed background colours: no texel even where they name one (the
    /// kernels decide it themselves; the reference pass here).
    #[cfg_attr(not(any(test, feature = "synthetic")), allow(dead_code))]
    backgrounds: Vec<u32>,
    /// Per eye, its pixels' prefix sums (built as tiles reach their rows).
    tables: EyeTables,
}

/// The pixel prefix tables of the eyes an analysis reads, one per eye (its
/// rows built once, as tiles reach them), shared by the 24-bit kernels'
/// [`TexelSolidAngles`] and the 32-bit path.
#[derive(Default)]
pub(crate) struct EyeTables {
    tables: Mutex<HashMap<EyeKey, Arc<EyePrefix>>>,
}

impl EyeTables {
    /// The pixel prefix sums of an image of `size` at `view`: one table per
    /// eye, shared by every tile of it. `None` for an image that does not
    /// fit inside its eye (a tile of another size than the manifest says: its
    /// texels get no solid angle, and no table the size a damaged header
    /// claims is allocated).
    pub(crate) fn pixel_prefix(&self, view: &TileView, size: [u32; 2]) -> Option<PixelPrefix> {
        let eye = [view.projection.width, view.projection.height];
        let fits =
            (0..2).all(|axis| u64::from(view.origin[axis]) + u64::from(size[axis]) <= u64::from(eye[axis]));
        if !fits {
            return None;
        }
        let mut tables = self.tables.lock().unwrap_or_else(PoisonError::into_inner);
        let table = tables
            .entry((eye, view.projection.tan_half_x.to_bits()))
            .or_insert_with(|| Arc::new(EyePrefix::new(view.projection)));
        Some(PixelPrefix::within(Arc::clone(table), view.origin, size))
    }
}

/// A worker's texel runs not yet added to [`TexelSolidAngles`]: texel key
/// and its run's solid angle in units (at most [`PendingRuns::BATCH`],
/// 512 KiB). Its buffer is the thread's, reused image after image (a new
/// one per image grew and page-faulted 512 KiB each time).
pub(crate) struct PendingRuns(Vec<(u32, u64)>);

impl PendingRuns {
    /// Runs added under one lock.
    const BATCH: usize = 1 << 15;
    /// Batches a worker holds before it waits for the lock (2 MiB).
    const MAX_BATCHES: usize = 4;
}

/// Adds `pending`'s runs to `units` (the locked sums) and empties it.
fn add_runs(mut units: std::sync::MutexGuard<'_, Vec<u64>>, pending: &mut PendingRuns) {
    for &(key, run) in &pending.0 {
        if let Some(sum) = units.get_mut(key as usize) {
            *sum += run;
        }
    }
    pending.0.clear();
}

std::thread_local! {
    /// The buffer of the thread's last [`PendingRuns`], for its next.
    static SPARE_RUNS: std::cell::Cell<Vec<(u32, u64)>> = const { std::cell::Cell::new(Vec::new()) };
}

impl Default for PendingRuns {
    fn default() -> PendingRuns {
        let mut runs = SPARE_RUNS.try_with(std::cell::Cell::take).unwrap_or_default();
        runs.reserve(PendingRuns::BATCH);
        PendingRuns(runs)
    }
}

impl Drop for PendingRuns {
    fn drop(&mut self) {
        let mut runs = std::mem::take(&mut self.0);
        runs.clear();
        let _ = SPARE_RUNS.try_with(|spare| spare.set(runs));
    }
}

/// An eye: its image size and the field of view's bits, what a table of
/// pixel solid angles is for. Keyed by the eye and not by the tile, since one
/// sum is shared by captures of several eyes (the observers' coarser
/// re-capture shares the fine one's set-up: a table keyed by a tile's origin
/// and size alone gave it the fine eye's solid angles).
type EyeKey = ([u32; 2], u64);

/// Stored rows of an [`EyePrefix`] built together (a row of corners kept
/// from the row above): 64 rows of a 6420-pixel eye are 1.6 MiB and 206k
/// `atan`.
const BAND_ROWS: usize = 64;

/// Every row's prefix sums of its pixels' solid angles for one eye, in
/// [`TEXEL_SOLID_ANGLE_UNITS_PER_SR`], using the eye's symmetry: the solid
/// angle of a pixel is the same as its mirror's across the eye's vertical and
/// horizontal centre lines, so only the top half of the rows is stored (a row
/// below the middle reads its mirror's) and of each row only the prefix sums
/// up to the middle and the row's total (a prefix past the middle is the total
/// less the mirrored prefix: exact, in integers). A quarter of the eye's
/// pixels and corners: 104 MiB and 13 M `atan` at 6420×8100, where a table
/// per tile position held every pixel (416 MiB, 52 M). Rows are built in
/// bands of [`BAND_ROWS`] the first time a tile reaches them, each band once
/// (`OnceLock`, outside any lock the other workers wait on).
pub(crate) struct EyePrefix {
    projection: crate::optics::solid_angle::EyeProjection,
    /// Stored values per row: the prefix sums at pixel edges `0..=half`
    /// (`half` = ⌈width / 2⌉), then the row's total.
    stride: usize,
    /// Stored rows: ⌈height / 2⌉.
    rows: usize,
    bands: Vec<OnceLock<Box<[u64]>>>,
}

impl EyePrefix {
    fn new(projection: crate::optics::solid_angle::EyeProjection) -> EyePrefix {
        let (width, height) = (projection.width as usize, projection.height as usize);
        let rows = height.div_ceil(2);
        EyePrefix {
            projection,
            stride: width.div_ceil(2) + 2,
            rows,
            bands: (0..rows.div_ceil(BAND_ROWS)).map(|_| OnceLock::new()).collect(),
        }
    }

    /// The stored row of eye row `y` (its own, or its mirror's below the
    /// middle): the prefix sums to the middle, then the total.
    #[inline]
    fn row(&self, y: usize) -> &[u64] {
        let stored = if y < self.rows { y } else { self.projection.height as usize - 1 - y };
        let band = self.bands[stored / BAND_ROWS].get_or_init(|| self.band(stored / BAND_ROWS));
        let start = (stored % BAND_ROWS) * self.stride;
        &band[start..start + self.stride]
    }

    /// The stored rows of band `band`: `F` at each pixel corner of the left
    /// half once (signed image-plane coordinates, centred, so a pixel and
    /// its mirror have the same corners but for sign), each pixel the
    /// difference of its four corners, rounded to units once.
    fn band(&self, band: usize) -> Box<[u64]> {
        let p = &self.projection;
        let (width, height) = (f64::from(p.width), f64::from(p.height));
        let half = self.stride - 2;
        let pitch = p.pitch();
        let us: Vec<f64> = (0..=half).map(|x| (x as f64 - width / 2.0) * pitch).collect();
        let corners = |y: usize| -> Vec<f64> {
            let v = (y as f64 - height / 2.0) * pitch;
            us.iter().map(|&u| corner(u, v)).collect()
        };
        let first = band * BAND_ROWS;
        let last = (first + BAND_ROWS).min(self.rows);
        let mut values = Vec::with_capacity((last - first) * self.stride);
        let mut above = corners(first);
        for y in first..last {
            let below = corners(y + 1);
            let mut sum = 0u64;
            values.push(0);
            for x in 0..half {
                let sr = (below[x + 1] - below[x] - above[x + 1] + above[x]).abs();
                sum += (sr * TEXEL_SOLID_ANGLE_UNITS_PER_SR).round() as u64;
                values.push(sum);
            }
            // Whole row: the half's pixels twice, a centre pixel (odd width) once.
            let whole = values[values.len() - 1 - (p.width as usize % 2)] + sum;
            values.push(whole);
            above = below;
        }
        values.into_boxed_slice()
    }
}

/// The pixel solid angles of a tile: where it lies in its eye's
/// [`EyePrefix`]. Row `y` ([`PixelPrefix::row`]) gives the prefix sum at
/// each pixel edge `x` of the tile, relative to the tile's left edge
/// (differences are what a run weighs, so the offset does not matter).
pub(crate) struct PixelPrefix {
    eye: Arc<EyePrefix>,
    origin: [usize; 2],
    size: [usize; 2],
}

/// One tile row's prefix sums ([`PixelPrefix::row`]): [`PrefixRow::at`]
/// the pixel edge `x` of the tile (`0..=width`).
#[derive(Clone, Copy)]
pub(crate) struct PrefixRow<'t> {
    /// The eye row's stored values (the prefix sums to the middle, then the total).
    stored: &'t [u64],
    /// The tile's left edge in the eye.
    x0: usize,
    /// Pixel edges of the tile: its width + 1 (0 past the last row).
    edges: usize,
    eye_width: usize,
}

impl PrefixRow<'_> {
    /// The prefix sum at the tile's pixel edge `x` (from the eye row's left
    /// edge), `None` past the tile's right edge.
    #[inline(always)]
    pub(crate) fn at(&self, x: usize) -> Option<u64> {
        if x >= self.edges {
            return None;
        }
        let edge = self.x0 + x;
        let half = self.stored.len() - 2;
        if edge <= half {
            self.stored.get(edge).copied()
        } else {
            // Past the middle: the total less the mirrored prefix.
            Some(self.stored.get(half + 1)? - self.stored.get(self.eye_width - edge)?)
        }
    }

    /// The tile row's pixel edges (its width + 1; 0 past its last row).
    #[cfg(test)]
    pub(crate) fn len(&self) -> usize {
        self.edges
    }

    /// Whether the row is past the tile's last row.
    #[cfg(test)]
    pub(crate) fn is_empty(&self) -> bool {
        self.edges == 0
    }
}

/// `F(u, v)`, the solid angle of the image-plane rectangle `[0, u] × [0, v]`
/// (signed: odd in `u` and in `v`).
fn corner(u: f64, v: f64) -> f64 {
    (u * v / (1.0 + u * u + v * v).sqrt()).atan()
}

impl PixelPrefix {
    /// The table of a tile of `size` pixels at `view`, with an eye table of
    /// its own (an analysis shares one per eye: [`EyeTables::pixel_prefix`]).
    #[cfg(test)]
    pub(crate) fn new(view: &TileView, size: [u32; 2]) -> PixelPrefix {
        PixelPrefix::within(Arc::new(EyePrefix::new(view.projection)), view.origin, size)
    }

    fn within(eye: Arc<EyePrefix>, origin: [u32; 2], size: [u32; 2]) -> PixelPrefix {
        PixelPrefix { eye, origin: origin.map(|o| o as usize), size: size.map(|s| s as usize) }
    }

    /// Row `y`'s prefix sums (none past the last row).
    #[inline]
    pub(crate) fn row(&self, y: u32) -> PrefixRow<'_> {
        let y = y as usize;
        let (stored, edges) = if y < self.size[1] {
            (self.eye.row(self.origin[1] + y), self.size[0] + 1)
        } else {
            (&[0, 0][..], 0)
        };
        PrefixRow { stored, x0: self.origin[0], edges, eye_width: self.eye.projection.width as usize }
    }
}

impl TexelSolidAngles {
    /// Zero for every texel of `palette`.
    pub(crate) fn new(palette: &Fcsp, backgrounds: &[u32]) -> TexelSolidAngles {
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
            tables: EyeTables::default(),
        }
    }

    /// The pixel prefix sums of an image of `size` at `view` ([`EyeTables::pixel_prefix`]).
    pub(crate) fn pixel_prefix(&self, view: &TileView, size: [u32; 2]) -> Option<PixelPrefix> {
        self.tables.pixel_prefix(view, size)
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
    pub(crate) fn row_runs<'r>(&'r self, prefix: PrefixRow<'r>, pending: &'r mut PendingRuns) -> RowRuns<'r> {
        RowRuns { sums: self, prefix, pending, open: None }
    }

    /// Adds the runs in `pending` to the sums and empties it.
    pub(crate) fn flush(&self, pending: &mut PendingRuns) {
        let units = self.units.lock().unwrap_or_else(PoisonError::into_inner);
        add_runs(units, pending);
    }

    /// [`TexelSolidAngles::flush`] once `pending` holds a batch, without
    /// waiting: while another worker is adding its batch, this one goes on
    /// counting and adds later, unless it holds [`PendingRuns::MAX_BATCHES`]
    /// batches (the sums are integers: the order they are added in does not
    /// matter).
    #[inline]
    pub(crate) fn flush_if_full(&self, pending: &mut PendingRuns) {
        if pending.0.len() < PendingRuns::BATCH {
            return;
        }
        match self.units.try_lock() {
            Ok(units) => add_runs(units, pending),
            Err(std::sync::TryLockError::Poisoned(poisoned)) => add_runs(poisoned.into_inner(), pending),
            Err(std::sync::TryLockError::WouldBlock) => {
                if pending.0.len() >= PendingRuns::MAX_BATCHES * PendingRuns::BATCH {
                    self.flush(pending);
                }
            }
        }
    }

    /// Per-texel sums in units (row-major over the palette).
    pub(crate) fn into_units(self) -> Vec<u64> {
        let units = self.units.into_inner().unwrap_or_else(PoisonError::into_inner);
        (0..self.texels as u32).map(|texel| units[color_key(texel) as usize]).collect()
    }

    /// Per-texel sums, sr (row-major over the palette).
    #[cfg(test)]
    pub(crate) fn into_sr(self) -> Vec<f64> {
        self.into_units().into_iter().map(|u| u as f64 / TEXEL_SOLID_ANGLE_UNITS_PER_SR).collect()
    }
}

/// One row's runs, as a counting kernel reports them ([`ColorRuns`]): each
/// start closes the open run, whose texel (if it is one) gets the row's
/// prefix-sum difference over it. [`RowRuns::finish`] closes the last. The
/// prefix sum at a run's start is the one its predecessor closed at: one
/// lookup per boundary, none between two runs that are no texel.
pub(crate) struct RowRuns<'r> {
    sums: &'r TexelSolidAngles,
    prefix: PrefixRow<'r>,
    pending: &'r mut PendingRuns,
    /// The open run's texel key and the prefix sum at its first pixel.
    open: Option<(u32, u64)>,
}

impl RowRuns<'_> {
    /// The row ends at pixel `end` (its width).
    pub(crate) fn finish(self, end: usize) {
        if let (Some((key, from)), Some(to)) = (self.open, self.prefix.at(end)) {
            self.pending.0.push((key, to - from));
        }
    }
}

impl ColorRuns for RowRuns<'_> {
    const ACTIVE: bool = true;

    #[inline(always)]
    fn start(&mut self, at: usize, color: u32, texel: bool) {
        let key = self.sums.key(color, texel);
        if self.open.is_none() && key.is_none() {
            return;
        }
        // Past the tile's edge (a row longer than its table): nothing more is added.
        let Some(here) = self.prefix.at(at) else {
            self.open = None;
            return;
        };
        if let Some((open, from)) = self.open {
            self.pending.0.push((open, here - from));
        }
        self.open = key.map(|key| (key, here));
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
    prefix: PrefixRow<'_>,
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
        if let (Some(key), Some(to), Some(from)) = (sums.key(color, texel), prefix.at(end), prefix.at(start))
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
            Arc::ptr_eq(
                &table.eye,
                &sums.pixel_prefix(&TileView { origin: [2, 0], ..view }, [4, 2]).unwrap().eye
            ),
            "one table per eye"
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
            // Relative to the tile's left edge (the table's sums start at the eye's).
            let prefix: Vec<u64> = (0..=100).map(|x| prefix.at(x).unwrap() - prefix.at(0).unwrap()).collect();
            for x in [1usize, 37, 100] {
                let edges = (row.edge(x) - row.edge(0)).abs();
                let units = prefix[x] as f64 / TEXEL_SOLID_ANGLE_UNITS_PER_SR;
                assert!((units - edges).abs() < 1e-9 * edges, "row {y}, pixel {x}: {units} vs {edges}");
            }
        }
        let whole = PixelPrefix::new(&TileView { projection, origin: [0, 0] }, [214, 270]);
        let total: u64 = (0..270).map(|y| whole.row(y).at(214).unwrap()).sum();
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
        let values = |table: &PixelPrefix| (0..=32).map(|x| table.row(5).at(x).unwrap()).collect::<Vec<_>>();
        assert_eq!(values(&second), values(&alone));
        assert!(values(&second)[32] > 3 * values(&first)[32], "a coarse pixel is about 4 fine ones");
    }

    /// The eye's table stores a quarter of it: a tile and its mirror across
    /// both centre lines (an eye of odd width and height, so a centre column
    /// and row straddle the middle) get the same integers pixel for pixel,
    /// and a tile below and right of the middle still weighs each pixel its
    /// exact solid angle.
    #[test]
    fn mirrored_tiles_get_the_same_integers_and_each_pixel_its_solid_angle() {
        let projection = EyeProjection::new(107.0, [215, 271]).unwrap();
        let eye = Arc::new(EyePrefix::new(projection));
        let tile = |origin| PixelPrefix::within(Arc::clone(&eye), origin, [60, 50]);
        let (top_left, bottom_right) = (tile([10, 5]), tile([215 - 70, 271 - 55]));
        let across = tile([80, 110]);
        let pixel = |table: &PixelPrefix, x: usize, y: u32| {
            let row = table.row(y);
            row.at(x + 1).unwrap() - row.at(x).unwrap()
        };
        for y in 0..50u32 {
            for x in 0..60usize {
                assert_eq!(pixel(&top_left, x, y), pixel(&bottom_right, 59 - x, 49 - y), "pixel {x}, {y}");
                let exact = projection.pixel_sr(80 + x as u32, 110 + y);
                let units = pixel(&across, x, y) as f64 / TEXEL_SOLID_ANGLE_UNITS_PER_SR;
                assert!((units - exact).abs() < 1e-9 * exact, "pixel {x}, {y}: {units} vs {exact}");
            }
        }
        assert_eq!(across.row(10).at(61), None, "past the tile's right edge");
        assert!(across.row(50).is_empty() && across.row(50).at(0).is_none(), "past its last row");
    }

    /// A full batch that finds the sums locked (another worker adding its
    /// own) stays with its worker, who goes on counting; the next try adds
    /// it all, the same integers.
    #[test]
    fn a_full_batch_waits_for_no_lock_and_adds_the_same_sums_later() {
        let palette = Fcsp::canonical([16, 16]).unwrap();
        let sums = TexelSolidAngles::new(&palette, &[255]);
        let mut pending = PendingRuns::default();
        pending.0.extend((0..PendingRuns::BATCH as u64).map(|i| (color_key((i % 7) as u32), i)));
        let held = sums.units.lock().unwrap();
        sums.flush_if_full(&mut pending);
        assert_eq!(pending.0.len(), PendingRuns::BATCH, "it waited for, or took, a held lock");
        drop(held);
        pending.0.push((color_key(3), 1));
        sums.flush_if_full(&mut pending);
        assert!(pending.0.is_empty());
        let units = sums.into_units();
        let expected = |texel: u64| (0..PendingRuns::BATCH as u64).filter(|i| i % 7 == texel).sum::<u64>();
        assert_eq!(units[3], expected(3) + 1);
        assert_eq!(units[0], expected(0));
        assert_eq!(units[7..].iter().sum::<u64>(), 0);
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
        assert_eq!(whole[7], table.row(3).at(40).unwrap());
    }
}
