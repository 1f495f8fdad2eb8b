//! When a candidate is *legible*, not just visible: the thresholds, their
//! defaults and where each default comes from, and each candidate's
//! timeline of legible and visible frames in one archive.
//!
//! A candidate is legible in an eye-frame when all of these hold: its
//! *characters* reach [`Thresholds::min_character_height_arcmin`] (the
//! measured visible angular height times the share of the display's height
//! the characters fill, [`CharacterHeight`]); for a display of known size,
//! its width foreshortened by the view angle holds
//! [`Thresholds::min_characters`] characters; its visible share reaches
//! [`Thresholds::min_visible_fraction`]; and the mean angle between the line
//! of sight and its surface normal is at most
//! [`Thresholds::max_view_angle_deg`]. A *frame* (one time step) counts as
//! legible when the candidate is legible to either eye (`--eyes any`, the
//! default: one eye reads a sign as well as two do) or to both
//! (`--eyes both`), and only inside a run of legible frames lasting at least
//! [`Thresholds::min_dwell_s`] (a message glimpsed for one frame is not
//! read). `docs/placement.md` gives the sources.
//!
//! The *solid-angle rule* ([`Thresholds::min_solid_angle_sr`]) replaces the
//! geometric rules with one: a visible solid angle of at least so many
//! steradians. It is the rule a rendered `frames.csv` (solid angles only)
//! can be scored by, so the rendered and the exact measure can be compared
//! on the same sets (the dwell still applies).

use std::sync::Arc;

use crate::error::{Error, Result};
pub use crate::format::placement::{CharacterHeight, EyeRule};
use crate::placement::eligible::{Fit, FitCandidate, fit_parts};
use crate::placement::table::{CandidateKind, PlacementTable, Sighting};

/// ISO 9241-3 (1992) §5.6, restated in ISO 9241-303: "the minimum character
/// height shall be 16 minutes of arc" (20–22' preferred for reading). It is
/// applied to the characters, whose height is [`CharacterHeight`] of the
/// display's.
pub(crate) const DEFAULT_MIN_CHARACTER_HEIGHT_ARCMIN: f64 = 16.0;
/// Where [`DEFAULT_MIN_CHARACTER_HEIGHT_ARCMIN`] comes from.
pub(crate) const CHARACTER_ARCMIN_SOURCE: &str = "ISO 9241-3:1992 / ISO 9241-303 minimum character height 16 arcmin \
     (20-22 arcmin preferred), applied to the characters; the road-sign alternative, MUTCD 2009 Sec. 2A.14 \
     (1 in of letter height per 40 ft of legibility distance), is 7.16 arcmin";
/// One line of capitals half as tall as the display: a quarter of the
/// height above and below for the border and margins. A design assumption,
/// no standard fixes it.
pub(crate) const DEFAULT_CHARACTER_FRACTION: f64 = 0.5;
/// Where [`DEFAULT_CHARACTER_FRACTION`] comes from.
pub(crate) const CHARACTER_HEIGHT_SOURCE: &str = "design assumption (no standard): one line of capitals half the display \
     height, a quarter above and below for border and margins; for a part (height unknown) the characters are \
     this share of its visible angular height";
/// A one-word message ("WALK", "STOP", "GO AHEAD" is two): four characters.
pub(crate) const DEFAULT_MIN_CHARACTERS: u32 = 4;
/// A character's width plus the space after it, per unit of its height: ISO
/// 9241-3 / ANSI-HFES 100 width-to-height 0.7 (lower end of the preferred
/// 0.7-0.9) and a stroke's width of spacing (about 1/7 of the height).
pub(crate) const CHARACTER_PITCH: f64 = 0.85;
/// Where [`DEFAULT_MIN_CHARACTERS`] and [`CHARACTER_PITCH`] come from.
pub(crate) const CHARACTERS_SOURCE: &str = "one short word (4 characters, e.g. WALK/STOP) at a pitch of 0.85 character \
     heights (ISO 9241-3 / ANSI-HFES 100 width-to-height 0.7 plus about one stroke of spacing); the display's \
     width is foreshortened by cos(view angle), its height not (measured); parts (size unknown) are not \
     width-checked";
/// No standard sets how much of an eHMI may be hidden; a design assumption:
/// four fifths of its face unobstructed.
pub(crate) const DEFAULT_MIN_VISIBLE_FRACTION: f64 = 0.8;
/// Where [`DEFAULT_MIN_VISIBLE_FRACTION`] comes from.
pub(crate) const VISIBLE_FRACTION_SOURCE: &str =
    "design assumption (no standard): at least 4/5 of the candidate's area unobstructed";
/// The half-luminance viewing angle LED-matrix displays are commonly
/// specified with (±60°); a flat display seen at 60° is also foreshortened
/// to half its width. A datasheet convention, not a standard.
pub(crate) const DEFAULT_MAX_VIEW_ANGLE_DEG: f64 = 60.0;
/// Where [`DEFAULT_MAX_VIEW_ANGLE_DEG`] comes from.
pub(crate) const VIEW_ANGLE_SOURCE: &str = "common LED/LCD datasheet half-luminance viewing angle of +-60 deg from \
     the normal (not a standard; cos 60 = 1/2 foreshortening)";
/// FHWA's changeable-message-sign guidance (Dudek 2004, *Changeable Message
/// Sign Operation and Messaging Handbook*, FHWA-OP-03-070): a message needs
/// at least one second of exposure per word; an eHMI message is one word.
pub(crate) const DEFAULT_MIN_DWELL_S: f64 = 1.0;
/// Where [`DEFAULT_MIN_DWELL_S`] comes from.
pub(crate) const DWELL_SOURCE: &str = "FHWA changeable message sign guidance (Dudek 2004, FHWA-OP-03-070): at least \
     1 s of exposure per word; a one-word message; runs of legible frames shorter than this do not count";
/// The seconds before the vehicle reaches the pedestrian in which the
/// crossing decision is made: about the Highway Capacity Manual's pedestrian
/// critical headway for one 3.5 m lane (L / S_p + t_s = 3.5 m / 1.07 m/s + 3 s
/// ≈ 6.3 s), rounded.
pub(crate) const DEFAULT_DECISION_WINDOW_S: f64 = 6.0;
/// Where [`DEFAULT_DECISION_WINDOW_S`] comes from.
pub(crate) const DECISION_WINDOW_SOURCE: &str = "about the HCM pedestrian critical headway for one 3.5 m lane \
     (lane width / 3.5 ft/s walking speed + 3 s start-up), rounded to 6 s; the window ends at the frame of \
     the smallest vehicle-pedestrian distance";

/// The legibility rule (see the module documentation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Thresholds {
    /// The characters' visible angular height must reach this, arcmin.
    pub min_character_height_arcmin: f64,
    pub character_height: CharacterHeight,
    /// A display of known size must hold this many characters across (0: no width check).
    pub min_characters: u32,
    pub min_visible_fraction: f64,
    pub max_view_angle_deg: f64,
    /// Legible runs shorter than this many seconds do not count (0: every frame counts).
    pub min_dwell_s: f64,
    pub decision_window_s: f64,
    pub eyes: EyeRule,
    /// The solid-angle rule: legible when the visible solid angle reaches
    /// this (sr), the geometric rules not applied; `None`: off.
    pub min_solid_angle_sr: Option<f64>,
}

impl Default for Thresholds {
    fn default() -> Thresholds {
        Thresholds {
            min_character_height_arcmin: DEFAULT_MIN_CHARACTER_HEIGHT_ARCMIN,
            character_height: CharacterHeight::Fraction(DEFAULT_CHARACTER_FRACTION),
            min_characters: DEFAULT_MIN_CHARACTERS,
            min_visible_fraction: DEFAULT_MIN_VISIBLE_FRACTION,
            max_view_angle_deg: DEFAULT_MAX_VIEW_ANGLE_DEG,
            min_dwell_s: DEFAULT_MIN_DWELL_S,
            decision_window_s: DEFAULT_DECISION_WINDOW_S,
            eyes: EyeRule::Any,
            min_solid_angle_sr: None,
        }
    }
}

/// `0.5` (a share of the display's height) or `0.05m` (metres).
pub fn parse_character_height(text: &str) -> Result<CharacterHeight> {
    let bad = || {
        Error::BadOptions(format!(
            "--character-height {text:?}: expected a share of the display height (0.5) or metres (0.05m)"
        ))
    };
    let trimmed = text.trim();
    let (number, metres) = match trimmed.strip_suffix('m') {
        Some(number) => (number, true),
        None => (trimmed, false),
    };
    let value: f64 = number.trim().parse().map_err(|_| bad())?;
    let height = if metres { CharacterHeight::Metres(value) } else { CharacterHeight::Fraction(value) };
    check_character_height(height)?;
    Ok(height)
}

fn check_character_height(height: CharacterHeight) -> Result<()> {
    let ok = match height {
        CharacterHeight::Fraction(f) => f.is_finite() && f > 0.0 && f <= 1.0,
        CharacterHeight::Metres(m) => m.is_finite() && m > 0.0 && m <= 20.0,
    };
    if ok {
        Ok(())
    } else {
        Err(Error::BadOptions(format!(
            "--character-height {height:?}: a share must be in (0, 1], metres in (0, 20]"
        )))
    }
}

impl Thresholds {
    /// Options out of range are an error naming the option.
    pub fn check(&self) -> Result<()> {
        let bad = |name: &str, value: f64, range: &str| {
            Err(Error::BadOptions(format!("--{name} {value}: must be {range}")))
        };
        if !(self.min_character_height_arcmin.is_finite() && self.min_character_height_arcmin >= 0.0) {
            return bad("min-character-height-arcmin", self.min_character_height_arcmin, "a number ≥ 0");
        }
        check_character_height(self.character_height)?;
        if self.min_characters > 1000 {
            return bad("min-characters", f64::from(self.min_characters), "at most 1000");
        }
        if !(0.0..=1.0).contains(&self.min_visible_fraction) {
            return bad("min-visible-fraction", self.min_visible_fraction, "from 0 to 1");
        }
        if !(0.0..=90.0).contains(&self.max_view_angle_deg) {
            return bad("max-view-angle-deg", self.max_view_angle_deg, "from 0 to 90");
        }
        if !(self.min_dwell_s.is_finite() && self.min_dwell_s >= 0.0) {
            return bad("min-dwell-s", self.min_dwell_s, "0 seconds or more");
        }
        if !(self.decision_window_s.is_finite() && self.decision_window_s > 0.0) {
            return bad("decision-window-s", self.decision_window_s, "more than 0 seconds");
        }
        match self.min_solid_angle_sr {
            Some(sr) if !(sr.is_finite() && sr > 0.0) => bad("min-solid-angle-sr", sr, "more than 0"),
            _ => Ok(()),
        }
    }

    /// The share of the visible height the characters fill, for a display
    /// of `size` (width, height m; `None` for a part).
    pub fn character_fraction(&self, size: Option<[f64; 2]>) -> f64 {
        match (self.character_height, size) {
            (CharacterHeight::Fraction(f), _) => f,
            (CharacterHeight::Metres(m), Some([_, h])) => (m / h).min(1.0),
            (CharacterHeight::Metres(_), None) => DEFAULT_CHARACTER_FRACTION,
        }
    }

    /// Is one eye's sighting of a candidate (a display of `size`, `None`
    /// for a part) legible?
    pub fn legible(&self, sighting: &Sighting, size: Option<[f64; 2]>) -> bool {
        if let Some(min) = self.min_solid_angle_sr {
            return sighting.solid_angle_sr > 0.0 && sighting.solid_angle_sr >= min;
        }
        let fraction = self.character_fraction(size);
        let wide_enough = size.is_none_or(|[w, h]| {
            let across = w * sighting.view_angle_deg.to_radians().cos();
            across >= f64::from(self.min_characters) * CHARACTER_PITCH * fraction * h - 1e-12
        });
        sighting.solid_angle_sr > 0.0
            && sighting.angular_height_deg * 60.0 * fraction >= self.min_character_height_arcmin
            && sighting.visible_fraction >= self.min_visible_fraction
            && sighting.view_angle_deg <= self.max_view_angle_deg
            && wide_enough
    }
}

/// The legible frames (ascending indices) without the runs of consecutive
/// frames shorter than `min_frames`.
pub(crate) fn apply_dwell(legible: Vec<usize>, min_frames: usize) -> Vec<usize> {
    let mut kept = Vec::with_capacity(legible.len());
    let mut start = 0;
    while start < legible.len() {
        let mut end = start + 1;
        while end < legible.len() && legible[end] == legible[end - 1] + 1 {
            end += 1;
        }
        if end - start >= min_frames {
            kept.extend_from_slice(&legible[start..end]);
        }
        start = end;
    }
    kept
}

/// The frames a dwell of `dwell_s` needs at `frame_s` seconds per frame.
pub(crate) fn dwell_frames(dwell_s: f64, frame_s: f64) -> usize {
    if dwell_s <= 0.0 || frame_s <= 0.0 { 1 } else { ((dwell_s / frame_s) - 1e-9).ceil().max(1.0) as usize }
}

/// One candidate's frames in one archive.
#[derive(Debug, Clone, PartialEq)]
pub struct Timeline {
    pub name: String,
    pub kind: CandidateKind,
    pub mirror: Option<String>,
    /// A display's width and height, m (`None` for a part).
    pub size_m: Option<[f64; 2]>,
    /// The frames (ascending indices into the table's frames) where it is
    /// legible under the eye rule: sparse, so memory goes with what is seen,
    /// not with frames × candidates (issue 34: a 3 MB table took 1.2 GB).
    pub legible: Vec<usize>,
    /// The frames where any eye sees any of it (any solid angle at all).
    pub visible: Vec<usize>,
    /// How its legible frames were scored: a part of a table with display
    /// patches through its most legible fitting patch, or not at all when
    /// none fits ([`crate::placement::eligible`]).
    pub fit: Fit,
}

impl FitCandidate for Timeline {
    fn name(&self) -> &str {
        &self.name
    }
    fn kind(&self) -> CandidateKind {
        self.kind
    }
    fn legible_frames(&mut self) -> &mut Vec<usize> {
        &mut self.legible
    }
    fn set_fit(&mut self, fit: Fit) {
        self.fit = fit;
    }
}

/// What one candidate scored in one archive.
pub use crate::format::placement::ExposureRecord as Exposure;

/// One archive, ready for the search: its frames' clock and every timeline.
#[derive(Debug, Clone, PartialEq)]
pub struct ArchiveTimelines {
    pub table: Arc<PlacementTable>,
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
        let seconds = |frames: usize| frames as f64 * self.table.frame_s;
        let first = timeline.legible.first().map(|&i| self.table.frames[i]);
        let in_window = timeline.legible.iter().filter(|&&i| self.in_window[i]).count();
        Exposure {
            legible_s: seconds(timeline.legible.len()),
            visible_s: seconds(timeline.visible.len()),
            first_legible_s: first.map(|f| f.time_s),
            first_legible_distance_m: first.map(|f| f.distance_m),
            decision_window_legible_s: seconds(in_window),
            texel_sample_interval_s: None,
        }
    }
}

/// Every candidate's timeline in `table` under `thresholds`; with display
/// patches in the table, a part is legible only through a patch that fits on
/// it ([`crate::placement::eligible`]).
pub fn timelines(table: Arc<PlacementTable>, thresholds: &Thresholds) -> ArchiveTimelines {
    timelines_with(table, thresholds, &std::collections::BTreeSet::new())
}

/// [`timelines`], where the patches in `unfit` stand for no part
/// ([`crate::placement::eligible::unfit_patches`]: a not-mountable list
/// other than the default).
pub(crate) fn timelines_with(
    table: Arc<PlacementTable>,
    thresholds: &Thresholds,
    unfit: &std::collections::BTreeSet<String>,
) -> ArchiveTimelines {
    let eyes = table.eyes.len();
    let dwell = dwell_frames(thresholds.min_dwell_s, table.frame_s);
    let timelines = table
        .candidates
        .values()
        .map(|candidate| {
            // Sightings are keyed (frame, eye), in order: one pass, sparse.
            let mut legible_eyes: Vec<(usize, usize)> = Vec::new();
            let mut visible: Vec<usize> = Vec::new();
            for (&(frame, _eye), sighting) in &candidate.sightings {
                if sighting.solid_angle_sr > 0.0 && visible.last() != Some(&frame) {
                    visible.push(frame);
                }
                let legible = usize::from(thresholds.legible(sighting, candidate.size_m));
                match legible_eyes.last_mut() {
                    Some((last, n)) if *last == frame => *n += legible,
                    _ => legible_eyes.push((frame, legible)),
                }
            }
            let legible: Vec<usize> = legible_eyes
                .into_iter()
                .filter(|&(_, n)| match thresholds.eyes {
                    EyeRule::Any => n > 0,
                    EyeRule::Both => n == eyes && n > 0,
                })
                .map(|(frame, _)| frame)
                .collect();
            let legible = apply_dwell(legible, dwell);
            Timeline {
                name: candidate.name.clone(),
                kind: candidate.kind,
                mirror: candidate.mirror.clone(),
                size_m: candidate.size_m,
                legible,
                visible,
                fit: Fit::Whole,
            }
        })
        .collect::<Vec<Timeline>>();
    let mut timelines = timelines;
    // A display must fit where it is said to be legible (one rule, every command).
    fit_parts(&mut timelines, unfit);
    let closest = table.frames.iter().min_by(|a, b| a.distance_m.total_cmp(&b.distance_m)).copied();
    let arrival_s = closest.map_or(0.0, |f| f.time_s);
    let start = arrival_s - thresholds.decision_window_s;
    let in_window =
        table.frames.iter().map(|f| f.time_s > start + 1e-9 && f.time_s <= arrival_s + 1e-9).collect();
    ArchiveTimelines { table, timelines, in_window, arrival_s }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dwell_keeps_only_runs_of_consecutive_frames_at_least_as_long_as_the_dwell() {
        // Runs 0–2 (3 frames), 5 (1), 7–8 (2), and 1_000_000 far away (1).
        let legible = vec![0, 1, 2, 5, 7, 8, 1_000_000];
        assert_eq!(apply_dwell(legible.clone(), 1), legible);
        assert_eq!(apply_dwell(legible.clone(), 2), vec![0, 1, 2, 7, 8]);
        assert_eq!(apply_dwell(legible.clone(), 3), vec![0, 1, 2]);
        assert!(apply_dwell(legible, 4).is_empty());
        assert!(apply_dwell(Vec::new(), 2).is_empty());
    }
}
