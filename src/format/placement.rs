//! `placement.json` (schema `ufcsr-placement/2`), written by `ufcsr analyze
//! placement` and read back by the report pages: one serde type per object,
//! closed (`deny_unknown_fields`), with its JSON Schema derived from the
//! same definition (`docs/schemas/placement.schema.json` is this type's
//! schema, checked by a test). `docs/placement.md` says what every number
//! means, how its interval is made and what it leaves out.
//!
//! The enums that name a kind, an objective, a method or an eye rule live
//! here so that both the search and the pages use one spelling.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// The `schema` field of placement.json.
pub const PLACEMENT_SCHEMA: &str = "ufcsr-placement/2";

/// Whether a candidate is a whole part of the vehicle or a display patch.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum CandidateKind {
    Part,
    Patch,
}

impl CandidateKind {
    /// `"part"` or `"patch"`, as the tables spell it.
    pub fn name(self) -> &'static str {
        match self {
            CandidateKind::Part => "part",
            CandidateKind::Patch => "patch",
        }
    }
}

/// What a set is chosen for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum Objective {
    /// The mean legible seconds over the archives.
    Mean,
    /// The legible seconds of the worst archive.
    WorstCase,
}

impl Objective {
    pub fn name(self) -> &'static str {
        match self {
            Objective::Mean => "mean",
            Objective::WorstCase => "worst_case",
        }
    }
}

/// How a set was found.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum Method {
    Exhaustive,
    Greedy,
}

impl Method {
    pub fn name(self) -> &'static str {
        match self {
            Method::Exhaustive => "exhaustive",
            Method::Greedy => "greedy",
        }
    }
}

/// Which eyes must read a candidate for a frame to count.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum EyeRule {
    /// Either eye (the default).
    Any,
    /// Every eye of the archive.
    Both,
}

impl EyeRule {
    pub fn name(self) -> &'static str {
        match self {
            EyeRule::Any => "any",
            EyeRule::Both => "both",
        }
    }
}

/// The whole file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PlacementDocument {
    /// Always [`PLACEMENT_SCHEMA`].
    pub schema: String,
    /// The tables read, in input order.
    pub archives: Vec<ArchiveRecord>,
    /// The legibility rule and the search's settings, with their sources.
    pub thresholds: ThresholdsRecord,
    /// How the intervals and probabilities were made.
    pub uncertainty: UncertaintyRecord,
    /// Every candidate of every archive, most legible seconds first.
    pub candidates: Vec<CandidateRecord>,
    /// Per kind, k (physical displays) and objective: the best set.
    pub combinations: Vec<CombinationRecord>,
    /// The best sets again with each threshold one step lower and higher.
    pub sensitivity: Vec<SensitivityRecord>,
    pub notes: Vec<String>,
    /// Candidates left out of every answer, and why (not mountable; no display fits); absent in
    /// older files.
    #[serde(default)]
    pub excluded: Vec<ExcludedRecord>,
}

/// Why a candidate may not be an answer (`docs/placement.md`, "What may be chosen").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum ExclusionReason {
    /// Its surface is in the not-mountable list (wheels, glass).
    NotMountable,
    /// A whole part on which no display patch of the measured size fits (or none is seen):
    /// exposure only.
    NoDisplayFits,
}

/// A candidate left out of the answers.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ExcludedRecord {
    pub candidate: String,
    pub kind: CandidateKind,
    pub reason: ExclusionReason,
    /// The rule in words.
    pub detail: String,
}

/// One table read.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ArchiveRecord {
    /// Path of the placement-frames.csv read.
    pub table: String,
    pub frames: usize,
    pub eyes: Vec<String>,
    pub seconds_per_frame: f64,
    /// frames x seconds_per_frame.
    pub duration_s: f64,
    /// Time of the frame with the smallest vehicle-pedestrian distance: the decision window's end.
    pub arrival_s: f64,
    /// [start, end] of the decision window, s.
    pub decision_window_s: [f64; 2],
    /// Why this table's answer may not follow today's rules: its display patches were laid out
    /// by an older capture (no `covers` in `placement-patches.csv`), so a display there may
    /// reach over glass or a tyre; capture again. Absent when there is nothing to say.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub warning: Option<String>,
}

/// The character height the angular threshold applies to.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum CharacterHeight {
    /// A share of the display's height (of the part's visible height for a part).
    Fraction(f64),
    /// Metres (for a part, whose height is not known, the default fraction is used).
    Metres(f64),
}

/// The legibility rule and the search's settings.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ThresholdsRecord {
    /// The characters' visible angular height must reach this, arcmin.
    pub min_character_height_arcmin: f64,
    pub character_height: CharacterHeight,
    /// The display's foreshortened width must hold this many characters.
    pub min_characters: u32,
    /// A character's width plus spacing, as a share of its height.
    pub character_pitch: f64,
    pub min_visible_fraction: f64,
    pub max_view_angle_deg: f64,
    /// Legible runs shorter than this do not count, s.
    pub min_dwell_s: f64,
    pub decision_window_s: f64,
    pub eyes: EyeRule,
    /// With it, legible means only a visible solid angle of at least this many steradians (the
    /// other rules are then not applied); null: off.
    pub min_solid_angle_sr: Option<f64>,
    /// A left/right pair is chosen together (it is two displays).
    pub symmetric: bool,
    /// Head nouns of the surfaces where no display can be mounted; candidates named so are scored
    /// but never chosen.
    pub not_mountable: Vec<String>,
    /// Patches of one part closer than this (centre to centre, m) are one region.
    pub region_radius_m: f64,
    /// Where each default comes from.
    pub sources: Sources,
}

/// Where each default comes from.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Sources {
    pub min_character_height_arcmin: String,
    pub character_height: String,
    pub min_characters: String,
    pub min_visible_fraction: String,
    pub max_view_angle_deg: String,
    pub min_dwell_s: String,
    pub decision_window_s: String,
    pub not_mountable: String,
    pub region_radius_m: String,
}

/// How the intervals and the probabilities are made.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct UncertaintyRecord {
    /// The random units: the archives (scenarios, observers, texel-sample seeds given).
    pub units: String,
    /// How many archives; no interval or probability with fewer than 2.
    pub archives: usize,
    /// Nominal coverage of the intervals.
    pub confidence: f64,
    /// Bootstrap replicates behind the probabilities.
    pub replicates: usize,
    pub seed: u64,
    /// A set counts as "within epsilon" in a replicate when it is at most this far below the
    /// replicate's best, s.
    pub epsilon_s: f64,
    pub method: String,
}

/// One candidate over all archives.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CandidateRecord {
    pub name: String,
    pub kind: CandidateKind,
    /// The display's width and height, m (patches; null for parts).
    pub display_size_m: Option<[f64; 2]>,
    /// False when the rule `thresholds.not_mountable` names its surface: scored, never chosen.
    pub mountable: bool,
    /// The region it was collapsed into (the region's best patch); null when it is the region's
    /// best itself or a part.
    pub region: Option<String>,
    /// Patches in its region (1 for parts and lone patches).
    pub region_members: usize,
    /// Mean over the archives of the seconds legible.
    pub legible_s: f64,
    /// Mean over the archives of the seconds visible at all.
    pub visible_s: f64,
    /// The latest first legible sighting over the archives; null when never legible in some archive.
    pub first_legible_s: Option<f64>,
    /// The smallest vehicle-pedestrian distance at first legible sighting over the archives.
    pub first_legible_distance_m: Option<f64>,
    pub decision_window_legible_s: f64,
    pub worst_case_legible_s: f64,
    /// The texel sample's bracket of `legible_s`: the mean over the archives
    /// of each archive's `texel_sample_interval_s` (null unless every archive
    /// has one). What it means: `docs/placement.md` ("One archive's texel sample").
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub texel_sample_interval_s: Option<[f64; 2]>,
    pub per_archive: Vec<ExposureRecord>,
    /// A part of a table with display patches: the patch its legible time comes from (its most
    /// legible fitting patch, in the first archive that has one); null for patches, for parts on
    /// which no display fits (see `excluded`) and for tables without patches.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub legible_through: Option<String>,
}

/// What one candidate scored in one archive.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ExposureRecord {
    /// Seconds legible (frames x seconds per frame).
    pub legible_s: f64,
    /// Seconds visible at all.
    pub visible_s: f64,
    /// Time of the first legible frame, s; null when never legible.
    pub first_legible_s: Option<f64>,
    /// Vehicle-pedestrian distance at that frame, m.
    pub first_legible_distance_m: Option<f64>,
    /// Seconds legible inside the decision window.
    pub decision_window_legible_s: f64,
    /// `[low, high]` legible seconds this archive's texel sample allows
    /// (`--sample` below 1: the visible fraction ± 1.96 standard errors and
    /// the angular height widened; equal to `legible_s` with every texel);
    /// null when the archive's sample counts (`unobstructed-parts.csv`) are
    /// not beside its table or the solid-angle rule scores it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub texel_sample_interval_s: Option<[f64; 2]>,
}

/// One choice in a set: a candidate, or a left/right pair (two displays).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct MemberRecord {
    pub candidates: Vec<String>,
    /// Physical displays: 1, or 2 for a pair.
    pub displays: usize,
    /// Mean seconds the set loses without this member.
    pub adds_s: f64,
    /// True when it adds no legible time to the others.
    pub adds_no_time: bool,
}

/// A chosen set and its scores.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CombinationRecord {
    /// At most this many physical displays (a symmetric pair is two).
    pub k: usize,
    /// Physical displays in the set (at most k).
    pub displays: usize,
    pub kind: CandidateKind,
    pub objective: Objective,
    pub method: Method,
    pub members: Vec<MemberRecord>,
    /// Mean over the archives of the seconds at least one is legible.
    pub legible_s: f64,
    /// The interval of legible_s over what varies (the archives), at `uncertainty.confidence`;
    /// null with one archive.
    pub interval_s: Option<[f64; 2]>,
    /// Share of bootstrap replicates in which this set is the best set of k, exact ties sharing
    /// (each of t tied sets 1/t); null with one archive or when no candidate is legible
    /// (`p_best_note` says which).
    pub p_best: Option<f64>,
    /// Share of replicates in which it is within `uncertainty.epsilon_s` of the best.
    pub p_within_epsilon: Option<f64>,
    /// Mean over the archives of legible_s / the archive's duration.
    pub share_of_time: f64,
    /// The smallest legible_s of any archive.
    pub worst_case_s: f64,
    /// Per archive, in input order.
    pub per_archive_s: Vec<f64>,
    /// No set of k displays does better on the objective (= the value when exhaustive).
    pub upper_bound_s: f64,
    pub gap_s: f64,
    /// Other sets of k displays whose legible_s lies inside this set's interval, best first.
    pub runners_up: Vec<RunnerUpRecord>,
    /// Sets exactly as legible as this one (a tie the search broke by order): the answer is the
    /// tied set, not this member alone; absent in older files.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub tied_with: Vec<Vec<String>>,
    /// Why there is no P(best): "n/a: one unit" or "no candidate legible"; absent otherwise.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub p_best_note: Option<String>,
}

/// A set as good as the best within the interval.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RunnerUpRecord {
    pub candidates: Vec<String>,
    pub displays: usize,
    pub legible_s: f64,
    /// Share of bootstrap replicates in which it is the best set.
    pub p_best: Option<f64>,
}

/// The best sets with one threshold moved one step.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SensitivityRecord {
    /// The threshold moved (its field name in `thresholds`).
    pub threshold: String,
    pub value: f64,
    pub sets: Vec<SensitivitySet>,
}

/// One best set under a moved threshold.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SensitivitySet {
    pub kind: CandidateKind,
    pub k: usize,
    /// Whether the best set is the one reported at the thresholds given.
    pub same_set: bool,
    pub candidates: Vec<String>,
    pub legible_s: f64,
    /// The reported set's legible_s under the moved threshold.
    pub reported_set_legible_s: f64,
}

/// One line naming what was left out, for the console and the pages
/// (empty when nothing was).
pub fn excluded_line(excluded: &[ExcludedRecord]) -> String {
    let of = |reason: ExclusionReason| -> Vec<&str> {
        excluded.iter().filter(|e| e.reason == reason).map(|e| e.candidate.as_str()).collect()
    };
    let mut parts = Vec::new();
    let not_mountable = of(ExclusionReason::NotMountable);
    if !not_mountable.is_empty() {
        parts.push(format!("not mountable (wheels, glass): {}", summarised(&not_mountable)));
    }
    let no_fit = of(ExclusionReason::NoDisplayFits);
    if !no_fit.is_empty() {
        parts.push(format!("no display fits (exposure only): {}", summarised(&no_fit)));
    }
    if parts.is_empty() { String::new() } else { format!("left out of the answers: {}", parts.join("; ")) }
}

/// Each archive's warning as a line naming its table (`warning: TABLE: ...`), in input order;
/// the console and the HTML report print these.
pub(crate) fn warning_lines(archives: &[ArchiveRecord]) -> Vec<String> {
    archives.iter().filter_map(|a| a.warning.as_ref().map(|w| format!("warning: {}: {w}", a.table))).collect()
}

/// Up to eight names, then how many more.
fn summarised(names: &[&str]) -> String {
    const SHOWN: usize = 8;
    let mut text = names.iter().take(SHOWN).copied().collect::<Vec<_>>().join(", ");
    if names.len() > SHOWN {
        text += &format!(" and {} more", names.len() - SHOWN);
    }
    text
}
