//! Which candidates the search may choose: not those on a surface where no
//! display can be mounted, and one patch per *region* so the answer lists
//! distinct places rather than ten patches 10 cm apart.
//!
//! **Mountable.** A candidate's *head noun* is the last word of its part's
//! name (the name before `@`, words split at `_`, `-`, `.` and spaces)
//! once side and position words (`left`, `right`, `front`, `rear`, `upper`,
//! …) and numbers are dropped: `tyre_front_left` → `tyre`,
//! `windshield_rail_left` → `rail`, `windshield` → `windshield`. A
//! candidate whose head noun is in the not-mountable list
//! ([`DEFAULT_NOT_MOUNTABLE`]: wheels, tyres, rims and glass; `--not-mountable`
//! replaces it) is scored and listed but never chosen.
//!
//! **Regions.** Among the mountable patches, most legible first, each patch
//! not yet in a region opens one and takes every other patch of the same
//! part whose centre lies within the region radius of its own
//! ([`DEFAULT_REGION_RADIUS_M`]); the search chooses among the regions'
//! first patches only. Parts are never collapsed.

use std::collections::BTreeMap;

use crate::placement::footprints::{PatchFootprint, centre_in_name, part_of};
use crate::placement::table::CandidateKind;

/// Surfaces where no display is mounted by default: the wheels (a display
/// on a turning rim or tyre is unreadable and unbuildable) and the glazing
/// (it must stay transparent; ECE R43 / FMVSS 205 — name it on the command
/// line to allow it).
pub const DEFAULT_NOT_MOUNTABLE: [&str; 15] = [
    "wheel",
    "wheels",
    "tyre",
    "tyres",
    "tire",
    "tires",
    "rim",
    "rims",
    "hubcap",
    "hubcaps",
    "glass",
    "windshield",
    "windscreen",
    "window",
    "windows",
];
/// Where [`DEFAULT_NOT_MOUNTABLE`] comes from.
pub(crate) const NOT_MOUNTABLE_SOURCE: &str = "wheels, tyres and rims turn; glazing must stay transparent (ECE R43 / \
     FMVSS 205 regulate it): a candidate whose part's head noun (last word without side/position words) is in \
     the list is scored but never chosen; --not-mountable replaces the list ('' allows every surface)";
/// Patches of one part whose centres are within 0.25 m are one place:
/// under the width of the 0.40 m display the demo uses, so two such
/// footprints overlap by more than a third.
pub const DEFAULT_REGION_RADIUS_M: f64 = 0.25;
/// Where [`DEFAULT_REGION_RADIUS_M`] comes from.
pub(crate) const REGION_RADIUS_SOURCE: &str = "design choice: patches of one part within 0.25 m (centre to centre) \
     overlap by more than a third of a 0.40 m display and are one place; the region's most legible patch \
     stands for it (0 turns collapsing off)";

/// Side and position words that do not name a surface.
const POSITION_WORDS: [&str; 20] = [
    "left", "right", "front", "rear", "back", "upper", "lower", "top", "bottom", "inner", "outer", "centre",
    "center", "middle", "l", "r", "fl", "fr", "rl", "rr",
];

/// The head noun of a candidate's part (see the module documentation).
pub(crate) fn head_noun(name: &str) -> String {
    part_of(name)
        .split(['_', '-', '.', ' '])
        .map(str::to_lowercase)
        .filter(|w| !w.is_empty() && !w.chars().all(|c| c.is_ascii_digit()))
        .rfind(|w| !POSITION_WORDS.contains(&w.as_str()))
        .unwrap_or_default()
}

/// Whether a display can be mounted on `name`'s surface under `not_mountable`.
pub fn mountable(name: &str, not_mountable: &[String]) -> bool {
    let noun = head_noun(name);
    !not_mountable.iter().any(|n| n.trim().eq_ignore_ascii_case(&noun))
}

/// One candidate as the region rule sees it.
pub(crate) struct Scored<'a> {
    pub name: &'a str,
    pub kind: CandidateKind,
    /// Mean legible seconds (the region's order).
    pub legible_s: f64,
}

/// Per candidate that may be chosen: the candidate standing for its region
/// (itself for parts and a region's first patch). Candidates `excluded`
/// (not mountable, no display fits: [`crate::placement::eligible`]) are absent.
pub(crate) fn representatives(
    scored: &[Scored],
    footprints: &BTreeMap<String, PatchFootprint>,
    excluded: &std::collections::BTreeSet<String>,
    radius_m: f64,
) -> BTreeMap<String, String> {
    let mut order: Vec<&Scored> = scored.iter().filter(|c| !excluded.contains(c.name)).collect();
    order.sort_by(|a, b| b.legible_s.total_cmp(&a.legible_s).then_with(|| a.name.cmp(b.name)));
    let centre = |name: &str| footprints.get(name).map(|f| f.centre).or_else(|| centre_in_name(name));
    let mut out: BTreeMap<String, String> = BTreeMap::new();
    for (i, head) in order.iter().enumerate() {
        if out.contains_key(head.name) {
            continue;
        }
        out.insert(head.name.to_string(), head.name.to_string());
        if head.kind != CandidateKind::Patch || radius_m <= 0.0 {
            continue;
        }
        let Some(at) = centre(head.name) else { continue };
        for other in &order[i + 1..] {
            if other.kind != CandidateKind::Patch
                || out.contains_key(other.name)
                || part_of(other.name) != part_of(head.name)
            {
                continue;
            }
            if centre(other.name).is_some_and(|c| distance(c, at) <= radius_m) {
                out.insert(other.name.to_string(), head.name.to_string());
            }
        }
    }
    out
}

fn distance(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn defaults() -> Vec<String> {
        DEFAULT_NOT_MOUNTABLE.iter().map(|s| s.to_string()).collect()
    }

    #[test]
    fn wheels_tyres_and_glass_are_not_mountable_but_a_windshield_rail_is() {
        let list = defaults();
        for name in
            ["tyre_front_left", "rim_rear_right", "windshield", "side_window_left", "wheel@0.40x0.15@x1y1z1"]
        {
            assert!(!mountable(name, &list), "{name}");
        }
        for name in
            ["windshield_rail_left", "front_bumper@0.40x0.15@x2.95y-0.76z0.46", "wheel_arch_left", "hood"]
        {
            assert!(mountable(name, &list), "{name}");
        }
        // The user's list replaces the default: glass allowed.
        let no_glass = vec!["tyre".to_string(), "rim".to_string()];
        assert!(mountable("windshield", &no_glass) && !mountable("tyre_front_left", &no_glass));
        assert!(mountable("tyre_front_left", &[]));
    }

    #[test]
    fn near_patches_of_one_part_are_one_region_led_by_the_most_legible() {
        let names = [
            "bumper@x2.95y0.00z0.46",
            "bumper@x2.95y0.10z0.46",
            "bumper@x2.95y0.60z0.46",
            "grill@x2.95y0.05z0.80",
        ];
        let scored: Vec<Scored> = names
            .iter()
            .zip([1.0, 2.0, 1.5, 0.5])
            .map(|(name, legible_s)| Scored { name, kind: CandidateKind::Patch, legible_s })
            .collect();
        let none = std::collections::BTreeSet::new();
        let regions = representatives(&scored, &BTreeMap::new(), &none, DEFAULT_REGION_RADIUS_M);
        assert_eq!(regions[names[0]], names[1], "10 cm away from a better patch: its region");
        assert_eq!(regions[names[1]], names[1]);
        assert_eq!(regions[names[2]], names[2], "50 cm away: a place of its own");
        assert_eq!(regions[names[3]], names[3], "another part: a place of its own");
        let off = representatives(&scored, &BTreeMap::new(), &none, 0.0);
        assert!(off.iter().all(|(k, v)| k == v));
    }
}
