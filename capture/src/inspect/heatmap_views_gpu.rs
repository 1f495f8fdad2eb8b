//! The analyzer's eight heatmap views, drawn with the capture's wgpu
//! renderer: `ufcsr-capture views RESULTS`.
//!
//! The analyzer draws its views on the CPU (it needs no GPU); this module
//! hands the same cameras ([`ufcsr::view_cameras`]) to [`Renderer`], with
//! the views' per-texel colours (plasma, grey for never seen) as its
//! external palette, white as background and no occluders. Everything else
//! (files, contact sheet, colour bar, labels) is the analyzer's
//! [`ufcsr::write_views_with`], so the two renderers differ only in how
//! they fill pixels, and `tests/it/views_gpu.rs` holds them to the same
//! pictures.

use std::path::{Path, PathBuf};

use glam::{DMat4, DVec3, DVec4};
use ufcsr::{Color, VehicleModel, ViewCamera, ViewTexture, WrittenViews};

use crate::error::{CaptureError, Result};
use crate::render::{GpuPalette, RenderSetup, Renderer, TileDraw, Vertex};
use crate::scene::occluders::Occluders;

/// White, as the CPU views' paper.
const PAPER: u32 = 0xFF_FFFF;

/// Where [`views_from_results`] reads and writes.
#[derive(Debug, Clone)]
pub struct ViewsOptions {
    /// A result folder: `result.json` and (unless `model` says otherwise)
    /// `heatmap.glb`.
    pub results: PathBuf,
    /// The vehicle model with its palette UVs (default `RESULTS/heatmap.glb`).
    pub model: Option<PathBuf>,
    /// Where `views/` and `views.png` go (default: the result folder).
    pub out: Option<PathBuf>,
    /// Each view is 400×300 pixels times this (`--views-scale`).
    pub views_scale: u32,
}

/// Draws the eight views of `texture` on `model` with the GPU and writes them
/// into `dir` as the analyzer does.
pub fn write_views_gpu(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    model: &VehicleModel,
    texture: &ViewTexture,
    dir: &Path,
) -> Result<WrittenViews> {
    let palette = GpuPalette::External { size: [texture.width, texture.height], rgba: texture.texel_rgba() };
    let vertices = model_vertices(model, [texture.width, texture.height]);
    let cameras = ufcsr::view_cameras(model, texture.views_scale);
    let size = cameras.first().map_or([1, 1], |camera| camera.size);
    let occluders = Occluders::default();
    let setup = RenderSetup {
        tile_size: size,
        palette: &palette,
        background: Color::from_packed(PAPER),
        vehicle: &vertices,
        occluders: &occluders,
        origin: DVec3::ZERO,
    };
    let renderer = Renderer::new(device, queue, &setup)?;
    // Draw all eight first, so a GPU error is reported as one; then the
    // analyzer writes them, with its sheet, each under its camera's name.
    let mut pictures = Vec::with_capacity(cameras.len());
    for camera in &cameras {
        let draw = TileDraw {
            moving: &[],
            clip_from_vehicle: clip_from_vehicle(camera),
            clip_from_world: DMat4::IDENTITY,
            occluders: &[],
        };
        let rgba = renderer.render_tile(device, queue, &draw)?;
        pictures
            .push((camera.name, rgba.chunks_exact(4).flat_map(|p| [p[0], p[1], p[2]]).collect::<Vec<u8>>()));
    }
    Ok(ufcsr::write_views_with(model, texture, dir, |camera| {
        // A missing picture is an empty one, which write_views_with refuses by name.
        Ok(pictures
            .iter()
            .find(|(name, _)| *name == camera.name)
            .map(|(_, rgb)| rgb.clone())
            .unwrap_or_default())
    })?)
}

/// Reads `result.json` and the model, and writes the views with the GPU:
/// what `ufcsr-capture views` does. Returns the files written.
pub fn views_from_results(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    options: &ViewsOptions,
) -> Result<WrittenViews> {
    let counts = ufcsr::read_texel_counts(&options.results.join("result.json"))?;
    let model_path = options.model.clone().unwrap_or_else(|| options.results.join("heatmap.glb"));
    if !model_path.is_file() {
        return Err(CaptureError::BadFile {
            path: model_path,
            message: "no vehicle model here (the result has no heatmap.glb; name the model with --model)"
                .into(),
        });
    }
    let model = VehicleModel::read(&model_path)?;
    // The scenario as the analysed archive's manifest says, when it is still there.
    let track = ufcsr::ScenarioTrack::from_archive(Path::new(&counts.archive));
    let scenario = track.as_ref().and_then(|track| track.name.as_deref());
    let texture = ViewTexture {
        counts: &counts.texel_counts,
        width: counts.width,
        height: counts.height,
        options: ufcsr::HeatmapOptions { scale: counts.scale, max: counts.max },
        caption: format!("{} · wgpu", ufcsr::views_caption(counts.measure, &counts.archive, scenario)),
        unit: ufcsr::measure_unit(counts.measure).to_string(),
        quantum: None,
        views_scale: options.views_scale,
        pedestrian_azimuths_deg: track.map_or_else(Vec::new, |track| {
            track.frames.iter().filter_map(ufcsr::TrackFrame::pedestrian_azimuth_deg).collect()
        }),
    };
    let out = options.out.clone().unwrap_or_else(|| options.results.clone());
    let mut outputs: Vec<String> =
        ufcsr::DIRECTIONS.iter().map(|(name, _)| format!("views/{name}.png")).collect();
    outputs.push("views.png".into());
    outputs.push("views.pdf".into());
    crate::job::overwrite_guard::refuse_overwriting_inputs(
        &out,
        &outputs.iter().map(String::as_str).collect::<Vec<_>>(),
        &[],
        &[options.results.join("result.json"), model_path],
    )?;
    write_views_gpu(device, queue, &model, &texture, &out)
}

/// The model's triangles as renderer vertices: each carries its triangle's
/// UVs in texel coordinates as its chart (see `shader.wgsl`), so the GPU
/// picks the texel the CPU views pick, clamped to the triangle.
fn model_vertices(model: &VehicleModel, size: [u32; 2]) -> Vec<Vertex> {
    let [width, height] = size.map(|s| s as f32);
    let mut vertices = Vec::new();
    for part in &model.parts {
        for (corners, uvs) in part.positions.chunks_exact(3).zip(part.uvs.chunks_exact(3)) {
            let chart = [0, 1, 2].map(|k| [uvs[k][0] * width, uvs[k][1] * height]);
            for k in 0..3 {
                vertices.push(Vertex { position: corners[k], uv: uvs[k], chart });
            }
        }
    }
    vertices
}

/// Vehicle frame → clip space for `camera`: the CPU views' orthographic
/// projection (x right, y up, pixel centres alike), depth in reversed Z
/// (nearer is larger, as the renderer's depth test wants) within 0.05–0.95.
fn clip_from_vehicle(camera: &ViewCamera) -> DMat4 {
    let [width, height] = camera.size.map(f64::from);
    let (kx, ky) = (camera.pixels_per_metre / (width / 2.0), camera.pixels_per_metre / (height / 2.0));
    let [near, far] = camera.depth_range;
    let kz = 0.9 / (far - near).max(1e-9);
    let [right, up, back] = [camera.right, camera.up, camera.back].map(DVec3::from_array);
    // Rows: x = (p·right − cx)·kx, y = (p·up − cy)·ky, z = 0.05 + (far + p·back)·kz.
    let rows = [
        (right * kx).extend(-camera.centre[0] * kx),
        (up * ky).extend(-camera.centre[1] * ky),
        (back * kz).extend(0.05 + far * kz),
        DVec4::W,
    ];
    DMat4::from_cols(rows[0], rows[1], rows[2], rows[3]).transpose()
}
