//! The best one, two, three … placements: the set of k choices that
//! maximizes the time at least one of them is legible, by the mean over the
//! archives and by the worst archive.
//!
//! Coverage ("at least one legible") is a monotone submodular set function,
//! so: exhaustive search where the number of k-sets is small (always for
//! the parts of a vehicle), else greedy with the data-dependent bound of
//! Nemhauser, Wolsey and Fisher (1978): for any set S,
//! OPT ≤ f(S) + (sum of the k largest marginal gains over S), taken at every
//! greedy prefix; the gap to it is reported. (Greedy is also within
//! 1 − 1/e of OPT, which the bound is never looser than at S = greedy's
//! result… and usually much tighter.) For the worst case (a minimum over
//! archives, not submodular) greedy is a heuristic and the bound is the
//! smallest per-archive bound.
//!
//! Frames are bitsets, one run of 64-bit words per archive, so a union is an
//! OR and a score a popcount per archive.

use std::ops::Range;

use crate::placement::legibility::ArchiveTimelines;
use crate::placement::table::CandidateKind;

/// At most this many k-sets are searched exhaustively; beyond, greedy.
pub const EXHAUSTIVE_LIMIT: u128 = 2_000_000;

/// What a set is chosen for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Objective {
    /// The mean legible seconds over the archives.
    Mean,
    /// The legible seconds of the worst archive.
    WorstCase,
}

/// How a set was found.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Method {
    Exhaustive,
    Greedy,
}

/// One choice: a candidate, or with `--symmetric` a left/right pair.
#[derive(Debug, Clone, PartialEq)]
pub struct Choice {
    /// The candidates it is made of (one, or a mirror pair).
    pub names: Vec<String>,
    pub kind: CandidateKind,
    /// Legible frames of all archives, [`Universe::ranges`] words each.
    pub bits: Vec<u64>,
}

/// The archives' frames as bit ranges.
#[derive(Debug, Clone, PartialEq)]
pub struct Universe {
    /// Per archive: its words of a bitset.
    pub ranges: Vec<Range<usize>>,
    /// Per archive: seconds one frame stands for.
    pub frame_s: Vec<f64>,
    /// Per archive: seconds its frames cover.
    pub duration_s: Vec<f64>,
    pub words: usize,
}

impl Universe {
    pub fn of(archives: &[ArchiveTimelines]) -> Universe {
        let mut ranges = Vec::new();
        let mut words = 0;
        for archive in archives {
            let length = archive.table.frames.len().div_ceil(64);
            ranges.push(words..words + length);
            words += length;
        }
        Universe {
            ranges,
            frame_s: archives.iter().map(|a| a.table.frame_s).collect(),
            duration_s: archives.iter().map(ArchiveTimelines::duration_s).collect(),
            words,
        }
    }

    /// Seconds covered per archive.
    pub fn seconds(&self, bits: &[u64]) -> Vec<f64> {
        self.ranges
            .iter()
            .zip(&self.frame_s)
            .map(|(range, &frame_s)| {
                bits[range.clone()].iter().map(|w| w.count_ones()).sum::<u32>() as f64 * frame_s
            })
            .collect()
    }

    /// The bits of per-archive legible flags (`None`: the candidate is not in that archive).
    pub fn bits<'a>(&self, flags: impl Iterator<Item = Option<&'a [bool]>>) -> Vec<u64> {
        let mut bits = vec![0u64; self.words];
        for (range, flags) in self.ranges.iter().zip(flags) {
            for (frame, _) in flags.into_iter().flatten().enumerate().filter(|&(_, &legible)| legible) {
                bits[range.start + frame / 64] |= 1u64 << (frame % 64);
            }
        }
        bits
    }
}

/// A chosen set and its scores.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Combination {
    pub k: usize,
    pub kind: &'static str,
    pub objective: Objective,
    pub method: Method,
    /// The candidates (a symmetric choice contributes both of its pair).
    pub candidates: Vec<String>,
    /// Mean over the archives of the seconds at least one is legible.
    pub legible_s: f64,
    /// Mean over the archives of legible_s / the archive's duration.
    pub share_of_time: f64,
    /// The smallest legible_s of any archive.
    pub worst_case_s: f64,
    /// Per archive, in input order.
    pub per_archive_s: Vec<f64>,
    /// No k-set can do better than this on the objective (= the objective's
    /// value when exhaustive).
    pub upper_bound_s: f64,
    /// upper_bound_s minus the objective's value.
    pub gap_s: f64,
}

fn union(a: &[u64], b: &[u64]) -> Vec<u64> {
    a.iter().zip(b).map(|(x, y)| x | y).collect()
}

fn mean(values: &[f64]) -> f64 {
    if values.is_empty() { 0.0 } else { values.iter().sum::<f64>() / values.len() as f64 }
}

fn worst(values: &[f64]) -> f64 {
    values.iter().copied().fold(f64::INFINITY, f64::min).min(f64::MAX)
}

/// The objective's value of per-archive seconds (ties broken by the mean).
fn value(objective: Objective, seconds: &[f64]) -> (f64, f64) {
    match objective {
        Objective::Mean => (mean(seconds), 0.0),
        Objective::WorstCase => (worst(seconds), mean(seconds)),
    }
}

/// The number of k-subsets of n.
pub fn binomial(n: usize, k: usize) -> u128 {
    (0..k as u128).fold(1u128, |acc, i| acc.saturating_mul(n as u128 - i) / (i + 1))
}

/// The best k-set of `choices` for `objective`, by the rule above:
/// exhaustive when there are at most `exhaustive_limit` k-sets.
pub fn best_set(
    universe: &Universe,
    choices: &[Choice],
    k: usize,
    objective: Objective,
    exhaustive_limit: u128,
) -> Option<Combination> {
    if choices.is_empty() || k == 0 {
        return None;
    }
    let k = k.min(choices.len());
    let (picked, method, bound) = if binomial(choices.len(), k) <= exhaustive_limit {
        let picked = exhaustive(universe, choices, k, objective);
        (picked, Method::Exhaustive, None)
    } else {
        let (picked, bound) = greedy(universe, choices, k, objective);
        (picked, Method::Greedy, Some(bound))
    };
    Some(combination(universe, choices, &picked, k, objective, method, bound))
}

fn combination(
    universe: &Universe,
    choices: &[Choice],
    picked: &[usize],
    k: usize,
    objective: Objective,
    method: Method,
    bound: Option<f64>,
) -> Combination {
    let bits = picked.iter().fold(vec![0u64; universe.words], |acc, &c| union(&acc, &choices[c].bits));
    let seconds = universe.seconds(&bits);
    let shares: Vec<f64> =
        seconds.iter().zip(&universe.duration_s).map(|(&s, &d)| if d > 0.0 { s / d } else { 0.0 }).collect();
    let achieved = value(objective, &seconds).0;
    let upper = bound.unwrap_or(achieved).max(achieved);
    Combination {
        k,
        kind: choices[picked[0]].kind.name(),
        objective,
        method,
        candidates: picked.iter().flat_map(|&c| choices[c].names.clone()).collect(),
        legible_s: mean(&seconds),
        share_of_time: mean(&shares),
        worst_case_s: worst(&seconds),
        per_archive_s: seconds,
        upper_bound_s: upper,
        gap_s: upper - achieved,
    }
}

/// Every k-set in lexicographic order; the first best wins ties.
fn exhaustive(universe: &Universe, choices: &[Choice], k: usize, objective: Objective) -> Vec<usize> {
    let mut best: Option<((f64, f64), Vec<usize>)> = None;
    let mut stack: Vec<usize> = Vec::with_capacity(k);
    let mut unions: Vec<Vec<u64>> = vec![vec![0u64; universe.words]];
    let mut next = 0usize;
    loop {
        if stack.len() == k {
            let score = value(objective, &universe.seconds(unions.last().unwrap()));
            if best.as_ref().is_none_or(|(b, _)| score > *b) {
                best = Some((score, stack.clone()));
            }
        }
        if stack.len() < k && next < choices.len() && choices.len() - next >= k - stack.len() {
            let bits = union(unions.last().unwrap(), &choices[next].bits);
            unions.push(bits);
            stack.push(next);
            next += 1;
            continue;
        }
        // Back up: the last pick moves one on.
        match stack.pop() {
            Some(last) => {
                unions.pop();
                next = last + 1;
            }
            None => break,
        }
    }
    best.map(|(_, set)| set).unwrap_or_default()
}

/// Greedy picks and the upper bound on the optimum (see the module doc).
fn greedy(universe: &Universe, choices: &[Choice], k: usize, objective: Objective) -> (Vec<usize>, f64) {
    let archives = universe.ranges.len();
    let mut picked: Vec<usize> = Vec::new();
    let mut covered = vec![0u64; universe.words];
    // Per archive (and for the mean): the smallest bound seen at any prefix.
    let mut archive_bounds = vec![f64::INFINITY; archives];
    let mut mean_bound = f64::INFINITY;
    for step in 0..=k {
        let base = universe.seconds(&covered);
        let gains: Vec<Vec<f64>> = choices
            .iter()
            .map(|c| {
                let with = universe.seconds(&union(&covered, &c.bits));
                with.iter().zip(&base).map(|(w, b)| w - b).collect()
            })
            .collect();
        for archive in 0..archives {
            let top = top_k_sum(gains.iter().map(|g| g[archive]), k);
            archive_bounds[archive] = archive_bounds[archive].min(base[archive] + top);
        }
        mean_bound = mean_bound.min(mean(&base) + top_k_sum(gains.iter().map(|g| mean(g)), k));
        if step == k {
            break;
        }
        let best = (0..choices.len()).filter(|c| !picked.contains(c)).max_by(|&a, &b| {
            let score = |c: usize| value(objective, &universe.seconds(&union(&covered, &choices[c].bits)));
            score(a).partial_cmp(&score(b)).unwrap_or(std::cmp::Ordering::Equal).then(b.cmp(&a))
        });
        let Some(best) = best else { break };
        covered = union(&covered, &choices[best].bits);
        picked.push(best);
    }
    let bound = match objective {
        Objective::Mean => mean_bound,
        Objective::WorstCase => worst(&archive_bounds).min(mean_bound),
    };
    (picked, bound)
}

fn top_k_sum(values: impl Iterator<Item = f64>, k: usize) -> f64 {
    let mut all: Vec<f64> = values.collect();
    all.sort_by(|a, b| b.total_cmp(a));
    all.iter().take(k).sum()
}

/// The definition, without bitsets or pruning (for tests): every k-subset of
/// `choices` scored frame by frame from the timelines' flags; the best
/// value of the objective.
pub fn brute_force_best(
    per_archive_flags: &[Vec<Vec<bool>>],
    frame_s: &[f64],
    k: usize,
    objective: Objective,
) -> f64 {
    let n = per_archive_flags.first().map_or(0, Vec::len);
    let mut best = f64::NEG_INFINITY;
    for mask in 0u64..(1u64 << n) {
        if mask.count_ones() as usize != k.min(n) {
            continue;
        }
        let seconds: Vec<f64> = per_archive_flags
            .iter()
            .zip(frame_s)
            .map(|(choices, &frame_s)| {
                let frames = choices.first().map_or(0, Vec::len);
                (0..frames).filter(|&f| (0..n).any(|c| mask >> c & 1 == 1 && choices[c][f])).count() as f64
                    * frame_s
            })
            .collect();
        best = best.max(value(objective, &seconds).0);
    }
    best
}
