//! The capture loop and the archive it writes.
//!
//! An archive folder holds `manifest.json` (the contract with
//! `ufcsr-analyze`), `pidt.png`, `parts.csv` and `tiles/fNNNN_EYE_rR_cC.png`.
//! Tiles that the vehicle's projected bounding box does not touch are neither
//! rendered nor written, only listed as empty; a rendered tile that comes out
//! pure background (the vehicle is hidden) is listed as empty too unless
//! `keep_background_tiles` is set. PNGs are encoded on worker threads while
//! the GPU renders the next tile. The manifest holds no timings, so the same
//! capture always writes the same archive.

use std::path::{Path, PathBuf};
use std::sync::mpsc::{Receiver, sync_channel};
use std::sync::{Arc, Mutex};
use std::time::Instant;

use serde_json::{Map, Value, json};
use ufcsr::{Color, MANIFEST_SCHEMA, Manifest, PaletteSpec, TileEntry};

use crate::error::{CaptureError, Result};
use crate::own_pidt::{self, OwnLabels};
use crate::palette::ExternalPalette;
use crate::pidt::{self, Pidt};
use crate::render::{Palette, RenderSetup, Renderer, TileDraw, vehicle_vertices};
use crate::rig::{Eye, box_corners, box_outside, vehicle_to_world};
use crate::scene::Scene;
use crate::unity::Scenario;
use crate::unwrap::{self, Unwrapped};

/// PNG compression of tiles.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Compression {
    Fastest,
    /// The default: about 10× faster to encode than `balanced`, ≈ 2.6× larger.
    #[default]
    Fast,
    Balanced,
    High,
}

impl Compression {
    fn png(self) -> png::Compression {
        match self {
            Compression::Fastest => png::Compression::Fastest,
            Compression::Fast => png::Compression::Fast,
            Compression::Balanced => png::Compression::Balanced,
            Compression::High => png::Compression::High,
        }
    }
}

impl std::str::FromStr for Compression {
    type Err = CaptureError;

    fn from_str(text: &str) -> Result<Compression> {
        match text.to_ascii_lowercase().as_str() {
            "fastest" => Ok(Compression::Fastest),
            "fast" => Ok(Compression::Fast),
            "balanced" | "default" => Ok(Compression::Balanced),
            "high" | "best" => Ok(Compression::High),
            other => Err(CaptureError::BadOptions(format!(
                "PNG compression must be fastest, fast, balanced or high, not {other:?}"
            ))),
        }
    }
}

/// Which frames to capture: all, or a list such as `0,30,60-90/10`.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct FrameSelection(Option<Vec<u32>>);

impl FrameSelection {
    /// Every frame.
    pub fn all() -> FrameSelection {
        FrameSelection(None)
    }

    /// The frames of a scenario with `count` frames.
    pub fn frames(&self, count: u32) -> Vec<u32> {
        match &self.0 {
            None => (0..count).collect(),
            Some(list) => list.iter().copied().filter(|&f| f < count).collect(),
        }
    }
}

impl std::str::FromStr for FrameSelection {
    type Err = CaptureError;

    /// Parses `all` or comma-separated frames and inclusive ranges `a-b`,
    /// optionally with a step `a-b/s`.
    fn from_str(text: &str) -> Result<FrameSelection> {
        if text.trim().eq_ignore_ascii_case("all") {
            return Ok(FrameSelection(None));
        }
        let bad =
            || CaptureError::BadOptions(format!("frames must look like 0,30,60-90/10 or all, not {text:?}"));
        let mut frames = Vec::new();
        for item in text.split(',') {
            let (range, step) = match item.split_once('/') {
                Some((range, step)) => (range, step.trim().parse::<u32>().map_err(|_| bad())?),
                None => (item, 1),
            };
            let (a, b) = match range.split_once('-') {
                Some((a, b)) => {
                    (a.trim().parse::<u32>().map_err(|_| bad())?, b.trim().parse::<u32>().map_err(|_| bad())?)
                }
                None => {
                    let a = range.trim().parse::<u32>().map_err(|_| bad())?;
                    (a, a)
                }
            };
            if step == 0 || b < a {
                return Err(bad());
            }
            frames.extend((a..=b).step_by(step as usize));
        }
        frames.sort_unstable();
        frames.dedup();
        Ok(FrameSelection(Some(frames)))
    }
}

/// How to capture.
#[derive(Debug, Clone)]
pub struct CaptureOptions {
    pub out: PathBuf,
    /// Size of the canonical palette (ignored with `palette_file`).
    pub palette: [u32; 2],
    /// An external palette PNG instead of the canonical palette.
    pub palette_file: Option<PathBuf>,
    pub keep_uvs: bool,
    /// A PIdT and legend painted for the kept UVs, used as is (see [`own_pidt`]).
    pub own_labels: Option<OwnLabels>,
    pub frames: FrameSelection,
    pub compression: Compression,
    pub resume: bool,
    pub keep_background_tiles: bool,
    /// Render every tile, even those the vehicle's bounds do not touch
    /// (for benchmarks and checks of the culling).
    pub no_cull: bool,
    pub progress: bool,
    /// PNG encoder threads (0: as many as cores).
    pub encoder_threads: usize,
}

impl Default for CaptureOptions {
    fn default() -> CaptureOptions {
        CaptureOptions {
            out: PathBuf::from("archive"),
            palette: [4096, 4096],
            palette_file: None,
            keep_uvs: false,
            own_labels: None,
            frames: FrameSelection::all(),
            compression: Compression::Fast,
            resume: false,
            keep_background_tiles: false,
            no_cull: false,
            progress: false,
            encoder_threads: 0,
        }
    }
}

/// What a capture did.
#[derive(Debug, Clone, Default)]
pub struct Summary {
    pub out: PathBuf,
    pub scenario: String,
    pub frames: u32,
    pub tiles: u64,
    /// Rendered by the GPU.
    pub rendered: u64,
    /// PNGs written.
    pub written: u64,
    /// Already on disk (`--resume`).
    pub resumed: u64,
    /// Not rendered: outside the vehicle's projected bounds.
    pub culled: u64,
    /// Rendered but pure background.
    pub background: u64,
    pub seconds: f64,
    /// Of which unwrap, PIdT and pipeline setup.
    pub setup_seconds: f64,
    pub texels_per_m2: f64,
    pub palette_share: f64,
    pub parts: usize,
    pub triangles: usize,
    /// What did not fit but did not stop the capture (own PIdT texels).
    pub warnings: Vec<String>,
}

impl Summary {
    /// Frames per second of the frame loop (both eyes, rendering, readback
    /// and PNG encoding; setup excluded).
    pub fn frames_per_second(&self) -> f64 {
        let seconds = self.seconds - self.setup_seconds;
        if seconds > 0.0 { f64::from(self.frames) / seconds } else { 0.0 }
    }
}

/// The palette of a capture.
pub struct PaletteChoice {
    /// What the renderer gets.
    pub palette: Palette,
    /// The external palette, if one was given.
    pub external: Option<ExternalPalette>,
    /// The texel holding the background colour (left out of the unwrap).
    pub background_texel: Option<(u32, u32)>,
}

/// Loads the palette the options ask for.
pub fn load_palette(options: &CaptureOptions) -> Result<PaletteChoice> {
    match &options.palette_file {
        None => Ok(PaletteChoice {
            palette: Palette::Canonical(options.palette),
            external: None,
            background_texel: unwrap::background_texel(options.palette),
        }),
        Some(path) => {
            let external = ExternalPalette::load(path)?;
            Ok(PaletteChoice {
                palette: Palette::External { size: external.size, rgba: external.rgba() },
                background_texel: external.texel_of(Color::DEFAULT_BACKGROUND),
                external: Some(external),
            })
        }
    }
}

/// The unwrap and PIdT of a vehicle for a palette size, avoiding the texel
/// that holds the background colour.
pub fn prepare(
    scene: &Scene,
    size: [u32; 2],
    background: Option<(u32, u32)>,
    keep_uvs: bool,
) -> Result<(Unwrapped, Pidt)> {
    let unwrapped = if keep_uvs {
        unwrap::keep_uvs_avoiding(&scene.vehicle, size, background)?
    } else {
        unwrap::unwrap_islands_avoiding(&scene.vehicle, size, background)?
    };
    let pidt = pidt::paint(&scene.vehicle, &unwrapped);
    Ok((unwrapped, pidt))
}

/// The file name of a tile, relative to the archive.
pub fn tile_file(frame: u32, eye: Eye, row: u32, col: u32) -> PathBuf {
    PathBuf::from(format!("tiles/f{frame:04}_{}_r{row}_c{col}.png", eye.name()))
}

struct EncodeJob {
    path: PathBuf,
    size: [u32; 2],
    rgba: Vec<u8>,
}

fn encoder_worker(
    jobs: Arc<Mutex<Receiver<EncodeJob>>>,
    compression: png::Compression,
    errors: Arc<Mutex<Vec<CaptureError>>>,
) {
    loop {
        let job = match jobs.lock() {
            Ok(receiver) => receiver.recv(),
            Err(_) => return,
        };
        let Ok(job) = job else { return };
        // Tiles are written as RGB: alpha is always 255 and the analyzer reads both.
        let rgb: Vec<u8> = job.rgba.chunks_exact(4).flat_map(|p| [p[0], p[1], p[2]]).collect();
        if let Err(error) = ufcsr::write_rgb_png(&job.path, job.size[0], job.size[1], &rgb, compression)
            && let Ok(mut errors) = errors.lock()
        {
            errors.push(error.into());
        }
    }
}

/// Captures one scenario of `scene` into `options.out` with a device the
/// caller created (see [`crate::gpu`]).
pub fn capture(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    scene: &Scene,
    scenario: &Scenario,
    options: &CaptureOptions,
) -> Result<Summary> {
    let start = Instant::now();
    let rig = &scene.rig;
    rig.check()?;
    let out = &options.out;
    let tiles_dir = out.join("tiles");
    std::fs::create_dir_all(&tiles_dir).map_err(|e| CaptureError::io(&tiles_dir, e))?;
    if !options.resume {
        // A fresh capture replaces the previous one: tiles it does not write
        // again must not linger beside the new manifest.
        remove_old_tiles(&tiles_dir)?;
    }

    let PaletteChoice { palette, external, background_texel } = load_palette(options)?;
    let palette_size = palette.size();
    let (unwrapped, painted) = prepare(scene, palette_size, background_texel, options.keep_uvs)?;
    let (pidt, part_count, label_warnings) = match &options.own_labels {
        None => {
            pidt::write_legend(&scene.vehicle, &painted, &out.join("parts.csv"))?;
            (painted, scene.vehicle.parts.len(), Vec::new())
        }
        Some(own) => {
            let loaded = own_pidt::load(own, &unwrapped)?;
            own_pidt::write_legend(&loaded.legend, &out.join("parts.csv"))?;
            (loaded.pidt, loaded.legend.parts.len(), loaded.warnings)
        }
    };
    pidt::write_png(&pidt, &out.join("pidt.png"))?;
    let palette_spec = match &external {
        None => PaletteSpec::Canonical { canonical: palette_size },
        Some(external) => {
            // The archive carries its palette so that it stands alone.
            ufcsr::write_rgb_png(
                &out.join("palette.png"),
                external.size[0],
                external.size[1],
                &external.rgb,
                png::Compression::Fast,
            )?;
            PaletteSpec::File(PathBuf::from("palette.png"))
        }
    };

    let vertices = vehicle_vertices(&scene.vehicle, &unwrapped);
    let background = Color::DEFAULT_BACKGROUND;
    let setup = RenderSetup {
        tile_size: rig.tile_pixels(),
        palette: &palette,
        background,
        vehicle: &vertices,
        occluders: &scene.occluders,
    };
    let renderer = Renderer::new(device, queue, &setup)?;
    drop(external);
    let setup_seconds = start.elapsed().as_secs_f64();

    let count = rig.frame_count(scenario.duration_s);
    let frames = options.frames.frames(count);
    let tiles_per_eye = u64::from(rig.tiles[0]) * u64::from(rig.tiles[1]);
    let total = frames.len() as u64 * 2 * tiles_per_eye;
    let progress = if options.progress {
        let bar = indicatif::ProgressBar::new(total);
        if let Ok(style) = indicatif::ProgressStyle::with_template(
            "{prefix} [{elapsed_precise}] {wide_bar} {pos}/{len} tiles ({per_sec}, eta {eta})",
        ) {
            bar.set_style(style);
        }
        bar.set_prefix(format!("scenario {}", scenario.name));
        bar
    } else {
        indicatif::ProgressBar::hidden()
    };

    let (vehicle_min, vehicle_max) = scene.vehicle.bounds();
    let vehicle_box = box_corners(vehicle_min, vehicle_max);
    let threads = if options.encoder_threads == 0 {
        std::thread::available_parallelism().map_or(2, |n| n.get())
    } else {
        options.encoder_threads
    };
    let mut summary = Summary {
        out: out.clone(),
        scenario: scenario.name.clone(),
        frames: frames.len() as u32,
        tiles: total,
        texels_per_m2: unwrapped.texels_per_m2,
        palette_share: pidt.share(),
        parts: part_count,
        triangles: scene.vehicle.triangles.len(),
        warnings: label_warnings,
        setup_seconds,
        ..Summary::default()
    };
    let mut entries = Vec::with_capacity(total as usize);
    let mut frame_records = Vec::with_capacity(frames.len());
    let errors = Arc::new(Mutex::new(Vec::new()));

    let render_result: Result<()> = std::thread::scope(|scope| {
        // A short queue: the GPU runs at most a few tiles ahead of the encoders.
        let (sender, receiver) = sync_channel::<EncodeJob>(threads * 2);
        let receiver = Arc::new(Mutex::new(receiver));
        for _ in 0..threads {
            let (receiver, errors) = (receiver.clone(), errors.clone());
            let compression = options.compression.png();
            scope.spawn(move || encoder_worker(receiver, compression, errors));
        }
        for &frame in &frames {
            let time_s = (f64::from(frame) / rig.fps).min(scenario.duration_s);
            let pose = scenario.motion.pose(time_s);
            let to_world = vehicle_to_world(&pose);
            let world_box = vehicle_box.map(|c| to_world.transform_point3(c));
            let ped = glam::dvec2(rig.pedestrian[0], rig.pedestrian[1]);
            let distance_m = (pose.position.truncate() - ped).length();
            let cameras = rig.cameras(&pose);
            let mut frame_tiles = Map::new();
            for (eye, camera) in Eye::BOTH.into_iter().zip(cameras) {
                let touched =
                    if options.no_cull { rig.all_tiles() } else { rig.tiles_touched(&camera, &world_box) };
                let mut written_here = 0u32;
                for tile in rig.all_tiles() {
                    let mut extra = Map::new();
                    extra.insert("time_s".into(), json!(round6(time_s)));
                    extra.insert("distance_m".into(), json!(round6(distance_m)));
                    let file = tile_file(frame, eye, tile.row, tile.col);
                    let path = out.join(&file);
                    let mut entry = TileEntry {
                        file: None,
                        frame,
                        eye: eye.name().into(),
                        row: tile.row,
                        col: tile.col,
                        empty: true,
                        extra,
                    };
                    progress.inc(1);
                    if !touched.contains(&tile) {
                        summary.culled += 1;
                        entries.push(entry);
                        continue;
                    }
                    if options.resume && png_size(&path) == Some(rig.tile_pixels()) {
                        summary.resumed += 1;
                        written_here += 1;
                        entry.file = Some(file);
                        entry.empty = false;
                        entries.push(entry);
                        continue;
                    }
                    let clip_from_world = rig.tile_matrix(tile) * camera.view_proj;
                    let visible: Vec<usize> = scene
                        .occluders
                        .objects
                        .iter()
                        .enumerate()
                        .filter(|(_, o)| !box_outside(&clip_from_world, &box_corners(o.2, o.3)))
                        .map(|(i, _)| i)
                        .collect();
                    let draw = TileDraw {
                        clip_from_vehicle: clip_from_world * to_world,
                        clip_from_world,
                        occluders: &visible,
                    };
                    let rgba = renderer.render_tile(device, queue, &draw)?;
                    summary.rendered += 1;
                    let [r, g, b] = background.rgb();
                    let all_background = rgba.chunks_exact(4).all(|p| p[0] == r && p[1] == g && p[2] == b);
                    if all_background && !options.keep_background_tiles {
                        summary.background += 1;
                        entries.push(entry);
                        continue;
                    }
                    sender
                        .send(EncodeJob { path, size: rig.tile_pixels(), rgba })
                        .map_err(|_| CaptureError::Gpu("PNG encoders stopped".into()))?;
                    summary.written += 1;
                    written_here += 1;
                    entry.file = Some(file);
                    entry.empty = false;
                    entries.push(entry);
                }
                frame_tiles.insert(eye.name().into(), json!(written_here));
            }
            frame_records.push(json!({
                "frame": frame,
                "time_s": round6(time_s),
                "vehicle": {
                    "position": pose.position.to_array().map(round6),
                    "yaw_deg": round6(pose.yaw_deg),
                },
                "distance_m": round6(distance_m),
                "tiles_with_vehicle": frame_tiles,
            }));
        }
        drop(sender);
        Ok(())
    });
    progress.finish_and_clear();
    render_result?;
    if let Ok(mut errors) = errors.lock()
        && let Some(error) = errors.drain(..).next()
    {
        return Err(error);
    }

    let mut extra = Map::new();
    extra.insert("scenario".into(), json!({"name": scenario.name, "duration_s": scenario.duration_s}));
    extra.insert("frames".into(), Value::Array(frame_records));
    extra.insert(
        "rig".into(),
        json!({
            "settings": rig,
            "vertical_fov_deg": round6(rig.vertical_fov_deg()),
            "pixels_per_degree": round6(rig.pixels_per_degree()),
            "tile_pixels": rig.tile_pixels(),
            "frame_count": count,
            "eye_offset": "eyes at the head ± ipd/2 along the head's right; both look along the head's direction",
            "projection": "perspective, square pixels, reversed Z (Depth32Float)",
        }),
    );
    extra.insert("scene".into(), scene.info.clone());
    extra.insert(
        "unwrap".into(),
        json!({
            "method": unwrapped.method,
            "labels": match &options.own_labels {
                None => json!("painted by part"),
                Some(own) => json!({"pidt": own.pidt, "parts": own.parts}),
            },
            "palette": palette_size,
            "background_texel": background_texel,
            "texels_per_m2": round6(unwrapped.texels_per_m2),
            "texel_size_mm": round6(1000.0 / unwrapped.texels_per_m2.sqrt()),
            "palette_share_used": round6(pidt.share()),
            "labelled_texels": pidt.labelled,
            "label_conflicts": pidt.conflicts,
            "triangles": scene.vehicle.triangles.len(),
            "vehicle_area_m2": round6(scene.vehicle.area()),
            // Surface per part, to turn the analyzer's per-part totals into
            // counts per square metre.
            "part_area_m2": scene
                .vehicle
                .parts
                .iter()
                .zip(unwrap::part_areas(&scene.vehicle))
                .map(|(name, area)| (name.clone(), json!(round6(area))))
                .collect::<Map<String, Value>>(),
        }),
    );
    extra.insert(
        "capture".into(),
        json!({
            "tool": concat!("ufcsr-capture ", env!("CARGO_PKG_VERSION")),
            "tiles_rendered": summary.rendered + summary.resumed,
            "tiles_culled": summary.culled,
            "tiles_background_only": summary.background,
        }),
    );
    let manifest = Manifest {
        schema: Some(MANIFEST_SCHEMA.into()),
        palette: Some(palette_spec),
        pidt: Some(PathBuf::from("pidt.png")),
        parts: Some(PathBuf::from("parts.csv")),
        background: Some(vec![background]),
        tiles: entries,
        extra,
    };
    manifest.write_to_dir(out)?;
    summary.seconds = start.elapsed().as_secs_f64();
    Ok(summary)
}

/// Removes files named like our tiles (`fNNNN_left|right_rR_cC.png`).
fn remove_old_tiles(dir: &Path) -> Result<()> {
    let entries = std::fs::read_dir(dir).map_err(|e| CaptureError::io(dir, e))?;
    for entry in entries {
        let entry = entry.map_err(|e| CaptureError::io(dir, e))?;
        let name = entry.file_name();
        let name = name.to_string_lossy();
        if is_tile_name(&name) {
            std::fs::remove_file(entry.path()).map_err(|e| CaptureError::io(entry.path(), e))?;
        }
    }
    Ok(())
}

/// True for `f0000_left_r0_c0.png` and the like.
fn is_tile_name(name: &str) -> bool {
    let Some(rest) = name.strip_prefix('f').and_then(|n| n.strip_suffix(".png")) else {
        return false;
    };
    let parts: Vec<&str> = rest.split('_').collect();
    let number = |text: &str, prefix: char| {
        text.strip_prefix(prefix).is_some_and(|n| !n.is_empty() && n.bytes().all(|b| b.is_ascii_digit()))
    };
    matches!(parts.as_slice(), [frame, eye, row, col]
        if !frame.is_empty() && frame.bytes().all(|b| b.is_ascii_digit())
            && (*eye == "left" || *eye == "right")
            && number(row, 'r')
            && number(col, 'c'))
}

/// Six decimals keep the manifest readable and stable across platforms.
fn round6(value: f64) -> f64 {
    (value * 1e6).round() / 1e6
}

/// Captures several scenarios; with `subfolders` each goes to `out/NAME`
/// (`--scenario all`), otherwise into `out` itself.
pub fn capture_all(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    scene: &Scene,
    names: &[String],
    subfolders: bool,
    options: &CaptureOptions,
) -> Result<Vec<Summary>> {
    if names.len() > 1 && !subfolders {
        return Err(CaptureError::BadOptions("several scenarios need one sub-folder each".into()));
    }
    let mut summaries = Vec::new();
    for name in names {
        let scenario = scene.scenario(name)?;
        let out: PathBuf = if subfolders { options.out.join(&scenario.name) } else { options.out.clone() };
        let options = CaptureOptions { out, ..options.clone() };
        summaries.push(capture(device, queue, scene, scenario, &options)?);
    }
    Ok(summaries)
}

/// Checks a written archive without the analyzer: every tile pixel is the
/// background or a canonical palette colour whose texel the PIdT labels.
/// Returns `(vehicle pixels, stray pixels)`.
pub fn verify(dir: &Path) -> Result<(u64, u64)> {
    let manifest =
        Manifest::load_from_dir(dir)?.ok_or_else(|| CaptureError::bad_input(dir, "no manifest.json"))?;
    // Colour → texel index: computed for the canonical palette, looked up otherwise.
    let (w, h, lookup) = match &manifest.palette {
        Some(PaletteSpec::Canonical { canonical: [w, h] }) => (*w, *h, None),
        Some(PaletteSpec::File(file)) => {
            let external = ExternalPalette::load(&dir.join(file))?;
            (external.size[0], external.size[1], Some(external.index()))
        }
        None => (4096, 4096, None),
    };
    let (size, pidt) = read_rgb_png(&dir.join("pidt.png"))?;
    if size != [w, h] {
        return Err(CaptureError::bad_input(dir, "pidt.png does not match the palette size"));
    }
    let (mut vehicle, mut stray) = (0u64, 0u64);
    for tile in &manifest.tiles {
        let Some(file) = &tile.file else { continue };
        let (_, rgb) = read_rgb_png(&dir.join(file))?;
        for p in rgb.chunks_exact(3) {
            let color = Color::from_rgb(p[0], p[1], p[2]);
            if color == Color::DEFAULT_BACKGROUND {
                continue;
            }
            let index = match &lookup {
                None => Some(color.packed() as usize),
                Some(lookup) => lookup.get(&color).map(|&i| i as usize),
            };
            let labelled = index.is_some_and(|index| {
                index < (w as usize) * (h as usize) && pidt[index * 3..index * 3 + 3] != [0, 0, 0]
            });
            if labelled {
                vehicle += 1;
            } else {
                stray += 1;
            }
        }
    }
    Ok((vehicle, stray))
}

/// The size of a readable PNG, from its header; `None` for anything else.
fn png_size(path: &Path) -> Option<[u32; 2]> {
    let file = std::fs::File::open(path).ok()?;
    let reader = png::Decoder::new(std::io::BufReader::new(file)).read_info().ok()?;
    let info = reader.info();
    Some([info.width, info.height])
}

/// Reads a PNG (any 8-bit format; alpha dropped) as RGB bytes, with the
/// analyzer's texture reader so both crates accept and reject the same files.
pub fn read_rgb_png(path: &Path) -> Result<([u32; 2], Vec<u8>)> {
    let image = ufcsr::decode::read_color_image(path, |_, _| Ok(()))?;
    let rgb = image.colors.iter().flat_map(|&color| Color::from_packed(color).rgb()).collect();
    Ok(([image.width, image.height], rgb))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_lists_parse() {
        let frames: FrameSelection = "0,30,60-90/10,5".parse().unwrap();
        assert_eq!(frames.frames(181), vec![0, 5, 30, 60, 70, 80, 90]);
        assert_eq!(frames.frames(40), vec![0, 5, 30]);
        assert_eq!("all".parse::<FrameSelection>().unwrap().frames(3), vec![0, 1, 2]);
        assert!("5-1".parse::<FrameSelection>().is_err());
        assert_eq!(tile_file(7, Eye::Right, 1, 4), PathBuf::from("tiles/f0007_right_r1_c4.png"));
        assert!(is_tile_name("f0007_right_r1_c4.png"));
        assert!(
            !is_tile_name("f0007_right_r1_c4.png.bak")
                && !is_tile_name("notes.png")
                && !is_tile_name("f1_up_r1_c1.png")
        );
    }
}
