//! `timings.json`: how long each stage of one analysis took, beside
//! `result.json` (which holds no timings, so that the same input always
//! gives the same result bytes).

use serde::{Deserialize, Serialize};

use schemars::JsonSchema;

/// Schema string of `timings.json`.
pub const TIMINGS_SCHEMA: &str = "ufcsr-timings/1";

/// ufcsr timings (`ufcsr-timings/1`): `timings.json` beside `result.json`,
/// the wall-clock seconds of one run. It differs on every run. Generated
/// from the types in src/format/timings.rs.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[schemars(title = "ufcsr timings (ufcsr-timings/1)")]
pub struct TimingsFile {
    /// `ufcsr-timings/1`.
    pub schema: String,
    /// The seconds.
    #[serde(flatten)]
    pub timings: Timings,
}

impl TimingsFile {
    /// `timings` as this version writes them.
    pub fn new(timings: Timings) -> TimingsFile {
        TimingsFile { schema: TIMINGS_SCHEMA.to_string(), timings }
    }
}

/// Wall-clock seconds per stage, and the thread count (kept out of
/// `result.json`, which must not change from run to run). The heatmap
/// (`heatmap_seconds`), the tables (`write_seconds`), the frame strip and
/// the views (`figure_seconds["frames_strip"]`, `["views"]`) are written
/// side by side, so their seconds overlap; `total_seconds` is the wall
/// clock.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct Timings {
    /// Threads counting.
    pub threads: usize,
    /// The row kernels used (`crate::count::scan::Kernel::name`).
    pub kernel: String,
    /// Reading the inputs.
    pub load_seconds: f64,
    /// Finding the all-background tiles.
    pub trim_seconds: f64,
    /// Counting.
    pub count_seconds: f64,
    /// Joining the counts with the labels.
    pub join_seconds: f64,
    /// The heatmap.
    pub heatmap_seconds: f64,
    /// The tables.
    pub write_seconds: f64,
    /// Seconds of each figure and the report page (`heatmap_glb`, `views`,
    /// `map`, `frames_strip`, `plots`, `report`).
    #[serde(default)]
    pub figure_seconds: std::collections::BTreeMap<String, f64>,
    /// From the start of the analysis to the last file of the result set
    /// written (moving the set into place, a rename per file, is after it).
    pub total_seconds: f64,
    /// Decoded pixels per second during counting, in millions.
    pub decoded_megapixels_per_second: f64,
}
