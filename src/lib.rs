//! # ufcsr — Unwrapped Full Color Space Recording
//!
//! Counts how often each texel of a vehicle's unwrapped surface is visible in
//! captured frames, joins the counts with a Part Identification Texture into
//! per-part statistics, and renders a heatmap texture.

mod analyze;
mod checks;
mod color;
mod count;
mod describe;
mod error;
mod files;
mod format;
mod input;
mod kernel;
mod output;
mod placement;
mod result;
mod testing;

pub use analyze::{analyze, analyze_counted, analyze_texel_counts};
pub use checks::{ColourChecks, ColourWarning, NeighbourSample};
pub use color::{AtomicColorSet, COLOR_COUNT, Color, ParseColorError, SeenSet, color_key};
pub use count::{
    Classifier, CountedTile, Counts, EmptyTile, FrameLabel, FrameRecord, ImageTally, KERNEL_ENV, Kernel,
    PartLookup, PartPixels, PartRows, PixelClass, RowScan, TileCounter, scan_image, scan_image_by_part,
};
pub use describe::{DEFAULT_PATTERN, DescribeOptions, Described, describe, parse_fov};
pub use error::{Error, Result};
#[cfg(feature = "cli")]
pub use files::remove_temporaries_on_interrupt;
pub use files::{
    GltfModel, MAX_COORDINATE_M, MODEL_LIMIT, SMALL_INPUT_LIMIT, check_accessors, check_coordinates,
    parse_gltf, read_gltf, read_limited, real_dir, refuse_overwriting_inputs, remove_on_interrupt,
    remove_stale_staging, remove_temporaries, resolve_inside, same_path, write_atomically,
    write_bytes_atomically, write_rgb_png,
};
pub use format::observers::{
    CoarserCapture, DEFAULT_TRUNCATE_SD, OBSERVERS_SCHEMA, ObserverPlace, ObserverPopulation, ObserverRecord,
    ObserverSampling, ObserverStudy, PartOverObservers, PopulationValue, ResolutionCheck, StatureGroup,
    US_ADULTS_SOURCE,
};
pub use input::{
    AnalyzeOptions, Archive, CaptureGeometry, Dedupe, EyeProjection, Fcsp, HeatmapOptions, ImageSource,
    Legend, LoadedLabels, MANIFEST_FILE, MANIFEST_SCHEMA, MEASURE_PIXELS, Manifest, PaletteChoice,
    PaletteRecord, PaletteSetting, Part, Pidt, PixelLayout, Progress, RowReader, Scale, ScenarioTrack, Shard,
    TileEntry, TileView, Timings, TrackFrame, TrimMode, UNLABELLED, inside_archive, parse_palette_size,
    read_color_image, read_file, verify_image_data, write_canonical_png,
};
pub use output::{
    CsvStyle, DEFAULT_VIEWS_SCALE, DIRECTIONS, FRAME_STRIP_FILE, MAP_FILE, MAP_SIZE, MapContent, MapFrame,
    ModelPart, NEVER_SEEN, ResultSetOptions, STRIP_BACKGROUND, STRIP_FRAME_HEIGHT, STRIP_UNLABELLED,
    SceneObject, SceneShapes, VIEW_BASE, VehicleModel, ViewCamera, ViewTexture, WrittenFiles, WrittenViews,
    ZBuffer, bar_ticks, csv_field, default_output_dir, format_counted_table, format_table, measure_unit,
    plasma, plot_font_available, render_heatmap, render_view, time_colour, view_cameras, views_caption,
    write_comparison, write_heatmap, write_parts_csv, write_results, write_results_with, write_scenario_map,
    write_scene_glb, write_views, write_views_with,
};
#[cfg(feature = "cli")]
pub use output::{Shell, print_completions, write_man_pages};
pub use placement::report::{WrittenPlacement, format_placement};
pub use placement::{
    CandidateKind, CandidateSummary, Combination, EXHAUSTIVE_LIMIT, Exposure, EyeRule, MAX_K, Mark, Method,
    Objective, PLACEMENT_FRAMES_COLUMNS, PLACEMENT_FRAMES_FILE, PLACEMENT_PATCHES_COLUMNS,
    PLACEMENT_PATCHES_FILE, PLACEMENT_PICTURE_FILE, PLACEMENT_SCHEMA, PLACEMENT_VIEWS_DIR, PatchFootprint,
    PicturedSet, Placement, PlacementOptions, PlacementTable, Thresholds, brute_force_best, placement,
    read_footprints, read_table, render_marked, resolve_table, write_placement,
};
pub use result::{
    Analysis, AnalysisResult, Comparison, FrameTable, Measures, PartStats, PartTable, RESULT_SCHEMA,
    ResolutionReport, compare_parts, join_parts, kendall_tau_b, merge_results, read_result_summary,
    read_texel_counts, write_result_json, write_timings_json,
};
#[doc(hidden)]
pub use testing::fuzz_entry;
#[cfg(feature = "synthetic")]
pub use testing::synthetic;
