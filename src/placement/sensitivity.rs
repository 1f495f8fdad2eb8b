//! Does the answer flip on a hair? Each threshold that decides legibility
//! is moved one step down and one step up (the others kept), the tables are
//! scored and searched again, and for every best set (by the mean) the
//! file records whether the best set stays the same place and how many
//! seconds the reported set keeps.
//!
//! Steps ([`steps`]): character height ±2 arcmin (16 is ISO's minimum, 20–22
//! preferred), character share ±0.1 (or ±10 % of metres), ±1 character of
//! width, visible fraction ±0.05, view angle ±5°, dwell ±0.25 s; under the
//! solid-angle rule that threshold ×/÷ 1.25 and the dwell. "The same place"
//! compares the sets' members by the region each belonged to at the given
//! thresholds, so a patch replaced by its 10 cm neighbour is no flip.

use crate::format::placement::{CharacterHeight, SensitivityRecord, SensitivitySet};
use crate::placement::legibility::Thresholds;

/// One moved threshold: its field name, its new value and the thresholds.
pub(crate) struct Step {
    pub threshold: &'static str,
    pub value: f64,
    pub thresholds: Thresholds,
}

/// Every threshold one step down and one step up (values out of range
/// left out).
pub(crate) fn steps(base: &Thresholds) -> Vec<Step> {
    let mut out = Vec::new();
    let mut push = |threshold: &'static str, value: f64, thresholds: Thresholds| {
        if thresholds.check().is_ok() && thresholds != *base {
            out.push(Step { threshold, value, thresholds });
        }
    };
    for sign in [-1.0, 1.0] {
        let dwell = (base.min_dwell_s + sign * 0.25).max(0.0);
        push("min_dwell_s", dwell, Thresholds { min_dwell_s: dwell, ..*base });
        if let Some(sr) = base.min_solid_angle_sr {
            let moved = if sign < 0.0 { sr / 1.25 } else { sr * 1.25 };
            push("min_solid_angle_sr", moved, Thresholds { min_solid_angle_sr: Some(moved), ..*base });
            continue;
        }
        let arcmin = base.min_character_height_arcmin + sign * 2.0;
        push(
            "min_character_height_arcmin",
            arcmin,
            Thresholds { min_character_height_arcmin: arcmin, ..*base },
        );
        let (value, height) = match base.character_height {
            CharacterHeight::Fraction(f) => (f + sign * 0.1, CharacterHeight::Fraction(f + sign * 0.1)),
            CharacterHeight::Metres(m) => {
                (m * (1.0 + sign * 0.1), CharacterHeight::Metres(m * (1.0 + sign * 0.1)))
            }
        };
        push("character_height", value, Thresholds { character_height: height, ..*base });
        let characters = base.min_characters.saturating_add_signed(sign as i32);
        push("min_characters", f64::from(characters), Thresholds { min_characters: characters, ..*base });
        let fraction = base.min_visible_fraction + sign * 0.05;
        push("min_visible_fraction", fraction, Thresholds { min_visible_fraction: fraction, ..*base });
        let angle = base.max_view_angle_deg + sign * 5.0;
        push("max_view_angle_deg", angle, Thresholds { max_view_angle_deg: angle, ..*base });
    }
    out.sort_by(|a, b| a.threshold.cmp(b.threshold).then(a.value.total_cmp(&b.value)));
    out
}

/// The record of one step from its best sets.
pub(crate) fn record(step: &Step, sets: Vec<SensitivitySet>) -> SensitivityRecord {
    SensitivityRecord { threshold: step.threshold.to_string(), value: step.value, sets }
}
