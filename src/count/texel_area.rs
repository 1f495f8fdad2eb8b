//! The solid angle each texel subtends, summed over every image: the
//! per-texel form of the rendered angular-area measure (issue 35), so the
//! default heatmap and views show a measure to quote rather than the
//! paper's per-texel count.
//!
//! Each pixel is weighted by the solid angle it subtends in its eye
//! ([`RowWeights`], the same weights the per-part tally uses, so the texels
//! of a part add up to the part's `solid_angle_sr`). Texel runs are short
//! (a pixel or two at most distances), so the weights are not computed per
//! run (two `atan` each, ≈ 44 ns, twenty times the count's ≈ 2 ns per
//! pixel) but once per tile position: a table of every pixel's solid angle
//! (f32, from the exact edges) built the first time a tile at that position
//! is decoded and shared by every later image there; a run then adds its
//! pixels' table entries. The sums are integers in
//! [`TEXEL_SOLID_ANGLE_UNITS_PER_SR`], added into one array shared by the
//! workers, so they do not depend on the order images are counted in.
//! Each run's sum is first appended to the worker's [`PendingRuns`] and
//! added to the array in batches under one lock: an atomic add per run
//! into the 128 MiB array missed the cache each time without overlapping
//! (the lock prefix), three quarters of the pass (`perf`); plain adds in a
//! batch overlap their misses (the default analysis of the generated
//! archive with a projection: 3.2× the CPU time of the pass-free analysis
//! with atomic adds, 2.4× batched; sorting each batch by texel made it
//! slower, 3.6×). Its cost: docs/performance.md#per-texel-angular-area.
//!
//! Memory: one `u64` per texel (128 MiB for a 4096² palette, 2 MiB at
//! 512²) and one `f32` per pixel of each tile position that showed texels
//! (at most the eye image: 208 MiB at 6420×8100, 2 MiB at the example's
//! 640×810), allocated only when angular area is measured (frames tallied
//! and the eyes' projection known).

use std::collections::HashMap;
use std::sync::{Arc, Mutex, PoisonError};

use crate::archive::palette::Fcsp;
use crate::count::part_lookup::Runs;
use crate::optics::solid_angle::{RowWeights, TileView};
use crate::png::rows::PixelLayout;

/// Units of [`TexelSolidAngles`]: 2⁻⁴⁸ sr. A pixel at 480 px/° (≈ 1.3e-9
/// sr) is ≈ 3.7e5 units (truncation costs ≤ 3e-6 of it); a texel may sum to
/// 2¹⁶ sr (10⁴ frames of a texel covering a sixth of the eye's view).
pub const TEXEL_SOLID_ANGLE_UNITS_PER_SR: f64 = (1u64 << 48) as f64;

/// Colour → texel, for the texels of a palette.
enum TexelOf {
    /// Texel index == colour, below the texel count.
    Canonical(u32),
    /// A palette image: its colours' texels.
    Map(HashMap<u32, u32>),
}

/// Per-texel solid angle summed over the images counted (shared by the
/// workers).
pub struct TexelSolidAngles {
    /// Per texel, units of [`TEXEL_SOLID_ANGLE_UNITS_PER_SR`].
    units: Mutex<Vec<u64>>,
    texel_of: TexelOf,
    /// Packed background colours: no texel even where they name one.
    backgrounds: Vec<u32>,
    /// Per tile position and size, every pixel's solid angle (sr), rows top
    /// to bottom ([`TexelSolidAngles::pixel_weights`]).
    weights: Mutex<HashMap<TilePlace, Arc<Vec<f32>>>>,
}

/// A worker's texel runs not yet added to [`TexelSolidAngles`]: texel and
/// its run's solid angle in units (at most [`PendingRuns::BATCH`], 512 KiB).
#[derive(Default)]
pub struct PendingRuns(Vec<(u32, u64)>);

impl PendingRuns {
    /// Runs added under one lock.
    const BATCH: usize = 1 << 15;
}

/// A tile position in its eye and its size in pixels: what a table of
/// pixel solid angles is for.
type TilePlace = ([u32; 2], [u32; 2]);

/// Every pixel's solid angle (sr) of an image of `size` pixels lying at
/// `view` in its eye, rows top to bottom: each the difference of its two
/// edges' [`RowWeights::edge`].
fn pixel_solid_angles(view: &TileView, [width, height]: [u32; 2]) -> Vec<f32> {
    let mut weights = Vec::with_capacity(width as usize * height as usize);
    for y in 0..height {
        let row = RowWeights::new(view, y);
        let mut left = row.edge(0);
        for x in 1..=width as usize {
            let right = row.edge(x);
            weights.push((right - left).abs() as f32);
            left = right;
        }
    }
    weights
}

impl TexelSolidAngles {
    /// Zero for every texel of `palette`.
    pub fn new(palette: &Fcsp, backgrounds: &[u32]) -> TexelSolidAngles {
        let count = palette.texel_count();
        let texel_of = match palette {
            Fcsp::Canonical { .. } => TexelOf::Canonical(count as u32),
            Fcsp::Image { colors, .. } => {
                TexelOf::Map(colors.iter().enumerate().map(|(texel, &color)| (color, texel as u32)).collect())
            }
        };
        TexelSolidAngles {
            units: Mutex::new(vec![0; count]),
            texel_of,
            backgrounds: backgrounds.to_vec(),
            weights: Mutex::new(HashMap::new()),
        }
    }

    /// The pixel solid angles of an image of `size` at `view`: built once
    /// per tile position and size, then shared. `None` for an image that
    /// does not fit inside its eye (a tile of another size than the
    /// manifest says: its texels get no solid angle, and no table the size
    /// a damaged header claims is allocated).
    pub fn pixel_weights(&self, view: &TileView, size: [u32; 2]) -> Option<Arc<Vec<f32>>> {
        let eye = [view.projection.width, view.projection.height];
        let fits =
            (0..2).all(|axis| u64::from(view.origin[axis]) + u64::from(size[axis]) <= u64::from(eye[axis]));
        if !fits {
            return None;
        }
        let mut tables = self.weights.lock().unwrap_or_else(PoisonError::into_inner);
        let table =
            tables.entry((view.origin, size)).or_insert_with(|| Arc::new(pixel_solid_angles(view, size)));
        Some(Arc::clone(table))
    }

    #[inline]
    fn texel(&self, color: u32) -> Option<usize> {
        if self.backgrounds.contains(&color) {
            return None;
        }
        match &self.texel_of {
            TexelOf::Canonical(count) => (color < *count).then_some(color as usize),
            TexelOf::Map(map) => map.get(&color).map(|&texel| texel as usize),
        }
    }

    /// Adds one decoded row, `weights` its pixels' solid angles (a row of
    /// [`TexelSolidAngles::pixel_weights`]): each run of one texel's colour
    /// adds its pixels' solid angles to that texel, through `pending`
    /// (added to the sums when it is full and by [`TexelSolidAngles::flush`]).
    pub fn add_row(&self, row: &[u8], layout: PixelLayout, weights: &[f32], pending: &mut PendingRuns) {
        match layout {
            PixelLayout::Rgb => self.add_runs(Runs::<3, false>::new(row), weights, pending),
            PixelLayout::Rgba => self.add_runs(Runs::<4, false>::new(row), weights, pending),
            PixelLayout::Gray => self.add_runs(Runs::<1, true>::new(row), weights, pending),
            PixelLayout::GrayAlpha => self.add_runs(Runs::<2, true>::new(row), weights, pending),
        }
        if pending.0.len() >= PendingRuns::BATCH {
            self.flush(pending);
        }
    }

    fn add_runs(
        &self,
        runs: impl Iterator<Item = (usize, usize, u32)>,
        weights: &[f32],
        pending: &mut PendingRuns,
    ) {
        for (start, end, color) in runs {
            let Some(texel) = self.texel(color) else { continue };
            let Some(pixels) = weights.get(start..end) else { continue };
            let sr: f64 = pixels.iter().map(|&w| f64::from(w)).sum();
            pending.0.push((texel as u32, (sr * TEXEL_SOLID_ANGLE_UNITS_PER_SR) as u64));
        }
    }

    /// Adds the runs in `pending` to the sums and empties it.
    pub fn flush(&self, pending: &mut PendingRuns) {
        let mut units = self.units.lock().unwrap_or_else(PoisonError::into_inner);
        for &(texel, run) in &pending.0 {
            if let Some(sum) = units.get_mut(texel as usize) {
                *sum += run;
            }
        }
        pending.0.clear();
    }

    /// Per-texel sums, sr (row-major over the palette).
    pub fn into_sr(self) -> Vec<f64> {
        let units = self.units.into_inner().unwrap_or_else(PoisonError::into_inner);
        units.into_iter().map(|u| u as f64 / TEXEL_SOLID_ANGLE_UNITS_PER_SR).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::optics::solid_angle::EyeProjection;

    #[test]
    fn a_row_adds_each_texels_pixels_solid_angles_and_skips_background_and_strays() {
        let palette = Fcsp::canonical([4, 4]).unwrap();
        let sums = TexelSolidAngles::new(&palette, &[3]);
        let projection = EyeProjection::new(90.0, [8, 2]).unwrap();
        let view = TileView { projection, origin: [0, 0] };
        // Texels 1,1,5 then background 3, a stray, texel 5, texel 1.
        let row: Vec<u8> = [1u32, 1, 5, 3, 0xFFFFFF, 5, 1, 1]
            .iter()
            .flat_map(|&c| [(c >> 16) as u8, (c >> 8) as u8, c as u8])
            .collect();
        let weights = sums.pixel_weights(&view, [8, 2]).unwrap();
        assert!(
            Arc::ptr_eq(&weights, &sums.pixel_weights(&view, [8, 2]).unwrap()),
            "one table per tile position"
        );
        assert!(sums.pixel_weights(&view, [9, 2]).is_none(), "wider than the eye: no table");
        let mut pending = PendingRuns::default();
        sums.add_row(&row, PixelLayout::Rgb, &weights[..8], &mut pending);
        sums.flush(&mut pending);
        let sr = sums.into_sr();
        let pixel = |x: u32| projection.pixel_sr(x, 0);
        // f32 weights: within 1e-7 of the exact pixel solid angles.
        let close = |a: f64, b: f64| (a - b).abs() < 1e-6 * b;
        assert!(close(sr[1], pixel(0) + pixel(1) + pixel(6) + pixel(7)), "{}", sr[1]);
        assert!(close(sr[5], pixel(2) + pixel(5)), "{}", sr[5]);
        assert_eq!(sr[3], 0.0, "background is no texel");
        assert_eq!(sr.iter().filter(|&&s| s > 0.0).count(), 2);
    }
}
