//! `frames-strip.png`: what the pedestrian saw — a few frames of one eye,
//! spread over the scenario, put together from the archive's tiles with
//! every vehicle pixel in its part's colour (the pixel's palette colour
//! names a texel, the PIdT gives the texel's part colour) and everything
//! else light grey. Each frame is labelled with its time and distance.
//!
//! Drawn only from tile PNGs: a `--count` archive has none, and an archive
//! on an image palette (`--palette FILE`) would need a search per colour;
//! [`frame_strip_skipped`] says why a strip is missing, for the report.

use std::collections::BTreeMap;
use std::path::Path;

use plotters::prelude::*;

use crate::error::{Error, Result};
use crate::input::manifest::{Manifest, TileEntry};
use crate::input::png_rows::read_color_image;

/// The strip's file name in a result set.
pub const FRAME_STRIP_FILE: &str = "frames-strip.png";
/// Frames in the strip.
const STRIP_FRAMES: usize = 5;
/// Height of one frame in the strip, pixels (frames are scaled to it).
pub const STRIP_FRAME_HEIGHT: u32 = 400;
/// Room for the label above each frame, and the gap between frames.
const LABEL: u32 = 34;
const GAP: u32 = 8;
/// Pixels that are not the vehicle (background, occluders).
pub const STRIP_BACKGROUND: [u8; 3] = [225, 225, 225];
/// Vehicle pixels whose texel no legend part names.
pub const STRIP_UNLABELLED: [u8; 3] = [90, 90, 90];

/// One eye-frame: its tiles by (row, column).
struct EyeFrameTiles<'a> {
    frame: u32,
    eye: &'a str,
    tiles: BTreeMap<(u32, u32), &'a TileEntry>,
}

impl EyeFrameTiles<'_> {
    fn written(&self) -> usize {
        self.tiles.values().filter(|tile| tile.file.is_some()).count()
    }

    /// A number of the tiles' records, else of the manifest's frame record.
    fn number(&self, manifest: &Manifest, key: &str) -> Option<f64> {
        let from_tiles = self.tiles.values().find_map(|tile| tile.extra.get(key)?.as_f64());
        from_tiles.or_else(|| {
            let frames = manifest.extra.get("frames")?.as_array()?;
            let record = frames
                .iter()
                .find(|f| f.get("frame").and_then(|n| n.as_u64()) == Some(u64::from(self.frame)))?;
            record.get(key)?.as_f64()
        })
    }
}

/// Why an archive gives no strip, or `None` when it can give one.
pub fn frame_strip_skipped(manifest: &Manifest, canonical_palette: bool) -> Option<&'static str> {
    let written =
        manifest.extra.get("capture").and_then(|c| c.get("tiles_written")).and_then(|w| w.as_bool());
    if written == Some(false) || !manifest.tiles.iter().any(|tile| tile.file.is_some()) {
        Some("the archive has no tile images (a --count capture), so there is no frame strip")
    } else if !canonical_palette {
        Some("the archive uses an image palette; the frame strip is drawn for canonical palettes only")
    } else {
        None
    }
}

/// The first eye's eye-frames that have written tiles, in frame order, and
/// `STRIP_FRAMES` of them spread evenly (first and last included).
fn chosen_frames(manifest: &Manifest) -> Vec<EyeFrameTiles<'_>> {
    let first_eye = manifest.tiles.iter().map(|tile| tile.eye.as_str()).min();
    let mut frames: BTreeMap<u32, EyeFrameTiles> = BTreeMap::new();
    for tile in manifest.tiles.iter().filter(|tile| Some(tile.eye.as_str()) == first_eye) {
        let entry = frames.entry(tile.frame).or_insert_with(|| EyeFrameTiles {
            frame: tile.frame,
            eye: &tile.eye,
            tiles: BTreeMap::new(),
        });
        entry.tiles.insert((tile.row, tile.col), tile);
    }
    let mut seen: Vec<EyeFrameTiles> = frames.into_values().filter(|frame| frame.written() > 0).collect();
    if seen.len() <= STRIP_FRAMES {
        return seen;
    }
    let last = seen.len() - 1;
    let picks: Vec<usize> = (0..STRIP_FRAMES).map(|k| k * last / (STRIP_FRAMES - 1)).collect();
    let mut index = 0;
    seen.retain(|_| {
        index += 1;
        picks.contains(&(index - 1))
    });
    seen
}

/// One eye-frame as the eye saw it, in part colours: RGB, its size, and
/// how many of its tiles could not be read.
fn assemble(archive: &Path, frame: &EyeFrameTiles, part_colours: &[u32]) -> (Vec<u8>, [u32; 2], usize) {
    let rows = frame.tiles.keys().map(|k| k.0).max().unwrap_or(0) + 1;
    let columns = frame.tiles.keys().map(|k| k.1).max().unwrap_or(0) + 1;
    let mut decoded = Vec::new();
    let mut unreadable = 0;
    for (&(row, column), tile) in &frame.tiles {
        let Some(file) = &tile.file else { continue };
        match read_color_image(&archive.join(file), |_, _| Ok(())) {
            Ok(image) => decoded.push((row, column, image)),
            Err(_) => unreadable += 1,
        }
    }
    let [tile_width, tile_height] =
        decoded.first().map_or([1, 1], |(_, _, image)| [image.width, image.height]);
    let size = [tile_width * columns, tile_height * rows];
    let mut rgb = STRIP_BACKGROUND.repeat((size[0] * size[1]) as usize);
    for (row, column, image) in decoded {
        if [image.width, image.height] != [tile_width, tile_height] {
            unreadable += 1;
            continue;
        }
        for (index, &colour) in image.colors.iter().enumerate() {
            let x = column * tile_width + index as u32 % tile_width;
            let y = row * tile_height + index as u32 / tile_width;
            let pixel = ((y * size[0] + x) * 3) as usize;
            let shown = match part_colours.get(colour as usize) {
                Some(&u32::MAX) => STRIP_UNLABELLED,
                Some(&BACKGROUND_TEXEL) | None => continue,
                Some(&part) => crate::Color::from_packed(part).rgb(),
            };
            rgb[pixel..pixel + 3].copy_from_slice(&shown);
        }
    }
    (rgb, size, unreadable)
}

/// Marks a background colour in the texel table.
const BACKGROUND_TEXEL: u32 = u32::MAX - 1;

/// Every texel's part colour (packed RGB) from the PIdT, `u32::MAX` where
/// no legend part names the texel's colour, [`BACKGROUND_TEXEL`] for the
/// capture's background colours.
fn part_colours(
    pidt: &Path,
    legend: &[crate::PartStats],
    palette: [u32; 2],
    background: &[crate::Color],
) -> Result<Vec<u32>> {
    let image = read_color_image(pidt, |width, height| {
        if [width, height] == palette {
            Ok(())
        } else {
            Err(Error::bad_file(
                pidt,
                format!("is {width}×{height}, the palette {}×{}", palette[0], palette[1]),
            ))
        }
    })?;
    let named: std::collections::HashSet<u32> =
        legend.iter().filter_map(|part| part.color.map(|c| c.packed())).collect();
    let mut colours: Vec<u32> =
        image.colors.into_iter().map(|c| if named.contains(&c) { c } else { u32::MAX }).collect();
    // Background colours may name texels of a canonical palette: they are not the vehicle.
    for colour in background {
        if let Some(texel) = colours.get_mut(colour.packed() as usize) {
            *texel = BACKGROUND_TEXEL;
        }
    }
    Ok(colours)
}

/// What the strip is drawn from.
pub struct StripInputs<'a> {
    pub archive: &'a Path,
    pub manifest: &'a Manifest,
    pub pidt: &'a Path,
    pub parts: &'a [crate::PartStats],
    /// The palette's width and height (canonical).
    pub palette: [u32; 2],
    /// The capture's background colours.
    pub background: &'a [crate::Color],
}

/// Writes the strip into `path`; returns the frames shown.
pub fn write_frame_strip(path: &Path, inputs: &StripInputs) -> Result<Vec<u32>> {
    let colours = part_colours(inputs.pidt, inputs.parts, inputs.palette, inputs.background)?;
    let frames = chosen_frames(inputs.manifest);
    let assembled: Vec<_> = frames.iter().map(|frame| assemble(inputs.archive, frame, &colours)).collect();
    let crop = vehicle_region(&assembled);
    let mut panels = Vec::new();
    for (frame, (rgb, size, unreadable)) in frames.iter().zip(assembled) {
        let (rgb, size) = cropped(&rgb, size, crop);
        let scaled = scale_to_height(&rgb, size, STRIP_FRAME_HEIGHT);
        let mut label = format!("{} eye, frame {}", frame.eye, frame.frame);
        if let Some(time) = frame.number(inputs.manifest, "time_s") {
            label.push_str(&format!(" · {time:.2} s"));
        }
        if let Some(distance) = frame.number(inputs.manifest, "distance_m") {
            label.push_str(&format!(" · {distance:.1} m"));
        }
        if unreadable > 0 {
            label.push_str(&format!(" · {unreadable} tiles unreadable"));
        }
        panels.push((scaled, label));
    }
    let width = panels.iter().map(|((_, size), _)| size[0] + GAP).sum::<u32>().max(GAP) - GAP;
    let height = STRIP_FRAME_HEIGHT + LABEL;
    let mut strip = [255u8; 3].repeat((width * height) as usize);
    let mut left = 0;
    for ((rgb, size), _) in &panels {
        for y in 0..size[1] {
            let from = (y * size[0] * 3) as usize;
            let to = (((y + LABEL) * width + left) * 3) as usize;
            strip[to..to + (size[0] * 3) as usize].copy_from_slice(&rgb[from..from + (size[0] * 3) as usize]);
        }
        left += size[0] + GAP;
    }
    label_panels(&mut strip, [width, height], &panels);
    crate::files::write_rgb_png(path, width, height, &strip, png::Compression::Fast)?;
    Ok(frames.iter().map(|frame| frame.frame).collect())
}

type Panel = ((Vec<u8>, [u32; 2]), String);

/// Each frame's label above it, when a font is found.
fn label_panels(strip: &mut [u8], [width, height]: [u32; 2], panels: &[Panel]) {
    if !crate::output::plots::font_available() {
        return;
    }
    let root = BitMapBackend::with_buffer(strip, (width, height)).into_drawing_area();
    let style = ("sans-serif", 18).into_font().color(&BLACK);
    let mut left = 0;
    let mut drawn: std::result::Result<(), _> = Ok(());
    for ((_, size), label) in panels {
        drawn = drawn.and(root.draw(&Text::new(label.clone(), (left as i32 + 4, 8), style.clone())));
        left += size[0] + GAP;
    }
    // Labels are a courtesy: a drawing error leaves the frames as they are.
    let _ = drawn.and(root.present());
}

/// The region (x, y, width, height) holding the vehicle in every frame,
/// with a margin of a fifth of its size, at least a sixth of the frame
/// high: one crop for all frames, so sizes compare.
fn vehicle_region(frames: &[(Vec<u8>, [u32; 2], usize)]) -> [u32; 4] {
    let Some((_, size, _)) = frames.first() else { return [0, 0, 1, 1] };
    let [width, height] = *size;
    let (mut low, mut high) = ([u32::MAX; 2], [0u32; 2]);
    for (rgb, frame_size, _) in frames.iter().filter(|(_, s, _)| s == size) {
        for (index, pixel) in rgb.chunks_exact(3).enumerate() {
            if pixel != STRIP_BACKGROUND {
                let (x, y) = (index as u32 % frame_size[0], index as u32 / frame_size[0]);
                low = [low[0].min(x), low[1].min(y)];
                high = [high[0].max(x), high[1].max(y)];
            }
        }
    }
    if low[0] > high[0] {
        return [0, 0, width, height];
    }
    let span = [high[0] - low[0] + 1, (high[1] - low[1] + 1).max(height / 6)];
    let margin = [span[0] / 5 + 4, span[1] / 5 + 4];
    let x = low[0].saturating_sub(margin[0]);
    let y = low[1].saturating_sub(margin[1]);
    [x, y, (high[0] + margin[0] + 1).min(width) - x, (low[1] + span[1] + margin[1]).min(height) - y]
}

/// `region` (x, y, width, height) of a picture of `size` (the whole
/// picture when it does not fit).
fn cropped(rgb: &[u8], size: [u32; 2], [x, y, width, height]: [u32; 4]) -> (Vec<u8>, [u32; 2]) {
    if x + width > size[0] || y + height > size[1] {
        return (rgb.to_vec(), size);
    }
    let mut out = Vec::with_capacity((width * height * 3) as usize);
    for row in y..y + height {
        let from = ((row * size[0] + x) * 3) as usize;
        out.extend_from_slice(&rgb[from..from + (width * 3) as usize]);
    }
    (out, [width, height])
}

/// Nearest-neighbour scaling of an RGB picture to `height` rows.
fn scale_to_height(rgb: &[u8], [width, old_height]: [u32; 2], height: u32) -> (Vec<u8>, [u32; 2]) {
    let new_width = ((u64::from(width) * u64::from(height)) / u64::from(old_height.max(1))).max(1) as u32;
    let mut out = Vec::with_capacity((new_width * height * 3) as usize);
    for y in 0..height {
        let source_y = (u64::from(y) * u64::from(old_height) / u64::from(height)) as u32;
        for x in 0..new_width {
            let source_x = (u64::from(x) * u64::from(width) / u64::from(new_width)) as u32;
            let i = ((source_y * width + source_x) * 3) as usize;
            out.extend_from_slice(&rgb[i..i + 3]);
        }
    }
    (out, [new_width, height])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_archive_without_tile_images_gives_no_strip_and_says_why() {
        let text = r#"{"tiles": [{"frame": 0, "eye": "left", "row": 0, "col": 0, "empty": true}]}"#;
        let manifest = Manifest::parse(Path::new("m.json"), text.as_bytes()).unwrap();
        assert!(frame_strip_skipped(&manifest, true).unwrap().contains("--count"));
        // A --count capture names its tiles but writes none.
        let tile = r#"[{"file": "t.png", "frame": 0, "eye": "left", "row": 0, "col": 0}]"#;
        let text = format!(r#"{{"tiles": {tile}, "capture": {{"tiles_written": false}}}}"#);
        let manifest = Manifest::parse(Path::new("m.json"), text.as_bytes()).unwrap();
        assert!(frame_strip_skipped(&manifest, true).unwrap().contains("--count"));
        let text = format!(r#"{{"tiles": {tile}}}"#);
        let manifest = Manifest::parse(Path::new("m.json"), text.as_bytes()).unwrap();
        assert_eq!(frame_strip_skipped(&manifest, true), None);
        assert!(frame_strip_skipped(&manifest, false).unwrap().contains("image palette"));
    }

    #[test]
    fn scaling_to_twice_the_height_doubles_each_pixel() {
        let rgb = [1, 1, 1, 2, 2, 2];
        let (scaled, size) = scale_to_height(&rgb, [2, 1], 2);
        assert_eq!(size, [4, 2]);
        assert_eq!(scaled[..12], [1, 1, 1, 1, 1, 1, 2, 2, 2, 2, 2, 2]);
    }
}
