//! The places the published eHMI studies tested, scored as named candidates
//! (issue 42 §7). The behavioural studies (Eisma et al. 2020, Bazilinskyy
//! et al. 2021, Dey et al. 2020) and the two visibility studies by
//! Gonzalez-Belmonte & Kwon (the seed paper, arXiv 2604.11406, and the
//! raycasting study, arXiv 2507.08973) name a handful of places on a car —
//! roof, windshield top, grille, bumper, above the front wheels, side
//! mirrors, headlights, wheels, hood. Those names are not ufcsr's part
//! names, and a display patch's name says only its part and centre, so
//! this file holds the one table that maps each published place to the
//! candidates of any vehicle (by the part's head noun, the word
//! [`head_noun`] finds, and for the windshield top by the patch's height),
//! and scores each place with the numbers `ufcsr placement` already has
//! for its candidates: legible and visible seconds, the 95 % t interval over
//! the archives, the texel-sample bracket, mountability and the rank among
//! all candidates of its kind. `docs/literature.md` sets these beside the
//! studies' own findings; the ranking is a geometric hypothesis for those
//! studies to test, not a rule for where an eHMI must go.

use std::io::Write;
use std::path::{Path, PathBuf};

use crate::error::Result;
use crate::files::write_atomically;
use crate::format::placement::{CandidateKind, CandidateRecord};
use crate::placement::footprints::{centre_in_name, part_of};
use crate::placement::regions::head_noun;
use crate::placement::report::Placement;
use crate::placement::uncertainty::t_interval;

/// `published-locations.csv`, written beside `placement.json`.
pub const PUBLISHED_LOCATIONS_FILE: &str = "published-locations.csv";

/// Which of a place's patches count: all, or the upper third of the
/// heights the place's patch centres span (a light bar along the top of
/// the windshield).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Zone {
    Whole,
    Top,
}

/// A place a published study tested or recommended.
#[derive(Debug, Clone, Copy)]
pub struct PublishedLocation {
    /// The place, as the studies name it.
    pub name: &'static str,
    /// Head nouns of the parts that are this place (lower case).
    pub nouns: &'static [&'static str],
    /// Only parts at the front: names with a rear/back word are left out
    /// (`Bumper_Rear`, `rear_fender_left`, `tyre_rear_left`).
    pub front_only: bool,
    pub zone: Zone,
    /// The studies that tested or recommended it (docs/literature.md cites them in full).
    pub studies: &'static str,
}

/// The published places, in the order the page lists them.
pub const PUBLISHED_LOCATIONS: [PublishedLocation; 9] = [
    PublishedLocation {
        name: "roof",
        nouns: &["roof"],
        front_only: false,
        zone: Zone::Whole,
        studies: "Eisma et al. 2020; Dey et al. 2020",
    },
    PublishedLocation {
        name: "windshield top",
        nouns: &["windshield", "windscreen"],
        front_only: false,
        zone: Zone::Top,
        studies: "Eisma et al. 2020 (windscreen); Bazilinskyy et al. 2021; Dey et al. 2020; arXiv 2604.11406; arXiv 2507.08973 v4",
    },
    PublishedLocation {
        name: "grille",
        nouns: &["grill", "grille"],
        front_only: false,
        zone: Zone::Whole,
        studies: "Eisma et al. 2020; Dey et al. 2020; arXiv 2604.11406",
    },
    PublishedLocation {
        name: "bumper",
        nouns: &["bumper"],
        front_only: true,
        zone: Zone::Whole,
        studies: "Bazilinskyy et al. 2021; Dey et al. 2020; arXiv 2604.11406; arXiv 2507.08973",
    },
    PublishedLocation {
        name: "above the front wheels (front fenders)",
        nouns: &["fender", "fenders", "wing"],
        front_only: true,
        zone: Zone::Whole,
        studies: "Eisma et al. 2020 (above the wheels); arXiv 2604.11406; arXiv 2507.08973",
    },
    PublishedLocation {
        name: "side mirrors",
        nouns: &["mirror", "mirrors"],
        front_only: false,
        zone: Zone::Whole,
        studies: "arXiv 2507.08973",
    },
    PublishedLocation {
        name: "headlights",
        nouns: &["headlight", "headlights", "headlamp", "headlamps"],
        front_only: true,
        zone: Zone::Whole,
        studies: "arXiv 2507.08973",
    },
    PublishedLocation {
        name: "front wheels",
        nouns: &["wheel", "wheels", "tyre", "tyres", "tire", "tires", "rim", "rims"],
        front_only: true,
        zone: Zone::Whole,
        studies: "arXiv 2507.08973 v4",
    },
    PublishedLocation {
        name: "hood",
        nouns: &["hood", "bonnet"],
        front_only: false,
        zone: Zone::Whole,
        studies: "arXiv 2604.11406",
    },
];

const REAR_WORDS: [&str; 2] = ["rear", "back"];

impl PublishedLocation {
    /// Whether the part of candidate `name` (a part, or a patch named
    /// `PART@…`) is this place, whatever its height.
    pub fn names_part(&self, name: &str) -> bool {
        let noun = head_noun(name);
        if !self.nouns.contains(&noun.as_str()) {
            return false;
        }
        let rear = || {
            part_of(name).split(['_', '-', '.', ' ']).any(|w| REAR_WORDS.contains(&w.to_lowercase().as_str()))
        };
        !(self.front_only && rear())
    }

    /// The indices of `candidates` (name, kind, patch centre) that are this
    /// place: every part it names, and its patches (for [`Zone::Top`] those
    /// in the upper third of the heights the place's patches span; a patch
    /// without a known centre is left out there).
    pub fn members(&self, candidates: &[(&str, CandidateKind, Option<[f64; 3]>)]) -> Vec<usize> {
        let named: Vec<usize> = (0..candidates.len()).filter(|&i| self.names_part(candidates[i].0)).collect();
        if self.zone == Zone::Whole {
            return named;
        }
        let heights: Vec<f64> = named
            .iter()
            .filter(|&&i| candidates[i].1 == CandidateKind::Patch)
            .filter_map(|&i| candidates[i].2.map(|c| c[2]))
            .collect();
        let top = heights.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let bottom = heights.iter().copied().fold(f64::INFINITY, f64::min);
        let line = top - (top - bottom) / 3.0 - 1e-9;
        named
            .into_iter()
            .filter(|&i| match candidates[i] {
                (_, CandidateKind::Part, _) => true,
                (_, CandidateKind::Patch, centre) => centre.is_some_and(|c| c[2] >= line),
            })
            .collect()
    }
}

/// The best candidate of one kind at a place, as the answer scored it.
#[derive(Debug, Clone, PartialEq)]
pub struct PlaceScore {
    pub candidate: String,
    /// Mean legible seconds over the archives.
    pub legible_s: f64,
    /// The 95 % Student-t interval of that mean over the archives (none with one archive).
    pub interval_s: Option<[f64; 2]>,
    /// Mean seconds visible at all (the exposure).
    pub visible_s: f64,
    /// The texel sample's bracket of `legible_s`, when every archive has one.
    pub texel_sample_interval_s: Option<[f64; 2]>,
    pub mountable: bool,
    /// 1 + the candidates of this kind with more legible seconds: tied candidates share a rank.
    pub rank: usize,
    /// The other candidates of this kind with exactly its legible seconds (a tie is reported as one).
    pub tied_with: usize,
    /// Candidates of this kind.
    pub of: usize,
}

impl PlaceScore {
    /// "4", or "4-48 (a tie of 45)" when other candidates have exactly its legible seconds.
    pub fn rank_text(&self) -> String {
        match self.tied_with {
            0 => self.rank.to_string(),
            n => format!("{}-{} (a tie of {})", self.rank, self.rank + n, n + 1),
        }
    }
}

/// One place on one vehicle: how many candidates are it, and the best part and patch.
#[derive(Debug, Clone)]
pub struct LocationScore {
    pub location: PublishedLocation,
    pub parts: usize,
    pub patches: usize,
    pub best_part: Option<PlaceScore>,
    pub best_patch: Option<PlaceScore>,
}

fn centre_of(placement: &Placement, c: &CandidateRecord) -> Option<[f64; 3]> {
    placement.footprints.get(&c.name).map(|f| f.centre).or_else(|| centre_in_name(&c.name))
}

fn score(candidates: &[CandidateRecord], best: &CandidateRecord) -> PlaceScore {
    let of_kind = candidates.iter().filter(|c| c.kind == best.kind);
    let per_archive: Vec<f64> = best.per_archive.iter().map(|e| e.legible_s).collect();
    PlaceScore {
        candidate: best.name.clone(),
        legible_s: best.legible_s,
        interval_s: t_interval(&per_archive),
        visible_s: best.visible_s,
        texel_sample_interval_s: best.texel_sample_interval_s,
        mountable: best.mountable,
        rank: 1 + of_kind.clone().filter(|c| c.legible_s > best.legible_s).count(),
        tied_with: of_kind.clone().filter(|c| c.legible_s == best.legible_s && c.name != best.name).count(),
        of: of_kind.count(),
    }
}

/// Every published place scored on the answer's candidates (a place this
/// vehicle has no candidate for is listed with none).
pub fn published_locations(placement: &Placement) -> Vec<LocationScore> {
    let candidates = &placement.document.candidates;
    let keyed: Vec<(&str, CandidateKind, Option<[f64; 3]>)> =
        candidates.iter().map(|c| (c.name.as_str(), c.kind, centre_of(placement, c))).collect();
    PUBLISHED_LOCATIONS
        .iter()
        .map(|location| {
            let members = location.members(&keyed);
            let best = |kind: CandidateKind| {
                members
                    .iter()
                    .map(|&i| &candidates[i])
                    .filter(|c| c.kind == kind)
                    .max_by(|a, b| a.legible_s.total_cmp(&b.legible_s).then_with(|| b.name.cmp(&a.name)))
                    .map(|c| score(candidates, c))
            };
            let count = |kind: CandidateKind| members.iter().filter(|&&i| candidates[i].kind == kind).count();
            LocationScore {
                location: *location,
                parts: count(CandidateKind::Part),
                patches: count(CandidateKind::Patch),
                best_part: best(CandidateKind::Part),
                best_patch: best(CandidateKind::Patch),
            }
        })
        .collect()
}

fn interval_text(interval: Option<[f64; 2]>) -> String {
    interval.map_or("no interval (one archive)".into(), |[lo, hi]| format!("95 % {lo:.2}-{hi:.2}"))
}

/// The console section "published locations".
pub fn format_published_locations(scores: &[LocationScore], archives: usize) -> String {
    let mut out = format!(
        "\npublished locations (places eHMI studies tested, as candidates of this vehicle; legible s with the 95 % \
         t interval over {archives} archive(s), visible s, rank among candidates of the kind; docs/literature.md):\n"
    );
    for s in scores {
        out += &format!("  {} ({})\n", s.location.name, s.location.studies);
        for (kind, best, n) in [("part", &s.best_part, s.parts), ("patch", &s.best_patch, s.patches)] {
            match best {
                None => out += &format!("    {kind:<5} none on this vehicle\n"),
                Some(p) => {
                    let mountable = if p.mountable { "" } else { " (not mountable)" };
                    out += &format!(
                        "    {kind:<5} {:<46} legible {:.3} s ({})  visible {:.3} s  rank {} of {}  best of {n}{mountable}\n",
                        p.candidate,
                        p.legible_s,
                        interval_text(p.interval_s),
                        p.visible_s,
                        p.rank_text(),
                        p.of
                    )
                }
            }
        }
    }
    out
}

fn optional(value: Option<f64>) -> String {
    value.map(|v| v.to_string()).unwrap_or_default()
}

/// Writes [`PUBLISHED_LOCATIONS_FILE`] into `out` (one row per place and
/// kind) and returns its path; refuses to replace one of `inputs`.
pub fn write_published_locations(
    scores: &[LocationScore],
    out: &Path,
    inputs: &[PathBuf],
) -> Result<PathBuf> {
    let path = out.join(PUBLISHED_LOCATIONS_FILE);
    crate::files::refuse_overwriting_inputs(std::slice::from_ref(&path), inputs)?;
    write_atomically(&path, |w| {
        writeln!(
            w,
            "location,studies,kind,candidates,best,legible_s,ci95_low_s,ci95_high_s,visible_s,\
             texel_sample_low_s,texel_sample_high_s,mountable,rank,of,tied_with"
        )?;
        for s in scores {
            for (kind, best, n) in [("part", &s.best_part, s.parts), ("patch", &s.best_patch, s.patches)] {
                let field = crate::output::csv_field;
                let (name, cells) = match best {
                    None => (String::new(), ",,,,,,,,,".to_string()),
                    Some(p) => (
                        field(&p.candidate),
                        format!(
                            "{},{},{},{},{},{},{},{},{},{}",
                            p.legible_s,
                            optional(p.interval_s.map(|i| i[0])),
                            optional(p.interval_s.map(|i| i[1])),
                            p.visible_s,
                            optional(p.texel_sample_interval_s.map(|i| i[0])),
                            optional(p.texel_sample_interval_s.map(|i| i[1])),
                            p.mountable,
                            p.rank,
                            p.of,
                            p.tied_with
                        ),
                    ),
                };
                writeln!(
                    w,
                    "{},{},{kind},{n},{name},{cells}",
                    field(s.location.name),
                    field(s.location.studies)
                )?;
            }
        }
        Ok(())
    })?;
    Ok(path)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn place(name: &str) -> &'static PublishedLocation {
        PUBLISHED_LOCATIONS.iter().find(|l| l.name == name).unwrap()
    }

    #[test]
    fn the_published_places_name_the_parts_of_the_truck_the_family_and_the_unity_f150() {
        let cases = [
            ("roof", "roof", true),
            ("grille", "grill", true),
            ("grille", "Grill", true),
            ("bumper", "front_bumper", true),
            ("bumper", "Bumper", true),
            ("bumper", "Bumper_Rear", false),
            ("bumper", "rear_bumper", false),
            ("above the front wheels (front fenders)", "front_fender_left", true),
            ("above the front wheels (front fenders)", "Fender_Front_Right", true),
            ("above the front wheels (front fenders)", "rear_fender_left", false),
            ("above the front wheels (front fenders)", "Low_Fender_Rear_Left", false),
            ("side mirrors", "side_mirror_left", true),
            ("headlights", "headlight_right", true),
            ("front wheels", "tyre_front_left", true),
            ("front wheels", "Rim_Front_Right", true),
            ("front wheels", "tyre_rear_left", false),
            ("front wheels", "wheel_arch_front_left", false),
            ("hood", "hood@0.40x0.15@x2.10y0.00z1.20", true),
            ("windshield top", "windshield", true),
            ("windshield top", "windshield_rail_left", false),
        ];
        for (location, part, expected) in cases {
            assert_eq!(place(location).names_part(part), expected, "{location}: {part}");
        }
    }

    #[test]
    fn the_windshield_top_keeps_the_upper_third_of_its_patches_and_the_part() {
        let patch = CandidateKind::Patch;
        let candidates = [
            ("windshield", CandidateKind::Part, None),
            ("windshield@0.40x0.15@x1.5y0z1.2", patch, Some([1.5, 0.0, 1.2])),
            ("windshield@0.40x0.15@x1.4y0z1.35", patch, Some([1.4, 0.0, 1.35])),
            ("windshield@0.40x0.15@x1.3y0z1.5", patch, Some([1.3, 0.0, 1.5])),
            ("windshield@0.40x0.15@x1.3y0.5z1.5", patch, Some([1.3, 0.5, 1.5])),
            ("hood@0.40x0.15@x2y0z1.2", patch, Some([2.0, 0.0, 1.2])),
        ];
        assert_eq!(place("windshield top").members(&candidates), vec![0, 3, 4]);
        assert_eq!(place("hood").members(&candidates), vec![5]);
    }
}
