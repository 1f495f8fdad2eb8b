//! The best placements of at most k *physical displays*: the set of choices
//! (a candidate is one display, a symmetric left/right pair two) that
//! maximizes the time at least one of them is legible, by the mean over the
//! archives and by the worst archive.
//!
//! Coverage ("at least one legible") is a monotone submodular set function,
//! so: exhaustive search where the number of sets is small (always for the
//! parts of a vehicle), else greedy with a data-dependent bound after
//! Nemhauser, Wolsey and Fisher (1978): for any set S and any feasible T,
//! f(T) ≤ f(S) + Σ_{t∈T} gain(t | S), so OPT ≤ f(S) + the largest sum of
//! marginal gains that fits in k displays (the k largest gains when every
//! choice is one display), taken at every greedy prefix; the gap to it is
//! reported. Greedy is run once per order of choice sizes (1 and 2 displays)
//! and the best result is kept. For the worst case (a minimum over archives,
//! not submodular) greedy is a heuristic and the bound is the smallest
//! per-archive bound.
//!
//! The archives carry weights (all 1 for the answer; bootstrap counts for
//! the probabilities of [`crate::placement::uncertainty`]). Frames are
//! bitsets, one run of 64-bit words per archive, so a union is an OR and a
//! score a popcount per archive. A choice keeps only its non-zero words
//! ([`SparseBits`]): stored whole, choices × frames words grew with the
//! square of the table (issue 41: 271 MB for a 2 MB table).

use std::ops::Range;

pub use crate::format::placement::{Method, Objective};
use crate::placement::legibility::ArchiveTimelines;
use crate::placement::table::CandidateKind;

/// At most this many sets are searched exhaustively; beyond, greedy.
pub const EXHAUSTIVE_LIMIT: u128 = 2_000_000;

/// How many of the next-best sets the search keeps for the runners-up.
pub(crate) const RUNNERS_UP: usize = 8;

/// One choice: a candidate, or with `--symmetric` a left/right pair.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Choice {
    /// The candidates it is made of (one, or a mirror pair): its displays.
    pub names: Vec<String>,
    pub kind: CandidateKind,
    /// Legible frames of all archives, [`Universe::ranges`] words each,
    /// the non-zero ones only.
    pub bits: SparseBits,
}

/// The non-zero 64-bit words of a bitset over the universe's frames, by
/// ascending word index: memory goes with the frames set, not with the
/// frames there are.
#[derive(Debug, Clone, PartialEq, Default)]
pub(crate) struct SparseBits {
    words: Vec<(usize, u64)>,
}

impl SparseBits {
    /// From (word index, bits) pairs in any order, indices repeated or not.
    pub(crate) fn from_words(mut words: Vec<(usize, u64)>) -> SparseBits {
        words.sort_unstable_by_key(|&(index, _)| index);
        let mut merged: Vec<(usize, u64)> = Vec::with_capacity(words.len());
        for (index, bits) in words {
            match merged.last_mut() {
                Some((last, word)) if *last == index => *word |= bits,
                _ if bits != 0 => merged.push((index, bits)),
                _ => {}
            }
        }
        merged.shrink_to_fit();
        SparseBits { words: merged }
    }

    /// The union with `other`.
    pub(crate) fn union(&self, other: &SparseBits) -> SparseBits {
        SparseBits::from_words(self.words.iter().chain(&other.words).copied().collect())
    }

    /// ORs the bits into the dense bitset `dense`.
    pub(crate) fn or_into(&self, dense: &mut [u64]) {
        for &(index, bits) in &self.words {
            dense[index] |= bits;
        }
    }

    /// The words stored (the non-zero ones).
    #[cfg(test)]
    pub(crate) fn stored_words(&self) -> usize {
        self.words.len()
    }
}

impl Choice {
    /// Physical displays: one per candidate.
    pub(crate) fn displays(&self) -> usize {
        self.names.len()
    }
}

/// The archives' frames as bit ranges, and their weights.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Universe {
    /// Per archive: its words of a bitset.
    pub ranges: Vec<Range<usize>>,
    /// Per archive: seconds one frame stands for.
    pub frame_s: Vec<f64>,
    /// Per archive: seconds its frames cover.
    pub duration_s: Vec<f64>,
    /// Per archive: its weight in the mean (1; a bootstrap's count).
    pub weights: Vec<f64>,
    pub words: usize,
}

impl Universe {
    pub(crate) fn of(archives: &[ArchiveTimelines]) -> Universe {
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
            weights: vec![1.0; archives.len()],
            words,
        }
    }

    /// The same frames with other weights.
    pub(crate) fn weighted(&self, weights: Vec<f64>) -> Universe {
        Universe { weights, ..self.clone() }
    }

    /// Seconds covered per archive.
    pub(crate) fn seconds(&self, bits: &[u64]) -> Vec<f64> {
        self.ranges
            .iter()
            .zip(&self.frame_s)
            .map(|(range, &frame_s)| {
                bits[range.clone()].iter().map(|w| w.count_ones()).sum::<u32>() as f64 * frame_s
            })
            .collect()
    }

    /// The bits of per-archive legible frames (frame indices; `None`:
    /// the candidate is not in that archive).
    pub(crate) fn bits<'a>(&self, legible: impl Iterator<Item = Option<&'a [usize]>>) -> Vec<u64> {
        let mut bits = vec![0u64; self.words];
        self.sparse_bits(legible).or_into(&mut bits);
        bits
    }

    /// [`Universe::bits`], the non-zero words only.
    pub(crate) fn sparse_bits<'a>(&self, legible: impl Iterator<Item = Option<&'a [usize]>>) -> SparseBits {
        let mut words = Vec::new();
        for (range, frames) in self.ranges.iter().zip(legible) {
            for &frame in frames.into_iter().flatten() {
                words.push((range.start + frame / 64, 1u64 << (frame % 64)));
            }
        }
        SparseBits::from_words(words)
    }

    /// Per archive, the frames set in the dense bitset `covered`.
    fn counts(&self, covered: &[u64]) -> Vec<u32> {
        self.ranges.iter().map(|range| covered[range.clone()].iter().map(|w| w.count_ones()).sum()).collect()
    }

    /// Seconds per archive of `covered` (its [`Universe::counts`] `counts`)
    /// with `add`, without building the union: work goes with `add`'s words.
    fn seconds_adding(&self, covered: &[u64], counts: &[u32], add: &SparseBits) -> Vec<f64> {
        let mut counts = counts.to_vec();
        let mut archive = 0;
        for &(index, bits) in &add.words {
            while self.ranges[archive].end <= index {
                archive += 1;
            }
            counts[archive] += (bits & !covered[index]).count_ones();
        }
        counts.iter().zip(&self.frame_s).map(|(&n, &frame_s)| n as f64 * frame_s).collect()
    }

    /// The weighted mean of per-archive values.
    pub(crate) fn mean(&self, values: &[f64]) -> f64 {
        let total: f64 = self.weights.iter().sum();
        if total <= 0.0 {
            return 0.0;
        }
        values.iter().zip(&self.weights).map(|(v, w)| v * w).sum::<f64>() / total
    }

    /// The least value of an archive with weight.
    pub(crate) fn worst(&self, values: &[f64]) -> f64 {
        values
            .iter()
            .zip(&self.weights)
            .filter(|(_, w)| **w > 0.0)
            .map(|(v, _)| *v)
            .fold(f64::INFINITY, f64::min)
            .min(f64::MAX)
    }

    /// The objective's value of per-archive seconds, ties broken by the mean.
    pub(crate) fn value(&self, objective: Objective, seconds: &[f64]) -> (f64, f64) {
        match objective {
            Objective::Mean => (self.mean(seconds), 0.0),
            Objective::WorstCase => (self.worst(seconds), self.mean(seconds)),
        }
    }

    /// The objective's value of the union of `picked`.
    pub(crate) fn score(&self, choices: &[Choice], picked: &[usize], objective: Objective) -> (f64, f64) {
        self.value(objective, &self.seconds(&union_of(self, choices, picked)))
    }
}

/// The frames any of `picked` is legible in.
pub(crate) fn union_of(universe: &Universe, choices: &[Choice], picked: &[usize]) -> Vec<u64> {
    picked.iter().fold(vec![0u64; universe.words], |acc, &c| union(&acc, &choices[c].bits))
}

fn union(a: &[u64], b: &SparseBits) -> Vec<u64> {
    let mut union = a.to_vec();
    b.or_into(&mut union);
    union
}

/// Physical displays of `picked`.
pub(crate) fn displays(choices: &[Choice], picked: &[usize]) -> usize {
    picked.iter().map(|&c| choices[c].displays()).sum()
}

/// The number of k-subsets of n (of all n when k ≥ n).
pub(crate) fn binomial(n: usize, k: usize) -> u128 {
    (0..k.min(n) as u128).fold(1u128, |acc, i| acc.saturating_mul(n as u128 - i) / (i + 1))
}

/// What the search found: the set (choice indices), how, the bound on any
/// set of k displays and the next-best sets it met (with their values).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Found {
    pub picked: Vec<usize>,
    pub method: Method,
    /// `None` when exhaustive (the value is the optimum).
    pub bound: Option<f64>,
    /// Other sets, best first (exhaustive: the next best of all; greedy:
    /// the best single-member swaps of the answer).
    pub runners_up: Vec<(Vec<usize>, f64)>,
}

/// The best set of at most `k` displays among `choices` for `objective`:
/// exhaustive when there are at most `exhaustive_limit` sets.
pub(crate) fn best_set(
    universe: &Universe,
    choices: &[Choice],
    k: usize,
    objective: Objective,
    exhaustive_limit: u128,
) -> Option<Found> {
    if choices.is_empty() || k == 0 || choices.iter().all(|c| c.displays() > k) {
        return None;
    }
    let found = if binomial(choices.len(), k) <= exhaustive_limit {
        let (picked, runners_up) = exhaustive(universe, choices, k, objective);
        Found { picked, method: Method::Exhaustive, bound: None, runners_up }
    } else {
        let (picked, bound) = greedy(universe, choices, k, objective);
        let runners_up = swaps(universe, choices, &picked, k, objective);
        Found { picked, method: Method::Greedy, bound: Some(bound), runners_up }
    };
    (!found.picked.is_empty()).then_some(found)
}

/// Keeps the best `RUNNERS_UP + 1` sets seen, best first.
#[derive(Default)]
struct Leaders {
    sets: Vec<((f64, f64), Vec<usize>)>,
}

impl Leaders {
    /// Offers a set; one that only adds members to a kept set scoring as
    /// well is no new place and is not kept.
    fn offer(&mut self, score: (f64, f64), set: &[usize]) {
        // Strictly better ranks first, and so does a tie with fewer members
        // (a member that adds nothing is left out); other ties stay behind
        // the sets found before them.
        let ahead = |kept_score: (f64, f64), kept: &[usize]| {
            score > kept_score || (score == kept_score && set.len() < kept.len())
        };
        if self.sets.len() > RUNNERS_UP && self.sets.last().is_some_and(|(s, kept)| !ahead(*s, kept)) {
            return;
        }
        if self.sets.iter().any(|(s, kept)| *s >= score && kept.iter().all(|c| set.contains(c))) {
            return;
        }
        let at = self.sets.iter().position(|(s, kept)| ahead(*s, kept)).unwrap_or(self.sets.len());
        self.sets.insert(at, (score, set.to_vec()));
        self.sets.truncate(RUNNERS_UP + 1);
    }
}

/// Every set of at most k displays in lexicographic order (a set before
/// its extensions); the first best (so the smallest in that order) wins
/// ties.
fn exhaustive(
    universe: &Universe,
    choices: &[Choice],
    k: usize,
    objective: Objective,
) -> (Vec<usize>, Vec<(Vec<usize>, f64)>) {
    struct Walk<'a> {
        universe: &'a Universe,
        choices: &'a [Choice],
        k: usize,
        objective: Objective,
        leaders: Leaders,
        stack: Vec<usize>,
    }
    fn visit(walk: &mut Walk, start: usize, used: usize, covered: &[u64]) {
        for c in start..walk.choices.len() {
            let size = walk.choices[c].displays();
            if used + size > walk.k {
                continue;
            }
            let bits = union(covered, &walk.choices[c].bits);
            walk.stack.push(c);
            let score = walk.universe.value(walk.objective, &walk.universe.seconds(&bits));
            walk.leaders.offer(score, &walk.stack);
            visit(walk, c + 1, used + size, &bits);
            walk.stack.pop();
        }
    }
    let mut walk =
        Walk { universe, choices, k, objective, leaders: Leaders::default(), stack: Vec::with_capacity(k) };
    visit(&mut walk, 0, 0, &vec![0u64; universe.words]);
    let mut sets = walk.leaders.sets.into_iter();
    let best = sets.next().map(|(_, set)| set).unwrap_or_default();
    (best, sets.map(|(score, set)| (set, score.0)).collect())
}

/// The sequences of choice sizes (1 or 2 displays) summing to `k`, each
/// greedy run's order.
fn size_orders(k: usize) -> Vec<Vec<usize>> {
    if k == 0 {
        return vec![Vec::new()];
    }
    let mut out = Vec::new();
    for first in [1usize, 2] {
        if first <= k {
            for mut rest in size_orders(k - first) {
                rest.insert(0, first);
                out.push(rest);
            }
        }
    }
    out
}

/// The largest sum of `gains` (one per choice) that fits in k displays.
fn fitting_sum(gains: &[f64], choices: &[Choice], k: usize) -> f64 {
    let mut by_size: [Vec<f64>; 2] = [Vec::new(), Vec::new()];
    for (gain, choice) in gains.iter().zip(choices) {
        if (1..=2).contains(&choice.displays()) {
            by_size[choice.displays() - 1].push(gain.max(0.0));
        }
    }
    for list in &mut by_size {
        list.sort_by(|a, b| b.total_cmp(a));
    }
    (0..=k / 2)
        .map(|pairs| {
            let two: f64 = by_size[1].iter().take(pairs).sum();
            let one: f64 = by_size[0].iter().take(k - 2 * pairs).sum();
            two + one
        })
        .fold(0.0, f64::max)
}

/// Greedy picks and the upper bound on the optimum (see the module doc).
fn greedy(universe: &Universe, choices: &[Choice], k: usize, objective: Objective) -> (Vec<usize>, f64) {
    let archives = universe.ranges.len();
    let mut archive_bounds = vec![f64::INFINITY; archives];
    let mut mean_bound = f64::INFINITY;
    let mut best: Option<((f64, f64), Vec<usize>)> = None;
    for order in size_orders(k) {
        let mut picked: Vec<usize> = Vec::new();
        let mut covered = vec![0u64; universe.words];
        for step in 0..=order.len() {
            let base = universe.seconds(&covered);
            let counts = universe.counts(&covered);
            let with = |c: &Choice| universe.seconds_adding(&covered, &counts, &c.bits);
            let gains: Vec<Vec<f64>> =
                choices.iter().map(|c| with(c).iter().zip(&base).map(|(w, b)| w - b).collect()).collect();
            for (archive, bound) in archive_bounds.iter_mut().enumerate() {
                let column: Vec<f64> = gains.iter().map(|g| g[archive]).collect();
                *bound = bound.min(base[archive] + fitting_sum(&column, choices, k));
            }
            let mean_gains: Vec<f64> = gains.iter().map(|g| universe.mean(g)).collect();
            mean_bound = mean_bound.min(universe.mean(&base) + fitting_sum(&mean_gains, choices, k));
            if !picked.is_empty() {
                let score = universe.value(objective, &base);
                if best.as_ref().is_none_or(|(b, _)| score > *b) {
                    best = Some((score, picked.clone()));
                }
            }
            let Some(&size) = order.get(step) else { break };
            let next = (0..choices.len())
                .filter(|c| !picked.contains(c) && choices[*c].displays() == size)
                .max_by(|&a, &b| {
                    let score = |c: usize| universe.value(objective, &with(&choices[c]));
                    score(a).partial_cmp(&score(b)).unwrap_or(std::cmp::Ordering::Equal).then(b.cmp(&a))
                });
            let Some(next) = next else { break };
            covered = union(&covered, &choices[next].bits);
            picked.push(next);
        }
    }
    let bound = match objective {
        Objective::Mean => mean_bound,
        Objective::WorstCase => universe.worst(&archive_bounds).min(mean_bound),
    };
    (best.map(|(_, set)| set).unwrap_or_default(), bound)
}

/// The sets that swap one member of `picked` for another choice of the
/// same size, best first (at most [`RUNNERS_UP`]).
fn swaps(
    universe: &Universe,
    choices: &[Choice],
    picked: &[usize],
    k: usize,
    objective: Objective,
) -> Vec<(Vec<usize>, f64)> {
    let mut leaders = Leaders::default();
    for (slot, &member) in picked.iter().enumerate() {
        for other in (0..choices.len()).filter(|c| !picked.contains(c)) {
            if choices[other].displays() != choices[member].displays() {
                continue;
            }
            let mut set = picked.to_vec();
            set[slot] = other;
            set.sort_unstable();
            if displays(choices, &set) <= k {
                leaders.offer(universe.score(choices, &set, objective), &set);
            }
        }
    }
    leaders.sets.into_iter().take(RUNNERS_UP).map(|(score, set)| (set, score.0)).collect()
}

/// The definition, without bitsets or pruning (for tests): every k-subset of
/// `choices` (one display each) scored frame by frame from the timelines'
/// flags; the best value of the objective.
pub fn brute_force_best(
    per_archive_flags: &[Vec<Vec<bool>>],
    frame_s: &[f64],
    k: usize,
    objective: Objective,
) -> f64 {
    let n = per_archive_flags.first().map_or(0, Vec::len);
    let plain = Universe {
        ranges: Vec::new(),
        frame_s: frame_s.to_vec(),
        duration_s: Vec::new(),
        weights: vec![1.0; per_archive_flags.len()],
        words: 0,
    };
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
        best = best.max(plain.value(objective, &seconds).0);
    }
    best
}
