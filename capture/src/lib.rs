//! # ufcsr-capture — record UFCSR archives with a headless, exact wgpu renderer
//!
//! Replaces the Unity project of the UFCSR paper: a vehicle mesh is unwrapped
//! so that every triangle owns its own texels of the canonical palette, a Part
//! Identification Texture (PIdT) labels those texels, and each frame of a
//! scenario is rendered unlit from both eyes of a pedestrian into tiles whose
//! pixels name the texel they show. The archive is what `ufcsr analyze` reads.
//!
//! The modules are private, one folder per stage (each folder's `mod.rs`
//! says what it holds): `scene` what is captured (scene file, meshes,
//! vehicle, rig, motion, the demo), `texture` the unwrap, palettes and PIdT,
//! `render` the GPU device and renderer, `job` the capture job (options,
//! frames, tile sinks, manifest, shards, batches, the overwrite guard), `exact`
//! the exact ray-traced measure, `study` the resolution study, `design` the
//! factorial study (plan, run, merge), `inspect` looking at a
//! vehicle or a result. The API is the flat list below: [`capture`],
//! [`capture_counted`] and [`measure_unobstructed`] are the entry points,
//! with a [`Scene`], [`CaptureOptions`] and a [`Gpu`]. The library draws no
//! progress bar: it reports to a [`ufcsr::Progress`] ([`CaptureProgress`]).
#![forbid(unsafe_code)]
// Unit tests may use std::fs directly (fixtures); production code goes through
// the file layer (clippy.toml, docs/reliability.md).
#![cfg_attr(test, allow(clippy::disallowed_methods, clippy::disallowed_types))]

mod design;
mod error;
mod exact;
mod inspect;
mod job;
mod render;
mod scene;
mod study;
mod texture;

pub use design::checks::check_inputs as check_design_inputs;
pub use design::merge::{merge_design, read_tasks};
pub use design::output::write_result_set as write_design_result_set;
pub use design::plan::{MAX_TASKS, Plan, PlannedTask, plan_checked, plan_design};
pub use design::report::write_result as write_design_result;
pub use design::run::{TASK_FILE, candidate_values, derived_seed, run_task, task_dir, write_task};
pub use design::stats::{
    CellData, INTERVAL_METHOD, Pair, cell_data, group_summary, main_effects, mean_interval, p_best,
};
pub use design::task_checks::check_task as check_design_task;
pub use design::{TaskOutcome, run_design};
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
    inspect, triangle_quality, view_values, views_from_results,
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
pub use scene::family::{BodyDims, BodyType, body_mesh};
// At the root: its entries reach into scene and design alike.
#[doc(hidden)]
pub mod fuzz_entry;
pub use scene::{
    ADJACENT_LANE_AHEAD_M, ADJACENT_LANE_M, Axes, DemoTraffic, Eye, EyeCamera, FollowOffset, FrameState, Key,
    LEAD_CAR_AHEAD_M, Mesh, Motion, MovingOccluder, OccluderObject, OccluderPath, Occluders,
    PEDESTRIAN_BODY_M, PartMapReport, PartMapSpec, PartRule, PartSource, PartsFrom, Pose, RegionReport, Rig,
    Scenario, Scene, SceneFile, StreetOptions, TileId, Track, UNMAPPED_PART, ValueOrTrack, VehicleSpec,
    box_corners, box_outside, degenerate_vehicle, load_vehicle, look_to, pedestrian_body,
    reversed_z_perspective, street_scene, triangle_area, vehicle_to_world,
};
pub use study::observers::displays::{
    DisplayOptions, DisplayStudy, OBSERVER_DISPLAYS_FILE, ObserverLegible, run_observer_displays,
    summarize_displays, write_display_study,
};
pub use study::observers::interval::{IntervalKind, percentile, population_value};
pub use study::observers::population::{
    MAX_OBSERVERS, SampledObserver, check_population, eye_height_quantile, normal_cdf, sample_observers,
};
pub use study::observers::{
    DEFAULT_SAFETY_FACTOR, HUMAN_IPD_M, ObserverOptions, ObserverPreset, PAPER_EYE_HEIGHT_M, PAPER_IPD_M,
    describe_observer, median_eye_height_m, people_by_default, run_observer_study,
    summarize as summarize_observers, write_observer_study,
};
pub use study::offsets::{FrameValues, IntervalOptions, error_at_offset, setting_error};
pub use study::{
    ErrorVsExact, Study, StudyMeasure, StudyOptions, StudyRow, StudyTables, exact_tables, run_study,
    run_study_with_tables, write_study,
};
pub use texture::{
    OwnLabelFiles, PartOverlap, PidtImage, UNLABELLED_COLOR, Unwrapped, UvOverlaps, background_texel,
    footprint, keep_uvs, paint_pidt, unwrap_islands, unwrap_islands_avoiding, uv_overlaps,
};
/// The capture's `--palette-size` (above 2^24 texels: 32-bit texel ids).
pub use ufcsr::parse_capture_palette_size;
/// The analyzer's one `--palette-size` parser, for the capture's commands.
pub use ufcsr::parse_palette_size;
