//! What the search chooses among: every candidate of one kind seen in any
//! archive, or with `--symmetric` every left/right pair as one choice (a
//! display on the left fender comes with one on the right).
//!
//! A candidate's mirror is the table's `mirror` column when the capture
//! wrote one (patches: the patch nearest the centre mirrored in the
//! vehicle's centre plane), else its name with the words `left` and `right`
//! swapped (`front_fender_left` ↔ `front_fender_right`), when that names a
//! candidate. Candidates without a mirror stay single choices.
//!
//! Only the candidates [`crate::placement::regions`] lets through are
//! choices: mountable ones, one per region of near patches. A pair is the
//! region's patch and its mirror (when that is mountable); the mirror's
//! own region is then taken by the pair.

use std::collections::{BTreeMap, BTreeSet};

use crate::placement::legibility::ArchiveTimelines;
use crate::placement::search::{Choice, SparseBits, Universe};
use crate::placement::table::CandidateKind;

/// `name` with the words `left` and `right` swapped (words split by `_`,
/// `-`, space or `.`); `None` when it has neither.
pub(crate) fn mirrored_name(name: &str) -> Option<String> {
    let mut out = String::with_capacity(name.len());
    let mut swapped = false;
    let mut word = String::new();
    let mut flush = |word: &mut String, out: &mut String| {
        match word.as_str() {
            "left" => {
                out.push_str("right");
                swapped = true;
            }
            "right" => {
                out.push_str("left");
                swapped = true;
            }
            other => out.push_str(other),
        }
        word.clear();
    };
    for c in name.chars() {
        if "_- .".contains(c) {
            flush(&mut word, &mut out);
            out.push(c);
        } else {
            word.push(c);
        }
    }
    flush(&mut word, &mut out);
    swapped.then_some(out)
}

/// Every candidate name of `kind` in the archives, with its mirror.
fn names_of(archives: &[ArchiveTimelines], kind: CandidateKind) -> BTreeMap<String, Option<String>> {
    let mut names = BTreeMap::new();
    for archive in archives {
        for timeline in archive.timelines.iter().filter(|t| t.kind == kind) {
            let entry = names.entry(timeline.name.clone()).or_insert(None);
            if entry.is_none() {
                *entry = timeline.mirror.clone();
            }
        }
    }
    let known: BTreeSet<String> = names.keys().cloned().collect();
    for (name, mirror) in names.iter_mut() {
        if mirror.is_none() {
            *mirror = mirrored_name(name).filter(|m| known.contains(m));
        }
        if mirror.as_deref() == Some(name.as_str()) || mirror.as_ref().is_some_and(|m| !known.contains(m)) {
            *mirror = None;
        }
    }
    names
}

/// Whether a left/right pair is one choice (two displays).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Pairing {
    /// Every candidate is a choice of its own.
    Single,
    /// A candidate and its mirror image are chosen together (`--symmetric`).
    Symmetric,
}

/// The choices of `kind`, in name order (pairs named by their first
/// member), among the candidates `representatives` lets through (each
/// mountable candidate's region's; see the module documentation).
pub(crate) fn choices(
    archives: &[ArchiveTimelines],
    universe: &Universe,
    kind: CandidateKind,
    pairing: Pairing,
    representatives: &BTreeMap<String, String>,
) -> Vec<Choice> {
    let names = names_of(archives, kind);
    let by_name: Vec<BTreeMap<&str, &[usize]>> = archives
        .iter()
        .map(|a| a.timelines.iter().map(|t| (t.name.as_str(), t.legible.as_slice())).collect())
        .collect();
    let mut taken: BTreeSet<String> = BTreeSet::new();
    let mut out = Vec::new();
    for (name, mirror) in &names {
        if taken.contains(name) || representatives.get(name) != Some(name) {
            continue;
        }
        // Paired, a candidate whose mirror is already in another pair is that
        // pair's place again, not a single display of its own.
        if pairing == Pairing::Symmetric && mirror.as_ref().is_some_and(|m| taken.contains(m)) {
            continue;
        }
        let mut members = vec![name.clone()];
        taken.insert(name.clone());
        if pairing == Pairing::Symmetric
            && let Some(mirror) = mirror
            && let Some(region) = representatives.get(mirror)
            && !taken.contains(mirror)
        {
            members.push(mirror.clone());
            taken.insert(mirror.clone());
            taken.insert(region.clone());
        }
        let mut bits = SparseBits::default();
        for member in &members {
            let flags = by_name.iter().map(|timelines| timelines.get(member.as_str()).copied());
            bits = bits.union(&universe.sparse_bits(flags));
        }
        out.push(Choice { names: members, kind, bits });
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Arc;

    use crate::placement::legibility::{Thresholds, timelines};
    use crate::placement::table::{CandidateRows, FrameInfo, PlacementTable, Sighting};

    /// `n` parts over `n` frames, part `i` seen in frame `i` only: the
    /// table grows with `n`, the frames × parts with `n²`.
    fn diagonal_table(n: usize) -> PlacementTable {
        let sighting = Sighting {
            solid_angle_sr: 1e-3,
            visible_fraction: 1.0,
            view_angle_deg: 10.0,
            angular_height_deg: 5.0,
        };
        let candidates = (0..n)
            .map(|i| {
                let name = format!("part{i:05}");
                let rows = CandidateRows {
                    name: name.clone(),
                    kind: CandidateKind::Part,
                    mirror: None,
                    size_m: None,
                    sightings: BTreeMap::from([((i, 0), sighting)]),
                };
                (name, rows)
            })
            .collect();
        PlacementTable {
            path: "diagonal.csv".into(),
            frames: (0..n)
                .map(|i| FrameInfo { frame: i as u64, time_s: i as f64 * 0.1, distance_m: (n - i) as f64 })
                .collect(),
            eyes: vec!["left".into()],
            frame_s: 0.1,
            candidates,
            rendered: false,
        }
    }

    /// Issue 41: each choice kept a whole bitset of every frame, so a table
    /// of n parts over n frames stored n²/64 words (271 MB for a 2 MB
    /// table); now a choice stores one word per legible frame at most.
    #[test]
    fn choices_store_words_in_proportion_to_legible_frames_not_to_frames_times_choices() {
        let thresholds =
            Thresholds { min_solid_angle_sr: Some(0.0), min_dwell_s: 0.0, ..Thresholds::default() };
        for n in [64, 4096] {
            let archives = vec![timelines(Arc::new(diagonal_table(n)), &thresholds)];
            let universe = Universe::of(&archives);
            let everyone: BTreeMap<String, String> =
                archives[0].timelines.iter().map(|t| (t.name.clone(), t.name.clone())).collect();
            let found = choices(&archives, &universe, CandidateKind::Part, Pairing::Single, &everyone);
            assert_eq!(found.len(), n);
            let stored: usize = found.iter().map(|c| c.bits.stored_words()).sum();
            assert_eq!(
                stored,
                n,
                "n = {n}: one word per legible frame (a dense bitset each: {})",
                n * n / 64
            );
            // The searches of one kind share its choices, not a copy each.
            let options = crate::placement::PlacementOptions::new(Vec::new());
            let scoring = crate::placement::score_and_search(
                &[Arc::clone(&archives[0].table)],
                &thresholds,
                &options,
                &BTreeMap::new(),
                &std::collections::BTreeSet::new(),
                &[crate::placement::search::Objective::Mean],
            );
            let parts: Vec<_> = scoring.searched.iter().filter(|s| s.kind == CandidateKind::Part).collect();
            assert_eq!(parts.len(), 3);
            assert!(parts.iter().all(|s| Arc::ptr_eq(&s.choices, &parts[0].choices)));
        }
    }
}
