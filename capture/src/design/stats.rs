//! The merge's arithmetic, on plain numbers (no files, no scenes), so its
//! intervals can be tested for coverage against a known answer.
//!
//! The random unit is one drawn observer with its own texel sample (and,
//! with generated traffic, its replicate's traffic): unit `u` of every cell
//! is drawn alike. A group of cells (one cell, one vehicle, all) is scored
//! per unit as the equal-weight mean over its cells (the fixed factors
//! averaged within each draw), then over the units: the mean with its 95 %
//! Student-t interval over the units, and P(best) by the bootstrap over
//! units (`ufcsr::placement::bootstrap_weights`, the placement's own resampler).

use std::collections::{BTreeMap, BTreeSet};

use ufcsr::{
    format::BestPlacement, format::CandidateSummary, format::CellLevels, format::DesignTask,
    format::GroupSummary, format::LevelEffect, format::MainEffect, format::MeanInterval,
};

/// What the intervals are, written into the result.
pub const INTERVAL_METHOD: &str = "95 % Student-t interval of the mean over the random units (one unit = one \
     drawn observer with its own texel sample seed and its replicate's generated traffic; units are independent \
     and drawn alike in every cell); a group of cells is averaged with equal weight over its cells within each \
     unit first. It covers the observers, the texel sample and the traffic draws, not the fixed factors' choice \
     of levels, the placement rules' thresholds or the population's declared figures. P(best) is the share of \
     1000 bootstrap resamples of the units in which the candidate has the largest mean legible time of its kind, \
     exact ties sharing (each of t tied candidates 1/t; none with one unit or when none is legible), beside \
     P(within 0.05 s) (optimistic for small n, as the placement's own P(best), docs/placement.md); candidates \
     not mountable or on which no display fits are never ranked (the placement's one rule). A main effect's level means, \
     effects (level mean minus the mean over the levels) and range (highest minus lowest level) are per-unit \
     contrasts with the same t interval (an effect and the range signed, they may be negative)";

/// Bootstrap resamples behind P(best).
pub(crate) const P_BEST_REPLICATES: usize = 1000;

/// One candidate's numbers in one unit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pair {
    pub legible_s: f64,
    pub decision_window_legible_s: f64,
    pub angular_area_deg2_s: f64,
}

/// One cell: per unit, per candidate name, its kind and numbers.
#[derive(Debug, Clone, PartialEq)]
pub struct CellData {
    pub cell: CellLevels,
    pub units: BTreeMap<u32, BTreeMap<String, Pair>>,
    pub kinds: BTreeMap<String, String>,
}

/// The tasks grouped by cell, in the order of `cells`.
pub fn cell_data(cells: &[CellLevels], tasks: &[DesignTask]) -> Vec<CellData> {
    cells
        .iter()
        .map(|cell| {
            let mut data = CellData { cell: cell.clone(), units: BTreeMap::new(), kinds: BTreeMap::new() };
            for task in tasks.iter().filter(|t| &t.cell == cell) {
                for unit in &task.units {
                    let values = data.units.entry(unit.unit).or_default();
                    for c in &unit.candidates {
                        data.kinds.insert(c.name.clone(), c.kind.clone());
                        let pair = Pair {
                            legible_s: c.legible_s,
                            decision_window_legible_s: c.decision_window_legible_s,
                            angular_area_deg2_s: c.angular_area_deg2_s,
                        };
                        values.insert(c.name.clone(), pair);
                    }
                }
            }
            data
        })
        .collect()
}

/// The mean and its 95 % t interval.
pub fn mean_interval(values: &[f64]) -> MeanInterval {
    let n = values.len();
    let mean = if n == 0 { 0.0 } else { values.iter().sum::<f64>() / n as f64 };
    MeanInterval { mean, ci95: ufcsr::placement::t_interval(values), n: n as u32 }
}

/// Per unit of the group (units every cell has), per candidate every cell
/// has, the equal-weight mean over the cells.
fn unit_means(cells: &[&CellData]) -> (Vec<String>, Vec<Vec<Pair>>) {
    let Some(first) = cells.first() else { return (Vec::new(), Vec::new()) };
    let units: Vec<u32> =
        first.units.keys().copied().filter(|u| cells.iter().all(|c| c.units.contains_key(u))).collect();
    let names: Vec<String> = first
        .kinds
        .keys()
        .filter(|name| cells.iter().all(|c| units.iter().all(|u| c.units[u].contains_key(*name))))
        .cloned()
        .collect();
    let k = cells.len() as f64;
    let per_unit = units
        .iter()
        .map(|u| {
            names
                .iter()
                .map(|name| {
                    let mut mean =
                        Pair { legible_s: 0.0, decision_window_legible_s: 0.0, angular_area_deg2_s: 0.0 };
                    for cell in cells {
                        let pair = cell.units[u][name];
                        mean.legible_s += pair.legible_s / k;
                        mean.decision_window_legible_s += pair.decision_window_legible_s / k;
                        mean.angular_area_deg2_s += pair.angular_area_deg2_s / k;
                    }
                    mean
                })
                .collect()
        })
        .collect();
    (names, per_unit)
}

/// The mean of a difference or an effect (may be negative) and its 95 % t interval.
pub(crate) fn signed_interval(values: &[f64]) -> MeanInterval {
    MeanInterval { ci95: ufcsr::placement::t_interval_signed(values), ..mean_interval(values) }
}

/// Per candidate of `among`: the share of bootstrap resamples of the units in which it has the
/// largest mean, exact ties sharing (each of t tied candidates 1/t), and the share in which it is
/// within ε ([`ufcsr::placement::DEFAULT_EPSILON_S`]) of the largest: the placement's own arithmetic
/// ([`ufcsr::placement::best_shares`]).
pub fn p_best(per_unit: &[Vec<f64>], among: &[usize], seed: u64) -> ufcsr::placement::BestShares {
    let resampling = ufcsr::placement::Resampling { replicates: P_BEST_REPLICATES, seed, epsilon_s: 0.0 };
    let weights = ufcsr::placement::bootstrap_weights(per_unit.len(), &resampling);
    let draws = weights.iter().map(|w| {
        let total: f64 = w.iter().sum::<f64>().max(1.0);
        among
            .iter()
            .map(|&c| per_unit.iter().zip(w).map(|(row, w)| row[c] * w).sum::<f64>() / total)
            .collect::<Vec<f64>>()
    });
    ufcsr::placement::best_shares(draws, among.len(), ufcsr::placement::DEFAULT_EPSILON_S)
}

/// Why a group has no P(best) for the candidates `among`: one unit, or none legible.
fn p_best_note(units: usize, among: &[&CandidateSummary]) -> Option<&'static str> {
    if units < 2 {
        Some(ufcsr::placement::ONE_UNIT)
    } else if among.iter().all(|c| c.legible_s.mean <= 0.0) {
        Some(ufcsr::placement::NO_CANDIDATE_LEGIBLE)
    } else {
        None
    }
}

/// The line naming every candidate the groups left out of their answers, and why (empty when none).
pub(crate) fn left_out_line<'a>(groups: impl Iterator<Item = &'a GroupSummary>) -> String {
    let mut excluded: Vec<ufcsr::format::ExcludedRecord> =
        groups.flat_map(|g| g.excluded.iter().cloned()).collect();
    excluded.sort_by(|a, b| a.candidate.cmp(&b.candidate));
    excluded.dedup_by(|a, b| a.candidate == b.candidate);
    ufcsr::placement::excluded_line(&excluded)
}

/// One group of cells scored (see the module documentation).
pub fn group_summary(group: String, cells: &[&CellData], seed: u64) -> GroupSummary {
    let (names, per_unit) = unit_means(cells);
    let kinds = cells.first().map(|c| c.kinds.clone()).unwrap_or_default();
    let column =
        |c: usize, f: fn(&Pair) -> f64| -> Vec<f64> { per_unit.iter().map(|row| f(&row[c])).collect() };
    let mut candidates: Vec<CandidateSummary> = (0..names.len())
        .map(|c| CandidateSummary {
            name: names[c].clone(),
            kind: kinds.get(&names[c]).cloned().unwrap_or_default(),
            legible_s: mean_interval(&column(c, |p| p.legible_s)),
            decision_window_legible_s: mean_interval(&column(c, |p| p.decision_window_legible_s)),
            angular_area_deg2_s: mean_interval(&column(c, |p| p.angular_area_deg2_s)),
        })
        .collect();
    let excluded = ufcsr::placement::default_exclusions(
        names.iter().map(|n| (n.as_str(), kinds.get(n).map_or("part", String::as_str))),
    );
    let legible: Vec<Vec<f64>> =
        per_unit.iter().map(|row| row.iter().map(|p| p.legible_s).collect()).collect();
    let mut best = Vec::new();
    for kind in ["part", "patch"] {
        let among: Vec<usize> = (0..names.len())
            .filter(|&c| candidates[c].kind == kind && !excluded.iter().any(|e| e.candidate == names[c]))
            .collect();
        if among.is_empty() {
            continue;
        }
        let shares = p_best(&legible, &among, seed);
        let note = p_best_note(per_unit.len(), &among.iter().map(|&c| &candidates[c]).collect::<Vec<_>>());
        let mut order: Vec<usize> = (0..among.len()).collect();
        order.sort_by(|&a, &b| {
            let (ca, cb) = (&candidates[among[a]], &candidates[among[b]]);
            cb.legible_s.mean.total_cmp(&ca.legible_s.mean).then(ca.name.cmp(&cb.name))
        });
        order.truncate(3);
        for (rank, &o) in order.iter().enumerate() {
            let c = &candidates[among[o]];
            let tied_with = among
                .iter()
                .map(|&other| &candidates[other])
                .filter(|other| {
                    other.name != c.name
                        && c.legible_s.mean > 0.0
                        && ufcsr::placement::tied_scores(other.legible_s.mean, c.legible_s.mean)
                })
                .map(|other| other.name.clone())
                .collect();
            best.push(BestPlacement {
                rank: rank as u32 + 1,
                name: c.name.clone(),
                kind: kind.into(),
                legible_s: c.legible_s,
                p_best: note.is_none().then_some(shares.p_best[o]),
                p_within_epsilon: note.is_none().then_some(shares.p_within_epsilon[o]),
                epsilon_s: Some(ufcsr::placement::DEFAULT_EPSILON_S),
                tied_with,
                p_best_note: note.map(String::from),
            });
        }
    }
    candidates.sort_by(|a, b| b.legible_s.mean.total_cmp(&a.legible_s.mean).then(a.name.cmp(&b.name)));
    GroupSummary { group, cells: cells.len() as u32, candidates, best, excluded }
}

/// A cell's level of one factor.
type LevelOf = fn(&CellLevels) -> &str;

/// Per factor with more than one level and per candidate in `names` (every
/// unit of every cell has it): each level's mean legible time and its effect
/// (the level's mean minus the mean over the levels), and the range, each
/// with its 95 % t interval over the random units. Within a unit, a level's
/// value is the equal-weight mean over the level's cells, so each effect is
/// a per-unit contrast and its t interval covers it as the group means'
/// does (tested against a known effect).
pub fn main_effects(cells: &[&CellData], names: &[String]) -> Vec<MainEffect> {
    let factors: [(&str, LevelOf); 3] =
        [("vehicle", |c| &c.vehicle), ("scenario", |c| &c.scenario), ("traffic", |c| &c.traffic)];
    let mut effects = Vec::new();
    for (factor, level_of) in factors {
        let levels: BTreeSet<&str> = cells.iter().map(|c| level_of(&c.cell)).collect();
        if levels.len() < 2 {
            continue;
        }
        let levels: Vec<&str> = levels.into_iter().collect();
        for name in names {
            if let Some(per_level) = per_level_units(cells, level_of, &levels, name) {
                effects.push(main_effect(factor, name, &levels, &per_level));
            }
        }
    }
    effects
}

/// Per level, per unit (the units every cell has): the candidate's mean
/// legible time over the level's cells; `None` when a cell or unit lacks it.
fn per_level_units(
    cells: &[&CellData],
    level_of: LevelOf,
    levels: &[&str],
    name: &str,
) -> Option<Vec<Vec<f64>>> {
    let first = cells.first()?;
    let units: Vec<u32> =
        first.units.keys().copied().filter(|u| cells.iter().all(|c| c.units.contains_key(u))).collect();
    if units.is_empty() || !cells.iter().all(|c| units.iter().all(|u| c.units[u].contains_key(name))) {
        return None;
    }
    let per_level = levels
        .iter()
        .map(|level| {
            let at: Vec<&CellData> = cells.iter().copied().filter(|c| level_of(&c.cell) == *level).collect();
            let k = at.len() as f64;
            units.iter().map(|u| at.iter().map(|c| c.units[u][name].legible_s).sum::<f64>() / k).collect()
        })
        .collect();
    Some(per_level)
}

/// One factor's effect on one candidate from its per-level, per-unit values.
fn main_effect(factor: &str, name: &str, levels: &[&str], per_level: &[Vec<f64>]) -> MainEffect {
    let units = per_level.first().map_or(0, Vec::len);
    let grand: Vec<f64> =
        (0..units).map(|u| per_level.iter().map(|l| l[u]).sum::<f64>() / per_level.len() as f64).collect();
    let means: Vec<MeanInterval> = per_level.iter().map(|values| mean_interval(values)).collect();
    let level_effects = levels
        .iter()
        .zip(per_level)
        .zip(&means)
        .map(|((level, values), mean)| {
            let effect: Vec<f64> = values.iter().zip(&grand).map(|(v, g)| v - g).collect();
            LevelEffect { level: level.to_string(), mean_s: *mean, effect_s: signed_interval(&effect) }
        })
        .collect();
    let by_mean = |a: &usize, b: &usize| means[*a].mean.total_cmp(&means[*b].mean).then(b.cmp(a));
    let high = (0..means.len()).max_by(by_mean).unwrap_or(0);
    let low = (0..means.len()).min_by(by_mean).unwrap_or(0);
    let difference: Vec<f64> = per_level[high].iter().zip(&per_level[low]).map(|(h, l)| h - l).collect();
    MainEffect {
        factor: factor.into(),
        candidate: name.into(),
        within_vehicle: None,
        levels: level_effects,
        range_s: signed_interval(&difference),
        highest: levels[high].into(),
        lowest: levels[low].into(),
    }
}
