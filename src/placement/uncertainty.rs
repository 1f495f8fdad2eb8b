//! How sure the placement answer is: for each best set (by the mean), the
//! interval of its legible seconds over what varies, the probability that
//! it is the best set, and the other sets as good within that interval.
//!
//! **The random units are the archives.** Each table given is one draw of
//! the conditions the answer should hold for: a scenario, a traffic
//! condition, an observer sampled from a population (`ufcsr capture
//! observers`), a texel sample drawn with another `--seed`. The answer is
//! their mean, so the archives are exchangeable when they are drawn alike
//! from one population (independent observers or seeds are; four fixed,
//! hand-made scenarios are not a random sample, and the interval then says
//! how far the mean could move if scenarios like them were drawn again).
//! Frames and eyes inside an archive are *not* units: they are correlated
//! in time, and the legible seconds of an archive are one number.
//!
//! * **Interval** (95 %): Student's t over the archives' seconds of the
//!   reported set, mean ± t(0.975, n−1) · s / √n; none with one archive.
//! * **P(best)**: a bootstrap over the archives (each replicate draws n
//!   archives with replacement, as weights) re-runs the search and credits
//!   the replicate's best; **exact ties share** ([`tied_best_credits`]:
//!   each of t sets as good as the best gets 1/t, among the answer, its
//!   runners-up and the replicate's own best), so a k-way tie gives 1/k
//!   each, whatever the order. **P(within ε)** how often the reported set
//!   is at most ε seconds below the replicate's best. No P(best) with one
//!   archive ([`ONE_UNIT`]) or when the best set is legible 0 s
//!   ([`NO_CANDIDATE_LEGIBLE`]). [`best_shares`] is the same arithmetic
//!   for a list of candidates (the design's merge uses it).
//! * **Runners-up**: the other sets the search met (exhaustive: the next
//!   best of all; greedy: single-member swaps) whose mean lies inside the
//!   interval, sets that only add or drop members of the answer and sets
//!   with a member that adds nothing left out (none when nothing is
//!   legible).
//!
//! `tests/it/placement_uncertainty.rs` measures the interval's coverage and
//! P(best)'s calibration on synthetic tables with a known answer.

use rayon::prelude::*;

use crate::format::placement::RunnerUpRecord;
use crate::placement::search::{Choice, Found, Objective, Universe, best_set};

/// Nominal coverage of the intervals.
pub(crate) const CONFIDENCE: f64 = 0.95;
/// Bootstrap replicates by default.
pub const DEFAULT_REPLICATES: usize = 1000;
/// The default ε of P(within ε), seconds: about three frames at 60 fps.
pub const DEFAULT_EPSILON_S: f64 = 0.05;

/// Why there is no P(best) with one random unit.
pub const ONE_UNIT: &str = "n/a: one unit";
/// Why there is no P(best) when the best is legible 0 s.
pub const NO_CANDIDATE_LEGIBLE: &str = "no candidate legible";
/// Scores this close (relative to the larger) are one tie: the same seconds
/// summed in another order differ by rounding only.
const TIE_TOLERANCE: f64 = 1e-12;

/// Whether `a` and `b` are the same score (an exact tie up to rounding).
pub fn tied(a: f64, b: f64) -> bool {
    (a - b).abs() <= TIE_TOLERANCE * a.abs().max(b.abs()).max(1.0)
}

/// One draw's credit to each score: each of the t scores tied with the
/// largest gets 1/t, the others 0 (exact and deterministic: no order
/// breaks a tie). Scores of −∞ never get credit; all −∞ (or none) gives 0s.
pub fn tied_best_credits(scores: &[f64]) -> Vec<f64> {
    let best = scores.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    if best == f64::NEG_INFINITY {
        return vec![0.0; scores.len()];
    }
    let ties = scores.iter().filter(|&&s| tied(s, best)).count() as f64;
    scores.iter().map(|&s| if tied(s, best) { 1.0 / ties } else { 0.0 }).collect()
}

/// P(best) (ties sharing) and P(within ε) of each candidate over draws.
#[derive(Debug, Clone, PartialEq)]
pub struct BestShares {
    pub p_best: Vec<f64>,
    pub p_within_epsilon: Vec<f64>,
}

/// Over `draws` (each a score per candidate, in one order): each
/// candidate's mean [`tied_best_credits`] and the share of draws in which
/// it is at most `epsilon` below the draw's best.
pub fn best_shares(draws: impl IntoIterator<Item = Vec<f64>>, candidates: usize, epsilon: f64) -> BestShares {
    let mut shares = BestShares { p_best: vec![0.0; candidates], p_within_epsilon: vec![0.0; candidates] };
    let mut n = 0usize;
    for scores in draws {
        n += 1;
        let best = scores.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        for (c, credit) in tied_best_credits(&scores).into_iter().enumerate().take(candidates) {
            shares.p_best[c] += credit;
            if scores[c] >= best - epsilon || tied(scores[c], best) {
                shares.p_within_epsilon[c] += 1.0;
            }
        }
    }
    for p in shares.p_best.iter_mut().chain(shares.p_within_epsilon.iter_mut()) {
        *p /= n.max(1) as f64;
    }
    shares
}

/// The bootstrap's settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Resampling {
    pub replicates: usize,
    pub seed: u64,
    pub epsilon_s: f64,
}

impl Default for Resampling {
    fn default() -> Resampling {
        Resampling { replicates: DEFAULT_REPLICATES, seed: 1, epsilon_s: DEFAULT_EPSILON_S }
    }
}

/// The 95 % t interval of the mean of `values` (seconds, so not below 0); `None` with fewer than two.
pub fn t_interval(values: &[f64]) -> Option<[f64; 2]> {
    t_interval_signed(values).map(|[lo, hi]| [lo.max(0.0), hi])
}

/// The 95 % t interval of the mean of `values` that may be negative (a difference, an effect);
/// `None` with fewer than two.
pub fn t_interval_signed(values: &[f64]) -> Option<[f64; 2]> {
    let n = values.len();
    if n < 2 {
        return None;
    }
    let mean = values.iter().sum::<f64>() / n as f64;
    let variance = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1) as f64;
    let half = crate::stats::t975(n - 1) * (variance / n as f64).sqrt();
    Some([mean - half, mean + half])
}

/// Per replicate: how often each archive was drawn.
pub fn bootstrap_weights(archives: usize, resampling: &Resampling) -> Vec<Vec<f64>> {
    // Seeded, so the probabilities do not change between runs.
    let mut random = crate::stats::SplitMix64(resampling.seed);
    (0..resampling.replicates)
        .map(|_| {
            let mut weights = vec![0.0; archives];
            for _ in 0..archives {
                weights[random.below(archives as u64) as usize] += 1.0;
            }
            weights
        })
        .collect()
}

/// What the bootstrap says of one best set.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Assessment {
    pub interval_s: Option<[f64; 2]>,
    pub p_best: Option<f64>,
    pub p_within_epsilon: Option<f64>,
    pub runners_up: Vec<RunnerUpRecord>,
    /// Sets exactly as legible as the reported one (choice indices).
    pub tied_with: Vec<Vec<usize>>,
    /// Why there is no P(best) ([`ONE_UNIT`], [`NO_CANDIDATE_LEGIBLE`]).
    pub note: Option<&'static str>,
}

fn sorted(set: &[usize]) -> Vec<usize> {
    let mut set = set.to_vec();
    set.sort_unstable();
    set
}

/// The interval, P(best), P(within ε) and the runners-up of `found`, the
/// best set of at most `k` displays by the mean (see the module doc).
pub(crate) fn assess(
    universe: &Universe,
    choices: &[Choice],
    found: &Found,
    k: usize,
    exhaustive_limit: u128,
    resampling: &Resampling,
) -> Assessment {
    let objective = Objective::Mean;
    let archives = universe.ranges.len();
    let seconds = universe.seconds(&crate::placement::search::union_of(universe, choices, &found.picked));
    let interval_s = t_interval(&seconds);
    let reported = sorted(&found.picked);
    let nested =
        |set: &[usize]| set.iter().all(|c| reported.contains(c)) || reported.iter().all(|c| set.contains(c));
    let value = universe.mean(&seconds);
    let low = interval_s.map_or(value - resampling.epsilon_s, |[low, _]| low.min(value - 1e-12));
    // Every member of a runner-up adds time: a set padded with a member that
    // adds nothing is the smaller set again, not another place.
    let minimal = |set: &[usize]| {
        let whole = universe.score(choices, set, objective).0;
        set.iter().all(|&m| {
            let without: Vec<usize> = set.iter().copied().filter(|&c| c != m).collect();
            universe.score(choices, &without, objective).0 < whole
        })
    };
    let runners: Vec<(Vec<usize>, f64)> = found
        .runners_up
        .iter()
        .filter(|(set, v)| value > 0.0 && *v >= low && !nested(&sorted(set)) && minimal(set))
        .map(|(set, v)| (sorted(set), *v))
        .collect();
    let tied_with: Vec<Vec<usize>> =
        runners.iter().filter(|(_, v)| value > 0.0 && tied(*v, value)).map(|(set, _)| set.clone()).collect();
    let note = if archives < 2 {
        Some(ONE_UNIT)
    } else if value <= 0.0 {
        Some(NO_CANDIDATE_LEGIBLE)
    } else {
        None
    };
    if note.is_some() || resampling.replicates == 0 {
        let runners_up = runners.iter().map(|(set, v)| runner_up(choices, set, *v, None)).collect();
        return Assessment { interval_s, p_best: None, p_within_epsilon: None, runners_up, tied_with, note };
    }
    // The sets credited in each replicate: the answer, then its runners-up;
    // the replicate's own best joins them when it is none of these.
    let mut pool: Vec<Vec<usize>> = vec![reported.clone()];
    pool.extend(runners.iter().map(|(set, _)| set.clone()));
    let weights = bootstrap_weights(archives, resampling);
    let draws: Vec<Vec<f64>> = weights
        .into_par_iter()
        .map(|w| {
            let replicate = universe.weighted(w);
            let best = best_set(&replicate, choices, k, objective, exhaustive_limit)
                .map(|f| sorted(&f.picked))
                .unwrap_or_default();
            let mut sets = pool.clone();
            if !pool.contains(&best) {
                sets.push(best);
            }
            let scores: Vec<f64> =
                sets.iter().map(|set| replicate.score(choices, set, objective).0).collect();
            minimal_scores(&sets, scores)
        })
        .collect();
    let shares = best_shares(draws, pool.len(), resampling.epsilon_s);
    Assessment {
        interval_s,
        p_best: Some(shares.p_best[0]),
        p_within_epsilon: Some(shares.p_within_epsilon[0]),
        runners_up: runners
            .iter()
            .enumerate()
            .map(|(i, (set, v))| runner_up(choices, set, *v, Some(shares.p_best[i + 1])))
            .collect(),
        tied_with,
        note,
    }
}

/// `scores` with a set that holds another set of `sets` scoring at least as
/// well set to −∞: a set padded with members that add nothing in this
/// replicate is the smaller set again, not a second best.
fn minimal_scores(sets: &[Vec<usize>], scores: Vec<f64>) -> Vec<f64> {
    sets.iter()
        .enumerate()
        .map(|(i, set)| {
            let padded = sets.iter().enumerate().any(|(j, other)| {
                j != i
                    && other.len() < set.len()
                    && other.iter().all(|c| set.contains(c))
                    && (scores[j] >= scores[i] || tied(scores[j], scores[i]))
            });
            if padded { f64::NEG_INFINITY } else { scores[i] }
        })
        .collect()
}

fn runner_up(choices: &[Choice], set: &[usize], legible_s: f64, p_best: Option<f64>) -> RunnerUpRecord {
    RunnerUpRecord {
        candidates: set.iter().flat_map(|&c| choices[c].names.clone()).collect(),
        displays: crate::placement::search::displays(choices, set),
        legible_s,
        p_best,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_t_interval_needs_two_values_and_holds_the_mean() {
        assert_eq!(t_interval(&[1.0]), None);
        let [low, high] = t_interval(&[1.0, 2.0, 3.0]).unwrap();
        // mean 2, s = 1, n = 3: half-width 4.303 / sqrt 3.
        assert!((high - 2.0 - 4.303 / 3f64.sqrt()).abs() < 1e-9 && low == 0.0);
    }

    #[test]
    fn bootstrap_weights_draw_n_archives_each_and_repeat_with_the_seed() {
        let resampling = Resampling { replicates: 50, seed: 9, epsilon_s: 0.0 };
        let a = bootstrap_weights(4, &resampling);
        assert!(a.iter().all(|w| w.iter().sum::<f64>() == 4.0));
        assert_eq!(a, bootstrap_weights(4, &resampling));
    }

    use crate::placement::search::{EXHAUSTIVE_LIMIT, SparseBits, best_set};
    use crate::placement::table::CandidateKind;

    /// `archives` archives of 64 frames at 0.1 s; `tied` choices legible in
    /// the same frames of every archive (frames 0..10 + archive), one less
    /// legible (frames 0..5).
    fn tie_of(tied: usize, archives: usize) -> (Universe, Vec<Choice>) {
        let universe = Universe {
            ranges: (0..archives).map(|a| a..a + 1).collect(),
            frame_s: vec![0.1; archives],
            duration_s: vec![6.4; archives],
            weights: vec![1.0; archives],
            words: archives,
        };
        let mask = |frames: u32| if frames >= 64 { u64::MAX } else { (1u64 << frames) - 1 };
        let mut choices: Vec<Choice> = (0..tied)
            .map(|c| Choice {
                names: vec![format!("tied_{c}")],
                kind: CandidateKind::Part,
                bits: SparseBits::from_words((0..archives).map(|a| (a, mask(10 + a as u32))).collect()),
            })
            .collect();
        choices.push(Choice {
            names: vec!["less".into()],
            kind: CandidateKind::Part,
            bits: SparseBits::from_words((0..archives).map(|a| (a, mask(5))).collect()),
        });
        (universe, choices)
    }

    fn assessed(universe: &Universe, choices: &[Choice]) -> Assessment {
        let found = best_set(universe, choices, 1, Objective::Mean, EXHAUSTIVE_LIMIT).unwrap();
        assess(universe, choices, &found, 1, EXHAUSTIVE_LIMIT, &Resampling::default())
    }

    #[test]
    fn an_exact_tie_of_k_sets_gives_each_one_over_k() {
        for t in [2usize, 3, 7] {
            let (universe, choices) = tie_of(t, 4);
            let a = assessed(&universe, &choices);
            let share = 1.0 / t as f64;
            assert!((a.p_best.unwrap() - share).abs() < 1e-9, "{t}: {:?}", a.p_best);
            assert_eq!(a.tied_with.len(), t - 1, "{t}");
            let tied: Vec<f64> = a
                .runners_up
                .iter()
                .filter(|r| r.candidates[0].starts_with("tied"))
                .map(|r| r.p_best.unwrap())
                .collect();
            assert_eq!(tied.len(), t - 1);
            assert!(tied.iter().all(|p| (p - share).abs() < 1e-9), "{t}: {tied:?}");
            assert_eq!(a.p_within_epsilon, Some(1.0));
            assert_eq!(a.note, None);
        }
    }

    #[test]
    fn one_unit_or_nothing_legible_gives_no_p_best() {
        let (universe, choices) = tie_of(1, 1);
        let a = assessed(&universe, &choices);
        assert_eq!((a.p_best, a.p_within_epsilon, a.note), (None, None, Some(ONE_UNIT)));
        let (universe, mut choices) = tie_of(3, 4);
        for c in &mut choices {
            c.bits = SparseBits::default();
        }
        let a = assessed(&universe, &choices);
        assert_eq!((a.p_best, a.note), (None, Some(NO_CANDIDATE_LEGIBLE)));
        assert!(a.tied_with.is_empty());
    }

    #[test]
    fn tied_credits_share_one_draw_exactly() {
        assert_eq!(tied_best_credits(&[1.0, 3.0, 3.0, 2.0]), vec![0.0, 0.5, 0.5, 0.0]);
        assert_eq!(tied_best_credits(&[2.0; 7]), vec![1.0 / 7.0; 7]);
        let shares = best_shares(vec![vec![1.0, 1.0, 0.97], vec![2.0, 1.0, 0.0]], 3, 0.05);
        assert_eq!(shares.p_best, vec![0.75, 0.25, 0.0]);
        assert_eq!(shares.p_within_epsilon, vec![1.0, 0.5, 0.5]);
    }
}
