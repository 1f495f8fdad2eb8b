//! Per-eye-frame visibility: for every eye-frame (or, without a manifest,
//! every image) and every part, the pixels showing the part and the distinct
//! texels of the part seen in it — `frames.csv`.
//!
//! The main counting path knows texels, not parts, and must stay as fast as
//! it is; so this is a second, optional tally ([`crate::AnalyzeOptions::frames`])
//! that rides along with the scan of each decoded row ([`PartLookup::add_row`]:
//! one table look-up per run of equal pixels, not per pixel) and, per
//! eye-frame, walks the distinct texels the scan already collected
//! ([`PartLookup::add_texels`]). The resolution-independent measures
//! ([`crate::measures`]) are sums over these rows.

use std::collections::BTreeMap;
use std::io::Write;
use std::path::Path;

use crate::bitset::{SeenSet, key_color};
use crate::color::COLOR_COUNT;
use crate::decode::PixelLayout;
use crate::error::{Error, Result};
use crate::manifest::Manifest;
use crate::output::write_atomically;
use crate::palette::Fcsp;
use crate::parts::{Legend, Pidt, UNLABELLED};
use crate::report::csv_field;

/// Name of the per-eye-frame table beside `result.json`.
pub const FRAMES_FILE: &str = "frames.csv";

/// Header of [`FRAMES_FILE`].
pub const FRAMES_HEADER: &str = "frame,time_s,eye,distance_m,part,pixels,texels";

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
    /// a texel (background wins, as in [`crate::scan::Classifier::classify`]).
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

    /// Adds the distinct texels of `seen` (keys from [`crate::bitset::color_key`])
    /// to `texels` (a [`PartLookup::tally`]) by part.
    pub fn add_texels(&self, seen: &SeenSet, texels: &mut [u64]) {
        for key in seen.keys() {
            texels[self.slot(key_color(key))] += 1;
        }
    }
}

/// One eye-frame of a manifest (group ids as [`crate::Archive`] numbers them).
#[derive(Debug, Clone, PartialEq)]
pub struct EyeFrame {
    pub frame: u32,
    pub eye: String,
    pub time_s: Option<f64>,
    pub distance_m: Option<f64>,
}

/// The eye-frames of `manifest`, indexed by eye-frame group: sorted by
/// `(frame, eye)`, as [`crate::Archive::from_manifest`] numbers them.
pub fn eye_frames(manifest: &Manifest) -> Vec<EyeFrame> {
    let records: BTreeMap<u64, &serde_json::Value> = manifest
        .extra
        .get("frames")
        .and_then(|frames| frames.as_array())
        .map(|frames| frames.iter().filter_map(|f| Some((f.get("frame")?.as_u64()?, f))).collect())
        .unwrap_or_default();
    let mut groups: BTreeMap<(u32, String), EyeFrame> = BTreeMap::new();
    for tile in &manifest.tiles {
        groups.entry((tile.frame, tile.eye.clone())).or_insert_with(|| {
            let number = |key: &str| {
                tile.extra
                    .get(key)
                    .and_then(serde_json::Value::as_f64)
                    .or_else(|| records.get(&u64::from(tile.frame))?.get(key)?.as_f64())
            };
            EyeFrame {
                frame: tile.frame,
                eye: tile.eye.clone(),
                time_s: number("time_s"),
                distance_m: number("distance_m"),
            }
        });
    }
    groups.into_values().collect()
}

/// How long one captured eye-frame stands for, and how many eyes look.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct FrameClock {
    /// Seconds between captured frames: the smallest gap between the frame
    /// numbers of the manifest over the rig's fps (a capture of every 20th
    /// frame at 60 fps: 1/3 s). `None` without the rig's fps.
    pub seconds_per_frame: Option<f64>,
    /// Distinct eyes in the manifest (2 for a stereo rig).
    pub eyes: usize,
    /// The rig's pixels per degree (at the image centre).
    pub pixels_per_degree: Option<f64>,
}

impl FrameClock {
    /// Reads the clock from a capture's manifest (`rig.settings.fps`,
    /// `rig.pixels_per_degree` and the tiles' frame numbers).
    pub fn from_manifest(manifest: &Manifest) -> FrameClock {
        let rig = manifest.extra.get("rig");
        let fps = rig.and_then(|rig| rig.get("settings")?.get("fps")?.as_f64()).filter(|fps| *fps > 0.0);
        let pixels_per_degree =
            rig.and_then(|rig| rig.get("pixels_per_degree")?.as_f64()).filter(|ppd| *ppd > 0.0);
        let mut frames: Vec<u32> = manifest.tiles.iter().map(|tile| tile.frame).collect();
        frames.sort_unstable();
        frames.dedup();
        let step = frames.windows(2).map(|pair| pair[1] - pair[0]).min().unwrap_or(1).max(1);
        let mut eyes: Vec<&str> = manifest.tiles.iter().map(|tile| tile.eye.as_str()).collect();
        eyes.sort_unstable();
        eyes.dedup();
        FrameClock {
            seconds_per_frame: fps.map(|fps| f64::from(step) / fps),
            eyes: eyes.len().max(1),
            pixels_per_degree,
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

/// Every eye-frame's tallies, in eye-frame order: the content of [`FRAMES_FILE`].
#[derive(Debug, Clone, PartialEq, Default)]
pub struct FrameTable {
    /// Part names, one column block per part.
    pub parts: Vec<String>,
    pub records: Vec<FrameRecord>,
}

impl FrameTable {
    /// Writes [`FRAMES_FILE`]: one row per eye-frame and part.
    pub fn write_csv(&self, path: &Path) -> Result<()> {
        write_atomically(path, |writer| {
            writeln!(writer, "{FRAMES_HEADER}")?;
            let parts: Vec<String> = self.parts.iter().map(|name| csv_field(name)).collect();
            for record in &self.records {
                let prefix = match &record.label {
                    FrameLabel::EyeFrame(eye_frame) => format!(
                        "{},{},{},{}",
                        eye_frame.frame,
                        optional(eye_frame.time_s),
                        csv_field(&eye_frame.eye),
                        optional(eye_frame.distance_m)
                    ),
                    FrameLabel::Image(position) => format!("{position},,,"),
                };
                for (part, name) in parts.iter().enumerate() {
                    writeln!(writer, "{prefix},{name},{},{}", record.pixels[part], record.texels[part])?;
                }
            }
            Ok(())
        })
    }
}

fn optional(value: Option<f64>) -> String {
    value.map(|v| v.to_string()).unwrap_or_default()
}

impl FrameTable {
    /// Reads a [`FRAMES_FILE`] back (for merging shards).
    pub fn read_csv(path: &Path) -> Result<FrameTable> {
        let bad = |message: String| Error::bad_file(path, message);
        let bytes = crate::input_file::read_limited(path, crate::input_file::IMAGE_LIMIT)?;
        let mut reader = csv::ReaderBuilder::new().has_headers(true).from_reader(bytes.as_slice());
        let header = reader.headers().map_err(|e| bad(e.to_string()))?.iter().collect::<Vec<_>>().join(",");
        if header != FRAMES_HEADER {
            return Err(bad(format!(
                "not a {FRAMES_FILE}: the header is {header:?}, expected {FRAMES_HEADER:?}"
            )));
        }
        let mut table = FrameTable::default();
        let mut part = 0;
        for (line, row) in reader.records().enumerate() {
            let row = row.map_err(|e| bad(e.to_string()))?;
            let field = |index: usize| row.get(index).unwrap_or_default();
            let number = |index: usize| -> Result<Option<f64>> {
                let text = field(index);
                if text.is_empty() {
                    return Ok(None);
                }
                text.parse().map(Some).map_err(|_| bad(format!("row {}: {text:?} is not a number", line + 2)))
            };
            let count = |index: usize| -> Result<u64> {
                field(index)
                    .parse()
                    .map_err(|_| bad(format!("row {}: {:?} is not a count", line + 2, field(index))))
            };
            let frame: u64 =
                field(0).parse().map_err(|_| bad(format!("row {}: no frame number", line + 2)))?;
            let label = if field(2).is_empty() && field(1).is_empty() && field(3).is_empty() {
                FrameLabel::Image(frame as usize)
            } else {
                let frame =
                    u32::try_from(frame).map_err(|_| bad(format!("row {}: frame too large", line + 2)))?;
                FrameLabel::EyeFrame(EyeFrame {
                    frame,
                    eye: field(2).to_string(),
                    time_s: number(1)?,
                    distance_m: number(3)?,
                })
            };
            let name = field(4);
            let fresh = table.records.last().is_none_or(|last: &FrameRecord| last.label != label);
            if fresh {
                part = 0;
                table.records.push(FrameRecord { label, pixels: Vec::new(), texels: Vec::new() });
            }
            if table.records.len() == 1 {
                table.parts.push(name.to_string());
            } else if table.parts.get(part).map(String::as_str) != Some(name) {
                return Err(bad(format!(
                    "row {}: part {name:?} out of the order of the first eye-frame",
                    line + 2
                )));
            }
            let record = table.records.last_mut().expect("pushed above");
            record.pixels.push(count(5)?);
            record.texels.push(count(6)?);
            part += 1;
        }
        if table.records.iter().any(|record| record.pixels.len() != table.parts.len()) {
            return Err(bad("an eye-frame lacks some parts' rows".into()));
        }
        Ok(table)
    }

    /// The tables of shards that together hold every eye-frame once, as one
    /// table in eye-frame order: what the whole archive's analysis gives.
    pub fn merged(shards: Vec<FrameTable>) -> Option<FrameTable> {
        let mut shards = shards.into_iter();
        let mut merged = shards.next()?;
        for shard in shards {
            merged.records.extend(shard.records);
        }
        let key = |label: &FrameLabel| match label {
            FrameLabel::EyeFrame(e) => (u64::from(e.frame), e.eye.clone()),
            FrameLabel::Image(position) => (*position as u64, String::new()),
        };
        merged.records.sort_by_key(|record| key(&record.label));
        Some(merged)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::color::Color;
    use crate::parts::Part;

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
            seen.insert(crate::bitset::color_key(color));
        }
        let mut texels = lookup.tally();
        lookup.add_texels(&seen, &mut texels);
        // The set holds texels only (the scan never records background).
        assert_eq!(texels, [2, 1, 1, 0]);
    }
}
