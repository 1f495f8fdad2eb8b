//! Stage 3, result: what an analysis found, as data — the result model
//! ([`AnalysisResult`], [`Analysis`]), summarizing counts into it
//! ([`summarize`]), `result.json` written and read back, per-part
//! statistics, per-eye-frame tables, the resolution-independent measures,
//! the resolution diagnostics, comparing results and merging shards'.
//! Nothing here draws or formats for people: that is [`crate::output`].

pub(crate) mod compare;
pub(crate) mod frames;
pub(crate) mod measures;
pub(crate) mod merge;
pub(crate) mod model;
pub(crate) mod part_stats;
pub(crate) mod resolution;
pub(crate) mod result_json;
pub(crate) mod summarize;
pub(crate) mod texel_area_file;

pub use compare::{Comparison, compare_parts, kendall_tau_b};
pub use frames::FrameTable;
pub use measures::Measures;
pub use merge::merge_results;
pub use model::{Analysis, AnalysisResult, RESULT_SCHEMA};
pub use part_stats::{PartStats, PartTable, join_parts};
pub use resolution::ResolutionReport;
pub use result_json::{read_result_summary, read_texel_counts, write_result_json, write_timings_json};
pub use texel_area_file::{
    TEXEL_AREA_FILE, TEXEL_AREA_UNITS_FILE, TexelAreaUnits, read_texel_area, read_texel_area_in,
    write_texel_area,
};
