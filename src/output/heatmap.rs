//! The heatmap texture: per-texel values painted with the plasma colormap.
//!
//! The image has the palette's size and layout (the vehicle's UV layout, not
//! a picture of the vehicle: `views.png` is that), so it can replace the FCSP
//! on the unwrapped mesh. `heatmap.png` ([`HEATMAP_FILE`]) shows the measure
//! to quote, the per-texel angular area (deg²·s, as [`AreaLevels`]), whenever
//! the analysis measured it, and the paper's count otherwise; the count is
//! then in `heatmap-count.png` ([`COUNT_HEATMAP_FILE`]). Texel `p` gets
//! `plasma(count(p) / max)` (or the log scale); never-seen texels (count 0) get the neutral no-data grey
//! [`NEVER_SEEN`] of the views, so an unseen vehicle is not a navy silhouette in
//! Blender (`heatmap.glb`) and "never seen" is not confused with "seen a
//! little" (plasma's dark end). Counts are integers, so the colour of
//! every possible count is computed once into a table and texels only look it
//! up — exact, and fast enough to paint 2^24 texels in a blink.

use std::path::Path;

use rayon::prelude::*;

use crate::archive::options::{HeatmapOptions, Scale};
use crate::error::Result;
use crate::files::write_rgb_png;

/// The neutral no-data colour of texels that were never seen (count 0), in
/// `heatmap.png`, `heatmap.glb` and the views: a grey outside plasma's hues.
pub const NEVER_SEEN: [u8; 3] = [160, 160, 160];

/// The colormap position in `[0, 1]` of `count` given `max`.
pub(crate) fn position(count: u32, max: u32, scale: Scale) -> f64 {
    if max == 0 {
        return 0.0;
    }
    let count = count.min(max);
    match scale {
        Scale::Linear => f64::from(count) / f64::from(max),
        Scale::Log => (f64::from(count)).ln_1p() / (f64::from(max)).ln_1p(),
    }
}

/// The plasma colour at position `t` in `[0, 1]`.
pub fn plasma(t: f64) -> [u8; 3] {
    let color = colorous::PLASMA.eval_continuous(t.clamp(0.0, 1.0));
    [color.r, color.g, color.b]
}

/// Paints the heatmap: `texel_counts` is row-major, `width` texels per row.
/// Returns RGB bytes.
pub fn render(texel_counts: &[u32], width: u32, options: HeatmapOptions) -> Vec<u8> {
    let largest = texel_counts.par_iter().copied().max().unwrap_or(0);
    let max = options.max.unwrap_or(largest);
    // One entry per count that occurs (clamped): exact colours, no per-texel
    // math. Up to the largest count present, not to `max`: `--max 4000000000`
    // must not build a 12 GB table.
    let top = max.min(largest);
    // Never seen: the neutral no-data grey; seen: plasma.
    let color_of =
        |count: u32| if count == 0 { NEVER_SEEN } else { plasma(position(count, max, options.scale)) };
    let mut rgb = vec![0u8; texel_counts.len() * 3];
    let row = width.max(1) as usize;
    // A table sized by the largest count's value, not by how many texels
    // there are: one count of 10⁹ would make it 3 GB (issue 34). Above
    // TABLE_LIMIT each texel's colour is computed (the same colours).
    let table: Vec<[u8; 3]> = if top <= TABLE_LIMIT { (0..=top).map(color_of).collect() } else { Vec::new() };
    rgb.par_chunks_mut(row * 3).zip(texel_counts.par_chunks(row)).for_each(|(out, counts)| {
        for (pixel, &count) in out.chunks_exact_mut(3).zip(counts) {
            let count = count.min(top);
            match table.get(count as usize) {
                Some(color) => pixel.copy_from_slice(color),
                None => pixel.copy_from_slice(&color_of(count)),
            }
        }
    });
    rgb
}

/// Per-texel angular area (deg²·s) as whole levels the count painters take:
/// `level = round(value / quantum)`, at least 1 for any value above 0 (a
/// texel seen a little is not painted as never seen). The quantum is a
/// power of ten putting the largest value between 10⁴ and 10⁵ levels, so the
/// colour bar's round ticks in levels are round values, and the rounding
/// (≤ half a quantum, under 5·10⁻⁵ of the largest value) is far below one
/// colour step of the 256 the PNG holds.
#[derive(Debug, Clone, PartialEq)]
pub struct AreaLevels {
    pub levels: Vec<u32>,
    /// Value (deg²·s) of one level.
    pub quantum: f64,
}

impl AreaLevels {
    /// The levels of `values` (deg²·s per texel; NaN and values ≤ 0 as 0).
    pub fn new(values: &[f32]) -> AreaLevels {
        AreaLevels::with_top(values, largest_area(values))
    }

    /// The levels of `values` with the quantum chosen for `largest` (the
    /// largest value of several results drawn on one scale, so one level
    /// is the same deg²·s in each).
    pub fn with_top(values: &[f32], largest: f32) -> AreaLevels {
        let quantum =
            if largest > 0.0 { 10f64.powf((f64::from(largest)).log10().floor() - 4.0) } else { 1.0 };
        let levels =
            values
                .par_iter()
                .map(|&v| {
                    if v > 0.0 && v.is_finite() {
                        ((f64::from(v) / quantum).round() as u32).max(1)
                    } else {
                        0
                    }
                })
                .collect();
        AreaLevels { levels, quantum }
    }

    /// The colour scale's top level for `--area-max` (deg²·s per texel;
    /// `None` = the largest texel's), as the angular-area `heatmap.png` and the views use it.
    pub fn top(&self, area_max: Option<f64>) -> Option<u32> {
        area_max.map(|max| self.level_of(max as f32))
    }

    /// The level of `value` (deg²·s): the colour scale's top for a shared
    /// largest value.
    pub fn level_of(&self, value: f32) -> u32 {
        if value > 0.0 && value.is_finite() {
            ((f64::from(value) / self.quantum).round() as u32).max(1)
        } else {
            0
        }
    }
}

/// The largest finite value of `values` (0 when none is above 0).
pub fn largest_area(values: &[f32]) -> f32 {
    values.par_iter().copied().filter(|v| v.is_finite()).fold(|| 0f32, f32::max).reduce(|| 0f32, f32::max)
}

/// The default heatmap texture's file name: the per-texel angular area
/// (deg²·s) when the analysis measured it, else the paper's count.
pub const HEATMAP_FILE: &str = "heatmap.png";

/// The paper-compatible count heatmap texture, written beside
/// [`HEATMAP_FILE`] when that shows the angular area.
pub const COUNT_HEATMAP_FILE: &str = "heatmap-count.png";

/// Where earlier versions wrote the angular-area heatmap (now
/// [`HEATMAP_FILE`]): a result set written into such a folder removes it,
/// and the comparison page still reads it from an earlier result.
pub(crate) const EARLIER_AREA_HEATMAP_FILE: &str = "heatmap-area.png";

/// The largest count painted through the colour table (3 MiB of it).
const TABLE_LIMIT: u32 = 1 << 20;

/// Paints and writes the heatmap PNG atomically.
pub fn write_heatmap(
    path: &Path,
    texel_counts: &[u32],
    width: u32,
    height: u32,
    options: HeatmapOptions,
) -> Result<()> {
    let rgb = render(texel_counts, width, options);
    write_rgb_png(path, [width, height], &rgb, png::Compression::Fast)
}

/// Paints and writes the angular-area heatmap atomically: `area`'s levels
/// on `scale`, from 0 to `area_max` (deg²·s per texel; `None` = the largest
/// texel's).
pub fn write_area_heatmap(
    path: &Path,
    area: &AreaLevels,
    [width, height]: [u32; 2],
    scale: Scale,
    area_max: Option<f64>,
) -> Result<()> {
    write_heatmap(path, &area.levels, width, height, HeatmapOptions { scale, max: area.top(area_max) })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn never_seen_is_grey_and_seen_texels_follow_plasma_clamped() {
        let rgb = render(&[0, 2, 4, 9], 4, HeatmapOptions { scale: Scale::Linear, max: Some(4) });
        assert_eq!(&rgb[0..3], &NEVER_SEEN, "never seen is the no-data grey, not plasma's navy");
        assert_eq!(&rgb[3..6], &plasma(0.5));
        assert_eq!(&rgb[6..9], &plasma(1.0));
        assert_eq!(&rgb[9..12], &plasma(1.0), "counts above --max clamp");
        // Plasma runs from dark blue-violet to yellow.
        assert!(plasma(0.0)[2] > plasma(0.0)[0] && plasma(1.0)[0] > 200 && plasma(1.0)[1] > 200);
        assert!((position(3, 15, Scale::Log) - 0.5).abs() < 1e-12);
    }

    #[test]
    fn area_levels_keep_round_ticks_and_never_paint_a_seen_texel_as_unseen() {
        let levels = AreaLevels::new(&[0.0, 0.0137, 1e-9, f32::NAN, -1.0, 0.00685]);
        // Largest 0.0137 → quantum 1e-6: 13 700 levels.
        assert!((levels.quantum - 1e-6).abs() < 1e-18, "{}", levels.quantum);
        assert_eq!(levels.levels, [0, 13_700, 1, 0, 0, 6_850]);
        assert_eq!(AreaLevels::new(&[0.0]).levels, [0]);
    }

    #[test]
    fn a_huge_count_paints_the_same_colors_without_a_table_of_its_size() {
        let counts = [0, 1, TABLE_LIMIT + 1, 1_000_000_000, u32::MAX];
        for scale in [Scale::Linear, Scale::Log] {
            let rgb = render(&counts, 5, HeatmapOptions { scale, max: None });
            for (pixel, &count) in rgb.chunks_exact(3).zip(&counts) {
                let expected = if count == 0 { NEVER_SEEN } else { plasma(position(count, u32::MAX, scale)) };
                assert_eq!(pixel, expected, "{count}");
            }
        }
    }
}
