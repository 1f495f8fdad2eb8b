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
//!   archives with replacement, as weights) re-runs the search and counts
//!   how often each set is the replicate's best; **P(within ε)** how often
//!   the reported set is at most ε seconds below the replicate's best.
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
pub const CONFIDENCE: f64 = 0.95;
/// Bootstrap replicates by default.
pub const DEFAULT_REPLICATES: usize = 1000;
/// The default ε of P(within ε), seconds: about three frames at 60 fps.
pub const DEFAULT_EPSILON_S: f64 = 0.05;

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
pub struct Assessment {
    pub interval_s: Option<[f64; 2]>,
    pub p_best: Option<f64>,
    pub p_within_epsilon: Option<f64>,
    pub runners_up: Vec<RunnerUpRecord>,
}

fn sorted(set: &[usize]) -> Vec<usize> {
    let mut set = set.to_vec();
    set.sort_unstable();
    set
}

/// The interval, P(best), P(within ε) and the runners-up of `found`, the
/// best set of at most `k` displays by the mean (see the module doc).
pub fn assess(
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
    if archives < 2 || resampling.replicates == 0 {
        let runners_up = runners.iter().map(|(set, v)| runner_up(choices, set, *v, None)).collect();
        return Assessment { interval_s, p_best: None, p_within_epsilon: None, runners_up };
    }
    let weights = bootstrap_weights(archives, resampling);
    let outcomes: Vec<(Vec<usize>, bool)> = weights
        .into_par_iter()
        .map(|w| {
            let replicate = universe.weighted(w);
            let best = best_set(&replicate, choices, k, objective, exhaustive_limit)
                .map(|f| sorted(&f.picked))
                .unwrap_or_default();
            let best_value = replicate.score(choices, &best, objective).0;
            let ours = replicate.score(choices, &reported, objective).0;
            (best, ours >= best_value - resampling.epsilon_s)
        })
        .collect();
    let share = |hits: usize| hits as f64 / outcomes.len() as f64;
    let p_of = |set: &[usize]| share(outcomes.iter().filter(|(best, _)| best == set).count());
    Assessment {
        interval_s,
        p_best: Some(p_of(&reported)),
        p_within_epsilon: Some(share(outcomes.iter().filter(|(_, within)| *within).count())),
        runners_up: runners.iter().map(|(set, v)| runner_up(choices, set, *v, Some(p_of(set)))).collect(),
    }
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
}
