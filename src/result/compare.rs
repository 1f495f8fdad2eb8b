//! How far one result is from another: the errors a resolution study reports.
//!
//! Two analyses of the same vehicle (same legend) at different settings are
//! compared part by part: the L1 and largest difference of their shares in
//! percentage points, Kendall's τ-b between their part rankings (by total and
//! by average, with the tied pairs reported, since parts the pedestrian
//! never sees all tie at zero), the overlap of their top-k parts by total,
//! and the difference in coverage (texels seen at least once). Everything is
//! computed from the parts tables, so a result loaded from `result.json`
//! compares as well as one just computed.

use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::result::part_stats::PartStats;

/// The error of `candidate` against `reference`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Comparison {
    /// Σ |share difference| over parts, percentage points.
    pub share_l1_pp: f64,
    /// Largest |share difference| of one part, percentage points.
    pub share_max_pp: f64,
    /// The part with the largest share difference.
    pub share_max_part: String,
    /// Kendall's τ-b of the rankings by total.
    pub kendall_tau_total: f64,
    /// Pairs of parts tied in either ranking by total (excluded by τ-b).
    pub tied_pairs_total: u64,
    /// Kendall's τ-b of the rankings by average.
    pub kendall_tau_average: f64,
    pub tied_pairs_average: u64,
    /// Parts shared by both top-k lists by total, out of k.
    pub top_k_overlap: usize,
    pub top_k: usize,
    /// Coverage (percentage of labelled texels seen) of the candidate minus the reference.
    pub coverage_difference_pp: f64,
}

/// Compares two parts tables of the same legend (matched by part name).
pub fn compare_parts(reference: &[PartStats], candidate: &[PartStats], top_k: usize) -> Result<Comparison> {
    let mut pairs = Vec::with_capacity(reference.len());
    for part in reference {
        let other = candidate.iter().find(|p| p.name == part.name).ok_or_else(|| {
            Error::BadOptions(format!("part {:?} is missing from the compared result", part.name))
        })?;
        pairs.push((part, other));
    }
    if candidate.len() != reference.len() {
        return Err(Error::BadOptions(format!(
            "the results have {} and {} parts: compare results of the same legend",
            reference.len(),
            candidate.len()
        )));
    }
    let (mut share_l1_pp, mut share_max_pp, mut share_max_part) = (0.0f64, 0.0f64, String::new());
    for (a, b) in &pairs {
        let difference = (a.share - b.share).abs();
        share_l1_pp += difference;
        if difference > share_max_pp {
            share_max_pp = difference;
            share_max_part = a.name.clone();
        }
    }
    let totals: Vec<(f64, f64)> = pairs.iter().map(|(a, b)| (a.total as f64, b.total as f64)).collect();
    let averages: Vec<(f64, f64)> = pairs.iter().map(|(a, b)| (a.average, b.average)).collect();
    let (kendall_tau_total, tied_pairs_total) = kendall_tau_b(&totals);
    let (kendall_tau_average, tied_pairs_average) = kendall_tau_b(&averages);
    let top = |parts: &[PartStats]| {
        let mut sorted: Vec<&PartStats> = parts.iter().collect();
        sorted.sort_by(|a, b| b.total.cmp(&a.total).then_with(|| a.name.cmp(&b.name)));
        sorted.into_iter().take(top_k).map(|p| p.name.clone()).collect::<Vec<_>>()
    };
    let (top_reference, top_candidate) = (top(reference), top(candidate));
    let top_k_overlap = top_reference.iter().filter(|name| top_candidate.contains(name)).count();
    let coverage = |parts: &[PartStats]| {
        let texels: u64 = parts.iter().map(|p| p.texels).sum();
        let seen: u64 = parts.iter().map(|p| p.texels_seen).sum();
        if texels == 0 { 0.0 } else { 100.0 * seen as f64 / texels as f64 }
    };
    Ok(Comparison {
        share_l1_pp,
        share_max_pp,
        share_max_part,
        kendall_tau_total,
        tied_pairs_total,
        kendall_tau_average,
        tied_pairs_average,
        top_k_overlap,
        top_k: top_k.min(reference.len()),
        coverage_difference_pp: coverage(candidate) - coverage(reference),
    })
}

/// The error of `candidate` against `reference` in the measure docs/science.md
/// says to quote (angular area, deg²·s, per part, matched by name): the L1
/// and largest difference of the parts' shares of the angular area,
/// percentage points; Kendall's τ-b of the rankings (tied pairs left out);
/// the overlap of the top-k. `None` when either lacks angular areas.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct AreaComparison {
    pub share_l1_pp: f64,
    pub share_max_pp: f64,
    pub share_max_part: String,
    pub kendall_tau: f64,
    pub tied_pairs: u64,
    pub top_k_overlap: usize,
    pub top_k: usize,
}

/// Compares the angular areas of two results' measures ([`AreaComparison`]).
pub(crate) fn compare_angular_areas(
    reference: &crate::result::measures::Measures,
    candidate: &crate::result::measures::Measures,
    top_k: usize,
) -> Option<AreaComparison> {
    let areas = |m: &crate::result::measures::Measures| -> Option<Vec<(String, f64)>> {
        m.parts.iter().map(|p| p.angular_area_deg2_s.map(|a| (p.name.clone(), a))).collect()
    };
    let (a, b) = (areas(reference)?, areas(candidate)?);
    let total = |parts: &[(String, f64)]| parts.iter().map(|p| p.1).sum::<f64>().max(f64::MIN_POSITIVE);
    let (total_a, total_b) = (total(&a), total(&b));
    let mut pairs = Vec::with_capacity(a.len());
    let (mut share_l1_pp, mut share_max_pp, mut share_max_part) = (0.0f64, 0.0f64, String::new());
    for (name, value) in &a {
        let other = b.iter().find(|(n, _)| n == name).map_or(0.0, |p| p.1);
        let difference = 100.0 * (value / total_a - other / total_b).abs();
        share_l1_pp += difference;
        if difference > share_max_pp {
            (share_max_pp, share_max_part) = (difference, name.clone());
        }
        pairs.push((*value, other));
    }
    let (kendall_tau, tied_pairs) = kendall_tau_b(&pairs);
    let top = |parts: &[(String, f64)]| {
        let mut sorted: Vec<&(String, f64)> = parts.iter().collect();
        sorted.sort_by(|x, y| y.1.total_cmp(&x.1).then_with(|| x.0.cmp(&y.0)));
        sorted.into_iter().take(top_k).map(|p| p.0.clone()).collect::<Vec<_>>()
    };
    let (top_a, top_b) = (top(&a), top(&b));
    let top_k_overlap = top_a.iter().filter(|name| top_b.contains(name)).count();
    Some(AreaComparison {
        share_l1_pp,
        share_max_pp,
        share_max_part,
        kendall_tau,
        tied_pairs,
        top_k_overlap,
        top_k,
    })
}

/// Kendall's τ-b of paired values, and the number of pairs tied in either
/// variable. τ-b = (C − D) / √((n₀ − n₁)(n₀ − n₂)); 1 when no pair can be
/// ranked (everything tied), so "no information" never reads as disagreement.
pub fn kendall_tau_b(values: &[(f64, f64)]) -> (f64, u64) {
    let (mut concordant, mut discordant, mut tied_x, mut tied_y, mut tied_either) =
        (0i64, 0i64, 0i64, 0i64, 0u64);
    for i in 0..values.len() {
        for j in i + 1..values.len() {
            let dx = values[i].0 - values[j].0;
            let dy = values[i].1 - values[j].1;
            if dx == 0.0 || dy == 0.0 {
                tied_either += 1;
            }
            if dx == 0.0 {
                tied_x += 1;
            }
            if dy == 0.0 {
                tied_y += 1;
            }
            if dx != 0.0 && dy != 0.0 {
                if (dx > 0.0) == (dy > 0.0) {
                    concordant += 1;
                } else {
                    discordant += 1;
                }
            }
        }
    }
    let n0 = (values.len() * values.len().saturating_sub(1) / 2) as i64;
    let denominator = (((n0 - tied_x) * (n0 - tied_y)) as f64).sqrt();
    let tau = if denominator == 0.0 { 1.0 } else { (concordant - discordant) as f64 / denominator };
    (tau, tied_either)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn part(name: &str, total: u64, texels: u64, seen: u64, share: f64) -> PartStats {
        PartStats {
            name: name.into(),
            color: None,
            texels,
            total,
            peak: 0,
            average: total as f64 / texels as f64,
            share,
            coverage: 100.0 * seen as f64 / texels as f64,
            texels_seen: seen,
        }
    }

    #[test]
    fn kendall_tau_b_matches_hand_computed_values() {
        // Same order: 1; reversed: -1.
        assert_eq!(kendall_tau_b(&[(1.0, 10.0), (2.0, 20.0), (3.0, 30.0)]), (1.0, 0));
        assert_eq!(kendall_tau_b(&[(1.0, 30.0), (2.0, 20.0), (3.0, 10.0)]), (-1.0, 0));
        // x = 1,2,3,4 and y = 1,3,2,4: C = 5, D = 1 → τ = 4/6.
        let (tau, ties) = kendall_tau_b(&[(1.0, 1.0), (2.0, 3.0), (3.0, 2.0), (4.0, 4.0)]);
        assert!((tau - 4.0 / 6.0).abs() < 1e-12 && ties == 0);
        // One tie in y: pairs n0 = 3, C = 2, D = 0, n2 = 1 → τ-b = 2/√(3·2).
        let (tau, ties) = kendall_tau_b(&[(1.0, 0.0), (2.0, 0.0), (3.0, 5.0)]);
        assert!((tau - 2.0 / 6f64.sqrt()).abs() < 1e-12 && ties == 1, "{tau} {ties}");
        // All tied: no information, reported as 1 with every pair tied.
        assert_eq!(kendall_tau_b(&[(0.0, 0.0), (0.0, 0.0)]), (1.0, 1));
    }

    #[test]
    fn shares_rankings_top_k_and_coverage_compare() {
        let reference =
            [part("hood", 60, 10, 10, 60.0), part("door", 30, 10, 5, 30.0), part("roof", 10, 10, 1, 10.0)];
        let candidate =
            [part("roof", 20, 10, 2, 20.0), part("door", 30, 10, 5, 30.0), part("hood", 50, 10, 10, 50.0)];
        let c = compare_parts(&reference, &candidate, 2).unwrap();
        assert!((c.share_l1_pp - 20.0).abs() < 1e-12 && (c.share_max_pp - 10.0).abs() < 1e-12);
        assert_eq!(c.share_max_part, "hood");
        assert_eq!((c.kendall_tau_total, c.tied_pairs_total), (1.0, 0));
        assert_eq!((c.top_k_overlap, c.top_k), (2, 2));
        assert!((c.coverage_difference_pp - 100.0 * (17.0 - 16.0) / 30.0).abs() < 1e-9);
        assert!(compare_parts(&reference, &candidate[..2], 2).is_err());
    }
}
