//! Whose eyes: people by default for answers, the paper's camera on request.
//!
//! The seed paper's rig puts the eyes 1.75 m high — a stature used as an
//! eye height, about the 96th percentile eye height of the default
//! population ([`ufcsr::format::ObserverPopulation::us_adults`], NCHS 2015–2018),
//! whose median is 1.571 m — and 0.1103594 m apart, which is not a human
//! interpupillary distance (ANSUR II 2012: 64.0 mm men, 61.7 mm women).
//! [`Rig::default`] stays the paper's, so the paper's captures and their
//! tests reproduce it; answers (placement candidates, design runs) take
//! [`ObserverPreset::Median`] unless the scene set its own eyes or the user
//! asked for `--rig paper`, and each says which observer it used
//! ([`describe_observer`]).

use ufcsr::{format::ObserverPlace, format::ObserverPopulation};

use super::population::eye_height_quantile;
use crate::scene::rig::Rig;

/// The seed paper's eye height, m (a stature).
pub const PAPER_EYE_HEIGHT_M: f64 = 1.75;
/// The seed paper's eye spacing, m (its Unity rig's camera offset).
pub const PAPER_IPD_M: f64 = 0.1103594;
/// A human interpupillary distance: the mean of ANSUR II 2012's men (64.0 mm)
/// and women (61.7 mm).
pub const HUMAN_IPD_M: f64 = 0.06285;

/// A named observer for `--rig paper` / `--rig median`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ObserverPreset {
    /// The seed paper's rig: eyes 1.75 m high, 0.1103594 m apart.
    Paper,
    /// A median adult of the default population: the median eye height, a human IPD.
    Median,
}

impl ObserverPreset {
    /// `paper` or `median` (any case); `None` for anything else (a JSON rig).
    pub fn parse(text: &str) -> Option<ObserverPreset> {
        match text.trim().to_ascii_lowercase().as_str() {
            "paper" => Some(ObserverPreset::Paper),
            "median" => Some(ObserverPreset::Median),
            _ => None,
        }
    }

    /// Eye height and IPD, metres.
    pub fn eyes(self) -> (f64, f64) {
        match self {
            ObserverPreset::Paper => (PAPER_EYE_HEIGHT_M, PAPER_IPD_M),
            ObserverPreset::Median => (median_eye_height_m(), HUMAN_IPD_M),
        }
    }

    /// Puts this observer's eyes on `rig` (the rest of the rig is kept).
    pub fn apply(self, rig: &mut Rig) {
        (rig.eye_height_m, rig.ipd_m) = self.eyes();
    }
}

/// The median eye height of the default population (US adults, equal
/// mixture of men and women, NCHS 2015–2018; eye height = stature − offset).
pub fn median_eye_height_m() -> f64 {
    eye_height_quantile(&ObserverPopulation::us_adults(ObserverPlace::Rig), 0.5)
}

/// For an answer: a rig that still has the paper's eyes (the default of the
/// demo, of scene files that set none, of the street generator) gets the
/// median adult's; a scene's own eyes are kept. Returns whether it changed.
pub fn people_by_default(rig: &mut Rig) -> bool {
    let paper = ObserverPreset::Paper.eyes();
    if (rig.eye_height_m, rig.ipd_m) != paper {
        return false;
    }
    ObserverPreset::Median.apply(rig);
    true
}

/// Which observer `rig`'s eyes are, in words, for every answer's console and JSON.
pub fn describe_observer(rig: &Rig) -> String {
    let eyes = (rig.eye_height_m, rig.ipd_m);
    let numbers = format!("eyes {:.3} m high, {:.1} mm apart", rig.eye_height_m, rig.ipd_m * 1000.0);
    if eyes == ObserverPreset::Paper.eyes() {
        format!(
            "the seed paper's rig ({numbers}: a stature used as an eye height, about the 96th percentile eye \
             height of US adults, and a camera spacing, not a human IPD; --rig paper)"
        )
    } else if eyes == ObserverPreset::Median.eyes() {
        format!(
            "a median US adult ({numbers}: the median eye height of the default population, NCHS 2015–2018, and \
             the mean IPD of ANSUR II 2012 men and women; --rig paper reproduces the paper)"
        )
    } else {
        format!("the scene's observer ({numbers})")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn answers_take_a_median_adult_unless_the_scene_or_the_user_chose_the_eyes() {
        let median = median_eye_height_m();
        assert!((median - 1.573).abs() < 0.01, "{median}");
        // The paper's eye height is about the 96th percentile of the population's eye heights.
        let population = ObserverPopulation::us_adults(ObserverPlace::Rig);
        let p96 = eye_height_quantile(&population, 0.96);
        assert!((p96 - PAPER_EYE_HEIGHT_M).abs() < 0.02, "{p96}");
        let mut rig = Rig::default();
        assert_eq!(
            (rig.eye_height_m, rig.ipd_m),
            (PAPER_EYE_HEIGHT_M, PAPER_IPD_M),
            "the default is the paper's"
        );
        assert!(describe_observer(&rig).contains("the seed paper's rig (eyes 1.750 m high, 110.4 mm apart"));
        assert!(people_by_default(&mut rig));
        assert_eq!((rig.eye_height_m, rig.ipd_m), (median, HUMAN_IPD_M));
        assert!(
            describe_observer(&rig).starts_with("a median US adult (eyes 1.57"),
            "{}",
            describe_observer(&rig)
        );
        // A scene's own eyes are kept, and named as such.
        let mut own = Rig { eye_height_m: 1.2, ..Rig::default() };
        assert!(!people_by_default(&mut own));
        assert_eq!(own.eye_height_m, 1.2);
        assert!(describe_observer(&own).starts_with("the scene's observer (eyes 1.200 m high"));
        // The preset reproduces the paper.
        ObserverPreset::parse("paper").unwrap().apply(&mut rig);
        assert_eq!((rig.eye_height_m, rig.ipd_m), (1.75, 0.1103594));
        assert_eq!(ObserverPreset::parse("Median"), Some(ObserverPreset::Median));
        assert_eq!(ObserverPreset::parse("{\"eye_height_m\": 1.6}"), None);
    }
}
