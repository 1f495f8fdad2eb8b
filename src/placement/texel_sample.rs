//! How far one archive's legible seconds may be from those of every texel,
//! when the exact measure ray traced only a sample of the texels
//! (`ufcsr capture … --measure unobstructed --sample 1/N --placement`).
//!
//! The multi-archive interval ([`crate::placement::uncertainty`]) covers
//! what varies *between* archives (observers, scenarios, seeds given as
//! archives); the texel sample of *one* archive is fixed in all its frames,
//! so its error is one shared draw that no spread over frames shows. This
//! module brackets it per candidate, from the sample's size alone:
//!
//! * **Visible fraction.** A candidate's `visible_fraction` is a ratio over
//!   its n sampled texels, drawn with probability f from its texels, so its
//!   standard error is √((1 − f) · p̃(1 − p̃) / (n + 4)) (binomial with the
//!   finite-population factor; p̃ = (n·p + 2)/(n + 4), Agresti–Coull, so a
//!   fraction of 0 or 1 still has an error). n is the part's sampled
//!   texels (`unobstructed-parts.csv` beside the table); for a display patch
//!   the part's sampled texels times the patch's share of the part's area
//!   (`part_area_m2` in the archive's `manifest.json`).
//! * **Angular height.** The visible samples' vertical extent can only be
//!   smaller than every texel's (a subset's range), so the measured height
//!   is a lower bound; the upper end divides it by r, the share of the
//!   whole that the range of m uniform points reaches with 97.5 %
//!   (P(R < r) = m·r^(m−1) − (m−1)·r^m = 0.025; m = n·p visible sampled
//!   texels; below 2 the height is left unbounded). A display patch's
//!   height is measured from its exact outline (the capture projects the
//!   W × H rectangle's edges, issue 42 §4), not from its samples, so it has
//!   no sampling error and is not widened: the bracket is around the exact
//!   value.
//!
//! The candidate's timeline is scored again twice under the same rule and
//! dwell: once with every sighting's visible fraction z = 1.96 standard
//! errors lower and its measured height (the low end), once z higher with
//! the widened height (the high end). Legibility only grows with either
//! number and the dwell only keeps more frames when more are legible, so
//! low ≤ the point ≤ high. The frames share one texel sample, so their
//! errors move together: the bracket treats them as one shift (a frame near
//! the threshold flips with the others), not as independent frames whose
//! errors would average out. Last, each legible run of the high end is
//! grown by one frame at each end and each of the low end shrunk by one:
//! the frame at which a threshold is crossed is known only to a frame (the
//! view angle, a mean over the visible samples, and the crossing itself
//! move with the sample). This allowance is *calibrated*, not derived:
//! without it the coverage test below measured 86.8 %, its misses one frame
//! at the end of a run. What it leaves out: the view angle's sampling
//! error (a mean over the visible samples), and under the solid-angle rule
//! (`--min-solid-angle-sr`) every geometric number: there no bracket is
//! given. With every texel (f = 1) the bracket is the point.
//! `tests/it/texel_sample.rs` (capture) measures its coverage against the
//! answer at f = 1.

use std::collections::BTreeMap;
use std::path::Path;
use std::sync::Arc;

use crate::error::{Error, Result};
use crate::files::{SMALL_INPUT_LIMIT, read_limited};
use crate::format::manifest::{MANIFEST_FILE, Manifest};
use crate::placement::footprints::part_of;
use crate::placement::legibility::{Thresholds, timelines_with};
use crate::placement::table::{CandidateKind, CandidateRows, PlacementTable};

/// The exact measure's per-part estimates, beside `placement-frames.csv`.
pub(crate) const UNOBSTRUCTED_PARTS_FILE: &str = "unobstructed-parts.csv";

/// Standard errors either side of the visible fraction (95 %, two-sided).
pub(crate) const TEXEL_SAMPLE_Z: f64 = 1.96;

/// One part's texel sample.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct PartSample {
    /// Texels with a footprint on the mesh.
    pub texels: u64,
    /// Of which ray traced.
    pub sampled: u64,
    /// The part's surface, m² (from the manifest; `None` without one).
    pub area_m2: Option<f64>,
}

/// Per part, what one archive's exact measure sampled.
pub(crate) type SampleCounts = BTreeMap<String, PartSample>;

/// The texel sample behind the table at `table`: `unobstructed-parts.csv`
/// beside it, and the part areas of `manifest.json` in the archive (the
/// folder above `results/`). `None` when there is no such file (a table
/// from elsewhere, or a rendered one).
pub(crate) fn read_sample_counts(table: &Path) -> Result<Option<SampleCounts>> {
    let path = table.with_file_name(UNOBSTRUCTED_PARTS_FILE);
    if !path.is_file() {
        return Ok(None);
    }
    let bytes = read_limited(&path, SMALL_INPUT_LIMIT)?;
    let mut reader = csv::ReaderBuilder::new().has_headers(true).from_reader(&bytes[..]);
    let header = reader.headers().map_err(|e| Error::bad_file(&path, format!("header: {e}")))?.clone();
    let column = |name: &str| {
        header
            .iter()
            .position(|h| h.trim() == name)
            .ok_or_else(|| Error::bad_file(&path, format!("no column {name:?}")))
    };
    let [part, texels, sampled] = [column("part")?, column("texels")?, column("sampled")?];
    let areas = part_areas(table)?;
    let mut counts = SampleCounts::new();
    for (index, record) in reader.records().enumerate() {
        let line = index + 2;
        let record = record.map_err(|e| Error::bad_file(&path, format!("line {line}: {e}")))?;
        let number = |at: usize| -> Result<u64> {
            let text = record.get(at).unwrap_or("").trim();
            text.parse().map_err(|_| Error::bad_file(&path, format!("line {line}: {text:?} is not a count")))
        };
        let name = record.get(part).unwrap_or("").trim().to_string();
        let sample = PartSample { texels: number(texels)?, sampled: number(sampled)?, area_m2: None };
        if sample.sampled > sample.texels {
            return Err(Error::bad_file(
                &path,
                format!("line {line}: more texels sampled than the part has"),
            ));
        }
        let area_m2 = areas.get(&name).copied().filter(|a| a.is_finite() && *a > 0.0);
        counts.insert(name, PartSample { area_m2, ..sample });
    }
    Ok(Some(counts))
}

/// The part areas the archive's manifest records (empty without one).
fn part_areas(table: &Path) -> Result<BTreeMap<String, f64>> {
    let Some(archive) = table.parent().and_then(Path::parent) else {
        return Ok(BTreeMap::new());
    };
    let path = archive.join(MANIFEST_FILE);
    if !path.is_file() {
        return Ok(BTreeMap::new());
    }
    let manifest = Manifest::parse(&path, &read_limited(&path, SMALL_INPUT_LIMIT)?)?;
    Ok(manifest.unwrap.map(|u| u.part_area_m2).unwrap_or_default())
}

/// A candidate's sampled texels n and sampling fraction f; `None` when the
/// counts do not say (an unknown part, a patch without the part's area).
fn candidate_sample(candidate: &CandidateRows, counts: &SampleCounts) -> Option<(f64, f64)> {
    let part = counts.get(part_of(&candidate.name))?;
    if part.texels == 0 || part.sampled == 0 {
        return None;
    }
    let fraction = part.sampled as f64 / part.texels as f64;
    let n = match (candidate.kind, candidate.size_m) {
        (CandidateKind::Part, _) => part.sampled as f64,
        (CandidateKind::Patch, Some([w, h])) => part.sampled as f64 * (w * h / part.area_m2?).min(1.0),
        (CandidateKind::Patch, None) => return None,
    };
    Some((n.max(1.0), fraction))
}

/// The standard error of a visible fraction `p` over `n` texels sampled
/// with probability `fraction`.
pub(crate) fn visible_fraction_se(p: f64, n: f64, fraction: f64) -> f64 {
    let shrunk = (n * p + 2.0) / (n + 4.0);
    ((1.0 - fraction).max(0.0) * shrunk * (1.0 - shrunk) / (n + 4.0)).sqrt()
}

/// The share r of the whole that the range of `m` uniform points reaches
/// with probability 1 − `alpha`: P(range < r) = m·r^(m−1) − (m−1)·r^m =
/// `alpha` (bisection; 0 below two points: the extent is then unbounded).
pub(crate) fn range_share_bound(m: f64, alpha: f64) -> f64 {
    if m < 2.0 {
        return 0.0;
    }
    let below = |r: f64| m * r.powf(m - 1.0) - (m - 1.0) * r.powf(m);
    let (mut lo, mut hi) = (0.0, 1.0);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if below(mid) < alpha { lo = mid } else { hi = mid }
    }
    0.5 * (lo + hi)
}

/// `table` with every sighting moved to one end of its bracket (`high`:
/// up); candidates the counts do not cover are dropped.
fn moved(table: &PlacementTable, counts: &SampleCounts, high: bool) -> PlacementTable {
    let mut out = table.clone();
    out.candidates.retain(|_, candidate| candidate_sample(candidate, counts).is_some());
    for candidate in out.candidates.values_mut() {
        let Some((n, fraction)) = candidate_sample(candidate, counts) else { continue };
        for sighting in candidate.sightings.values_mut() {
            let p = sighting.visible_fraction;
            let shift = TEXEL_SAMPLE_Z * visible_fraction_se(p, n, fraction);
            if high {
                sighting.visible_fraction = (p + shift).min(1.0);
                if fraction < 1.0 && candidate.kind == CandidateKind::Part {
                    sighting.angular_height_deg /= range_share_bound(n * p, 0.025);
                }
            } else {
                sighting.visible_fraction = (p - shift).max(0.0);
            }
        }
    }
    out
}

/// The frames of `legible` (ascending indices below `frames`) with every run
/// of consecutive frames grown by one frame at each end (`grow`), or shrunk
/// by one at each end: the crossing frame of a threshold is known to a frame.
pub(crate) fn run_edges(legible: &[usize], frames: usize, grow: bool) -> usize {
    let mut on = vec![false; frames];
    for &f in legible.iter().filter(|&&f| f < frames) {
        on[f] = true;
    }
    let edge = |f: usize| {
        let before = f > 0 && on[f - 1];
        let after = f + 1 < frames && on[f + 1];
        (before, after)
    };
    (0..frames)
        .filter(|&f| {
            let (before, after) = edge(f);
            if grow { on[f] || before || after } else { on[f] && before && after }
        })
        .count()
}

/// Per candidate of `table`, the `[low, high]` legible seconds its texel
/// sample allows (see the module documentation); empty under the
/// solid-angle rule or for a rendered table.
pub(crate) fn legible_brackets(
    table: &PlacementTable,
    counts: &SampleCounts,
    thresholds: &Thresholds,
    unfit: &std::collections::BTreeSet<String>,
) -> BTreeMap<String, [f64; 2]> {
    if table.rendered || thresholds.min_solid_angle_sr.is_some() {
        return BTreeMap::new();
    }
    let frames = table.frames.len();
    // With every texel of its part the bracket is the point.
    let sampled = |name: &str| {
        table.candidates.get(name).and_then(|c| candidate_sample(c, counts)).is_some_and(|(_, f)| f < 1.0)
    };
    let seconds = |high: bool| -> BTreeMap<String, f64> {
        let scored = timelines_with(Arc::new(moved(table, counts, high)), thresholds, unfit);
        scored
            .timelines
            .iter()
            .map(|t| {
                let legible =
                    if sampled(&t.name) { run_edges(&t.legible, frames, high) } else { t.legible.len() };
                (t.name.clone(), legible as f64 * table.frame_s)
            })
            .collect()
    };
    let (low, high) = (seconds(false), seconds(true));
    low.into_iter().filter_map(|(name, lo)| Some((name.clone(), [lo, *high.get(&name)?]))).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_texel_has_no_visible_fraction_error_and_a_smaller_sample_more() {
        assert_eq!(visible_fraction_se(0.8, 400.0, 1.0), 0.0);
        let quarter = visible_fraction_se(0.8, 100.0, 0.25);
        let sixteenth = visible_fraction_se(0.8, 25.0, 1.0 / 16.0);
        assert!(quarter > 0.0 && sixteenth > 2.0 * quarter, "{quarter} {sixteenth}");
        // All visible in the sample is not certainty.
        assert!(visible_fraction_se(1.0, 25.0, 1.0 / 16.0) > 0.02);
    }

    #[test]
    fn runs_grow_and_shrink_by_one_frame_at_each_end() {
        // Runs 0–2, 5, 8–9 of 10 frames.
        let legible = [0, 1, 2, 5, 8, 9];
        // Grown: 0–3, 4–6, 7–9 (the edges of the table bound it).
        assert_eq!(run_edges(&legible, 10, true), 10);
        // Shrunk: 1 only (the lone frame and the two-frame run vanish; the table's
        // edge counts as an end).
        assert_eq!(run_edges(&legible, 10, false), 1);
        assert_eq!(run_edges(&[], 10, true), 0);
    }

    #[test]
    fn the_range_of_m_uniform_points_reaches_the_bound_in_97_5_percent() {
        // Two points: P(R < r) = 2r − r², so r = 1 − √0.975.
        assert!((range_share_bound(2.0, 0.025) - (1.0 - 0.975f64.sqrt())).abs() < 1e-9);
        // More points reach further; one point says nothing.
        assert!(range_share_bound(50.0, 0.025) > range_share_bound(10.0, 0.025));
        assert!((0.85..0.9).contains(&range_share_bound(50.0, 0.025)));
        assert_eq!(range_share_bound(1.0, 0.025), 0.0);
    }
}
