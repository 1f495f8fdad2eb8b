//! # ufcsr — Unwrapped Full Color Space Recording
//!
//! Counts how often each texel of a vehicle's unwrapped surface is visible in
//! captured frames, joins the counts with a Part Identification Texture into
//! per-part statistics, and renders a heatmap texture.

pub mod analyze;
pub mod archive;
pub mod bitset;
pub mod color;
pub mod compare;
pub mod compare_report;
pub mod count;
pub mod decode;
pub mod error;
pub mod frames;
#[doc(hidden)]
pub mod fuzz_entry;
pub mod heatmap;
pub mod heatmap_views;
pub mod html_report;
pub mod input_file;
pub mod manifest;
pub mod measures;
pub mod merge;
pub mod options;
pub mod output;
pub mod palette;
pub mod parts;
pub mod plots;
pub mod report;
pub mod resolution;
pub mod scan;
pub mod shard;
#[cfg(feature = "synthetic")]
pub mod synthetic;
pub mod tile_counter;
pub mod trim;
pub mod vehicle_model;

pub use analyze::{
    Analysis, AnalyzeOptions, Dedupe, MEASURE_PIXELS, PaletteChoice, Progress, Timings, WrittenFiles,
    analyze, analyze_counted, analyze_texel_counts, default_output_dir, write_results,
};
pub use archive::{Archive, ImageSource};
pub use color::{COLOR_COUNT, Color, ParseColorError};
pub use compare::{Comparison, compare_parts, kendall_tau_b};
pub use compare_report::write_comparison;
pub use count::Counts;
pub use error::{Error, Result};
pub use frames::{FrameTable, PartLookup};
pub use heatmap::{HeatmapOptions, Scale};
pub use manifest::{MANIFEST_FILE, MANIFEST_SCHEMA, Manifest, PaletteSpec, TileEntry};
pub use measures::Measures;
pub use merge::merge_results;
#[cfg(feature = "cli")]
pub use output::remove_temporaries_on_interrupt;
pub use output::{remove_temporaries, write_atomically, write_bytes_atomically, write_rgb_png};
pub use palette::{Fcsp, PaletteDescription};
pub use parts::{Legend, Part, PartStats, PartTable, Pidt, UNLABELLED, join_parts};
pub use report::{
    AnalysisResult, RESULT_SCHEMA, format_table, read_result_summary, read_texel_counts, write_parts_csv,
    write_result_json, write_timings_json,
};
pub use resolution::{CaptureGeometry, ResolutionReport};
pub use scan::{Classifier, ImageTally, PixelClass, scan_image, scan_image_by_part};
pub use shard::Shard;
pub use tile_counter::TileCounter;
pub use trim::{EmptyTile, TrimMode};
pub use vehicle_model::{ModelPart, VehicleModel};
