//! The factorial study's three files as typed values (issue 36): the
//! **design file** a user writes (`ufcsr design plan|run|merge DESIGN`:
//! vehicles × scenarios × traffic, a pedestrian population, measure
//! settings, replicates and seeds), the **task file** each task writes when
//! it is complete (`tasks/task-NNNN/task.json`: per drawn observer, each
//! candidate's legible time and angular area) and the **result** the merge
//! writes (`design.json`: per cell, per vehicle and overall, each candidate
//! with its interval, the best placements with P(best), the main effects).
//! One type per file, so the capture that writes them and any reader agree
//! by construction and the JSON Schemas come from the same definitions;
//! `docs/design.md` says what every field and number means.
//!
//! The analyzer cannot depend on the capture, so a body type is a plain name
//! here ("sedan", "van", …) and its dimension overrides plain numbers; the
//! capture checks and converts them when it plans.

use std::collections::BTreeMap;

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};
use serde_json::{Map, Value};

use crate::format::observers::ObserverPopulation;
use crate::format::placement::ExcludedRecord;

/// The design file's `schema` value.
pub const DESIGN_SCHEMA: &str = "ufcsr-design/1";
/// A task file's `schema` value. Version 3: a task's values follow the
/// display-fit and mountability rules and record the files it read (`inputs`);
/// a version-2 task predates them, so `run` measures it again and `merge` refuses it.
pub const DESIGN_TASK_SCHEMA: &str = "ufcsr-design-task/3";
/// The merged result's `schema` value.
pub const DESIGN_RESULT_SCHEMA: &str = "ufcsr-design-result/2";

/// A study design: the factors, their levels, how they are crossed.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Design {
    /// [`DESIGN_SCHEMA`].
    pub schema: String,
    /// A name for the report.
    pub name: String,
    /// Factor `vehicle`: at least one level.
    pub vehicles: Vec<VehicleLevel>,
    /// Factor `scenario`: at least one level.
    #[serde(deserialize_with = "strict_levels")]
    pub scenarios: Vec<ScenarioLevel>,
    /// Factor `traffic` (default: one level, `none`).
    #[serde(default = "default_traffic", deserialize_with = "strict_levels")]
    pub traffic: Vec<TrafficLevel>,
    /// Who looks: observers drawn in every task (absent: one observer, the
    /// scenario's own pedestrian at the rig's eye height).
    #[serde(default)]
    pub population: Option<DesignPopulation>,
    /// How each run is measured.
    pub measure: DesignMeasure,
    /// `full` (every combination) or listed cells.
    #[serde(default)]
    pub crossing: Crossing,
    /// Independent repetitions of every cell (new observers, new texel sample), at least 1.
    #[serde(default = "one")]
    pub replicates: u32,
    /// The seed every random draw of the study derives from.
    #[serde(default = "one_u64")]
    pub seed: u64,
}

fn default_traffic() -> Vec<TrafficLevel> {
    vec![TrafficLevel { name: "none".into(), kind: TrafficKind::None }]
}

fn one() -> u32 {
    1
}

fn one_u64() -> u64 {
    1
}

/// A vehicle: a model file, or a body of the parametric family.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct VehicleLevel {
    /// The level's name, unique in the factor (used in cells and the report).
    pub name: String,
    /// A vehicle model (glTF/GLB/OBJ), relative to the design file; or
    /// `demo` for the demo pickup. Exactly one of `model` and `body`.
    #[serde(default)]
    pub model: Option<String>,
    /// A body type of the parametric family: sedan, suv, van, pickup or bus.
    #[serde(default)]
    pub body: Option<String>,
    /// Overrides of the body type's typical dimensions (only with `body`).
    #[serde(default)]
    pub dims: Option<BodyDimsOverride>,
    /// Display candidates of this size, width × height in metres (none:
    /// the parts only).
    #[serde(default)]
    pub display_m: Option<[f64; 2]>,
}

/// Dimensions of a family body, metres and degrees; each absent one keeps
/// the body type's typical value.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct BodyDimsOverride {
    pub length_m: Option<f64>,
    pub width_m: Option<f64>,
    pub height_m: Option<f64>,
    pub bonnet_length_m: Option<f64>,
    pub bonnet_height_m: Option<f64>,
    pub windshield_rake_deg: Option<f64>,
    pub wheelbase_m: Option<f64>,
}

/// A scenario level. A field its kind does not have (`"speed"` for
/// `"speed_mps"`) is refused, not dropped.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct ScenarioLevel {
    /// The level's name, unique in the factor.
    pub name: String,
    #[serde(flatten)]
    pub source: ScenarioSource,
}

/// Where a scenario comes from.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(tag = "kind", rename_all = "kebab-case")]
pub enum ScenarioSource {
    /// The demo intersection's scenario A, B, C or D.
    Demo { scenario: String },
    /// The street design of the raycasting study (`docs/design.md`).
    Street(StreetScenario),
    /// A scene file's scenario (the scene's own vehicle is replaced by the level's).
    Scene { file: String, scenario: String },
}

/// One vehicle position of the street design.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct StreetScenario {
    /// Vehicle position 1–8 (1–3 near lane, 4–6 far lane, 7–8 alleyways).
    pub position: u32,
    /// The pedestrian's place on the near sidewalk, 1–3 (`docs/design.md`).
    #[serde(default = "one")]
    pub pedestrian: u32,
    /// Metres per second: 0 = static, more = approaching the position along its lane.
    #[serde(default)]
    pub speed_mps: f64,
}

/// A traffic level. A field its kind does not have is refused, not dropped.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct TrafficLevel {
    /// The level's name, unique in the factor.
    pub name: String,
    #[serde(flatten)]
    pub kind: TrafficKind,
}

/// What else is on the road.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(tag = "kind", rename_all = "kebab-case")]
pub enum TrafficKind {
    /// Nothing.
    None,
    /// The demo's twin alongside (demo scenarios only).
    AdjacentLane,
    /// The demo's twin ahead in the lane (demo scenarios only).
    LeadCar,
    /// `vehicles` other vehicles of the same model, placed by the street
    /// generator from a seed derived from the design's (street scenarios only; at most 7).
    Generated { vehicles: u32 },
}

/// A level's `name` and its flattened `kind` fields, every field known: serde's
/// `deny_unknown_fields` does not work beside `flatten`, so the fields the kind
/// has are the ones it writes back (each is written, defaults included), and any
/// other field of the object is an error naming it.
fn level_fields<T: Serialize + serde::de::DeserializeOwned>(
    mut fields: Map<String, Value>,
) -> Result<(String, T), String> {
    let name = match fields.remove("name") {
        Some(Value::String(name)) => name,
        Some(other) => return Err(format!("name: {other} is not a string")),
        None => return Err("missing field `name`".into()),
    };
    let kind: T =
        serde_json::from_value(Value::Object(fields.clone())).map_err(|e| format!("{name:?}: {e}"))?;
    let known = serde_json::to_value(&kind).map_err(|e| format!("{name:?}: {e}"))?;
    if let Some(field) = fields.keys().find(|field| known.get(field.as_str()).is_none()) {
        let mut has: Vec<&str> =
            known.as_object().map(|o| o.keys().map(String::as_str).collect()).unwrap_or_default();
        has.insert(0, "name");
        return Err(format!("{name:?}: unknown field {field:?} (this kind of level has {})", has.join(", ")));
    }
    Ok((name, kind))
}

/// A factor's levels, each through [`level_fields`] (the field attribute keeps the levels'
/// derived schema, which a container `try_from` would replace by a bare object).
fn strict_levels<'de, D, T>(deserializer: D) -> Result<Vec<T>, D::Error>
where
    D: serde::Deserializer<'de>,
    T: TryFrom<Map<String, Value>, Error = String>,
{
    let levels = Vec::<Map<String, Value>>::deserialize(deserializer)?;
    levels
        .into_iter()
        .enumerate()
        .map(|(i, fields)| T::try_from(fields).map_err(|e| serde::de::Error::custom(format!("[{i}] {e}"))))
        .collect()
}

impl TryFrom<Map<String, Value>> for ScenarioLevel {
    type Error = String;

    fn try_from(fields: Map<String, Value>) -> Result<Self, String> {
        level_fields(fields).map(|(name, source)| ScenarioLevel { name, source })
    }
}

impl TryFrom<Map<String, Value>> for TrafficLevel {
    type Error = String;

    fn try_from(fields: Map<String, Value>) -> Result<Self, String> {
        level_fields(fields).map(|(name, kind)| TrafficLevel { name, kind })
    }
}

/// Who looks: observers drawn from a population in every task.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct DesignPopulation {
    /// As the observer study's population file (`place`, `groups`, `truncate_sd`).
    pub population: ObserverPopulation,
    /// Observers drawn per task, at least 1.
    pub observers: u32,
}

/// How each run is measured: the exact measure, sampled.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct DesignMeasure {
    /// Share of texels measured, in (0, 1].
    pub sample: f64,
    /// Canonical palette side, texels (e.g. 256, 1024).
    pub palette: u32,
    /// Every n-th frame, at least 1.
    #[serde(default = "one")]
    pub frame_step: u32,
    /// Candidate patch spacing, metres (default 0.10).
    #[serde(default)]
    pub patch_spacing_m: Option<f64>,
    /// The rendered measure at this ppd: not run by designs yet (refused when set).
    #[serde(default)]
    pub rendered_ppd: Option<f64>,
}

/// How the factors are crossed.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum Crossing {
    /// Every vehicle × scenario × traffic.
    #[default]
    Full,
    /// Only these cells.
    Cells(Vec<CellLevels>),
}

/// One cell: a level of each factor, by name.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CellLevels {
    pub vehicle: String,
    pub scenario: String,
    #[serde(default = "none_name")]
    pub traffic: String,
}

fn none_name() -> String {
    "none".into()
}

impl std::fmt::Display for CellLevels {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "vehicle={} scenario={} traffic={}", self.vehicle, self.scenario, self.traffic)
    }
}

/// One candidate's values in one observer's run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct CandidateValue {
    pub name: String,
    /// `part` or `patch`.
    pub kind: String,
    /// Seconds legible under the placement rules (docs/placement.md): legible frames, each inside a run
    /// of at least the dwell, × seconds per frame; `ufcsr placement`'s `legible_s`.
    pub legible_s: f64,
    /// Of those, the seconds inside the decision window (the window ending at the smallest
    /// vehicle–pedestrian distance); `ufcsr placement`'s `decision_window_legible_s`.
    pub decision_window_legible_s: f64,
    /// Visible angular area, deg²·s per eye.
    pub angular_area_deg2_s: f64,
}

/// One drawn observer's run of a task.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct UnitValues {
    /// The unit's index within the cell (replicate × observers + observer).
    pub unit: u32,
    pub eye_height_m: f64,
    pub position: [f64; 3],
    /// The texel sample's seed.
    pub seed: u64,
    pub candidates: Vec<CandidateValue>,
}

/// `task.json`: one finished task (one cell, one replicate).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct DesignTask {
    /// [`DESIGN_TASK_SCHEMA`].
    pub schema: String,
    /// The design's hash (merge refuses a task of another design).
    pub design_hash: String,
    pub task: u32,
    pub cell: CellLevels,
    pub replicate: u32,
    pub units: Vec<UnitValues>,
    pub seconds: f64,
    /// Every input file the task read (the vehicle model and its buffers, a scene file and what it
    /// names), by path relative to the design's folder, with its FNV-1a 64 fingerprint: merge
    /// refuses tasks that read different versions of one file. Absent (empty) when the task read
    /// no file (built-in bodies, the demo) and in tasks of older versions.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub inputs: BTreeMap<String, String>,
}

/// A mean over the random units with its interval.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct MeanInterval {
    pub mean: f64,
    /// 95 % t interval of the mean (`None` with fewer than two units).
    pub ci95: Option<[f64; 2]>,
    /// Units behind it.
    pub n: u32,
}

/// One candidate over the units of a group of cells.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct CandidateSummary {
    pub name: String,
    pub kind: String,
    pub legible_s: MeanInterval,
    /// Legible seconds inside the decision window.
    pub decision_window_legible_s: MeanInterval,
    pub angular_area_deg2_s: MeanInterval,
}

/// One of the best placements.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct BestPlacement {
    pub rank: u32,
    pub name: String,
    pub kind: String,
    pub legible_s: MeanInterval,
    /// Share of bootstrap resamples of the units in which it is the best of its kind, exact ties
    /// sharing (each of t tied candidates 1/t); null with one unit or when no candidate of its kind
    /// is legible (`p_best_note` says which).
    pub p_best: Option<f64>,
    /// Share of resamples in which it is within `epsilon_s` of the best of its kind; absent in
    /// older files.
    #[serde(default)]
    pub p_within_epsilon: Option<f64>,
    /// The ε of `p_within_epsilon`, s (the placement's `--epsilon-s` default).
    #[serde(default)]
    pub epsilon_s: Option<f64>,
    /// Candidates of its kind with exactly the same mean legible time (a tie: the answer is the
    /// tied set); absent in older files.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub tied_with: Vec<String>,
    /// Why there is no P(best): "n/a: one unit" or "no candidate legible".
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub p_best_note: Option<String>,
}

/// A group of cells: one cell, one vehicle, or all.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct GroupSummary {
    /// `cell …`, `vehicle NAME` or `all`.
    pub group: String,
    pub cells: u32,
    /// Largest mean legible time first.
    pub candidates: Vec<CandidateSummary>,
    /// The best 1–3 parts and the best 1–3 displays, each with P(best); never a candidate of
    /// `excluded`.
    pub best: Vec<BestPlacement>,
    /// Candidates left out of `best` and P(best), and why (not mountable; no display fits), by
    /// the placement's one rule (`docs/placement.md`); absent in older files.
    #[serde(default)]
    pub excluded: Vec<ExcludedRecord>,
}

/// One level of a factor in a main effect.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct LevelEffect {
    pub level: String,
    /// The candidate's mean legible time over the cells at this level (equal weight per cell), s,
    /// with its interval over the random units.
    pub mean_s: MeanInterval,
    /// That mean minus the mean over all the factor's levels, s, with its interval over the units.
    pub effect_s: MeanInterval,
}

/// How much one factor moves one candidate's legible time.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct MainEffect {
    pub factor: String,
    pub candidate: String,
    /// For a display (`display_main_effects`): the vehicle whose cells alone it is computed over,
    /// since a patch's name carries its place on that body. Absent for a part (all cells).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub within_vehicle: Option<String>,
    /// Per level, in the levels' order: its mean and its effect.
    pub levels: Vec<LevelEffect>,
    /// The largest level mean minus the smallest, s, with the interval of the per-unit difference
    /// between those two levels (picked by the means, so with close levels it is the interval of
    /// that pair, not of the range).
    pub range_s: MeanInterval,
    /// The level with the largest mean and the one with the smallest.
    pub highest: String,
    pub lowest: String,
}

/// `design.json`: the merged result.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct DesignResult {
    /// [`DESIGN_RESULT_SCHEMA`].
    pub schema: String,
    pub design: String,
    pub design_hash: String,
    pub tasks: u32,
    /// What the intervals are, in one sentence.
    pub interval: String,
    /// The answer first: per body type and across all.
    pub answer: Vec<String>,
    pub cells: Vec<GroupSummary>,
    pub vehicles: Vec<GroupSummary>,
    pub overall: GroupSummary,
    pub main_effects: Vec<MainEffect>,
    /// Per vehicle with displays, its best 1–3 displays' main effects of every factor other than
    /// the vehicle, over that vehicle's cells only (`within_vehicle`); absent in older files.
    #[serde(default)]
    pub display_main_effects: Vec<MainEffect>,
}
