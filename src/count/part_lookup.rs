//! Tallies by part while counting: colour → part slot ([`PartLookup`]) and
//! one eye-frame's (or image's) pixels and texels per part ([`FrameRecord`]).
//!
//! The main counting path knows texels, not parts, and must stay as fast as
//! it is; so this is a second, optional tally ([`crate::AnalyzeOptions::frames`])
//! that rides along with the scan of each decoded row ([`PartLookup::add_row`]:
//! one table look-up per run of equal pixels, not per pixel) and, per
//! eye-frame, walks the distinct texels the scan already collected
//! ([`PartLookup::add_texels`]).

use crate::color::COLOR_COUNT;
use crate::color::sets::{SeenSet, key_color};
use crate::input::capture_facts::EyeFrame;
use crate::input::labels::{Legend, Pidt, UNLABELLED};
use crate::input::palette::Fcsp;
use crate::input::png_rows::PixelLayout;

/// The part name used for texels whose PIdT colour is in no legend entry.
pub const UNLABELLED_NAME: &str = "(unlabelled)";

/// The part name used for every texel when there is no PIdT.
pub const ALL_TEXELS_NAME: &str = "(all texels)";

/// Slot value of colours that are no texel (or background).
const NO_PART: u16 = u16::MAX;

/// Colour → part slot, for tallying pixels and texels by part.
pub struct PartLookup {
    /// Part names, in slot order: the legend's parts, then
    /// [`UNLABELLED_NAME`] (with a PIdT), or [`ALL_TEXELS_NAME`] alone.
    pub names: Vec<String>,
    /// Slot per colour (`0xRRGGBB`); colours past the end are no texel.
    slot_of_color: Vec<u16>,
}

impl PartLookup {
    /// The lookup for `palette`, by the legend's parts when a PIdT is given;
    /// the `backgrounds` (packed colours) map to no part even where they name
    /// a texel (background wins, as in [`crate::count::scan::Classifier::classify`]).
    pub fn new(palette: &Fcsp, parts: Option<(&Legend, &Pidt)>, backgrounds: &[u32]) -> PartLookup {
        use rayon::prelude::*;
        let names: Vec<String> = match parts {
            Some((legend, _)) => {
                legend.parts.iter().map(|p| p.name.clone()).chain([UNLABELLED_NAME.to_string()]).collect()
            }
            None => vec![ALL_TEXELS_NAME.to_string()],
        };
        // Legend index per texel, unlabelled texels in the last slot.
        let unlabelled = (names.len() - 1) as u16;
        let slot_of_texel = |texel: usize| match parts {
            Some((_, pidt)) => match pidt.part_of_texel.get(texel) {
                Some(&UNLABELLED) | None => unlabelled,
                Some(&part) => part,
            },
            None => 0,
        };
        let mut slot_of_color: Vec<u16> = match palette {
            // Texel index == colour.
            Fcsp::Canonical { .. } => (0..palette.texel_count()).into_par_iter().map(slot_of_texel).collect(),
            Fcsp::Image { colors, .. } => {
                let mut table = vec![NO_PART; COLOR_COUNT];
                for (texel, &color) in colors.iter().enumerate() {
                    table[color as usize] = slot_of_texel(texel);
                }
                table
            }
        };
        for &background in backgrounds {
            if let Some(slot) = slot_of_color.get_mut(background as usize) {
                *slot = NO_PART;
            }
        }
        PartLookup { names, slot_of_color }
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
        match self.slot_of_color.get(color as usize) {
            Some(&slot) if slot != NO_PART => usize::from(slot),
            _ => self.parts(),
        }
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
        let mut previous = u32::MAX; // no pixel packs to this
        let mut slot = self.parts();
        let mut run = 0u64;
        for pixel in row.chunks_exact(BYTES) {
            let color = if GRAY {
                u32::from(pixel[0]) * 0x01_0101
            } else {
                (u32::from(pixel[0]) << 16) | (u32::from(pixel[1]) << 8) | u32::from(pixel[2])
            };
            if color != previous {
                pixels[slot] += run;
                run = 0;
                previous = color;
                slot = self.slot(color);
            }
            run += 1;
        }
        pixels[slot] += run;
    }

    /// Adds the distinct texels of `seen` (keys from [`crate::color::color_key`])
    /// to `texels` (a [`PartLookup::tally`]) by part.
    pub fn add_texels(&self, seen: &SeenSet, texels: &mut [u64]) {
        for key in seen.keys() {
            texels[self.slot(key_color(key))] += 1;
        }
    }
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
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::color::Color;
    use std::path::Path;

    use crate::input::labels::Part;

    #[test]
    fn rows_are_tallied_by_part_with_background_and_strays_apart() {
        let palette = Fcsp::canonical(4, 4).unwrap();
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
        let pidt = Pidt::from_colors(4, 4, &colors, &legend);
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
        let mut seen = SeenSet::new();
        for color in [1u32, 2, 9, 15] {
            seen.insert(crate::color::color_key(color));
        }
        let mut texels = lookup.tally();
        lookup.add_texels(&seen, &mut texels);
        // The set holds texels only (the scan never records background).
        assert_eq!(texels, [2, 1, 1, 0]);
    }
}
