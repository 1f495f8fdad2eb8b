//! # ufcsr — Unwrapped Full Color Space Recording
//!
//! Counts how often each texel of a vehicle's unwrapped surface is visible in
//! captured frames, joins the counts with a Part Identification Texture into
//! per-part statistics, and renders a heatmap texture.

mod analyze;
mod archive;
mod bitset;
mod color;
mod compare;
mod compare_report;
mod count;
mod decode;
mod error;
mod frames;
#[doc(hidden)]
pub mod fuzz_entry;
mod heatmap;
mod heatmap_views;
mod html_report;
mod input_file;
mod manifest;
mod measures;
mod merge;
mod model_input;
mod options;
mod output;
mod palette;
mod parts;
mod plots;
mod report;
mod resolution;
mod scan;
mod shard;
#[cfg(feature = "synthetic")]
pub mod synthetic;
mod tile_counter;
mod trim;
mod vehicle_model;

pub use analyze::{
    Analysis, AnalyzeOptions, Dedupe, MEASURE_PIXELS, PaletteChoice, Progress, Timings, WrittenFiles,
    analyze, analyze_counted, analyze_texel_counts, default_output_dir, write_results,
};
pub use archive::{Archive, ImageSource};
pub use bitset::{AtomicColorSet, SeenSet};
pub use color::{COLOR_COUNT, Color, ParseColorError};
pub use compare::{Comparison, compare_parts, kendall_tau_b};
pub use compare_report::write_comparison;
pub use count::Counts;
pub use decode::{PixelLayout, RowReader, read_color_image, read_file};
pub use error::{Error, Result};
pub use frames::{FrameTable, PartLookup};
pub use heatmap::{HeatmapOptions, Scale, plasma, render as render_heatmap, write_heatmap};
pub use heatmap_views::{
    DIRECTIONS, NEVER_SEEN, ViewCamera, ViewTexture, WrittenViews, render_view, view_cameras, views_caption,
    write_views, write_views_with,
};
pub use input_file::{SMALL_INPUT_LIMIT, read_limited};
pub use manifest::{MANIFEST_FILE, MANIFEST_SCHEMA, Manifest, PaletteSpec, TileEntry};
pub use measures::Measures;
pub use merge::merge_results;
pub use model_input::{
    GltfModel, MAX_COORDINATE_M, MODEL_LIMIT, check_coordinates, read_gltf, resolve_inside,
};
#[cfg(feature = "cli")]
pub use output::remove_temporaries_on_interrupt;
pub use output::{remove_temporaries, write_atomically, write_bytes_atomically, write_rgb_png};
pub use palette::{Fcsp, PaletteDescription, parse_size as parse_palette_size, write_canonical_png};
pub use parts::{Legend, Part, PartStats, PartTable, Pidt, UNLABELLED, join_parts};
pub use plots::font_available as plot_font_available;
pub use report::{
    AnalysisResult, RESULT_SCHEMA, csv_field, format_table, read_result_summary, read_texel_counts,
    write_parts_csv, write_result_json, write_timings_json,
};
pub use resolution::{CaptureGeometry, ResolutionReport};
pub use scan::{
    Classifier, ImageTally, KERNEL_ENV, Kernel, PixelClass, RowScan, scan_image, scan_image_by_part,
};
pub use shard::Shard;
pub use tile_counter::TileCounter;
pub use trim::{EmptyTile, TrimMode};
pub use vehicle_model::{ModelPart, VehicleModel};
