//! `frames-strip.png`: what the pedestrian saw — a few frames of one eye,
//! spread over the scenario, put together from the archive's tiles with
//! every vehicle pixel in its part's colour (the pixel's palette colour
//! names a texel, the PIdT gives the texel's part colour) and everything
//! else light grey. Each frame is labelled with its time and distance, and
//! a colour key below names the parts covering most of the strip.
//!
//! Drawn only from tile PNGs: a `--count` archive has none, and an archive
//! on an image palette (`--palette FILE`) would need a search per colour;
//! [`frame_strip_skipped`] says why a strip is missing, for the report.

use std::collections::{BTreeMap, HashMap};
use std::path::Path;
use std::sync::{Arc, Mutex};

use plotters::prelude::*;
use rayon::prelude::*;

use crate::archive::labels::LoadedLabels;
use crate::archive::manifest::{Manifest, TileEntry};
use crate::archive::palette::Fcsp;
use crate::count::part_lookup::PartLookup;
use crate::error::Result;
use crate::format::manifest::FrameEntry;
use crate::output::legend::{LegendEntry, TextLayout};
use crate::output::part_names::readable_part_name;
use crate::png::rows::{RowReader, read_file};

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

    /// A number of the tiles' records, else of the manifest's frame record
    /// (`time_s` or `distance_m`, chosen by `tile` and `frame`).
    fn number(
        &self,
        manifest: &Manifest,
        tile: fn(&TileEntry) -> Option<f64>,
        frame: fn(&FrameEntry) -> Option<f64>,
    ) -> Option<f64> {
        self.tiles.values().find_map(|entry| tile(entry)).or_else(|| {
            manifest.frame_records().iter().find(|record| record.frame == self.frame).and_then(frame)
        })
    }
}

/// Why an archive gives no strip, or `None` when it can give one.
pub(crate) fn frame_strip_skipped(manifest: &Manifest, canonical_palette: bool) -> Option<&'static str> {
    if !manifest.tiles_written() || !manifest.tiles.iter().any(|tile| tile.file.is_some()) {
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

/// What a pixel of the strip shows: an index into [`TexelsShown::colours`].
type Shown = u16;
/// Not the vehicle (background, occluders, a colour that is no texel).
const NOT_VEHICLE: Shown = 0;
/// A vehicle texel no legend part names.
const UNLABELLED: Shown = 1;

/// What each texel of the palette shows, and the colour of each [`Shown`]:
/// the analysis's own PIdT resolved against its legend (not read again),
/// the capture's background colours apart.
struct TexelsShown {
    /// Colour → legend part, unlabelled or neither (background, no
    /// texel): the lookup the per-part counting uses, whose two-level
    /// table stays in cache (the PIdT's flat one, 32 MiB at 4096², missed
    /// on nearly every vehicle pixel, neighbouring pixels showing texels
    /// rows apart).
    parts: PartLookup,
    /// What each of the lookup's slots shows: the legend's parts, then
    /// unlabelled, then neither.
    shown_of_slot: Vec<Shown>,
    colors: Vec<[u8; 3]>,
}

impl TexelsShown {
    /// A texel shows its part's colour when a legend part names it,
    /// [`STRIP_UNLABELLED`] when none does; the capture's `background`
    /// colours (which may name texels) are not the vehicle.
    fn new(labels: &LoadedLabels, background: &[crate::Color]) -> Self {
        let mut colors = vec![STRIP_BACKGROUND, STRIP_UNLABELLED];
        colors.extend(labels.legend.parts.iter().map(|part| part.color.rgb()));
        let backgrounds: Vec<u32> = background.iter().map(|color| color.packed()).collect();
        let palette = Fcsp::Canonical { width: labels.pidt.width, height: labels.pidt.height };
        let parts = PartLookup::new(&palette, Some((&labels.legend, &labels.pidt)), &backgrounds);
        let legend_parts = labels.legend.parts.len() as Shown;
        let shown_of_slot = (2..legend_parts + 2).chain([UNLABELLED, NOT_VEHICLE]).collect();
        TexelsShown { parts, shown_of_slot, colors }
    }

    /// What a pixel of colour `colour` shows.
    fn of_color(&self, color: u32) -> Shown {
        self.shown_of_slot[usize::from(self.parts.slot_table().get(color))]
    }

    fn is_vehicle(&self, shown: Shown) -> bool {
        self.colors[usize::from(shown)] != STRIP_BACKGROUND
    }
}

/// One tile as runs of what it shows, row by row: a tile is decoded once
/// and kept in a few kilobytes, not as a full-size picture.
struct ShownTile {
    size: [u32; 2],
    /// Per row, the index of its first run in `runs`; one more entry at the end.
    row_starts: Vec<usize>,
    /// `(end x, shown)` of each run, row after row.
    runs: Vec<(u32, Shown)>,
}

impl ShownTile {
    /// Decodes the tile in `bytes` (read from `path`).
    fn decode(path: &Path, bytes: &[u8], texels: &TexelsShown) -> Result<ShownTile> {
        let mut reader = RowReader::new(path, bytes)?;
        let size = [reader.width(), reader.height()];
        let layout = reader.layout();
        let mut tile = ShownTile { size, row_starts: vec![0], runs: Vec::new() };
        if reader.interlaced() {
            let colors = reader.into_colors()?;
            for row in colors.chunks_exact(size[0].max(1) as usize) {
                tile.push_row(row.iter().copied(), texels);
            }
        } else {
            while let Some(row) = reader.next_row()? {
                tile.push_row(row.chunks_exact(layout.bytes_per_pixel()).map(|p| layout.pack(p)), texels);
            }
            reader.finish()?;
        }
        Ok(tile)
    }

    /// Adds a row of pixel colours as its runs of what they show.
    fn push_row(&mut self, colors: impl Iterator<Item = u32>, texels: &TexelsShown) {
        let first = self.runs.len();
        let mut last = (u32::MAX, NOT_VEHICLE);
        for (x, color) in colors.enumerate() {
            if color != last.0 {
                last = (color, texels.of_color(color));
            }
            let in_row = self.runs.len() > first;
            match self.runs.last_mut() {
                Some(run) if in_row && run.1 == last.1 => run.0 = x as u32 + 1,
                _ => self.runs.push((x as u32 + 1, last.1)),
            }
        }
        self.row_starts.push(self.runs.len());
    }

    /// The runs of row `y`.
    fn row(&self, y: u32) -> &[(u32, Shown)] {
        &self.runs[self.row_starts[y as usize]..self.row_starts[y as usize + 1]]
    }
}

/// One eye-frame as the eye saw it: its tiles in place, its size, and
/// how many of its tiles could not be read.
struct ShownFrame {
    size: [u32; 2],
    tile_size: [u32; 2],
    tiles: BTreeMap<(u32, u32), Arc<ShownTile>>,
    unreadable: usize,
}

/// Tiles decoded so far, by their file's bytes, for files small enough to
/// keep: an archive that writes every tile (`--keep-background-tiles`, a
/// Unity export) repeats one all-background file in most places, and the
/// strip decodes it once.
#[derive(Default)]
struct TileCache {
    by_bytes: Mutex<HashMap<Vec<u8>, Arc<ShownTile>>>,
}

/// Files up to this size are kept as keys of the [`TileCache`].
const CACHED_FILE_BYTES: usize = 256 * 1024;

impl TileCache {
    /// The tile in `path` (`None`: it could not be read).
    fn read(&self, path: &Path, texels: &TexelsShown) -> Option<Arc<ShownTile>> {
        let bytes = read_file(path).ok()?;
        let cached = bytes.len() <= CACHED_FILE_BYTES;
        if cached && let Some(tile) = self.by_bytes.lock().ok()?.get(&bytes[..]) {
            return Some(tile.clone());
        }
        let tile = Arc::new(ShownTile::decode(path, &bytes, texels).ok()?);
        if cached {
            self.by_bytes.lock().ok()?.insert(bytes.to_vec(), tile.clone());
        }
        Some(tile)
    }
}

impl ShownFrame {
    /// The frame's written tiles, decoded in parallel; the first readable
    /// tile sets the tile size, and a tile of another size counts as
    /// unreadable.
    fn read(archive: &Path, frame: &EyeFrameTiles, texels: &TexelsShown, decoded: &TileCache) -> ShownFrame {
        let rows = frame.tiles.keys().map(|k| k.0).max().unwrap_or(0) + 1;
        let columns = frame.tiles.keys().map(|k| k.1).max().unwrap_or(0) + 1;
        let written: Vec<((u32, u32), &Path)> =
            frame.tiles.iter().filter_map(|(&place, entry)| Some((place, entry.file.as_deref()?))).collect();
        let read: Vec<_> = written
            .par_iter()
            .map(|&(place, file)| (place, decoded.read(&archive.join(file), texels)))
            .collect();
        let (mut tiles, mut unreadable) = (BTreeMap::new(), 0);
        let mut tile_size = None;
        for (place, tile) in read {
            match tile {
                Some(tile) if *tile_size.get_or_insert(tile.size) == tile.size => {
                    tiles.insert(place, tile);
                }
                _ => unreadable += 1,
            }
        }
        let tile_size = tile_size.unwrap_or([1, 1]);
        ShownFrame { size: [tile_size[0] * columns, tile_size[1] * rows], tile_size, tiles, unreadable }
    }

    /// The smallest box `[low, high]` (inclusive) of the vehicle's pixels.
    fn vehicle_box(&self, texels: &TexelsShown) -> Option<[[u32; 2]; 2]> {
        let (mut low, mut high) = ([u32::MAX; 2], [0u32; 2]);
        for (&(row, column), tile) in &self.tiles {
            let origin = [column * self.tile_size[0], row * self.tile_size[1]];
            for y in 0..tile.size[1] {
                let mut start = 0;
                for &(end, shown) in tile.row(y) {
                    if texels.is_vehicle(shown) {
                        low = [low[0].min(origin[0] + start), low[1].min(origin[1] + y)];
                        high = [high[0].max(origin[0] + end - 1), high[1].max(origin[1] + y)];
                    }
                    start = end;
                }
            }
        }
        (low[0] <= high[0]).then_some([low, high])
    }

    /// `region` (x, y, width, height; the whole frame when it does not fit)
    /// scaled to `height` rows, nearest neighbour, as RGB.
    fn panel(
        &self,
        [x, y, width, height]: [u32; 4],
        out_height: u32,
        texels: &TexelsShown,
    ) -> (Vec<u8>, [u32; 2]) {
        let region = if x + width > self.size[0] || y + height > self.size[1] {
            [0, 0, self.size[0], self.size[1]]
        } else {
            [x, y, width, height]
        };
        let [x0, y0, width, height] = region;
        let out_width = ((u64::from(width) * u64::from(out_height)) / u64::from(height.max(1))).max(1) as u32;
        let mut out = Vec::with_capacity((out_width * out_height * 3) as usize);
        for out_y in 0..out_height {
            let source_y = y0 + (u64::from(out_y) * u64::from(height) / u64::from(out_height)) as u32;
            let (row, local_y) = (source_y / self.tile_size[1], source_y % self.tile_size[1]);
            // The tile under the pixel, its row's runs and the run reached.
            let mut place: Option<(u32, u32)> = None;
            let mut runs: &[(u32, Shown)] = &[];
            let mut at = 0;
            for out_x in 0..out_width {
                let source_x = x0 + (u64::from(out_x) * u64::from(width) / u64::from(out_width)) as u32;
                let (column, local_x) = (source_x / self.tile_size[0], source_x % self.tile_size[0]);
                if place != Some((row, column)) {
                    place = Some((row, column));
                    runs = self.tiles.get(&(row, column)).map_or(&[][..], |tile| tile.row(local_y));
                    at = 0;
                }
                while at < runs.len() && runs[at].0 <= local_x {
                    at += 1;
                }
                let shown = runs.get(at).map_or(NOT_VEHICLE, |run| run.1);
                out.extend_from_slice(&texels.colors[usize::from(shown)]);
            }
        }
        (out, [out_width, out_height])
    }
}

/// What the strip is drawn from.
pub(crate) struct StripInputs<'a> {
    pub archive: &'a Path,
    pub manifest: &'a Manifest,
    /// The legend and PIdT the analysis joined with.
    pub labels: &'a LoadedLabels,
    /// The capture's background colours.
    pub background: &'a [crate::Color],
}

/// Writes the strip into `path`; returns the frames shown.
pub(crate) fn write_frame_strip(path: &Path, inputs: &StripInputs) -> Result<Vec<u32>> {
    let texels = TexelsShown::new(inputs.labels, inputs.background);
    let frames = chosen_frames(inputs.manifest);
    let cache = TileCache::default();
    let shown: Vec<ShownFrame> =
        frames.iter().map(|frame| ShownFrame::read(inputs.archive, frame, &texels, &cache)).collect();
    let crop = vehicle_region(&shown, &texels);
    let mut panels = Vec::new();
    for (frame, shown) in frames.iter().zip(&shown) {
        let scaled = shown.panel(crop, STRIP_FRAME_HEIGHT, &texels);
        let unreadable = shown.unreadable;
        let mut label = format!("{} eye, frame {}", frame.eye, frame.frame);
        if let Some(time) = frame.number(inputs.manifest, |t| t.time_s, |f| f.time_s) {
            label.push_str(&format!(" · {time:.2} s"));
        }
        if let Some(distance) = frame.number(inputs.manifest, |t| t.distance_m, |f| f.distance_m) {
            label.push_str(&format!(" · {distance:.1} m"));
        }
        if unreadable > 0 {
            label.push_str(&format!(" · {unreadable} tiles unreadable"));
        }
        panels.push((scaled, label));
    }
    let width = panels.iter().map(|((_, size), _)| size[0] + GAP).sum::<u32>().max(GAP) - GAP;
    let parts: Vec<(String, [u8; 3])> =
        inputs.labels.legend.parts.iter().map(|part| (part.name.clone(), part.color.rgb())).collect();
    let key = key_layout(&strip_key(&panels, &parts), width, STRIP_FRAME_HEIGHT + LABEL);
    let height = key.1;
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
    key.0.draw(&mut strip, [width, height]);
    crate::files::write_figure_png(path, [width, height], &strip, crate::output::figure::DPI)?;
    Ok(frames.iter().map(|frame| frame.frame).collect())
}

type Panel = ((Vec<u8>, [u32; 2]), String);

/// Parts named in the strip's colour key at most (the most pixels first).
const KEY_PARTS: usize = 12;
/// Text size of the key, plotters pixels (the frames' labels' size).
const KEY_TEXT_PX: f64 = 18.0;

/// The strip's colour key (issue 44 §2): the parts covering most of the
/// strip in their colours, named by [`readable_part_name`], then the
/// vehicle's pixels of no part and what is not the vehicle, when shown.
fn strip_key(panels: &[Panel], parts: &[(String, [u8; 3])]) -> Vec<LegendEntry> {
    let mut pixels: HashMap<[u8; 3], u64> = HashMap::new();
    for ((rgb, _), _) in panels {
        for pixel in rgb.chunks_exact(3) {
            *pixels.entry([pixel[0], pixel[1], pixel[2]]).or_default() += 1;
        }
    }
    let mut shown: Vec<(u64, usize)> = parts
        .iter()
        .enumerate()
        .filter(|(_, (_, color))| *color != STRIP_BACKGROUND && *color != STRIP_UNLABELLED)
        .filter_map(|(index, (_, color))| pixels.get(color).map(|&count| (count, index)))
        .collect();
    shown.sort_by(|a, b| b.0.cmp(&a.0).then(a.1.cmp(&b.1)));
    let mut entries: Vec<LegendEntry> = shown
        .iter()
        .take(KEY_PARTS)
        .map(|&(_, index)| LegendEntry { color: parts[index].1, label: readable_part_name(&parts[index].0) })
        .collect();
    if shown.len() > KEY_PARTS {
        let more = shown.len() - KEY_PARTS;
        entries.push(LegendEntry { color: [255, 255, 255], label: format!("{more} more parts (parts.csv)") });
    }
    for (color, label) in [(STRIP_UNLABELLED, "vehicle, no part"), (STRIP_BACKGROUND, "not the vehicle")] {
        if pixels.contains_key(&color) {
            entries.push(LegendEntry { color, label: label.to_string() });
        }
    }
    entries
}

/// The key laid out below the frames (from `top`), wrapped to the strip's
/// `width`; and the strip's height with it.
fn key_layout(entries: &[LegendEntry], width: u32, top: u32) -> (TextLayout, u32) {
    let mut layout = TextLayout::new(KEY_TEXT_PX);
    let room = f64::from(width.saturating_sub(8).max(1));
    let bottom = layout.entries(entries, 4, top + 6, room);
    (layout, bottom + 6)
}

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

/// The region (x, y, width, height) holding the vehicle in every frame
/// of the first frame's size, with a margin of a fifth of its size, at
/// least a sixth of the frame high: one crop for all frames, so sizes compare.
fn vehicle_region(frames: &[ShownFrame], texels: &TexelsShown) -> [u32; 4] {
    let Some(first) = frames.first() else { return [0, 0, 1, 1] };
    let [width, height] = first.size;
    let boxes = frames.iter().filter(|frame| frame.size == first.size).filter_map(|f| f.vehicle_box(texels));
    let Some([low, high]) = boxes
        .reduce(|[l, h], [l2, h2]| [[l[0].min(l2[0]), l[1].min(l2[1])], [h[0].max(h2[0]), h[1].max(h2[1])]])
    else {
        return [0, 0, width, height];
    };
    let span = [high[0] - low[0] + 1, (high[1] - low[1] + 1).max(height / 6)];
    let margin = [span[0] / 5 + 4, span[1] / 5 + 4];
    let x = low[0].saturating_sub(margin[0]);
    let y = low[1].saturating_sub(margin[1]);
    [x, y, (high[0] + margin[0] + 1).min(width) - x, (low[1] + span[1] + margin[1]).min(height) - y]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::archive::labels::Pidt;

    #[test]
    fn an_archive_without_tile_images_gives_no_strip_and_says_why() {
        let text = r#"{"tiles": [{"frame": 0, "eye": "left", "row": 0, "col": 0, "empty": true}]}"#;
        let manifest = Manifest::parse(Path::new("m.json"), text.as_bytes()).unwrap();
        assert!(frame_strip_skipped(&manifest, true).unwrap().contains("--count"));
        // A --count capture names its tiles but writes none.
        let tile = r#"[{"file": "t.png", "frame": 0, "eye": "left", "row": 0, "col": 0}]"#;
        let capture = r#"{"tool": "t", "tiles_rendered": 1, "tiles_culled": 0, "tiles_background_only": 0, "tiles_written": false}"#;
        let text = format!(r#"{{"tiles": {tile}, "capture": {capture}}}"#);
        let manifest = Manifest::parse(Path::new("m.json"), text.as_bytes()).unwrap();
        assert!(frame_strip_skipped(&manifest, true).unwrap().contains("--count"));
        let text = format!(r#"{{"tiles": {tile}}}"#);
        let manifest = Manifest::parse(Path::new("m.json"), text.as_bytes()).unwrap();
        assert_eq!(frame_strip_skipped(&manifest, true), None);
        assert!(frame_strip_skipped(&manifest, false).unwrap().contains("image palette"));
    }

    /// A frame of two 2×1 tiles side by side; pixel colours name texels
    /// 0-3, which show shown indices 2, 2, 3 and not-the-vehicle.
    fn two_tile_frame() -> (ShownFrame, TexelsShown) {
        // Texels 0 and 1 are legend part 0, texel 2 part 1; texel 3 is background.
        let pidt = Pidt {
            width: 4,
            height: 1,
            part_of_texel: vec![0, 0, 1, 0],
            part_texels: vec![3, 1],
            unlabelled_colors: Default::default(),
        };
        let parts = [0x010101, 0x020202]
            .map(|c| crate::Part { name: format!("part {c}"), color: crate::Color::from_packed(c) });
        let legend = crate::Legend::new(Path::new("p.csv"), parts.to_vec()).unwrap();
        let labels = LoadedLabels { legend, pidt: Arc::new(pidt) };
        let texels = TexelsShown::new(&labels, &[crate::Color::from_packed(3)]);
        assert_eq!(texels.colors, [STRIP_BACKGROUND, STRIP_UNLABELLED, [1; 3], [2; 3]]);
        // Past the palette is no texel either.
        assert_eq!([0, 1, 2, 3, 4].map(|color| texels.of_color(color)), [2, 2, 3, NOT_VEHICLE, NOT_VEHICLE]);
        let tile = |runs: Vec<(u32, Shown)>| {
            Arc::new(ShownTile { size: [2, 1], row_starts: vec![0, runs.len()], runs })
        };
        let tiles =
            BTreeMap::from([((0, 0), tile(vec![(2, 2)])), ((0, 1), tile(vec![(1, 3), (2, NOT_VEHICLE)]))]);
        (ShownFrame { size: [4, 1], tile_size: [2, 1], tiles, unreadable: 0 }, texels)
    }

    #[test]
    fn scaling_to_twice_the_height_doubles_each_pixel() {
        let (frame, texels) = two_tile_frame();
        let (scaled, size) = frame.panel([0, 0, 4, 1], 2, &texels);
        assert_eq!(size, [8, 2]);
        let row =
            [[1u8; 3], [1; 3], [1; 3], [1; 3], [2; 3], [2; 3], STRIP_BACKGROUND, STRIP_BACKGROUND].concat();
        assert_eq!(scaled, [row.clone(), row].concat());
        // A region that does not fit the frame shows the whole frame.
        assert_eq!(frame.panel([3, 0, 4, 1], 2, &texels), (scaled, size));
    }

    #[test]
    fn the_vehicle_box_spans_the_pixels_that_show_a_part() {
        let (frame, texels) = two_tile_frame();
        assert_eq!(frame.vehicle_box(&texels), Some([[0, 0], [2, 0]]));
        // A run that shows nothing but continues a row is not the vehicle.
        let mut tile = ShownTile { size: [4, 1], row_starts: vec![0], runs: Vec::new() };
        tile.push_row([5, 5, 0, 0].into_iter(), &texels);
        assert_eq!(tile.runs, [(2, NOT_VEHICLE), (4, 2)]);
    }

    #[test]
    fn the_key_names_the_parts_covering_most_of_the_strip_in_their_colours() {
        let (frame, texels) = two_tile_frame();
        // Part 0 covers 4 of the 8 pixels, part 1 two, background two.
        let panel = frame.panel([0, 0, 4, 1], 2, &texels);
        let parts = [("windshield_rail_left".to_string(), [1u8; 3]), ("hood".to_string(), [2; 3])];
        let key = strip_key(&[(panel, "frame 0".into())], &parts);
        let labels: Vec<(&str, [u8; 3])> = key.iter().map(|e| (e.label.as_str(), e.color)).collect();
        assert_eq!(
            labels,
            [("windshield rail, left", [1; 3]), ("hood", [2; 3]), ("not the vehicle", STRIP_BACKGROUND)]
        );
        // The key lies below the frames and each entry's swatch shows its colour.
        let (layout, height) = key_layout(&key, 400, STRIP_FRAME_HEIGHT + LABEL);
        assert!(height > STRIP_FRAME_HEIGHT + LABEL);
        let mut rgb = [255u8; 3].repeat((400 * height) as usize);
        layout.draw(&mut rgb, [400, height]);
        for (index, entry) in key.iter().enumerate() {
            let (x, y) = layout.swatch_centre(index);
            assert!(y as u32 >= STRIP_FRAME_HEIGHT + LABEL, "{} overlaps the frames", entry.label);
            let i = (y as usize * 400 + x as usize) * 3;
            assert_eq!(rgb[i..i + 3], entry.color, "{}", entry.label);
        }
    }
}
