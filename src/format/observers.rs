//! The observer study's two files as typed values: the **population file**
//! a user writes (`ufcsr observers --population FILE`: where people
//! stand and how tall they are, with the sources of the figures) and
//! **`observers.json`**, which the study writes (every sampled observer, and
//! per part the population mean with its 95 % interval, the spread over
//! people and the resolution error folded in; with `--display WxH` the same
//! for every candidate display's legible seconds, in `displays`, absent
//! otherwise so files written before it still read). One type per file, read and
//! written through serde, so the capture that writes them and any reader
//! agree by construction and the JSON Schema (`schemars`) comes from the
//! same definition; `docs/science.md` says what every number means.

use std::collections::BTreeMap;
use std::path::PathBuf;

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// `observers.json`'s `schema` value.
pub const OBSERVERS_SCHEMA: &str = "ufcsr-observers/1";

/// The source the default adult groups' figures are taken from.
pub const US_ADULTS_SOURCE: &str = "CDC/NCHS, Anthropometric Reference Data for Children and Adults: United States, \
     2015-2018, Vital Health Stat 3(46), 2021: adults aged 20 and over (figures not re-verified here; check them \
     before citing); eye height = stature - 0.11 m (Pheasant & Haslegrave, Bodyspace, 3rd ed., 2006: stature \
     minus standing eye height about 0.11 m for men and 0.105 m for women; not re-verified here)";

/// The default truncation of each group's normal stature, in its standard
/// deviations (a draw outside is drawn again: 0.27 % of the normal's mass).
pub const DEFAULT_TRUNCATE_SD: f64 = 3.0;

/// Where the sampled pedestrians stand, on the ground (world `[x, y]` metres;
/// the height of the ground is the rig's pedestrian's).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(tag = "kind", rename_all = "kebab-case")]
pub enum ObserverPlace {
    /// The scene rig's own pedestrian, standing or walking: only the eye height varies.
    Rig,
    /// Uniformly along the kerb segment from `from` to `to`.
    Kerb { from: [f64; 2], to: [f64; 2] },
    /// Uniformly over the axis-aligned rectangle with opposite corners `corner` and `opposite`.
    Area { corner: [f64; 2], opposite: [f64; 2] },
}

/// One group of people: stature normal with `stature_mean_m` and
/// `stature_sd_m` (truncated at the population's `truncate_sd`), eye height
/// = stature − `eye_offset_m`; drawn with probability `weight` / Σ weights.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct StatureGroup {
    pub name: String,
    /// Relative weight of the group in the mixture (any positive scale).
    pub weight: f64,
    pub stature_mean_m: f64,
    pub stature_sd_m: f64,
    /// Stature minus standing eye height, metres.
    pub eye_offset_m: f64,
    /// Where the figures come from (printed with the results).
    #[serde(default)]
    pub source: String,
}

/// The population the observers are drawn from.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ObserverPopulation {
    pub place: ObserverPlace,
    /// The mixture of groups; default: US adults, women and men in equal weight.
    #[serde(default = "ObserverPopulation::us_adult_groups")]
    pub groups: Vec<StatureGroup>,
    /// Each group's normal stature is truncated at ± this many standard deviations.
    #[serde(default = "default_truncate_sd")]
    pub truncate_sd: f64,
}

fn default_truncate_sd() -> f64 {
    DEFAULT_TRUNCATE_SD
}

impl ObserverPopulation {
    /// The default mixture: US adults aged 20 and over, women and men in
    /// equal weight, stature 161.3 cm (SD 7.1) and 175.3 cm (SD 7.6), eye
    /// height 0.11 m below (sources: [`US_ADULTS_SOURCE`]).
    pub fn us_adult_groups() -> Vec<StatureGroup> {
        let group = |name: &str, mean, sd| StatureGroup {
            name: name.into(),
            weight: 0.5,
            stature_mean_m: mean,
            stature_sd_m: sd,
            eye_offset_m: 0.11,
            source: US_ADULTS_SOURCE.into(),
        };
        vec![group("women", 1.613, 0.071), group("men", 1.753, 0.076)]
    }

    /// The default population standing at `place`.
    pub fn us_adults(place: ObserverPlace) -> ObserverPopulation {
        ObserverPopulation { place, groups: Self::us_adult_groups(), truncate_sd: DEFAULT_TRUNCATE_SD }
    }
}

/// How the observers were chosen.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(tag = "kind", rename_all = "kebab-case")]
pub enum ObserverSampling {
    /// Independent draws from the population (SplitMix64 from `seed`): the
    /// mean over them estimates the population mean, with a 95 % interval.
    Random { observers: u32, seed: u64 },
    /// A deterministic grid (cell midpoints of `positions` places × `heights`
    /// eye heights over `eye_heights_m`, uniform weights): **no interval** is
    /// claimed for its mean (its error is a quadrature error, not a spread).
    Grid { positions: u32, heights: u32, eye_heights_m: [f64; 2] },
}

/// How each observer's own resolution error is bounded.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(tag = "kind", rename_all = "kebab-case")]
pub enum ResolutionCheck {
    /// Not bounded: the intervals leave the resolution error out (and say so).
    None,
    /// A second, coarser capture of each observer at half the ppd and twice
    /// the frame step; the bound is `safety_factor` × |fine − coarse| per
    /// part (a two-grid convergence index for first-order convergence).
    Coarser { safety_factor: f64 },
}

/// One observer's second, coarser capture (for the resolution bound).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct CoarserCapture {
    pub ppd: f64,
    pub frame_step: u32,
    /// Per part, deg²·s per eye.
    pub angular_area_deg2_s: Vec<f64>,
    /// Per part, texels seen per eye-frame, summed.
    pub count: Vec<f64>,
}

/// One observer's capture, per legend part (the file's `parts` order).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct ObserverRecord {
    /// Ground point, world metres (for a walking pedestrian, where the walk starts).
    pub position: [f64; 3],
    /// The population group drawn (`None` on a grid).
    pub group: Option<String>,
    /// The stature drawn (`None` on a grid).
    pub stature_m: Option<f64>,
    pub eye_height_m: f64,
    /// Wall seconds of this observer's captures (the shared set-up is the file's `setup_seconds`).
    pub seconds: f64,
    /// Per part: visible angular area, deg²·s per eye.
    pub angular_area_deg2_s: Vec<f64>,
    /// Per part: texels seen per eye-frame, summed (the paper's count, `--dedupe frame`).
    pub count: Vec<f64>,
    /// Per part: the bound on this observer's angular-area resolution error, deg²·s (`None`: not checked).
    pub angular_area_bound_deg2_s: Option<Vec<f64>>,
    /// The coarser capture behind the bound.
    pub coarser: Option<CoarserCapture>,
    /// The observer's results folder.
    pub results: PathBuf,
}

/// A value over the observers.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct PopulationValue {
    /// Mean over the observers.
    pub mean: f64,
    /// 95 % interval of the population mean: `mean` ± the sum of
    /// `monte_carlo_half_width` and `resolution_bound`, its low end cut at 0
    /// when no observer's value is negative. `None` on a grid, or with one observer.
    pub mean_ci95: Option<[f64; 2]>,
    /// Student-t half-width t(0.975, n−1) · s / √n (`None` on a grid).
    pub monte_carlo_half_width: Option<f64>,
    /// Mean over the observers of their resolution bounds (`None`: not checked).
    pub resolution_bound: Option<f64>,
    /// 2.5th and 97.5th percentiles of the observers' values (linear
    /// interpolation between order statistics): the spread over people.
    pub p2_5: f64,
    pub p97_5: f64,
}

/// One part over the observers.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct PartOverObservers {
    pub part: String,
    /// deg²·s per eye.
    pub angular_area_deg2_s: PopulationValue,
    /// % of the vehicle's angular area.
    pub angular_area_share_percent: PopulationValue,
    /// % of the count's grand total.
    pub count_share_percent: PopulationValue,
    /// Share of observers for whom the part is among the five with the largest angular area, 0–1.
    pub top5_frequency: f64,
}

/// One candidate display patch (or whole part) over the observers.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct DisplayOverObservers {
    /// The placement table's name (a patch: `part@WxH@xXyYzZ`).
    pub candidate: String,
    /// `part` or `patch`.
    pub kind: String,
    /// Legible seconds under the placement answer's default rule ([`crate::placement::Thresholds::default`]).
    pub legible_s: PopulationValue,
}

/// One observer's legible seconds per candidate (the study's `observers` order).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct ObserverDisplayRecord {
    /// Per candidate this observer sees, legible seconds (a candidate not listed: 0 s).
    pub legible_s: BTreeMap<String, f64>,
    /// The same at twice the frame step, behind the resolution bound (`None`: not checked).
    pub coarser_legible_s: Option<BTreeMap<String, f64>>,
}

/// The displays of an observer study (`observers --display WxH`): every
/// observer measured exactly with placement candidates, and per candidate
/// the legible seconds summarised as the parts' values are.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct ObserverDisplays {
    /// Display width × height, metres.
    pub display_m: [f64; 2],
    /// Spacing of the candidate patch centres, metres.
    pub spacing_m: f64,
    /// Share of the texels each observer's exact measure samples, in (0, 1].
    pub sample: f64,
    /// One sentence: what the intervals are and what they leave out.
    pub interval: String,
    /// Per observer, in the study's `observers` order.
    pub observers: Vec<ObserverDisplayRecord>,
    /// Largest mean legible time first.
    pub summary: Vec<DisplayOverObservers>,
    /// Candidates no placement answer may hold, and why (not mountable; no display fits: the
    /// placement's one rule, `docs/placement.md`); absent in older files.
    #[serde(default)]
    pub excluded: Vec<crate::format::placement::ExcludedRecord>,
    /// Wall seconds of the display measures, all observers.
    pub seconds: f64,
}

/// `observers.json`: a finished observer study.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct ObserverStudy {
    /// [`OBSERVERS_SCHEMA`].
    pub schema: String,
    pub scenario: String,
    pub ppd: f64,
    pub frame_step: u32,
    pub population: ObserverPopulation,
    pub sampling: ObserverSampling,
    pub resolution_check: ResolutionCheck,
    /// One sentence: what the intervals are and what they leave out.
    pub interval: String,
    pub parts: Vec<String>,
    pub observers: Vec<ObserverRecord>,
    /// Sorted by mean angular area, largest first.
    pub summary: Vec<PartOverObservers>,
    /// Wall seconds for all observers.
    pub seconds: f64,
    /// Wall seconds of the set-up the observers share, left out of each observer's `seconds`.
    pub setup_seconds: f64,
    /// Per candidate display, with `--display WxH`; absent without (and in files written before it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub displays: Option<ObserverDisplays>,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_population_file_needs_only_the_place_and_gets_the_documented_defaults() {
        let read: ObserverPopulation =
            serde_json::from_str(r#"{"place": {"kind": "kerb", "from": [0, 0], "to": [4, -2]}}"#).unwrap();
        assert_eq!(
            read,
            ObserverPopulation::us_adults(ObserverPlace::Kerb { from: [0.0, 0.0], to: [4.0, -2.0] })
        );
        let typo = serde_json::from_str::<ObserverPopulation>(r#"{"place": {"kind": "rig"}, "group": []}"#);
        assert!(typo.unwrap_err().to_string().contains("group"));
    }

    fn study(displays: Option<ObserverDisplays>) -> ObserverStudy {
        ObserverStudy {
            schema: OBSERVERS_SCHEMA.into(),
            scenario: "A".into(),
            ppd: 6.0,
            frame_step: 30,
            population: ObserverPopulation::us_adults(ObserverPlace::Rig),
            sampling: ObserverSampling::Random { observers: 2, seed: 1 },
            resolution_check: ResolutionCheck::None,
            interval: "t".into(),
            parts: vec!["hood".into()],
            observers: Vec::new(),
            summary: Vec::new(),
            seconds: 1.0,
            setup_seconds: 0.5,
            displays,
        }
    }

    #[test]
    fn a_study_without_displays_writes_no_displays_key_and_a_file_written_before_them_still_reads() {
        let json = serde_json::to_value(study(None)).unwrap();
        assert!(json.get("displays").is_none(), "{json}");
        let read: ObserverStudy = serde_json::from_value(json).unwrap();
        assert_eq!(read, study(None));
    }

    #[test]
    fn a_study_with_displays_reads_back_every_candidate_and_observer() {
        let value = PopulationValue {
            mean: 1.5,
            mean_ci95: Some([0.5, 2.5]),
            monte_carlo_half_width: Some(0.8),
            resolution_bound: Some(0.2),
            p2_5: 1.0,
            p97_5: 2.0,
        };
        let displays = ObserverDisplays {
            display_m: [0.4, 0.15],
            spacing_m: 0.3,
            sample: 1.0,
            interval: "t".into(),
            observers: vec![ObserverDisplayRecord {
                legible_s: [("hood".to_string(), 2.0)].into(),
                coarser_legible_s: Some([("hood".to_string(), 1.8)].into()),
            }],
            summary: vec![DisplayOverObservers {
                candidate: "hood".into(),
                kind: "part".into(),
                legible_s: value,
            }],
            excluded: Vec::new(),
            seconds: 3.0,
        };
        let written = serde_json::to_string(&study(Some(displays.clone()))).unwrap();
        let read: ObserverStudy = serde_json::from_str(&written).unwrap();
        assert_eq!(read.displays, Some(displays));
    }
}
