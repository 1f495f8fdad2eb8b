//! When a candidate is *legible*, not just visible: the thresholds, their
//! defaults and where each default comes from, and each candidate's
//! timeline of legible and visible frames in one archive.
//!
//! A candidate is legible in an eye-frame when all three hold: its visible
//! angular height reaches [`Thresholds::min_angular_height_arcmin`], its
//! visible share reaches [`Thresholds::min_visible_fraction`], and the mean
//! angle between the line of sight and its surface normal is at most
//! [`Thresholds::max_view_angle_deg`]. A *frame* (one time step) counts as
//! legible when the candidate is legible to either eye (`--eyes any`, the
//! default: one eye reads a sign as well as two do) or to both
//! (`--eyes both`). `docs/placement.md` gives the sources.
//!
//! The *solid-angle rule* ([`Thresholds::min_solid_angle_sr`]) replaces the
//! three with one: a visible solid angle of at least so many steradians. It
//! is the rule a rendered `frames.csv` (solid angles only) can be scored by,
//! so the rendered and the exact measure can be compared on the same sets.

use crate::error::{Error, Result};
use crate::placement::table::{CandidateKind, PlacementTable, Sighting};

/// ISO 9241-3 (1992) §5.6, restated in ISO 9241-303: "the minimum character
/// height shall be 16 minutes of arc" (20–22' preferred for reading). The
/// candidate's visible angular height stands for the height of one line of
/// characters filling the display.
pub const DEFAULT_MIN_ANGULAR_HEIGHT_ARCMIN: f64 = 16.0;
/// Where [`DEFAULT_MIN_ANGULAR_HEIGHT_ARCMIN`] comes from.
pub const ANGULAR_HEIGHT_SOURCE: &str = "ISO 9241-3:1992 / ISO 9241-303 minimum character height 16 arcmin \
     (20-22 arcmin preferred); the road-sign alternative, MUTCD 2009 Sec. 2A.14 (1 in of letter height per \
     40 ft of legibility distance), is 7.16 arcmin";
/// No standard sets how much of an eHMI may be hidden; a design assumption:
/// four fifths of its face unobstructed.
pub const DEFAULT_MIN_VISIBLE_FRACTION: f64 = 0.8;
/// Where [`DEFAULT_MIN_VISIBLE_FRACTION`] comes from.
pub const VISIBLE_FRACTION_SOURCE: &str =
    "design assumption (no standard): at least 4/5 of the candidate's area unobstructed";
/// The half-luminance viewing angle LED-matrix displays are commonly
/// specified with (±60°); a flat display seen at 60° is also foreshortened
/// to half its width. A datasheet convention, not a standard.
pub const DEFAULT_MAX_VIEW_ANGLE_DEG: f64 = 60.0;
/// Where [`DEFAULT_MAX_VIEW_ANGLE_DEG`] comes from.
pub const VIEW_ANGLE_SOURCE: &str = "common LED/LCD datasheet half-luminance viewing angle of +-60 deg from \
     the normal (not a standard; cos 60 = 1/2 foreshortening)";
/// The seconds before the vehicle reaches the pedestrian in which the
/// crossing decision is made: about the Highway Capacity Manual's pedestrian
/// critical headway for one 3.5 m lane (L / S_p + t_s = 3.5 m / 1.07 m/s + 3 s
/// ≈ 6.3 s), rounded.
pub const DEFAULT_DECISION_WINDOW_S: f64 = 6.0;
/// Where [`DEFAULT_DECISION_WINDOW_S`] comes from.
pub const DECISION_WINDOW_SOURCE: &str = "about the HCM pedestrian critical headway for one 3.5 m lane \
     (lane width / 3.5 ft/s walking speed + 3 s start-up), rounded to 6 s; the window ends at the frame of \
     the smallest vehicle-pedestrian distance";

/// Which eyes must read a candidate for a frame to count.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
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

/// The legibility rule (see the module documentation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Thresholds {
    pub min_angular_height_arcmin: f64,
    pub min_visible_fraction: f64,
    pub max_view_angle_deg: f64,
    pub decision_window_s: f64,
    pub eyes: EyeRule,
    /// The solid-angle rule: legible when the visible solid angle reaches
    /// this (sr), the other three thresholds not applied; `None`: off.
    pub min_solid_angle_sr: Option<f64>,
}

impl Default for Thresholds {
    fn default() -> Thresholds {
        Thresholds {
            min_angular_height_arcmin: DEFAULT_MIN_ANGULAR_HEIGHT_ARCMIN,
            min_visible_fraction: DEFAULT_MIN_VISIBLE_FRACTION,
            max_view_angle_deg: DEFAULT_MAX_VIEW_ANGLE_DEG,
            decision_window_s: DEFAULT_DECISION_WINDOW_S,
            eyes: EyeRule::Any,
            min_solid_angle_sr: None,
        }
    }
}

impl Thresholds {
    /// Options out of range are an error naming the option.
    pub fn check(&self) -> Result<()> {
        let bad = |name: &str, value: f64, range: &str| {
            Err(Error::BadOptions(format!("--{name} {value}: must be {range}")))
        };
        if !(self.min_angular_height_arcmin.is_finite() && self.min_angular_height_arcmin >= 0.0) {
            return bad("min-angular-height-arcmin", self.min_angular_height_arcmin, "a number ≥ 0");
        }
        if !(0.0..=1.0).contains(&self.min_visible_fraction) {
            return bad("min-visible-fraction", self.min_visible_fraction, "from 0 to 1");
        }
        if !(0.0..=90.0).contains(&self.max_view_angle_deg) {
            return bad("max-view-angle-deg", self.max_view_angle_deg, "from 0 to 90");
        }
        if !(self.decision_window_s.is_finite() && self.decision_window_s > 0.0) {
            return bad("decision-window-s", self.decision_window_s, "more than 0 seconds");
        }
        match self.min_solid_angle_sr {
            Some(sr) if !(sr.is_finite() && sr > 0.0) => bad("min-solid-angle-sr", sr, "more than 0"),
            _ => Ok(()),
        }
    }

    /// Is one eye's sighting legible?
    pub fn legible(&self, sighting: &Sighting) -> bool {
        if let Some(min) = self.min_solid_angle_sr {
            return sighting.solid_angle_sr > 0.0 && sighting.solid_angle_sr >= min;
        }
        sighting.solid_angle_sr > 0.0
            && sighting.angular_height_deg * 60.0 >= self.min_angular_height_arcmin
            && sighting.visible_fraction >= self.min_visible_fraction
            && sighting.view_angle_deg <= self.max_view_angle_deg
    }
}

/// One candidate's frames in one archive.
#[derive(Debug, Clone, PartialEq)]
pub struct Timeline {
    pub name: String,
    pub kind: CandidateKind,
    pub mirror: Option<String>,
    /// Per frame: legible under the eye rule.
    pub legible: Vec<bool>,
    /// Per frame: visible to any eye (any solid angle at all).
    pub visible: Vec<bool>,
}

/// What one candidate scored in one archive.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Exposure {
    /// Seconds legible (frames × seconds per frame).
    pub legible_s: f64,
    /// Seconds visible at all.
    pub visible_s: f64,
    /// Time of the first legible frame, s; `None` when never legible.
    pub first_legible_s: Option<f64>,
    /// Vehicle-pedestrian distance at that frame, m.
    pub first_legible_distance_m: Option<f64>,
    /// Seconds legible inside the decision window.
    pub decision_window_legible_s: f64,
}

/// One archive, ready for the search: its frames' clock and every timeline.
#[derive(Debug, Clone, PartialEq)]
pub struct ArchiveTimelines {
    pub table: PlacementTable,
    pub timelines: Vec<Timeline>,
    /// Per frame: inside the decision window.
    pub in_window: Vec<bool>,
    /// The window's end (time of the smallest distance), s.
    pub arrival_s: f64,
}

impl ArchiveTimelines {
    /// Seconds the archive's frames cover.
    pub fn duration_s(&self) -> f64 {
        self.table.frames.len() as f64 * self.table.frame_s
    }

    /// The exposure of `timeline` (one of this archive's).
    pub fn exposure(&self, timeline: &Timeline) -> Exposure {
        let seconds = |flags: &[bool]| flags.iter().filter(|&&f| f).count() as f64 * self.table.frame_s;
        let first = timeline.legible.iter().position(|&l| l).map(|i| self.table.frames[i]);
        let in_window: Vec<bool> =
            timeline.legible.iter().zip(&self.in_window).map(|(&l, &w)| l && w).collect();
        Exposure {
            legible_s: seconds(&timeline.legible),
            visible_s: seconds(&timeline.visible),
            first_legible_s: first.map(|f| f.time_s),
            first_legible_distance_m: first.map(|f| f.distance_m),
            decision_window_legible_s: seconds(&in_window),
        }
    }
}

/// Every candidate's timeline in `table` under `thresholds`.
pub fn timelines(table: PlacementTable, thresholds: &Thresholds) -> ArchiveTimelines {
    let frames = table.frames.len();
    let eyes = table.eyes.len();
    let timelines = table
        .candidates
        .values()
        .map(|candidate| {
            let mut legible_eyes = vec![0usize; frames];
            let mut visible = vec![false; frames];
            for (&(frame, _eye), sighting) in &candidate.sightings {
                visible[frame] |= sighting.solid_angle_sr > 0.0;
                legible_eyes[frame] += usize::from(thresholds.legible(sighting));
            }
            let legible = legible_eyes
                .iter()
                .map(|&n| match thresholds.eyes {
                    EyeRule::Any => n > 0,
                    EyeRule::Both => n == eyes && n > 0,
                })
                .collect();
            Timeline {
                name: candidate.name.clone(),
                kind: candidate.kind,
                mirror: candidate.mirror.clone(),
                legible,
                visible,
            }
        })
        .collect();
    let closest = table.frames.iter().min_by(|a, b| a.distance_m.total_cmp(&b.distance_m)).copied();
    let arrival_s = closest.map_or(0.0, |f| f.time_s);
    let start = arrival_s - thresholds.decision_window_s;
    let in_window =
        table.frames.iter().map(|f| f.time_s > start + 1e-9 && f.time_s <= arrival_s + 1e-9).collect();
    ArchiveTimelines { table, timelines, in_window, arrival_s }
}
