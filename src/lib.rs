//! # ufcsr — Unwrapped Full Color Space Recording
//!
//! Counts how often each texel of a vehicle's unwrapped surface is visible in
//! captured frames, joins the counts with a Part Identification Texture into
//! per-part statistics, and renders a heatmap texture.
//!
//! The root exports the entry points and their option and result types
//! ([`analyze`], [`Archive`], [`placement`], …). Four public modules hold the
//! rest, each one flat list: [`format`] (the typed files both crates and outside
//! readers exchange), [`files`] (the file layer every read and write goes
//! through), [`output`] (results, heatmaps, figures) and [`placement`] (the
//! placement answer's parts). Every other module is private.
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
pub mod files;
pub mod format;
mod optics;
pub mod output;
pub mod placement;
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
    TrimMode, UNLABELLED, VehicleModel, frame_spacing_warning, inside_archive, parse_palette_size,
    write_canonical_png,
};
pub use checks::{ColorChecks, ColorWarning, NeighbourSample};
pub use color::{AtomicColorSet, COLOR_COUNT, Color, ParseColorError, SeenSet, color_key};
pub use count::{
    Classifier, CountedTile, Counts, EmptyTile, FrameLabel, FrameRecord, ImageTally, KERNEL_ENV, Kernel,
    PartLookup, PartPixels, PartRows, PixelClass, RowScan, TileCounter, scan_image, scan_image_by_part,
};
pub use describe::{DEFAULT_PATTERN, DescribeOptions, Described, SoloSummary, describe, parse_fov};
pub use error::{Error, Result};
// Issue 41: a capture that has not finished marks its folder; the analyzer refuses it.
pub use archive::{MAX_RGBA32_TEXELS, parse_capture_palette_size, rgba32_id, rgba32_pixel};
pub use count::read_rgba32_ids;
pub use optics::{EyeProjection, TileView};
pub use placement::report::format_placement;
pub use placement::{Placement, PlacementOptions, placement, write_placement};
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
