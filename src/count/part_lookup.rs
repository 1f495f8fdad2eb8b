//! Tallies by part while counting: colour → part slot ([`PartLookup`]) and
//! one eye-frame's (or image's) pixels and texels per part ([`FrameRecord`]).
//!
//! The main counting path knows texels, not parts, and must stay as fast as
//! it is; so this is a second, optional tally ([`crate::AnalyzeOptions::frames`])
//! that rides along with the scan of each decoded row ([`PartLookup::add_row`]:
//! one table look-up per run of equal pixels, not per pixel, and one solid
//! angle per span of one part) and, per
//! eye-frame, walks the distinct texels the scan already collected
//! ([`PartLookup::add_texels`]).

use crate::archive::capture_facts::EyeFrame;
use crate::archive::labels::{Legend, Pidt, UNLABELLED};
use crate::archive::palette::Fcsp;
use crate::color::COLOR_COUNT;
use crate::color::sets::{SeenSet, key_color};
use crate::count::slot_table::SlotTable;
use crate::optics::solid_angle::{RowWeights, TileView};
use crate::png::rows::PixelLayout;
use crate::simd::SlotSpans;

/// The part name used for texels whose PIdT colour is in no legend entry.
pub(crate) const UNLABELLED_NAME: &str = "(unlabelled)";

/// The part name used for every texel when there is no PIdT.
pub(crate) const ALL_TEXELS_NAME: &str = "(all texels)";

/// Colour → part slot, for tallying pixels and texels by part.
pub struct PartLookup {
    /// Part names, in slot order: the legend's parts, then
    /// [`UNLABELLED_NAME`] (with a PIdT), or [`ALL_TEXELS_NAME`] alone.
    pub names: Vec<String>,
    /// Slot per colour (`0xRRGGBB`); background and colours that are no
    /// texel get the slot after the parts'.
    slots: SlotTable,
}

impl PartLookup {
    /// The lookup for `palette`, by the legend's parts when a PIdT is given;
    /// the `backgrounds` (packed colours) map to no part even where they name
    /// a texel (background wins, as in [`crate::count::scan::Classifier::classify`]).
    pub fn new(palette: &Fcsp, parts: Option<(&Legend, &Pidt)>, backgrounds: &[u32]) -> PartLookup {
        let names: Vec<String> = match parts {
            Some((legend, _)) => {
                legend.parts.iter().map(|p| p.name.clone()).chain([UNLABELLED_NAME.to_string()]).collect()
            }
            None => vec![ALL_TEXELS_NAME.to_string()],
        };
        // Legend index per texel, unlabelled texels in the last slot;
        // background and colours that are no texel in the slot after it.
        let unlabelled = (names.len() - 1) as u16;
        let no_part = names.len() as u16;
        let slot_of_texel = |texel: usize| match parts {
            Some((_, pidt)) => match pidt.part_of_texel.get(texel) {
                Some(&UNLABELLED) | None => unlabelled,
                Some(&part) => part,
            },
            None => 0,
        };
        let background = |color: u32| backgrounds.contains(&color);
        let slots = match palette {
            // Texel index == colour.
            Fcsp::Canonical { width, height } => SlotTable::new([*width, *height], no_part, |color| {
                if background(color) { no_part } else { slot_of_texel(color as usize) }
            }),
            Fcsp::Image { colors, .. } => {
                let mut flat = vec![no_part; COLOR_COUNT];
                for (texel, &color) in colors.iter().enumerate() {
                    if !background(color) {
                        flat[color as usize] = slot_of_texel(texel);
                    }
                }
                SlotTable::new([4096, 4096], no_part, |color| flat[color as usize])
            }
        };
        PartLookup { names, slots }
    }

    /// Number of part slots (the length of a tally, see [`PartLookup::tally`]).
    pub fn parts(&self) -> usize {
        self.names.len()
    }

    /// A zeroed tally: one count per part plus one slot for non-texels.
    pub fn tally(&self) -> Vec<u64> {
        vec![0; self.parts() + 1]
    }

    /// One table load: background and strays are folded into the table.
    #[inline(always)]
    fn slot(&self, color: u32) -> usize {
        usize::from(self.slots.get(color))
    }

    /// Adds the pixels of one decoded row to `pixels` (a [`PartLookup::tally`])
    /// by part. Runs of one colour — background, or a magnified texel — cost
    /// one comparison per pixel and one look-up per run.
    pub fn add_row(&self, row: &[u8], layout: PixelLayout, pixels: &mut [u64]) {
        match layout {
            PixelLayout::Rgb => self.add_row_of::<3, false>(row, pixels),
            PixelLayout::Rgba => self.add_row_of::<4, false>(row, pixels),
            PixelLayout::Gray => self.add_row_of::<1, true>(row, pixels),
            PixelLayout::GrayAlpha => self.add_row_of::<2, true>(row, pixels),
        }
    }

    #[inline(always)]
    fn add_row_of<const BYTES: usize, const GRAY: bool>(&self, row: &[u8], pixels: &mut [u64]) {
        for (start, end, slot) in self.part_spans::<BYTES, GRAY>(row) {
            pixels[slot] += (end - start) as u64;
        }
    }

    /// The row's maximal spans of one part slot, `(first pixel, end, slot)`:
    /// runs of equal colour, joined while their colours name the same part.
    #[inline(always)]
    fn part_spans<'r, const BYTES: usize, const GRAY: bool>(
        &'r self,
        row: &'r [u8],
    ) -> impl Iterator<Item = (usize, usize, usize)> + 'r {
        let mut runs =
            Runs::<BYTES, GRAY>::new(row).map(|(start, end, color)| (start, end, self.slot(color)));
        let mut pending = runs.next();
        std::iter::from_fn(move || {
            let (start, mut end, slot) = pending?;
            pending = None;
            for (next_start, next_end, next_slot) in runs.by_ref() {
                if next_slot != slot {
                    pending = Some((next_start, next_end, next_slot));
                    break;
                }
                end = next_end;
            }
            Some((start, end, slot))
        })
    }

    /// Adds the pixels of row `y` of an image to `tally` by part, and, when
    /// the tally knows where the image lies in its eye ([`PartPixels::view`]),
    /// their solid angle (one pair of `atan` per run of equal pixels).
    pub fn add_row_at(&self, row: &[u8], layout: PixelLayout, y: u32, tally: &mut PartPixels) {
        if tally.view.is_none() {
            return self.add_row(row, layout, &mut tally.pixels);
        }
        let mut spans = RowSpans::new(tally, y);
        match layout {
            PixelLayout::Rgb => self.add_spans::<3, false>(row, &mut spans),
            PixelLayout::Rgba => self.add_spans::<4, false>(row, &mut spans),
            PixelLayout::Gray => self.add_spans::<1, true>(row, &mut spans),
            PixelLayout::GrayAlpha => self.add_spans::<2, true>(row, &mut spans),
        }
        spans.finish(row.len() / layout.bytes_per_pixel());
    }

    /// Pixels and solid angles by part: one solid angle per span of one
    /// part (two `atan` at each end), so a part covered by many texels, each
    /// a few pixels wide, costs what one run does. The spans go through
    /// [`RowSpans`], as the AVX-512 kernel's do, so both add the same bits.
    fn add_spans<const BYTES: usize, const GRAY: bool>(&self, row: &[u8], spans: &mut RowSpans) {
        for (start, _, slot) in self.part_spans::<BYTES, GRAY>(row) {
            spans.change(start, slot);
        }
    }

    /// The slot table, for a kernel that looks slots up itself (see
    /// [`RowSpans`]).
    pub(crate) fn slot_table(&self) -> &SlotTable {
        &self.slots
    }

    /// Adds the distinct texels of `seen` (keys from [`crate::color::color_key`])
    /// to `texels` (a [`PartLookup::tally`]) by part.
    pub fn add_texels(&self, seen: &SeenSet, texels: &mut [u64]) {
        // A word of the set holds two runs of 32 consecutive colours (the
        // key's low 5 bits are the colour's): each run is added a block of
        // the slot table at a time.
        seen.for_each_word(|index, word| {
            for half in 0..2u32 {
                let members = (word >> (32 * half)) as u32;
                if members != 0 {
                    let first = key_color(((index as u32) << 6) | (half << 5));
                    self.slots.add_32(first, members, texels);
                }
            }
        });
    }
}

/// One row's part tally built by a kernel that finds the pixels where the
/// slot changes itself (the AVX-512 counting kernel, in the same pass as its
/// count): it calls [`RowSpans::change`] at each, and [`RowSpans::finish`] at
/// the row's end. The spans are those of [`PartLookup::part_spans`], and
/// [`PartLookup::add_row_at`] adds its own through it too, so both paths
/// do the same float operations in the same order: the same bits.
pub(crate) struct RowSpans<'t> {
    pixels: &'t mut [u64],
    solid: &'t mut [u128],
    /// With a [`PartPixels::view`]: the row's weights.
    weights: Option<RowWeights>,
    /// The open span: its first pixel, slot and left edge's `G`.
    start: usize,
    slot: usize,
    start_edge: f64,
}

impl<'t> RowSpans<'t> {
    /// Row `y` of the image `tally` is for, before its first pixel.
    pub(crate) fn new(tally: &'t mut PartPixels, y: u32) -> RowSpans<'t> {
        let weights = tally.view.map(|view| RowWeights::new(&view, y));
        let start_edge = weights.as_ref().map_or(0.0, |weights| weights.edge(0));
        let (pixels, solid) = (&mut tally.pixels, &mut tally.solid_angle_units);
        RowSpans { pixels, solid, weights, start: 0, slot: 0, start_edge }
    }

    /// Pixel `at` has slot `slot`, unlike the pixel before it (or it is the
    /// row's first pixel): the open span ends there.
    #[inline]
    pub(crate) fn change(&mut self, at: usize, slot: usize) {
        if at > self.start {
            self.close(at);
        }
        self.start = at;
        self.slot = slot;
    }

    /// The row ends at pixel `end` (its width).
    pub(crate) fn finish(mut self, end: usize) {
        if end > self.start {
            self.close(end);
        }
    }

    /// Adds the open span, which ends at `end`.
    fn close(&mut self, end: usize) {
        self.pixels[self.slot] += (end - self.start) as u64;
        if let Some(weights) = &self.weights {
            let edge = weights.edge(end);
            self.solid[self.slot] += solid_angle_units(edge - self.start_edge);
            self.start_edge = edge;
        }
    }
}

/// The fused kernel's view of a row's spans.
impl SlotSpans for RowSpans<'_> {
    #[inline(always)]
    fn change(&mut self, at: usize, slot: usize) {
        RowSpans::change(self, at, slot);
    }

    #[inline(always)]
    fn finish(self, end: usize) {
        RowSpans::finish(self, end);
    }
}

/// The maximal runs of equal colour in a decoded row, `(first pixel, end,
/// colour)`: the colour is `0xRRGGBB` (grey `g` as `0xgggggg`); alpha is
/// ignored, as by the counting kernels. A run's end is found 16 bytes at a
/// time (each byte against the byte one pixel earlier, alpha masked out), so
/// a run of background or of a magnified texel costs a few word compares, not
/// one per pixel, and the runs are exactly those a pixel-by-pixel comparison
/// gives (the solid-angle sums depend on where runs end).
pub(crate) struct Runs<'r, const BYTES: usize, const GRAY: bool> {
    row: &'r [u8],
    /// Pixels in the row.
    pixels: usize,
    /// The next run's first pixel.
    next: usize,
}

impl<'r, const BYTES: usize, const GRAY: bool> Runs<'r, BYTES, GRAY> {
    /// Bytes of a 16-byte block that carry colour: all but alpha (RGBA's 4th
    /// and grey-alpha's 2nd byte of each pixel); blocks stay aligned to
    /// pixels for 1, 2 and 4 bytes per pixel, and RGB has no alpha.
    const COLOR_BYTES: u128 = match BYTES {
        2 => 0x00FF_00FF_00FF_00FF_00FF_00FF_00FF_00FF,
        4 => 0x00FF_FFFF_00FF_FFFF_00FF_FFFF_00FF_FFFF,
        _ => u128::MAX,
    };

    pub(crate) fn new(row: &'r [u8]) -> Self {
        Runs { row, pixels: row.len() / BYTES, next: 0 }
    }

    #[inline(always)]
    fn color(&self, pixel: usize) -> u32 {
        let p = &self.row[pixel * BYTES..];
        if GRAY {
            u32::from(p[0]) * 0x01_0101
        } else {
            (u32::from(p[0]) << 16) | (u32::from(p[1]) << 8) | u32::from(p[2])
        }
    }

    /// The first pixel after `first` whose colour differs from `first`'s.
    #[inline(always)]
    fn run_end(&self, first: usize, color: u32) -> usize {
        let bytes = self.pixels * BYTES;
        let mut k = (first + 1) * BYTES;
        while k + 16 <= bytes {
            let block = |at: usize| {
                let mut bytes = [0u8; 16];
                bytes.copy_from_slice(&self.row[at..at + 16]);
                u128::from_le_bytes(bytes)
            };
            if (block(k) ^ block(k - BYTES)) & Self::COLOR_BYTES != 0 {
                break;
            }
            k += 16;
        }
        // Every colour byte before k equals the one a pixel earlier: the
        // pixels before k / BYTES have `color`; check the rest one by one.
        let mut pixel = (k / BYTES).max(first + 1);
        while pixel < self.pixels && self.color(pixel) == color {
            pixel += 1;
        }
        pixel
    }
}

impl<const BYTES: usize, const GRAY: bool> Iterator for Runs<'_, BYTES, GRAY> {
    type Item = (usize, usize, u32);

    #[inline(always)]
    fn next(&mut self) -> Option<(usize, usize, u32)> {
        let first = self.next;
        if first >= self.pixels {
            return None;
        }
        let color = self.color(first);
        self.next = self.run_end(first, color);
        Some((first, self.next, color))
    }
}

/// Units of [`PartPixels::solid_angle_units`]: 2⁻⁸⁰ sr. Runs' solid angles
/// are added as integers, so an eye-frame's sum does not depend on the order
/// its tiles are counted in (the PNG path and the capture's `--count` give
/// the same bits); a pixel at 480 px/° (≈ 1.3e-9 sr) is ≈ 1.6e15 units, and
/// 2¹²⁸ units are 2⁴⁸ sr.
pub(crate) const SOLID_ANGLE_UNITS_PER_SR: f64 = (1u128 << 80) as f64;

/// `sr` (≥ 0, or a rounding error below 0) in [`SOLID_ANGLE_UNITS_PER_SR`].
fn solid_angle_units(sr: f64) -> u128 {
    (sr.abs() * SOLID_ANGLE_UNITS_PER_SR) as u128
}

/// One image's (or eye-frame's) tally by part: pixels and, when the eye's
/// projection is known, the solid angle they subtend. Both have one slot per
/// part plus one for non-texels, as [`PartLookup::tally`].
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PartPixels {
    pub pixels: Vec<u64>,
    /// Solid angle in units of 2⁻⁸⁰ sr ([`SOLID_ANGLE_UNITS_PER_SR`]); zero
    /// where no image of the tally had a [`PartPixels::view`].
    pub solid_angle_units: Vec<u128>,
    /// Where the image being scanned lies in its eye (`None`: unknown).
    pub view: Option<TileView>,
}

impl PartPixels {
    /// A zeroed tally for `lookup`'s parts.
    pub fn new(lookup: &PartLookup) -> PartPixels {
        PartPixels { pixels: lookup.tally(), solid_angle_units: vec![0; lookup.parts() + 1], view: None }
    }

    /// Adds `other`'s pixels and solid angles.
    pub fn add(&mut self, other: &PartPixels) {
        self.pixels.iter_mut().zip(&other.pixels).for_each(|(sum, pixels)| *sum += pixels);
        self.solid_angle_units.iter_mut().zip(&other.solid_angle_units).for_each(|(sum, u)| *sum += u);
    }

    /// Back to zero (the view stays).
    pub fn clear(&mut self) {
        self.pixels.fill(0);
        self.solid_angle_units.fill(0);
    }
}

/// One eye-frame's tallies by part from tiles counted in memory (the
/// capture's `--count`, [`crate::TileCounter`]), before it is labelled by
/// the manifest's eye-frames.
pub(crate) struct TiledEyeFrame {
    pub frame: u32,
    pub eye: String,
    /// Its pixels (and solid angles) by part, the non-texel slot last.
    pub pixels: PartPixels,
    /// Its distinct texels by part, without the non-texel slot.
    pub texels: Vec<u64>,
}

/// The eye-frames' tallies by part of tiles counted in memory.
pub(crate) struct TiledParts {
    /// Part names ([`PartLookup::names`]).
    pub names: Vec<String>,
    /// Whether pixels were weighted by their solid angle (the eyes'
    /// projection was known).
    pub weighted: bool,
    pub records: Vec<TiledEyeFrame>,
}

/// What one row block of [`FRAMES_FILE`] is about.
#[derive(Debug, Clone, PartialEq)]
pub enum FrameLabel {
    /// An eye-frame of the manifest.
    EyeFrame(EyeFrame),
    /// An image of an archive without manifest: its position in name order
    /// (written as the `frame` column; `eye`, time and distance are empty).
    Image(usize),
}

/// One eye-frame's (or image's) tallies by part.
#[derive(Debug, Clone, PartialEq)]
pub struct FrameRecord {
    pub label: FrameLabel,
    /// Pixels showing each part ([`PartLookup::names`] order).
    pub pixels: Vec<u64>,
    /// Distinct texels of each part seen.
    pub texels: Vec<u64>,
    /// Solid angle each part subtends, sr (the sum of its pixels' solid
    /// angles in the eye's projection); `None` when the projection is unknown.
    pub solid_angle_sr: Option<Vec<f64>>,
}

impl FrameRecord {
    /// The record of one eye-frame: its pixels (and solid angles, when
    /// `weighted`) and the distinct texels of `seen`, by part, without the
    /// non-texel slot.
    pub fn from_tally(
        label: FrameLabel,
        lookup: &PartLookup,
        tally: PartPixels,
        seen: &SeenSet,
        weighted: bool,
    ) -> FrameRecord {
        let mut texels = lookup.tally();
        lookup.add_texels(seen, &mut texels);
        texels.pop();
        FrameRecord::from_parts(label, tally, texels, weighted)
    }

    /// The record of a tally and its texels (the non-texel slots dropped
    /// from the tally; `texels` already without it).
    pub fn from_parts(label: FrameLabel, tally: PartPixels, texels: Vec<u64>, weighted: bool) -> FrameRecord {
        let PartPixels { mut pixels, mut solid_angle_units, .. } = tally;
        pixels.pop();
        solid_angle_units.pop();
        let solid_angle_sr = solid_angle_units.iter().map(|&u| u as f64 / SOLID_ANGLE_UNITS_PER_SR).collect();
        FrameRecord { label, pixels, texels, solid_angle_sr: weighted.then_some(solid_angle_sr) }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::color::Color;
    use std::path::Path;

    use crate::archive::labels::Part;

    #[test]
    fn rows_are_tallied_by_part_with_background_and_strays_apart() {
        let palette = Fcsp::canonical([4, 4]).unwrap();
        let legend = Legend::new(
            Path::new("parts.csv"),
            vec![
                Part { name: "a".into(), color: Color::from_packed(0x010101) },
                Part { name: "b".into(), color: Color::from_packed(0x020202) },
            ],
        )
        .unwrap();
        // Texels 0-7 are part a, 8-14 part b, 15 unlabelled.
        let mut colors = vec![0x010101; 8];
        colors.extend(vec![0x020202; 7]);
        colors.push(0x030303);
        let pidt = Pidt::from_colors([4, 4], &colors, &legend);
        // Texel 3 is background.
        let lookup = PartLookup::new(&palette, Some((&legend, &pidt)), &[3]);
        assert_eq!(lookup.names, ["a", "b", UNLABELLED_NAME]);
        let row: Vec<u8> = [1u32, 1, 3, 9, 9, 9, 15, 0xFFFFFF, 2]
            .iter()
            .flat_map(|&c| [(c >> 16) as u8, (c >> 8) as u8, c as u8, 255])
            .collect();
        let mut pixels = lookup.tally();
        lookup.add_row(&row, PixelLayout::Rgba, &mut pixels);
        // a: 1,1,2; b: 9,9,9; unlabelled: 15; none: background 3 and stray.
        assert_eq!(pixels, [3, 3, 1, 2]);
        // Spans of one part join runs of different texels (the stray and the
        // background texel 3 are both "no part", so they join too).
        let spans: Vec<_> = lookup.part_spans::<4, false>(&row).collect();
        assert_eq!(spans, [(0, 2, 0), (2, 3, 3), (3, 6, 1), (6, 7, 2), (7, 8, 3), (8, 9, 0)]);
        let joined: Vec<_> =
            lookup.part_spans::<4, false>(&[0, 0, 1, 255, 0, 0, 2, 255, 0, 0, 1, 7]).collect();
        assert_eq!(joined, [(0, 3, 0)]);
        // Weighted: the same pixels, and each part's solid angle is the sum
        // of its pixels' (row 5 of a tile at [10, 20] of a 4 px/° eye).
        let projection = crate::optics::solid_angle::EyeProjection::new(107.0, [428, 540]).unwrap();
        let mut tally = PartPixels::new(&lookup);
        tally.view = Some(TileView { projection, origin: [10, 20] });
        lookup.add_row_at(&row, PixelLayout::Rgba, 5, &mut tally);
        assert_eq!(tally.pixels, pixels);
        let sr = |xs: &[u32]| xs.iter().map(|&x| projection.pixel_sr(10 + x, 25)).sum::<f64>();
        for (part, xs) in [&[0u32, 1, 8][..], &[3, 4, 5], &[6], &[2, 7]].iter().enumerate() {
            let units = tally.solid_angle_units[part] as f64 / SOLID_ANGLE_UNITS_PER_SR;
            assert!((units - sr(xs)).abs() < 1e-15, "part {part}");
        }
        let mut seen = SeenSet::new();
        for color in [1u32, 2, 9, 15] {
            seen.insert(crate::color::color_key(color));
        }
        let mut texels = lookup.tally();
        lookup.add_texels(&seen, &mut texels);
        // The set holds texels only (the scan never records background).
        assert_eq!(texels, [2, 1, 1, 0]);
    }

    /// The runs as a pixel-by-pixel comparison finds them (the old loop).
    fn runs_one_by_one(row: &[u8], bytes: usize, gray: bool) -> Vec<(usize, usize, u32)> {
        let mut runs: Vec<(usize, usize, u32)> = Vec::new();
        for (x, p) in row.chunks_exact(bytes).enumerate() {
            let color = if gray {
                u32::from(p[0]) * 0x01_0101
            } else {
                (u32::from(p[0]) << 16) | (u32::from(p[1]) << 8) | u32::from(p[2])
            };
            match runs.last_mut() {
                Some(run) if run.2 == color => run.1 = x + 1,
                _ => runs.push((x, x + 1, color)),
            }
        }
        runs
    }

    #[test]
    fn runs_found_a_block_at_a_time_are_those_found_pixel_by_pixel() {
        // Rows of runs 1-70 pixels long over a few colours (so equal
        // neighbours across a block edge happen), random alpha, odd lengths.
        let mut state = 0x1234_5678_u64;
        let mut random = |n: u64| {
            state = state.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
            (state >> 33) % n
        };
        for case in 0..400 {
            for (bytes, gray) in [(1usize, true), (2, true), (3, false), (4, false)] {
                let mut row = Vec::new();
                let pixels = 1 + random(300) as usize;
                while row.len() < pixels * bytes {
                    let run = 1 + random(if case % 2 == 0 { 70 } else { 4 }) as usize;
                    let color = [random(3) as u8, random(2) as u8, random(2) as u8];
                    for _ in 0..run {
                        match bytes {
                            1 => row.push(color[0]),
                            2 => row.extend([color[0], random(256) as u8]),
                            3 => row.extend(color),
                            _ => row.extend([color[0], color[1], color[2], random(256) as u8]),
                        }
                    }
                }
                row.truncate(pixels * bytes + random(bytes as u64) as usize); // a stray partial pixel
                let found: Vec<_> = match (bytes, gray) {
                    (1, _) => Runs::<1, true>::new(&row).collect(),
                    (2, _) => Runs::<2, true>::new(&row).collect(),
                    (3, _) => Runs::<3, false>::new(&row).collect(),
                    _ => Runs::<4, false>::new(&row).collect(),
                };
                assert_eq!(found, runs_one_by_one(&row, bytes, gray), "case {case}, {bytes} bytes per pixel");
            }
        }
    }
}
