//! `study.json`, what `ufcsr study` writes: every setting's error
//! against the exact measure of the whole scenario with its 95 % interval,
//! its precision against the finest setting, the Pareto front and the
//! recommendation. Typed here so the capture writes it and scripts, tests and
//! the analyzer read it through one definition (no string-key look-ups).
//! What each number means: `docs/science.md` ("The resolution study").

use std::path::PathBuf;

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// The share error of a candidate's part totals against a reference's
/// (the same parts in the same order).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct ShareError {
    /// Σ |share difference| over parts, percentage points.
    pub share_l1_pp: f64,
    /// Largest |share difference| of one part, percentage points.
    pub share_max_pp: f64,
    pub share_max_part: String,
    /// Kendall's τ-b between the rankings by total.
    pub kendall_tau_b: f64,
    /// Parts in both top-5 lists by total, out of 5 (or fewer parts).
    pub top5_overlap: usize,
}

/// One setting against the exact measure of the whole scenario (every frame,
/// every texel unless `--exact-sample`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct ErrorVsExact {
    /// `count` or `angular-area`.
    pub measure: String,
    /// The setting as the study captured it (frames 0, step, 2·step, …)
    /// against the exact measure summed over every frame.
    #[serde(flatten)]
    pub error: ShareError,
    /// 95 % interval `[low, high]` of the share L1 a capture at this setting
    /// gets when its frames start at an offset drawn uniformly from
    /// 0 … step − 1 (a prediction interval over offsets; it always contains
    /// `share_l1_pp`).
    pub ci95_pp: [f64; 2],
    /// Bootstrap replicates drawn per offset whose resolution error had to be
    /// imputed (0: every offset was computed exactly).
    pub replicates: u32,
    /// The exact measure on this setting's frames against it on every frame:
    /// what the frame step alone costs at the study's offset 0.
    pub frame_step_pp: f64,
    /// `frame_step_pp` over every offset of the step, `[smallest, largest]`.
    pub frame_step_range_pp: [f64; 2],
    /// The rendered setting against the exact measure on its own frames: what
    /// the resolution alone costs.
    pub resolution_pp: f64,
    /// Frame offsets of the step (`min(step, frames)`).
    pub offsets: u32,
    /// Offsets with a frame this resolution did not render, whose resolution
    /// error is imputed by the block bootstrap.
    pub imputed_offsets: u32,
    /// The most the exact reference's texel sampling moves an end of the interval
    /// (a basic bootstrap of the reference, 2.5–97.5 %; 0 with every texel).
    pub texel_sampling_pp: f64,
}

/// One setting of a study.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct StudyRow {
    pub ppd: f64,
    pub frame_step: u32,
    pub frames: u32,
    /// Wall seconds to capture, count and write this setting's results (the
    /// set-up every setting shares is [`Study::setup_seconds`]). Reported, not
    /// ranked by: it moves with the machine's load.
    pub seconds: f64,
    /// The cost the recommendation and the front rank by: pixels rendered
    /// over every tile the vehicle's bounds touch, every eye and frame of the
    /// setting (≈ ppd² × field area × eye-frames; culled tiles left out). A
    /// function of the scene and the setting alone, so two runs of one study
    /// rank alike however loaded the machine was (0 in studies written
    /// before it was recorded).
    #[serde(default)]
    pub pixels_rendered: u64,
    pub grand_total: u64,
    pub texels_seen: u64,
    /// Against the finest setting (highest ppd, smallest step), same measure:
    /// precision, not accuracy.
    pub precision: ShareError,
    /// Against the exact measure of the whole scenario, when the study computed it.
    pub error_vs_exact: Option<ErrorVsExact>,
    /// No other setting is both cheaper ([`StudyRow::pixels_rendered`]) and
    /// closer (by the error the study ranks by).
    pub pareto: bool,
    /// The setting's `result.json`.
    pub results: PathBuf,
}

impl StudyRow {
    /// `"20 px/° every 3"`.
    pub fn label(&self) -> String {
        format!("{} px/° every {}", self.ppd, self.frame_step)
    }

    /// The error the study ranks by: against the exact measure when computed.
    pub fn ranking_error(&self) -> f64 {
        self.error_vs_exact.as_ref().map_or(self.precision.share_l1_pp, |e| e.error.share_l1_pp)
    }

    /// The error the recommendation holds to the tolerance: the upper end of
    /// the 95 % interval against the exact measure, or the precision without it.
    pub fn upper_error(&self) -> f64 {
        self.error_vs_exact.as_ref().map_or(self.precision.share_l1_pp, |e| e.ci95_pp[1])
    }
}

/// The setting recommended, or the closest when none is within tolerance.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct StudyPick {
    pub setting: String,
    pub ppd: f64,
    pub frame_step: u32,
    /// Measured, reported only.
    pub seconds: f64,
    /// The cost it was picked by ([`StudyRow::pixels_rendered`]).
    #[serde(default)]
    pub pixels_rendered: u64,
    /// `exact` (against the exact measure) or `precision` (against the finest setting).
    pub against: String,
    pub share_l1_pp: f64,
    pub ci95_pp: Option<[f64; 2]>,
}

/// What the exact reference cost and covered.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct ExactReference {
    /// Share of the texels ray traced (1: all).
    pub sample: f64,
    pub sampled_texels: u64,
    pub labelled_texels: u64,
    /// Every frame of the scenario, each eye.
    pub eye_frames: u64,
    pub seconds: f64,
    pub results: PathBuf,
}

/// A finished study: `study.json`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct Study {
    pub scenario: String,
    pub measure: String,
    /// The precision reference (finest setting).
    pub reference: String,
    pub exact: Option<ExactReference>,
    pub tolerance_pp: f64,
    /// Wall seconds of the set-up the settings share (unwrap, PIdT, the
    /// archive's files, renderer), built once and left out of each row's `seconds`.
    pub setup_seconds: f64,
    pub rows: Vec<StudyRow>,
    /// The cheapest setting (fewest [`StudyRow::pixels_rendered`]; ties: the
    /// smaller error) whose error (its 95 % interval's upper end, against the
    /// exact measure when computed) is within the tolerance.
    pub recommended: Option<StudyPick>,
    /// Why nothing is recommended.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reason: Option<String>,
    /// The closest setting, when none is within the tolerance.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub closest: Option<StudyPick>,
}
