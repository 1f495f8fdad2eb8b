//! The capture job: one scenario of a scene into an archive folder.
//!
//! An archive folder holds `manifest.json` (the contract with
//! `ufcsr analyze`), `pidt.png`, `parts.csv` and `tiles/fNNNN_EYE_rR_cC.png`.
//! [`capture`] runs in stages: [`prepare`] the palette, unwrap, labels and
//! renderer once; render every frame with [`FrameCapture`] into a
//! [`TileSink`] (the PNG [`EncoderPool`] here); then write the manifest
//! ([`build_manifest`]). [`verify`] checks a written archive without the
//! analyzer.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::time::Instant;

use ufcsr::{Color, Fcsp, Manifest, PaletteRecord};

use crate::error::{CaptureError, Result};
use crate::job::capture_shard;
use crate::job::encoder_pool::{EncoderPool, OldTiles};
use crate::job::frame_capture::FrameCapture;
use crate::job::manifest_builder::{ManifestParts, TileFiles, build_manifest};
use crate::job::options::{CaptureOptions, Summary, TileTally};
use crate::job::tile_sink::TileSink;
use crate::job::{ARCHIVE_FILES, ARCHIVE_FOLDERS, SCENE_FILE, VEHICLE_FILE};
use crate::render::{GpuPalette, RenderSetup, Renderer, vehicle_vertices};
use crate::scene::Scene;
use crate::scene::scenario::Scenario;
use crate::texture::pidt::own as own_pidt;
use crate::texture::pidt::painted::{self as pidt, PidtImage};
use crate::texture::uv_islands::{self, Unwrapped};

/// Loads the palette the options ask for: the canonical palette of
/// `options.palette`, or the palette image `options.palette_file` (its
/// colours checked unique by the analyzer's loader, which names a repeated
/// colour and both places).
/// A canonical palette of more than 2^24 texels is one of 32-bit texel ids
/// (up to `ufcsr::MAX_RGBA32_TEXELS`): its archive is `rgba32`.
pub(crate) fn load_palette(options: &CaptureOptions) -> Result<Fcsp> {
    let [width, height] = options.palette;
    Ok(match &options.palette_file {
        None if u64::from(width) * u64::from(height) > ufcsr::COLOR_COUNT as u64 => {
            Fcsp::canonical_rgba32([width, height])?
        }
        None => Fcsp::canonical([width, height])?,
        Some(path) => Fcsp::from_png(path)?,
    })
}

/// The texel holding the background colour, if the palette has it (left
/// out of the unwrap, so no surface is ever drawn in the background colour).
pub(crate) fn palette_background_texel(palette: &Fcsp) -> Option<(u32, u32)> {
    let width = palette.width() as usize;
    let texel = palette.texel_of(Color::DEFAULT_BACKGROUND.packed())?;
    Some(((texel % width) as u32, (texel / width) as u32))
}

/// The unwrap and PIdT of a vehicle for a palette size, avoiding the texel
/// that holds the background colour.
pub fn prepare(
    scene: &Scene,
    size: [u32; 2],
    background: Option<(u32, u32)>,
    keep_uvs: bool,
) -> Result<(Unwrapped, PidtImage)> {
    let unwrapped = if keep_uvs {
        uv_islands::keep_uvs_avoiding(&scene.vehicle, size, background)?
    } else {
        uv_islands::unwrap_islands_avoiding(&scene.vehicle, size, background)?
    };
    let pidt = pidt::paint(&scene.vehicle, &unwrapped);
    Ok((unwrapped, pidt))
}

/// What [`prepare_archive`] built once for a capture.
pub struct PreparedCapture {
    pub renderer: Renderer,
    pub unwrapped: Unwrapped,
    pub pidt: PidtImage,
    pub palette: PaletteRecord,
    pub palette_size: [u32; 2],
    pub background_texel: Option<(u32, u32)>,
    pub background: Color,
    /// Parts in the legend written to `parts.csv`.
    pub part_count: usize,
    /// What did not fit but did not stop the capture (own PIdT texels).
    pub warnings: Vec<String>,
}

/// Stage one: loads the palette, unwraps and labels the vehicle, writes
/// `pidt.png`, `parts.csv` (and `palette.png` for an external palette) into
/// `options.out`, and builds the renderer.
pub(crate) fn prepare_archive(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    scene: &Scene,
    options: &CaptureOptions,
) -> Result<PreparedCapture> {
    let out = &options.out;
    prepare_folder(scene, options)?;
    let palette = load_palette(options)?;
    let palette_size = [palette.width(), palette.height()];
    let background_texel = palette_background_texel(&palette);
    let (unwrapped, painted) = prepare(scene, palette_size, background_texel, options.keep_uvs)?;
    let (pidt, part_count, warnings) = match &options.own_labels {
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
    let texel_rgb = palette.texel_rgb();
    let palette_record = match &palette {
        Fcsp::Canonical { .. } => PaletteRecord::Canonical { canonical: palette_size },
        Fcsp::Image { .. } => {
            // The archive carries its palette so that it stands alone.
            let path = out.join("palette.png");
            ufcsr::files::write_rgb_png(
                &path,
                [palette_size[0], palette_size[1]],
                &texel_rgb,
                png::Compression::Fast,
            )?;
            PaletteRecord::File(PathBuf::from("palette.png"))
        }
    };
    let vertices = vehicle_vertices(&scene.vehicle, &unwrapped);
    let background = Color::DEFAULT_BACKGROUND;
    write_models(scene, &vertices, &palette_png(&texel_rgb, palette_size)?, background, out)?;
    let gpu_palette = GpuPalette::of(&palette, &texel_rgb);
    let setup = RenderSetup {
        tile_size: scene.rig.tile_pixels(),
        palette: &gpu_palette,
        background,
        vehicle: &vertices,
        occluders: &scene.occluders,
        origin: scene.rig.head(),
    };
    let renderer = Renderer::new(device, queue, &setup)?;
    Ok(PreparedCapture {
        renderer,
        unwrapped,
        pidt,
        palette: palette_record,
        palette_size,
        background_texel,
        background,
        part_count,
        warnings,
    })
}

/// Makes `options.out` ready for an archive: refuses it when writing the
/// archive's files or folders there would replace one of the capture's
/// inputs, creates it, and replaces links where its own folders go.
pub(crate) fn prepare_folder(scene: &Scene, options: &CaptureOptions) -> Result<()> {
    let out = &options.out;
    crate::job::overwrite_guard::refuse_overwriting_inputs(
        out,
        &ARCHIVE_FILES,
        &ARCHIVE_FOLDERS,
        &capture_inputs(scene, options),
    )?;
    ufcsr::files::create_output_dir(out)?;
    crate::job::overwrite_guard::unlink_owned_folders(out, &ARCHIVE_FOLDERS)?;
    // Issue 41: the folder is marked unfinished until the whole manifest is
    // written, so what an interruption leaves is refused by the analyzer
    // (and the interrupt message says so).
    ufcsr::files::mark_unfinished(out)?;
    // Issue 34: an earlier archive's manifest goes before anything of the
    // new one is written, so a capture interrupted (or out of disk) from
    // here on never leaves it over a mix of old and new tiles, which the
    // analyzer would count under it; the manifest is written last. The
    // placement tables in results/ describe that archive too: a capture
    // without --placement leaves none beside its own results.
    let mut stale = vec![ufcsr::MANIFEST_FILE.to_string()];
    if options.shard.is_none() {
        stale.extend(
            [ufcsr::placement::PLACEMENT_FRAMES_FILE, ufcsr::placement::PLACEMENT_PATCHES_FILE]
                .map(|f| format!("results/{f}")),
        );
    }
    for name in stale {
        ufcsr::files::remove_inside(out, &out.join(name))?;
    }
    Ok(())
}

/// Every file a capture of `scene` with `options` reads: the scene's files,
/// an external palette, an own PIdT and its legend.
pub(crate) fn capture_inputs(scene: &Scene, options: &CaptureOptions) -> Vec<PathBuf> {
    let mut inputs = scene.input_files.clone();
    inputs.extend(options.palette_file.iter().cloned());
    if let Some(own) = &options.own_labels {
        inputs.extend([own.pidt.clone(), own.parts.clone()]);
    }
    inputs
}

/// Writes `vehicle.glb` (the mesh exactly as unwrapped, with the palette
/// as its texture, so results go back onto the vehicle and the capture can
/// be rendered again) and `scene.glb` (the occluders, world coordinates, in
/// the background colour they are drawn in).
fn write_models(
    scene: &Scene,
    vertices: &[crate::render::Vertex],
    palette_png: &[u8],
    background: Color,
    out: &Path,
) -> Result<()> {
    vehicle_model(scene, vertices).write_glb(&out.join(VEHICLE_FILE), Some(("palette", palette_png)))?;
    // glTF colour factors are linear: the background's sRGB value decoded.
    let linear = |v: u8| {
        let c = f64::from(v) / 255.0;
        (if c <= 0.04045 { c / 12.92 } else { ((c + 0.055) / 1.055).powf(2.4) }) as f32
    };
    let [r, g, b] = background.rgb();
    let color = [linear(r), linear(g), linear(b), 1.0];
    ufcsr::output::write_scene_glb(&out.join(SCENE_FILE), &scene.occluders.scene_objects(), color)?;
    Ok(())
}

/// The palette's texels `texel_rgb` (of a palette of `size`) as PNG bytes
/// for `vehicle.glb` (the canonical palette's rows step by one colour, so
/// it compresses to a few hundred kB even at 4096²).
fn palette_png(texel_rgb: &[u8], size: [u32; 2]) -> Result<Vec<u8>> {
    let mut bytes = Vec::new();
    let encoded = ufcsr::files::encode_rgb_png(&mut bytes, size, texel_rgb, png::Compression::Fast.into());
    encoded.map_err(|e| CaptureError::BadOptions(format!("encoding the palette for vehicle.glb: {e}")))?;
    Ok(bytes)
}

/// Longest scenario a capture accepts: a day (longer is a unit mistake, and
/// would select billions of frames).
pub const MAX_SCENARIO_SECONDS: f64 = 86_400.0;

/// What must hold before any frame is rendered, so that bad values are
/// errors naming the problem instead of `null`s in the manifest.
fn check_capturable(scene: &Scene, scenario: &Scenario) -> Result<()> {
    let duration = scenario.duration_s;
    if !(duration.is_finite() && (0.0..=MAX_SCENARIO_SECONDS).contains(&duration)) {
        return Err(CaptureError::BadOptions(format!(
            "scenario {}: duration {duration} s is not between 0 and {MAX_SCENARIO_SECONDS} s",
            scenario.name
        )));
    }
    scenario.motion.check()?;
    if let Some(index) = scene.vehicle.parts.iter().position(|name| name.trim().is_empty()) {
        return Err(CaptureError::BadOptions(format!(
            "vehicle part {index} has an empty name (check `rename` in the scene file): the legend needs a name per part"
        )));
    }
    Ok(())
}

/// The vehicle's triangles by part, with their palette UVs.
fn vehicle_model(scene: &Scene, vertices: &[crate::render::Vertex]) -> ufcsr::VehicleModel {
    let mesh = &scene.vehicle;
    let mut parts: Vec<ufcsr::ModelPart> =
        mesh.parts.iter().map(|name| ufcsr::ModelPart { name: name.clone(), ..Default::default() }).collect();
    for (triangle, corners) in vertices.chunks_exact(3).enumerate() {
        let Some(part) = mesh.triangle_part.get(triangle).and_then(|&p| parts.get_mut(p as usize)) else {
            continue;
        };
        for vertex in corners {
            part.positions.push(vertex.position);
            part.uvs.push(vertex.uv);
        }
    }
    parts.retain(|part| !part.positions.is_empty());
    ufcsr::VehicleModel { parts }
}

/// The tiles of a whole capture, as the frame loop produced them.
pub struct CapturedTiles {
    pub entries: Vec<ufcsr::TileEntry>,
    pub frame_records: Vec<ufcsr::format::FrameEntry>,
    pub tally: TileTally,
    pub frames: u32,
    pub tiles: u64,
    /// What the impossible-scene checks found (see [`crate::job::scene_checks`]).
    pub warnings: Vec<String>,
}

/// Stage two: renders the selected frames of `scenario` into `sink`.
pub fn capture_frames(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    scene: &Scene,
    scenario: &Scenario,
    options: &CaptureOptions,
    prepared: &PreparedCapture,
    sink: &mut dyn TileSink,
) -> Result<CapturedTiles> {
    let rig = &scene.rig;
    check_capturable(scene, scenario)?;
    let frames = frames_to_capture(scene, scenario, options)?;
    // Over the whole selection, so that every shard warns alike.
    let selected = crate::job::scene_checks::selected_frames(scene, scenario, options)?;
    let warnings = crate::job::scene_checks::scene_warnings(scene, scenario, &selected)?;
    let tiles_per_eye = u64::from(rig.tiles[0]) * u64::from(rig.tiles[1]);
    let total = frames.len() as u64 * 2 * tiles_per_eye;
    let progress = &options.progress;
    progress.start(total);
    let frame_capture = FrameCapture {
        device,
        queue,
        renderer: &prepared.renderer,
        scene,
        scenario,
        background: prepared.background,
        no_cull: options.no_cull,
        no_scissor: options.no_scissor,
        keep_background_tiles: options.keep_background_tiles,
        vehicle_box: FrameCapture::vehicle_box(scene),
    };
    let mut captured = CapturedTiles {
        entries: Vec::with_capacity(total as usize),
        frame_records: Vec::with_capacity(frames.len()),
        tally: TileTally::default(),
        frames: frames.len() as u32,
        tiles: total,
        warnings,
    };
    let result = frames.iter().try_for_each(|&(position, frame)| {
        // A tile's index is its place in the whole capture, shards or not.
        let first_index = position * 2 * tiles_per_eye as usize;
        let frame = frame_capture.capture(frame, first_index, sink, &|| progress.advance(1))?;
        captured.entries.extend(frame.entries);
        captured.frame_records.push(frame.record);
        captured.tally.add(frame.tally);
        Ok(())
    });
    progress.finish();
    // Finish the sink even after an error, so no worker outlives the capture;
    // the first error wins.
    let finished = sink.finish();
    result.and(finished)?;
    Ok(captured)
}

/// The `(position in the selection, frame)` pairs this capture renders: the
/// selected frames, or this shard's part of them. An empty list is an error.
pub(crate) fn frames_to_capture(
    scene: &Scene,
    scenario: &Scenario,
    options: &CaptureOptions,
) -> Result<Vec<(usize, u32)>> {
    let selected = crate::job::scene_checks::selected_frames(scene, scenario, options)?;
    let frames = capture_shard::frames_of_shard(&selected, options.shard);
    if frames.is_empty()
        && let Some(shard) = options.shard
    {
        return Err(CaptureError::BadOptions(format!(
            "shard {shard} has no frame: only {} frames are selected; use at most {} shards",
            selected.len(),
            selected.len()
        )));
    }
    Ok(frames)
}

/// Captures one scenario of `scene` into `options.out` as PNG tiles, with a
/// device the caller created (see [`crate::render::gpu`]).
pub fn capture(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    scene: &Scene,
    scenario: &Scenario,
    options: &CaptureOptions,
) -> Result<Summary> {
    let start = Instant::now();
    scene.rig.check()?;
    let prepared = prepare_archive(device, queue, scene, options)?;
    let setup_seconds = start.elapsed().as_secs_f64();
    let old_tiles = match options.shard {
        None => OldTiles::All,
        Some(_) => {
            // The whole archive's manifest, if one is left from an earlier
            // capture, no longer describes it: `assemble` writes a new one.
            ufcsr::files::remove_inside(&options.out, &options.out.join(ufcsr::MANIFEST_FILE))?;
            let frames = frames_to_capture(scene, scenario, options)?;
            OldTiles::OfFrames(frames.into_iter().map(|(_, frame)| frame).collect())
        }
    };
    let mut pool = EncoderPool::start(
        &options.out,
        scene.rig.tile_pixels(),
        options.compression,
        options.tile_filter,
        options.encoder_threads,
        if options.resume { OldTiles::Keep } else { old_tiles },
    )?;
    let captured = capture_frames(device, queue, scene, scenario, options, &prepared, &mut pool)?;
    let summary = summarize(scene, scenario, options, &prepared, &captured, setup_seconds);
    write_manifest(scene, scenario, options, &prepared, captured, TileFiles::Written)?;
    Ok(Summary { seconds: start.elapsed().as_secs_f64(), ..summary })
}

/// The summary of a capture (its `seconds` still to be filled in).
pub(crate) fn summarize(
    scene: &Scene,
    scenario: &Scenario,
    options: &CaptureOptions,
    prepared: &PreparedCapture,
    captured: &CapturedTiles,
    setup_seconds: f64,
) -> Summary {
    let tally = captured.tally;
    Summary {
        out: options.out.clone(),
        scenario: scenario.name.clone(),
        frames: captured.frames,
        tiles: captured.tiles,
        tally,
        pixels: (captured.tiles - tally.culled)
            * u64::from(scene.rig.tile_pixels()[0])
            * u64::from(scene.rig.tile_pixels()[1]),
        seconds: 0.0,
        setup_seconds,
        texels_per_m2: prepared.unwrapped.texels_per_m2,
        palette_share: prepared.pidt.share(),
        parts: prepared.part_count,
        triangles: scene.vehicle.triangles.len(),
        warnings: prepared.warnings.iter().chain(&captured.warnings).cloned().collect(),
    }
}

/// Stage three: writes `manifest.json` for the captured tiles (a shard: its
/// part of it, `shards/manifest-I-of-N.json`).
pub(crate) fn write_manifest(
    scene: &Scene,
    scenario: &Scenario,
    options: &CaptureOptions,
    prepared: &PreparedCapture,
    captured: CapturedTiles,
    tiles: TileFiles,
) -> Result<Manifest> {
    let manifest = build_manifest(ManifestParts {
        scene,
        scenario,
        options,
        palette: prepared.palette.clone(),
        palette_size: prepared.palette_size,
        background_texel: prepared.background_texel,
        background: prepared.background,
        unwrapped: &prepared.unwrapped,
        pidt: &prepared.pidt,
        tiles: captured.entries,
        frame_records: captured.frame_records,
        tally: captured.tally,
        tile_files: tiles,
        warnings: prepared.warnings.iter().chain(&captured.warnings).cloned().collect(),
    });
    match options.shard {
        None => {
            manifest.write_to_dir(&options.out)?;
            ufcsr::files::mark_finished(&options.out)?;
        }
        Some(shard) => {
            let mut manifest = manifest.clone();
            // What assemble accounts for: the whole selection and this shard's tiles.
            let selected = crate::job::scene_checks::selected_frames(scene, scenario, options)?;
            let record = capture_shard::shard_record(shard, &selected, manifest.tiles.len());
            if let Some(capture) = &mut manifest.capture {
                capture.shard = Some(record);
            }
            let path = capture_shard::partial_manifest_path(&options.out, shard);
            let dir = options.out.join(capture_shard::SHARDS_DIR);
            ufcsr::files::real_dir(&dir)?;
            let bytes = serde_json::to_vec_pretty(&manifest)
                .map_err(|e| CaptureError::bad_file(&path, e.to_string()))?;
            ufcsr::files::write_bytes_atomically(&path, &bytes)?;
        }
    }
    Ok(manifest)
}

/// Runs `job` for each named scenario; with `subfolders` each goes to
/// `out/NAME` (`--scenario all`), otherwise into `out` itself.
pub fn for_each_scenario<T>(
    scene: &Scene,
    names: &[String],
    subfolders: bool,
    options: &CaptureOptions,
    mut job: impl FnMut(&Scenario, &CaptureOptions) -> Result<T>,
) -> Result<Vec<T>> {
    if names.len() > 1 && !subfolders {
        return Err(CaptureError::BadOptions("several scenarios need one sub-folder each".into()));
    }
    let mut done = Vec::new();
    for name in names {
        let scenario = scene.scenario(name)?;
        // A link planted at OUT/NAME is replaced by a real folder, never written through.
        let out: PathBuf = if subfolders {
            ufcsr::files::output_sub_dir(&options.out, Path::new(&scenario.name))?
        } else {
            options.out.clone()
        };
        done.push(job(scenario, &CaptureOptions { out, ..options.clone() })?);
    }
    Ok(done)
}

/// Captures several scenarios as PNG archives (see [`for_each_scenario`]).
pub fn capture_all(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    scene: &Scene,
    names: &[String],
    subfolders: bool,
    options: &CaptureOptions,
) -> Result<Vec<Summary>> {
    for_each_scenario(scene, names, subfolders, options, |scenario, options| {
        capture(device, queue, scene, scenario, options)
    })
}

/// Checks a written archive without the analyzer: every tile pixel is the
/// background or a canonical palette colour whose texel the PIdT labels.
/// Returns `(vehicle pixels, stray pixels)`.
pub fn verify(dir: &Path) -> Result<(u64, u64)> {
    let manifest =
        Manifest::load_from_dir(dir)?.ok_or_else(|| CaptureError::bad_file(dir, "no manifest.json"))?;
    // Colour → texel index: computed for the canonical palette, looked up otherwise.
    let (w, h, lookup) = match &manifest.palette {
        Some(PaletteRecord::Canonical { canonical: [w, h] }) => (*w, *h, None),
        Some(PaletteRecord::File(file)) => {
            let palette = Fcsp::from_png(&ufcsr::inside_archive(dir, "palette", file)?)?;
            let index: HashMap<Color, u32> = (0..palette.texel_count())
                .map(|t| (Color::from_packed(palette.color_of(t)), t as u32))
                .collect();
            (palette.width(), palette.height(), Some(index))
        }
        None => (4096, 4096, None),
    };
    let (size, pidt) = read_rgb_png(&dir.join("pidt.png"))?;
    if size != [w, h] {
        return Err(CaptureError::bad_file(dir, "pidt.png does not match the palette size"));
    }
    let (mut vehicle, mut stray) = (0u64, 0u64);
    let rgba32 = manifest.texel_ids() == ufcsr::format::TexelIds::Rgba32;
    for tile in &manifest.tiles {
        let Some(file) = &tile.file else { continue };
        let place = format!("tile {}", tile.place());
        let path = ufcsr::inside_archive(dir, &place, file)?;
        // 32-bit ids carry their high byte in alpha; 24-bit ones are the RGB.
        let ids = if rgba32 {
            ufcsr::read_rgba32_ids(&path)?.1
        } else {
            ufcsr::read_color_image(&path, |_| Ok(()))?.colors
        };
        for id in ids {
            if id == Color::DEFAULT_BACKGROUND.packed() {
                continue;
            }
            let index = match &lookup {
                None => Some(id as usize),
                Some(lookup) => lookup.get(&Color::from_packed(id)).map(|&i| i as usize),
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

/// Reads a PNG (any 8-bit format; alpha dropped) as RGB bytes, with the
/// analyzer's texture reader so both crates accept and reject the same files.
pub fn read_rgb_png(path: &Path) -> Result<([u32; 2], Vec<u8>)> {
    let image = ufcsr::read_color_image(path, |_| Ok(()))?;
    let rgb = image.colors.iter().flat_map(|&color| Color::from_packed(color).rgb()).collect();
    Ok(([image.width, image.height], rgb))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::job::options::FrameSelection;
    use crate::job::tile_sink::{is_tile_name, tile_file};
    use crate::scene::rig::Eye;

    /// Each kept frame stands for the `step` frames centred on it (the frame clock: step / fps), so
    /// every Nth frame keeps the middles of the blocks `[0, N)`, `[N, 2N)`, … that lie mostly in the
    /// scenario: they stand for its `count` frames to within half a step, and for its duration
    /// (`count − 1` frame intervals) exactly when the step divides it. 2 s at 60 fps every 30th
    /// frame: frames 15–105, 2 s, where frames 0–120 read 2.5 s.
    #[test]
    fn every_nth_frame_keeps_the_middle_of_each_step_and_stands_for_the_scenarios_time() {
        assert_eq!(FrameSelection::every(30).frames(121), vec![15, 45, 75, 105]);
        assert_eq!(FrameSelection::every(90).frames(121), vec![45]);
        let third = FrameSelection::every(3).frames(181);
        assert_eq!((third.len(), third[0], third[59]), (60, 1, 178), "the paper's 3 s, 0-179/3 moved by one");
        assert_eq!(
            FrameSelection::every(1).frames(181),
            (0..181).collect::<Vec<_>>(),
            "every frame, the last too"
        );
        for count in 1..=400u32 {
            for step in 1..=count {
                let kept = FrameSelection::every(step).frames(count);
                let time = u64::try_from(kept.len()).unwrap() * u64::from(step);
                let off = time.abs_diff(u64::from(count));
                assert!(2 * off <= u64::from(step), "{count} frames every {step}th: {time} frames of time");
                if step > 1 && (count - 1) % step == 0 {
                    assert_eq!(time, u64::from(count - 1), "{count} frames every {step}th");
                }
                // The middle of each block of `step` frames from frame 0.
                assert!(kept.iter().enumerate().all(|(j, &f)| f == j as u32 * step + step / 2));
            }
        }
        // Other phases (a study's offsets): each frame kept while most of its step is inside.
        assert_eq!(crate::job::stepped_frames(121, 30, 0), vec![30, 60, 90, 120]);
        assert_eq!(crate::job::stepped_frames(121, 30, 29), vec![29, 59, 89, 119]);
        // A step over twice the scenario keeps one frame, at the phase or the scenario's middle.
        assert_eq!(FrameSelection::every(300).frames(121), vec![60]);
        assert_eq!(crate::job::stepped_frames(121, 300, 7), vec![7]);
        assert!(FrameSelection::every(3).frames(0).is_empty());
    }

    #[test]
    fn frame_lists_parse() {
        let frames: FrameSelection = "0,30,60-90/10,5".parse().unwrap();
        assert_eq!(frames.frames(181), vec![0, 5, 30, 60, 70, 80, 90]);
        assert_eq!(frames.frames(40), vec![0, 5, 30]);
        assert_eq!("all".parse::<FrameSelection>().unwrap().frames(3), vec![0, 1, 2]);
        assert!("5-1".parse::<FrameSelection>().is_err());
        // Every Nth frame, whatever the scenario's length (--preview's selection): the middles of
        // frames 0–9 and 10–19; of 20–29 only half lie in 25 frames, more than half in 26.
        assert_eq!("all/10".parse::<FrameSelection>().unwrap().frames(25), vec![5, 15]);
        assert_eq!("all/10".parse::<FrameSelection>().unwrap().frames(26), vec![5, 15, 25]);
        assert_eq!(FrameSelection::every(10), "ALL/10".parse().unwrap());
        assert!("all/0".parse::<FrameSelection>().is_err() && "all/x".parse::<FrameSelection>().is_err());
        assert_eq!(tile_file(7, Eye::Right, 1, 4), PathBuf::from("tiles/f0007_right_r1_c4.png"));
        assert!(is_tile_name("f0007_right_r1_c4.png"));
        assert!(
            !is_tile_name("f0007_right_r1_c4.png.bak")
                && !is_tile_name("notes.png")
                && !is_tile_name("f1_up_r1_c1.png")
        );
    }
}
