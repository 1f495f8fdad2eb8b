//! Which candidates may be an answer, in one place (issue 42 §1–§2): every
//! command that ranks placements (`ufcsr-analyze placement`, the observer
//! study's displays, `ufcsr design run|merge` and the pages that show them)
//! asks this module, so no command can answer with a surface another
//! command refuses.
//!
//! * **A display must fit where it is said to be legible.** When a table
//!   measured display patches (the capture's `--display WxH`), a whole part
//!   is legible only through the patches that fit on it: its legible frames
//!   are those of its most legible fitting patch in that archive
//!   ([`fit_parts`], applied inside [`crate::placement::timelines`]), and a
//!   part on which no W × H patch fits (or none is ever seen) keeps its
//!   visible seconds but has no legible time: *exposure only*, "no display
//!   fits", never a candidate of an answer. A table without patches (no
//!   display size measured) scores whole parts as surfaces, without a fit
//!   check, and says so ([`Fit::Whole`]).
//! * **Mountable**: [`crate::placement::regions::mountable`] over
//!   [`crate::placement::DEFAULT_NOT_MOUNTABLE`] (placement's
//!   `--not-mountable` replaces the list; the design and the observers use
//!   the default).
//!
//! [`exclusions`] lists every candidate left out and why; each output
//! carries that list (`excluded` in placement.json and design.json, a line
//! on the console and on the pages).

use std::collections::{BTreeMap, BTreeSet};

pub(crate) use crate::format::placement::{ExcludedRecord, ExclusionReason};
use crate::placement::footprints::{PatchFootprint, part_of};
use crate::placement::regions::{head_noun, mountable};
use crate::placement::table::CandidateKind;

/// How a candidate's legible time is scored.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub enum Fit {
    /// A display patch, or a part of a table without patches (no display
    /// size known): scored on its own surface.
    #[default]
    Whole,
    /// A part scored through its most legible fitting display patch (named).
    Through(String),
    /// A part on which no display patch of the table fits or is seen:
    /// exposure only.
    NoDisplayFits,
}

/// One candidate as [`fit_parts`] sees it: name, kind, legible frames.
pub(crate) trait FitCandidate {
    fn name(&self) -> &str;
    fn kind(&self) -> CandidateKind;
    fn legible_frames(&mut self) -> &mut Vec<usize>;
    fn set_fit(&mut self, fit: Fit);
}

/// Applies the fit rule to one archive's candidates (see the module
/// documentation): with any display patch in the archive, each part's
/// legible frames become its most legible patch's (ties: the first name),
/// and a part without a patch has none. Patches in `unfit`
/// ([`unfit_patches`]) do not stand for their part.
pub(crate) fn fit_parts<T: FitCandidate>(candidates: &mut [T], unfit: &BTreeSet<String>) {
    if !candidates.iter().any(|c| c.kind() == CandidateKind::Patch) {
        return;
    }
    let mut best: BTreeMap<String, (String, Vec<usize>)> = BTreeMap::new();
    for c in candidates.iter_mut().filter(|c| c.kind() == CandidateKind::Patch && !unfit.contains(c.name())) {
        let (part, name) = (part_of(c.name()).to_string(), c.name().to_string());
        let frames = c.legible_frames().clone();
        let better = best.get(&part).is_none_or(|(_, held)| frames.len() > held.len());
        if better {
            best.insert(part, (name, frames));
        }
    }
    for c in candidates.iter_mut().filter(|c| c.kind() == CandidateKind::Part) {
        match best.get(c.name()) {
            Some((patch, frames)) => {
                *c.legible_frames() = frames.clone();
                c.set_fit(Fit::Through(patch.clone()));
            }
            None => {
                c.legible_frames().clear();
                c.set_fit(Fit::NoDisplayFits);
            }
        }
    }
}

/// Why `name` may not be an answer, if it may not: not mountable under
/// `not_mountable` (its own part, or a part its display `covers`), or (a
/// part, when `patch_parts` is `Some`: the parts holding a display patch)
/// no display fits on it.
pub(crate) fn exclusion(
    name: &str,
    kind: CandidateKind,
    covers: &[String],
    not_mountable: &[String],
    patch_parts: Option<&BTreeSet<&str>>,
) -> Option<ExcludedRecord> {
    let record = |reason: ExclusionReason, detail: String| ExcludedRecord {
        candidate: name.to_string(),
        kind,
        reason,
        detail,
    };
    if !mountable(name, not_mountable) {
        let noun = head_noun(name);
        return Some(record(
            ExclusionReason::NotMountable,
            format!(
                "not mountable: its surface '{noun}' is in the not-mountable list (wheels turn, glass stays clear)"
            ),
        ));
    }
    if let Some(part) = covers.iter().find(|part| !mountable(part, not_mountable)) {
        let noun = head_noun(part);
        return Some(record(
            ExclusionReason::NotMountable,
            format!(
                "not mountable: the display covers part '{part}', whose surface '{noun}' is in the not-mountable \
                 list (wheels turn, glass stays clear)"
            ),
        ));
    }
    if kind == CandidateKind::Part && patch_parts.is_some_and(|parts| !parts.contains(part_of(name))) {
        return Some(record(
            ExclusionReason::NoDisplayFits,
            "no display fits: no display patch of the measured size fits on this part (or none is ever seen); \
             exposure only"
                .into(),
        ));
    }
    None
}

/// The display patches of `candidates` (name, kind) that may not stand for
/// their part: the part is mountable under `not_mountable` but the display
/// covers a part that is not (`footprints`' `covers`), so a bumper is not
/// legible through a bumper display over a listed grill. Empty under the
/// default list, where a patch covers surface of its own part's kind only.
pub(crate) fn unfit_patches<'a>(
    candidates: impl Iterator<Item = (&'a str, CandidateKind)>,
    footprints: &BTreeMap<String, PatchFootprint>,
    not_mountable: &[String],
) -> BTreeSet<String> {
    candidates
        .filter(|&(name, kind)| kind == CandidateKind::Patch && mountable(part_of(name), not_mountable))
        .filter(|&(name, _)| {
            footprints.get(name).is_some_and(|f| f.covers.iter().any(|part| !mountable(part, not_mountable)))
        })
        .map(|(name, _)| name.to_string())
        .collect()
}

/// Every candidate of `candidates` (name, kind) left out of the answers, and
/// why, in name order. A patch whose footprint names the parts it covers
/// (`footprints`, from `placement-patches.csv`) is mountable only if each
/// of them is, and stands for no part otherwise ([`unfit_patches`]). Parts
/// are fit-checked only when some candidate is a display patch.
pub fn exclusions<'a>(
    candidates: impl Iterator<Item = (&'a str, CandidateKind)> + Clone,
    footprints: &BTreeMap<String, PatchFootprint>,
    not_mountable: &[String],
) -> Vec<ExcludedRecord> {
    let unfit = unfit_patches(candidates.clone(), footprints, not_mountable);
    let patches = candidates.clone().filter(|(_, k)| *k == CandidateKind::Patch);
    let any_patch = patches.clone().next().is_some();
    let patch_parts: BTreeSet<&str> =
        patches.filter(|(n, _)| !unfit.contains(*n)).map(|(n, _)| part_of(n)).collect();
    let fit_checked = any_patch.then_some(&patch_parts);
    let covers = |name: &str| footprints.get(name).map_or(&[][..], |f| &f.covers[..]);
    let mut out: Vec<ExcludedRecord> = candidates
        .filter_map(|(name, kind)| exclusion(name, kind, covers(name), not_mountable, fit_checked))
        .collect();
    out.sort_by(|a, b| a.candidate.cmp(&b.candidate));
    out.dedup_by(|a, b| a.candidate == b.candidate);
    out
}

/// The candidates of `excluded` left out as not mountable: the one judgement
/// ([`exclusions`], the parts a display covers included) that every record
/// and line about mountability reads.
pub(crate) fn not_mountable(excluded: &[ExcludedRecord]) -> BTreeSet<&str> {
    excluded
        .iter()
        .filter(|e| e.reason == ExclusionReason::NotMountable)
        .map(|e| e.candidate.as_str())
        .collect()
}

/// [`exclusions`] under the default not-mountable list, for candidates whose kind is written
/// `part`/`patch` (the design's task files and the observer study carry it so). Their
/// patches' covered parts are not needed: under the default list a patch covers only
/// surface of its own part's kind (the capture's layout).
pub fn default_exclusions<'a>(candidates: impl Iterator<Item = (&'a str, &'a str)>) -> Vec<ExcludedRecord> {
    let kind = |k: &str| if k == "patch" { CandidateKind::Patch } else { CandidateKind::Part };
    let listed: Vec<(&str, CandidateKind)> = candidates.map(|(name, k)| (name, kind(k))).collect();
    exclusions(listed.iter().copied(), &BTreeMap::new(), &default_not_mountable())
}

/// The default not-mountable list as owned strings (the design's and the observers' rule).
pub fn default_not_mountable() -> Vec<String> {
    crate::placement::DEFAULT_NOT_MOUNTABLE.iter().map(|s| s.to_string()).collect()
}

pub use crate::format::placement::excluded_line;

#[cfg(test)]
mod tests {
    use super::*;

    struct C(&'static str, CandidateKind, Vec<usize>, Fit);

    impl FitCandidate for C {
        fn name(&self) -> &str {
            self.0
        }
        fn kind(&self) -> CandidateKind {
            self.1
        }
        fn legible_frames(&mut self) -> &mut Vec<usize> {
            &mut self.2
        }
        fn set_fit(&mut self, fit: Fit) {
            self.3 = fit;
        }
    }

    #[test]
    fn a_part_narrower_than_the_display_has_no_legible_time_and_a_wider_one_its_best_patchs() {
        use CandidateKind::{Part, Patch};
        // The rail is legible as a whole surface in 30 frames but holds no patch;
        // the bumper holds two patches, legible 10 and 20 frames.
        let mut candidates = vec![
            C("windshield_rail_left", Part, (0..30).collect(), Fit::Whole),
            C("front_bumper", Part, (0..5).collect(), Fit::Whole),
            C("front_bumper@0.40x0.15@x2.9y0.5z0.4", Patch, (0..10).collect(), Fit::Whole),
            C("front_bumper@0.40x0.15@x2.9y0.0z0.4", Patch, (5..25).collect(), Fit::Whole),
        ];
        fit_parts(&mut candidates, &BTreeSet::new());
        assert!(candidates[0].2.is_empty());
        assert_eq!(candidates[0].3, Fit::NoDisplayFits);
        assert_eq!(candidates[1].2, (5..25).collect::<Vec<_>>());
        assert_eq!(candidates[1].3, Fit::Through("front_bumper@0.40x0.15@x2.9y0.0z0.4".into()));
        // Without patches (no display measured) parts stay whole surfaces.
        let mut parts = vec![C("windshield_rail_left", Part, (0..30).collect(), Fit::Whole)];
        fit_parts(&mut parts, &BTreeSet::new());
        assert_eq!((parts[0].2.len(), &parts[0].3), (30, &Fit::Whole));
    }

    #[test]
    fn exclusions_name_glass_wheels_and_parts_no_display_fits_with_the_reason() {
        use CandidateKind::{Part, Patch};
        let names = [
            ("windshield", Part),
            ("tyre_front_left", Part),
            ("windshield_rail_left", Part),
            ("front_bumper", Part),
            ("front_bumper@0.40x0.15@x2.9y0.0z0.4", Patch),
            ("windshield@0.40x0.15@x1.4y0.0z1.5", Patch),
        ];
        let out = exclusions(names.iter().copied(), &BTreeMap::new(), &default_not_mountable());
        let got: Vec<(&str, ExclusionReason)> =
            out.iter().map(|e| (e.candidate.as_str(), e.reason)).collect();
        assert_eq!(
            got,
            vec![
                ("tyre_front_left", ExclusionReason::NotMountable),
                ("windshield", ExclusionReason::NotMountable),
                ("windshield@0.40x0.15@x1.4y0.0z1.5", ExclusionReason::NotMountable),
                ("windshield_rail_left", ExclusionReason::NoDisplayFits),
            ]
        );
        let line = excluded_line(&out);
        assert!(
            line.contains("not mountable")
                && line.contains("no display fits (exposure only): windshield_rail_left"),
            "{line}"
        );
        // Without patches no part is fit-checked.
        let parts_only = exclusions(names[..4].iter().copied(), &BTreeMap::new(), &default_not_mountable());
        assert_eq!(parts_only.len(), 2);
    }
}
