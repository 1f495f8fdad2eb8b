//! # ufcsr-capture — record UFCSR archives with a headless, exact wgpu renderer
//!
//! Replaces the Unity project of the UFCSR paper: a vehicle mesh is unwrapped
//! so that every triangle owns its own texels of the canonical palette, a Part
//! Identification Texture (PIdT) labels those texels, and each frame of a
//! scenario is rendered unlit from both eyes of a pedestrian into tiles whose
//! pixels name the texel they show. The archive is what `ufcsr analyze` reads.
//!
//! One folder per stage (each folder's `mod.rs`
//! says what it holds): `scene` what is captured (scene file, meshes,
//! vehicle, rig, motion, the demo), `texture` the unwrap, palettes and PIdT,
//! `render` the GPU device and renderer, `job` the capture job (options,
//! frames, tile sinks, manifest, shards, batches, the overwrite guard), `exact`
//! the exact ray-traced measure, `study` the resolution study, `design` the
//! factorial study (plan, run, merge), `inspect` looking at a
//! vehicle or a result. `scene`, `study` and `design` are public, each one
//! flat list (a scene's parts, the studies' options and results, the design
//! pipeline); the others are private. The root is the flat list below: [`capture`],
//! [`capture_counted`] and [`measure_unobstructed`] are the entry points,
//! with a [`Scene`], [`CaptureOptions`] and a [`Gpu`]. The library draws no
//! progress bar: it reports to a [`ufcsr::Progress`] ([`CaptureProgress`]).
#![forbid(unsafe_code)]
// Unit tests may use std::fs directly (fixtures); production code goes through
// the file layer (clippy.toml, docs/reliability.md).
#![cfg_attr(test, allow(clippy::disallowed_methods, clippy::disallowed_types))]

pub mod design;
mod error;
mod exact;
mod inspect;
mod job;
mod render;
pub mod scene;
pub mod study;
mod texture;

pub use design::merge::merge_design;
pub use design::plan::plan_design;
pub use design::run_design;
pub use error::{CaptureError, Result};
pub use exact::{
    DEFAULT_PATCH_SPACING_M, DEFAULT_TEXEL_SAMPLES, DEG2_PER_SR, EDGE_ON_F32_ULPS, EDGE_ON_RELATIVE,
    EyeFrame, MAX_TEXEL_SAMPLES, MeasureOptions, Obstacles, PLACEMENT_FRAMES_FILE, PLACEMENT_PATCHES_COLUMNS,
    PLACEMENT_PATCHES_FILE, PartEstimate, PlacementCandidates, PlacementWritten, SURFACE_LIFT_RELATIVE,
    SampledTexel, SurfaceSample, SurfaceSamples, TexelVisibility, Tracer, TriangleBvh, UnobstructedCapture,
    estimate_parts, eye_frame, eye_frames, is_sampled, measure_unobstructed, parse_display,
    seconds_per_frame, surface_samples, texel_visibility, visible_solid_angle,
};
pub use inspect::{
    InspectOptions, Inspection, PartInfo, Sliver, TriangleQuality, UvState, ViewValues, ViewsOptions,
    inspect, inspect_fleet, triangle_quality, view_values, views_from_results,
};
pub use job::{
    Assembled, Batch, CaptureOptions, CaptureProgress, CaptureSetup, CapturedTiles, Compression,
    CountedCapture, FrameSelection, MAX_FRAMES, MAX_SCENARIO_SECONDS, MAX_SELECTED_FRAMES, MAX_TILES,
    PreparedCapture, Summary, Task, TileFilter, TileTally, assemble, capture, capture_all, capture_counted,
    capture_frames, for_each_scenario, load_batch, partial_manifest_path, plan_batch, prepare, read_rgb_png,
    verify,
};
pub use render::{
    Backend, Gpu, GpuPalette, PixelRect, RenderSetup, Renderer, TileDraw, Vertex, vehicle_vertices,
};
// At the root: its entries reach into scene and design alike.
#[doc(hidden)]
pub mod fuzz_entry;
pub use scene::{Mesh, Rig, Scenario, Scene, load_vehicle};
pub use study::observers::run_observer_study;
pub use study::run_study;
pub use texture::{
    OwnLabelFiles, PartOverlap, PidtImage, UNLABELLED_COLOR, Unwrapped, UvOverlaps, background_texel,
    footprint, keep_uvs, paint_pidt, unwrap_islands, unwrap_islands_avoiding, uv_overlaps,
};
/// The capture's `--palette-size` (above 2^24 texels: 32-bit texel ids).
pub use ufcsr::parse_capture_palette_size;
/// The analyzer's one `--palette-size` parser, for the capture's commands.
pub use ufcsr::parse_palette_size;
