//! # ufcsr — Unwrapped Full Color Space Recording
//!
//! Counts how often each texel of a vehicle's unwrapped surface is visible in
//! captured frames, joins the counts with a Part Identification Texture into
//! per-part statistics, and renders a heatmap texture.
//!
//! No `unsafe` outside `simd/`, the vector kernels, which allows it under
//! the rules its module doc states (docs/reliability.md, "Unsafe code").
#![deny(unsafe_code)]
// Unit tests may use std::fs directly (fixtures); production code goes through
// the file layer (clippy.toml, docs/reliability.md).
#![cfg_attr(test, allow(clippy::disallowed_methods, clippy::disallowed_types))]

mod analyze;
mod archive;
mod checks;
mod color;
mod count;
mod describe;
mod error;
mod files;
mod format;
mod optics;
mod output;
mod placement;
mod png;
mod result;
mod simd;
mod stats;
mod testing;

pub use self::png::{PixelLayout, RowReader, read_color_image, read_file, verify_image_data};
pub use analyze::{analyze, analyze_counted, analyze_texel_counts};
pub use archive::{
    AnalyzeOptions, Archive, CaptureGeometry, Dedupe, Fcsp, HeatmapOptions, ImageSource, Legend,
    LoadedLabels, MANIFEST_FILE, MANIFEST_SCHEMA, Manifest, ModelPart, PaletteChoice, PaletteRecord,
    PaletteSetting, Part, Pidt, Progress, Scale, ScenarioTrack, Shard, TileEntry, Timings, TrackFrame,
    TrimMode, UNLABELLED, VehicleModel, inside_archive, parse_palette_size, write_canonical_png,
};
pub use checks::{ColorChecks, ColorWarning, NeighbourSample};
pub use color::{AtomicColorSet, COLOR_COUNT, Color, ParseColorError, SeenSet, color_key};
pub use count::{
    Classifier, CountedTile, Counts, EmptyTile, FrameLabel, FrameRecord, ImageTally, KERNEL_ENV, Kernel,
    PartLookup, PartPixels, PartRows, PixelClass, RowScan, TileCounter, scan_image, scan_image_by_part,
};
pub use describe::{DEFAULT_PATTERN, DescribeOptions, Described, SoloSummary, describe, parse_fov};
pub use error::{Error, Result};
pub use files::{
    GltfModel, IMAGE_LIMIT, MAX_COORDINATE_M, MODEL_LIMIT, PngEncoding, SMALL_INPUT_LIMIT, Staging,
    check_accessors, check_coordinates, copy_into, create_output_dir, create_private_dir, crosses_link,
    encode_rgb_png, open_regular, output_sub_dir, parse_gltf, read_gltf, read_limited, read_limited_text,
    real_dir, refuse_overwriting_inputs, refuse_replacing_non_file, remove_dead_runs, remove_inside,
    remove_on_interrupt, remove_stale_staging, remove_stale_temporaries, remove_temporaries, resolve_inside,
    same_path, write_atomically, write_bytes_atomically, write_figure_png, write_rgb_png,
};
// Issue 41: a capture that has not finished marks its folder; the analyzer refuses it.
pub use files::{UNFINISHED_FILE, mark_finished, mark_unfinished, refuse_unfinished, unfinished_outputs};
pub use format::design::{
    BestPlacement, BodyDimsOverride, CandidateSummary, CandidateValue, CellLevels, Crossing,
    DESIGN_RESULT_SCHEMA, DESIGN_SCHEMA, DESIGN_TASK_SCHEMA, Design, DesignMeasure, DesignPopulation,
    DesignResult, DesignTask, GroupSummary, LevelEffect, MainEffect, MeanInterval, ScenarioLevel,
    ScenarioSource, StreetScenario, TrafficKind, TrafficLevel, UnitValues, VehicleLevel,
};
pub use format::manifest::{
    CaptureRecord, DemoScenario, EyePose, EyeProjectionRecord, FollowRecord, FrameEntry, LabelsRecord,
    OccluderPose, PaintedByPart, PedestrianSetting, PoseRecord, RigRecord, RigSettings, ScenarioRecord,
    SceneRecord, ShardRecord, TrackKey, TrafficRecord, UnwrapRecord,
};
pub use format::observers::{
    CoarserCapture, DEFAULT_TRUNCATE_SD, DisplayOverObservers, OBSERVERS_SCHEMA, ObserverDisplayRecord,
    ObserverDisplays, ObserverPlace, ObserverPopulation, ObserverRecord, ObserverSampling, ObserverStudy,
    PartOverObservers, PopulationValue, ResolutionCheck, StatureGroup, US_ADULTS_SOURCE,
};
pub use format::placement::{
    ArchiveRecord, CandidateRecord, CombinationRecord, ExcludedRecord, ExclusionReason, ExposureRecord,
    MemberRecord, PlacementDocument, RunnerUpRecord, SensitivityRecord, SensitivitySet, ThresholdsRecord,
    UncertaintyRecord,
};
pub use format::placement_csv::{PLACEMENT_FRAMES_OPTIONAL, PLACEMENT_TABLE_LIMIT, PlacementFrameRow};
pub use format::result::{
    ColorTexels, CountMeasure, DedupeReport, FailedImage, ImageCounts, PartMeasure, PixelCounts, ResultFile,
    Settings, StrayImage, TexelCountsJson, TrimReport, UnlabelledReport,
};
pub use format::timings::{TIMINGS_SCHEMA, TimingsFile};
pub use format::{ErrorVsExact, ExactReference, ShareError, Study, StudyPick, StudyRow};
pub use format::{Format, SCHEMAS, check_version, parse_json};
pub use optics::{EyeProjection, TileView};
pub use output::html_escape;
pub use output::{
    AREA_HEATMAPS, AREA_UNIT, AreaLevels, COUNT_HEATMAP_FILE, COUNT_HEATMAPS, ComparisonOptions, CsvStyle,
    DEFAULT_VIEWS_SCALE, DIRECTIONS, FRAME_STRIP_FILE, FigureSize, Figures, HEATMAP_FILE, LEGEND_LINE,
    LEGEND_TEXT_PX, LegendEntry, MAP_FILE, MAP_SIZE, MIN_TEXT_PT, MM_PER_PT, MapContent, MapFrame,
    NEEDS_ITS_FOLDER, NEVER_SEEN, OKABE_ITO, OWN_SCALES, PlotText, QUOTED_HEADING, RANKED_HEADING,
    ResultSetOptions, SHARED_SCALE, STRIP_BACKGROUND, STRIP_FRAME_HEIGHT, STRIP_UNLABELLED, SceneObject,
    SceneShapes, TextLayout, VIEW_BASE, VIEWS_PDF_FILE, ViewCamera, ViewTexture, WrittenComparison,
    WrittenFiles, WrittenViews, ZBuffer, area_views_caption, bar_ticks, csv_field, default_output_dir,
    format_counted_table, format_table, largest_area, measure_unit, plasma, plot_font_available,
    render_heatmap, render_view, sheet_text_px, text_px_for, time_color, view_cameras, views_caption,
    write_area_heatmap, write_comparison, write_comparison_with, write_heatmap, write_parts_csv,
    write_results, write_results_with, write_scenario_map, write_scene_glb, write_views,
};
pub use placement::eligible::{Fit, default_exclusions, default_not_mountable, excluded_line, exclusions};
pub use placement::legibility::{ArchiveTimelines, Timeline};
pub use placement::literature::{
    LocationScore, PUBLISHED_LOCATIONS, PUBLISHED_LOCATIONS_FILE, PlaceScore, PublishedLocation, Zone,
    format_published_locations, published_locations, write_published_locations,
};
pub use placement::report::{WrittenPlacement, format_placement};
pub use placement::uncertainty::{
    BestShares, NO_CANDIDATE_LEGIBLE, ONE_UNIT, best_shares, bootstrap_weights, t_interval,
    t_interval_signed, tied as tied_scores, tied_best_credits,
};
pub use placement::{
    CandidateKind, CharacterHeight, DEFAULT_EPSILON_S, DEFAULT_NOT_MOUNTABLE, DEFAULT_REGION_RADIUS_M,
    DEFAULT_REPLICATES, EXHAUSTIVE_LIMIT, Exposure, EyeRule, MAX_K, Mark, Method, Objective,
    PLACEMENT_FRAMES_COLUMNS, PLACEMENT_FRAMES_FILE, PLACEMENT_PATCHES_COLUMNS, PLACEMENT_PATCHES_FILE,
    PLACEMENT_PICTURE_FILE, PLACEMENT_SCHEMA, PLACEMENT_VIEWS_DIR, PatchFootprint, PicturedSet, Placement,
    PlacementOptions, PlacementTable, Resampling, Thresholds, brute_force_best, parse_character_height,
    placement, read_footprints, read_table, render_marked, resolve_table, timelines, write_placement,
};
pub use result::{
    Analysis, AnalysisResult, Comparison, FrameTable, Measures, PartStats, PartTable, RESULT_SCHEMA,
    ResolutionReport, TEXEL_AREA_FILE, TEXEL_AREA_UNITS_FILE, TexelAreaUnits, compare_parts, join_parts,
    kendall_tau_b, merge_results, read_result_summary, read_texel_area, read_texel_area_in,
    read_texel_counts, write_result_json, write_texel_area, write_timings_json,
};
pub use stats::{SplitMix64, t975};
#[doc(hidden)]
pub use testing::fuzz_entry;
#[cfg(feature = "synthetic")]
pub use testing::kernel_checks::{KernelCheck, kernel_checks};
#[cfg(feature = "synthetic")]
pub use testing::synthetic;
