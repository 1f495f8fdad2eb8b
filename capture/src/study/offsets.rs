//! A study setting's error against the exact measure of the *whole*
//! scenario, and the 95 % interval of the error a capture at that setting
//! gets at an arbitrary frame offset.
//!
//! A capture every `s`-th frame may start at any of the offsets `0 … s − 1`;
//! which one is chance (where the scenario starts against the frame grid), and
//! the error depends on it far more than on the resolution (on demo A, 20 px/°
//! every 30th frame is 0.9–5.9 pp off depending on the offset). So the
//! interval is a **prediction interval over offsets**: the 2.5 and 97.5
//! percentiles of the share L1 (against the exact measure summed over every
//! frame) of a capture whose offset is drawn uniformly. Per offset `o`, the
//! rendered part totals are `Σ_{f ∈ F(s,o)} e(f) + d(f)`: `e`, the exact
//! measure per frame (both eyes summed), is known on every frame, so the
//! frame-subsampling part is computed exactly for every offset; `d = r − e`,
//! the resolution's own difference, is known on every frame this resolution
//! rendered (the union of its settings' frames). A frame this resolution did
//! not render takes the `d` of the nearest rendered frame in time, and the
//! offset's sum gets the spread of that imputation, `d(f) − d(g)`, as the
//! difference of two moving-block bootstrap sums of the centred `d` over the
//! rendered frames in time order (whole frames, both eyes together, blocks of
//! `⌈n^⅓⌉` frames), `replicates` draws each.
//! Each offset weighs the same. When the grid renders every frame at a resolution (step 1 in the
//! grid), nothing is imputed and the interval is the exact range over offsets.
//!
//! When the exact measure sampled the texels (`--exact-sample`), the share L1
//! of the reference itself is uncertain, and biased up: noise in the reference
//! adds to a distance. A basic bootstrap corrects both: the reference is drawn
//! again around itself (normal draws of each part's relative standard error,
//! the `--sample` estimator's), the change of the setting's share L1 gives the
//! 2.5–97.5 % range of how far the sampled L1 lies from the one against every
//! texel, and the interval over offsets moves by it (mostly down). The bound
//! through the triangle inequality that stood here before (plus the noise of
//! imputed offsets) covered always but moved each end by 36 pp at 1/8 of a 256²
//! palette; this correction moves them by 12 pp there and still covers all 792
//! cases of `capture/tests/it/study_coverage.rs` — a reference that noisy cannot
//! judge a 1 pp tolerance, and the interval says so. Nothing changes when every
//! texel is ray traced (6.3 s for demo A at 1024²).

use ufcsr::format::ErrorVsExact;

use crate::exact::accuracy::{share_error, share_l1_pp};
use ufcsr::SplitMix64;

/// One resolution's per-frame part values, indexed by frame number (every
/// frame of the scenario), both eyes summed.
#[derive(Debug, Clone, Copy)]
pub struct FrameValues<'a> {
    /// The exact measure on every frame.
    pub exact: &'a [Vec<f64>],
    /// The rendered values where this resolution rendered the frame.
    pub rendered: &'a [Option<Vec<f64>>],
}

/// How [`setting_error`] draws its interval.
#[derive(Debug, Clone, Copy)]
pub struct IntervalOptions<'a> {
    /// The setting's frame step.
    pub step: u32,
    /// The offset the setting was captured at: its point value.
    pub offset: u32,
    /// Per part, the exact totals' relative standard error from texel
    /// sampling (empty or zeros when every texel was ray traced).
    pub relative_error: &'a [f64],
    /// Bootstrap draws per offset that needs imputation.
    pub replicates: u32,
    pub seed: u64,
}

fn sum_frames(rows: &[Vec<f64>], frames: &[usize], parts: usize) -> Vec<f64> {
    let mut sum = vec![0.0; parts];
    for &f in frames {
        sum.iter_mut().zip(&rows[f]).for_each(|(s, v)| *s += v);
    }
    sum
}

/// The frames of a capture every `step`-th frame from `offset`, as every command keeps them
/// ([`crate::job::stepped_frames`]; the setting's own frames at its phase).
fn offset_frames(step: u32, offset: u32, frames: usize) -> Vec<usize> {
    let frames = u32::try_from(frames).unwrap_or(u32::MAX);
    crate::job::stepped_frames(frames, step, offset).into_iter().map(|f| f as usize).collect()
}

/// The share L1 against the exact measure of every frame of a capture every
/// `step`-th frame from `offset`, when this resolution rendered all its
/// frames (`None` otherwise): the true error at that offset.
pub fn error_at_offset(values: FrameValues, step: u32, offset: u32) -> Option<f64> {
    let parts = values.exact.first().map_or(0, Vec::len);
    let all = sum_frames(values.exact, &(0..values.exact.len()).collect::<Vec<_>>(), parts);
    let frames = offset_frames(step, offset, values.exact.len());
    let rendered: Option<Vec<Vec<f64>>> = frames.iter().map(|&f| values.rendered[f].clone()).collect();
    let rendered = rendered?;
    let indices: Vec<usize> = (0..rendered.len()).collect();
    Some(share_l1_pp(&all, &sum_frames(&rendered, &indices, parts)))
}

/// What one offset contributes to the pooled distribution.
struct OffsetDraws {
    frame_step_pp: f64,
    /// `(share L1, weight)`; the weights of one offset add up to 1.
    values: Vec<(f64, f64)>,
    imputed: bool,
}

/// The resolution differences `r − e` of the rendered frames, in time order,
/// with their frame numbers, and their mean.
struct Known {
    frames: Vec<usize>,
    differences: Vec<Vec<f64>>,
    /// The differences less their mean per part: what the bootstrap draws.
    centred: Vec<Vec<f64>>,
}

impl Known {
    fn new(values: FrameValues) -> Known {
        let (mut frames, mut differences) = (Vec::new(), Vec::new());
        for (f, (r, e)) in values.rendered.iter().zip(values.exact).enumerate() {
            if let Some(r) = r {
                frames.push(f);
                differences.push(r.iter().zip(e).map(|(a, b)| a - b).collect::<Vec<f64>>());
            }
        }
        let parts = values.exact.first().map_or(0, Vec::len);
        let n = differences.len().max(1) as f64;
        let mean: Vec<f64> = (0..parts).map(|p| differences.iter().map(|d| d[p]).sum::<f64>() / n).collect();
        let centred = differences.iter().map(|d| d.iter().zip(&mean).map(|(v, m)| v - m).collect()).collect();
        Known { frames, differences, centred }
    }

    /// The difference of the rendered frame nearest to `frame` (the earlier on a tie).
    fn nearest(&self, frame: usize) -> &[f64] {
        let at = self.frames.partition_point(|&f| f < frame);
        let pick = match (at.checked_sub(1), self.frames.get(at)) {
            (Some(before), Some(&after)) if after - frame < frame - self.frames[before] => at,
            (Some(before), _) => before,
            (None, _) => at,
        };
        &self.differences[pick]
    }
}

/// Adds `sign` × `count` centred resolution differences drawn in moving blocks from `centred`.
fn add_blocks(sum: &mut [f64], centred: &[Vec<f64>], (count, sign): (usize, f64), random: &mut SplitMix64) {
    let block = ((centred.len() as f64).cbrt().ceil() as usize).clamp(1, centred.len());
    let mut left = count;
    while left > 0 {
        let start = (random.next_u64() % (centred.len() - block + 1) as u64) as usize;
        let take = block.min(left);
        for d in &centred[start..start + take] {
            sum.iter_mut().zip(d).for_each(|(s, v)| *s += sign * v);
        }
        left -= take;
    }
}

fn offset_draws(
    values: FrameValues,
    all: &[f64],
    known: &Known,
    (options, offset): (&IntervalOptions, u32),
    random: &mut SplitMix64,
) -> OffsetDraws {
    let parts = all.len();
    let frames = offset_frames(options.step, offset, values.exact.len());
    let mut base = sum_frames(values.exact, &frames, parts);
    let frame_step_pp = share_l1_pp(all, &base);
    // A frame not rendered takes the difference of the nearest rendered frame; the bootstrap
    // then adds the spread of the differences around their mean.
    let mut missing = 0;
    for &f in &frames {
        let difference: Vec<f64> = match &values.rendered[f] {
            Some(r) => r.iter().zip(&values.exact[f]).map(|(a, b)| a - b).collect(),
            None if known.frames.is_empty() => continue,
            None => {
                missing += 1;
                known.nearest(f).to_vec()
            }
        };
        base.iter_mut().zip(difference).for_each(|(s, d)| *s += d);
    }
    if missing == 0 || options.replicates == 0 {
        return OffsetDraws { frame_step_pp, values: vec![(share_l1_pp(all, &base), 1.0)], imputed: false };
    }
    let weight = 1.0 / f64::from(options.replicates);
    let draws = (0..options.replicates)
        .map(|_| {
            let mut sum = base.clone();
            // The imputed frame's own difference less its neighbour's: two draws.
            add_blocks(&mut sum, &known.centred, (missing, 1.0), random);
            add_blocks(&mut sum, &known.centred, (missing, -1.0), random);
            (share_l1_pp(all, &sum), weight)
        })
        .collect();
    OffsetDraws { frame_step_pp, values: draws, imputed: true }
}

/// The weighted `q`-quantile: the smallest value whose cumulative weight reaches `q` of the total.
fn weighted_quantile(sorted: &[(f64, f64)], q: f64) -> f64 {
    let total: f64 = sorted.iter().map(|(_, w)| w).sum();
    let mut cumulative = 0.0;
    for &(value, weight) in sorted {
        cumulative += weight;
        if cumulative >= q * total * (1.0 - 1e-12) {
            return value;
        }
    }
    sorted.last().map_or(0.0, |(v, _)| *v)
}

/// How the reference's texel sampling moves a share L1 (see the module doc), as a basic
/// bootstrap: the reference over every frame is drawn again around itself (each part's total
/// times `1 + relative error × z`), and the change of the setting's share L1 against it,
/// `Δ = L1(rendered, redrawn) − L1(rendered, reference)`, stands for how far the sampled
/// reference's L1 lies from the one against every texel. A share L1 against a noisy reference
/// is biased up (noise adds to it), so `Δ` is mostly positive and the interval moves *down*.
/// The setting's own offset's `Δ` stands for every offset: the noise is one factor per part,
/// common to every frame (the same sampled texels), so in an imputed offset it enters the
/// exact side and the imputed rendered side alike and cancels to first order.
///
/// The basic bootstrap alone is not honest at the low end: a share L1 is not
/// a smooth function near zero (|x| has a corner there), so when the
/// setting's true error is small beside the reference's noise the sampled
/// L1 is mostly that noise, `Δ` a fraction of it, and `point − Δ` stays well
/// above the truth (1/8 of demo A at 1024², 20 px/° every frame: 0.079–1.928
/// pp around a true 0.0549 pp). The low end is therefore the interval's less
/// the 97.5th percentile of the reference's own noise, `L1(redrawn,
/// reference)` — by the triangle inequality the true L1 is at least the
/// sampled one less that noise — and the high end stays the basic
/// bootstrap's (which the noise only pushes up).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
struct TexelSampling {
    /// 2.5th and 97.5th percentile of `Δ`.
    delta: [f64; 2],
    /// 97.5th percentile of the reference's noise as a share L1, `L1(redrawn, reference)`.
    noise: f64,
}

impl TexelSampling {
    /// The interval over offsets `[low, high]` corrected for the reference's sampling.
    fn correct(self, [low, high]: [f64; 2]) -> [f64; 2] {
        [(low - self.noise.max(self.delta[1])).max(0.0), (high - self.delta[0]).max(0.0)]
    }

    /// The most it moves an end of the interval, for `study.json`.
    fn largest_shift_pp(self) -> f64 {
        self.delta[0].abs().max(self.delta[1].abs()).max(self.noise)
    }
}

fn texel_sampling(
    all: &[f64],
    rendered: &[f64],
    relative_error: &[f64],
    random: &mut SplitMix64,
) -> Option<TexelSampling> {
    if !relative_error.iter().any(|e| *e > 0.0) {
        return None;
    }
    let jitter = |values: &[f64], z: &[f64]| -> Vec<f64> {
        values
            .iter()
            .zip(relative_error.iter().zip(z))
            .map(|(v, (e, z))| (v * (1.0 + e * z)).max(0.0))
            .collect()
    };
    let point = share_l1_pp(rendered, all);
    let draws = crate::study::BOOTSTRAP_REPLICATES as usize;
    let mut noises = Vec::with_capacity(draws);
    let mut deltas: Vec<f64> = (0..draws)
        .map(|_| {
            let z: Vec<f64> = (0..all.len()).map(|_| random.normal()).collect();
            let redrawn = jitter(all, &z);
            noises.push(share_l1_pp(all, &redrawn));
            share_l1_pp(rendered, &redrawn) - point
        })
        .collect();
    let quantile = |values: &mut Vec<f64>, q: f64| -> f64 {
        values.sort_by(f64::total_cmp);
        values
            .get(
                ((q * (values.len().max(1) - 1) as f64).round() as usize).min(values.len().saturating_sub(1)),
            )
            .copied()
            .unwrap_or(0.0)
    };
    Some(TexelSampling {
        delta: [quantile(&mut deltas, 0.025), quantile(&mut deltas, 0.975)],
        noise: quantile(&mut noises, 0.975),
    })
}

/// The setting's error against the exact measure of every frame at its own
/// offset, and the interval over offsets (module doc). `None` when the
/// setting's own frames were not all rendered.
pub fn setting_error(
    parts: &[String],
    measure: &str,
    values: FrameValues,
    options: &IntervalOptions,
) -> Option<ErrorVsExact> {
    let frames = values.exact.len();
    let all = sum_frames(values.exact, &(0..frames).collect::<Vec<_>>(), parts.len());
    let own = offset_frames(options.step, options.offset, frames);
    let rendered: Option<Vec<Vec<f64>>> = own.iter().map(|&f| values.rendered[f].clone()).collect();
    let rendered = sum_frames(&rendered?, &(0..own.len()).collect::<Vec<_>>(), parts.len());
    let exact_own = sum_frames(values.exact, &own, parts.len());
    let known = Known::new(values);
    let mut random = SplitMix64(options.seed);
    let offsets = options.step.max(1).min(frames.max(1) as u32);
    let draws: Vec<OffsetDraws> =
        (0..offsets).map(|o| offset_draws(values, &all, &known, (options, o), &mut random)).collect();
    let imputed = draws.iter().filter(|d| d.imputed).count() as u32;
    let mut pool: Vec<(f64, f64)> = draws.iter().flat_map(|d| d.values.iter().copied()).collect();
    pool.sort_by(|a, b| a.0.total_cmp(&b.0));
    let steps: Vec<f64> = draws.iter().map(|d| d.frame_step_pp).collect();
    let error = share_error(parts, &all, &rendered);
    let texel = texel_sampling(&all, &rendered, options.relative_error, &mut random);
    let point = error.share_l1_pp;
    let over_offsets = [weighted_quantile(&pool, 0.025), weighted_quantile(&pool, 0.975)];
    // With every texel ray traced the interval holds the point (its own offset); against a
    // sampled reference the point itself is biased up and the corrected interval may lie below it.
    let ci95_pp = match texel {
        Some(texel) => texel.correct(over_offsets),
        None => [over_offsets[0].max(0.0).min(point), over_offsets[1].max(point)],
    };
    Some(ErrorVsExact {
        measure: measure.into(),
        ci95_pp,
        replicates: if imputed > 0 { options.replicates } else { 0 },
        frame_step_pp: share_l1_pp(&all, &exact_own),
        frame_step_range_pp: [
            steps.iter().copied().fold(f64::INFINITY, f64::min),
            steps.iter().copied().fold(0.0, f64::max),
        ],
        resolution_pp: share_l1_pp(&exact_own, &rendered),
        offsets,
        imputed_offsets: imputed,
        texel_sampling_pp: texel.map_or(0.0, TexelSampling::largest_shift_pp),
        error,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names(n: usize) -> Vec<String> {
        (0..n).map(|i| format!("p{i}")).collect()
    }

    /// Two parts; part 0 is seen only in the first half of 8 frames.
    fn exact() -> Vec<Vec<f64>> {
        (0..8).map(|f| vec![if f < 4 { 2.0 } else { 0.0 }, 1.0]).collect()
    }

    fn options(step: u32, relative_error: &[f64]) -> IntervalOptions<'_> {
        IntervalOptions { step, offset: 0, relative_error, replicates: 200, seed: 1 }
    }

    #[test]
    fn a_perfect_render_every_frame_has_no_error_and_a_point_interval() {
        let exact = exact();
        let rendered: Vec<Option<Vec<f64>>> = exact.iter().cloned().map(Some).collect();
        let values = FrameValues { exact: &exact, rendered: &rendered };
        let e = setting_error(&names(2), "angular-area", values, &options(1, &[])).unwrap();
        assert_eq!((e.error.share_l1_pp, e.ci95_pp, e.offsets, e.imputed_offsets), (0.0, [0.0, 0.0], 1, 0));
    }

    #[test]
    fn the_frame_step_error_is_against_every_frame_and_ranges_over_the_offsets() {
        // Every 3rd frame of a perfect render: offset 0 sees frames 0, 3, 6 (part 0 in two of
        // three: totals 4 and 3, shares 57.1/42.9), against every frame 8 and 8 (50/50): 14.29 pp.
        // Offset 1 (1, 4, 7: 2 and 3) 20 pp, offset 2 (2, 5: 2 and 2) 0 pp.
        let exact = exact();
        let rendered: Vec<Option<Vec<f64>>> = exact.iter().cloned().map(Some).collect();
        let values = FrameValues { exact: &exact, rendered: &rendered };
        let e = setting_error(&names(2), "angular-area", values, &options(3, &[])).unwrap();
        let close = |a: f64, b: f64| (a - b).abs() < 1e-9;
        assert!(close(e.error.share_l1_pp, 100.0 / 7.0), "{e:?}");
        assert!(close(e.frame_step_pp, 100.0 / 7.0));
        assert!(close(e.frame_step_range_pp[0], 0.0) && close(e.frame_step_range_pp[1], 20.0), "{e:?}");
        // Every offset rendered: the interval is the exact range over the offsets.
        assert!(close(e.ci95_pp[0], 0.0) && close(e.ci95_pp[1], 20.0), "{e:?}");
        assert_eq!((e.imputed_offsets, e.replicates, e.resolution_pp), (0, 0, 0.0));
        for (offset, want) in [(0, 100.0 / 7.0), (1, 20.0), (2, 0.0)] {
            assert!(close(error_at_offset(values, 3, offset).unwrap(), want));
        }
    }

    #[test]
    fn offsets_the_resolution_did_not_render_are_imputed_and_widen_the_interval() {
        // Rendered only on the frames every 2nd frame keeps (its phase 1: frames 1, 3, 5, 7), with
        // part 1 read 10 % high; offset 0 keeps frames 2, 4, 6 (frame 0's two frames are half
        // outside), which are imputed.
        let exact = exact();
        let rendered: Vec<Option<Vec<f64>>> =
            exact.iter().enumerate().map(|(f, e)| (f % 2 == 1).then(|| vec![e[0], e[1] * 1.1])).collect();
        let values = FrameValues { exact: &exact, rendered: &rendered };
        let own = IntervalOptions { offset: crate::job::step_phase(2), ..options(2, &[]) };
        let e = setting_error(&names(2), "angular-area", values, &own).unwrap();
        assert_eq!((e.offsets, e.imputed_offsets, e.replicates), (2, 1, 200));
        assert!(e.ci95_pp[0] <= e.error.share_l1_pp && e.error.share_l1_pp <= e.ci95_pp[1], "{e:?}");
        assert!(e.resolution_pp > 0.0 && e.frame_step_pp == 0.0, "{e:?}");
        // The setting's own frames must have been rendered.
        assert!(
            setting_error(&names(2), "count", values, &IntervalOptions { offset: 0, ..options(2, &[]) })
                .is_none()
        );
    }

    #[test]
    fn texel_sampling_moves_both_ends_of_the_interval_and_not_the_point() {
        let exact = exact();
        let rendered: Vec<Option<Vec<f64>>> = exact.iter().map(|e| Some(vec![e[0] * 1.05, e[1]])).collect();
        let values = FrameValues { exact: &exact, rendered: &rendered };
        let sharp = setting_error(&names(2), "angular-area", values, &options(1, &[])).unwrap();
        let noisy = setting_error(&names(2), "angular-area", values, &options(1, &[0.01, 0.01])).unwrap();
        assert_eq!(sharp.texel_sampling_pp, 0.0);
        assert!(noisy.texel_sampling_pp > 0.1, "{noisy:?}");
        assert!(noisy.ci95_pp[0] < sharp.ci95_pp[0] && noisy.ci95_pp[1] > sharp.ci95_pp[1], "{noisy:?}");
        assert_eq!(noisy.error, sharp.error);
    }

    #[test]
    fn against_a_noisy_reference_the_interval_covers_a_setting_error_far_below_the_noise() {
        // 30 parts; the setting is 0.2 % off per part (a true share L1 of about 0.1 pp), the
        // reference ray traced a sample with 5 % relative error per part (its own noise about
        // 2 pp): the sampled L1 is mostly noise. Over 200 references drawn around the truth the
        // interval must hold the true error in at least 95 % of them, and stay within the
        // sampled L1 plus twice the noise.
        let mut random = SplitMix64(7);
        let parts = 30;
        let truth: Vec<f64> = (0..parts).map(|_| 0.2 + random.uniform()).collect();
        let rendered: Vec<f64> = truth.iter().map(|t| t * (1.0 + 0.002 * random.normal())).collect();
        let true_error = share_l1_pp(&truth, &rendered);
        let relative = vec![0.05; parts];
        let (mut covered, runs) = (0, 200);
        for seed in 0..runs {
            let reference: Vec<f64> = truth.iter().map(|t| t * (1.0 + 0.05 * random.normal())).collect();
            let exact = vec![reference];
            let frames = vec![Some(rendered.clone())];
            let values = FrameValues { exact: &exact, rendered: &frames };
            let options = IntervalOptions { seed, ..options(1, &relative) };
            let e = setting_error(&names(parts), "angular-area", values, &options).unwrap();
            if e.ci95_pp[0] <= true_error && true_error <= e.ci95_pp[1] {
                covered += 1;
            }
            assert!(e.ci95_pp[1] <= e.error.share_l1_pp + 2.0 * e.texel_sampling_pp, "{e:?}");
            assert!(e.texel_sampling_pp > 1.0, "the reference's noise is reported: {e:?}");
        }
        assert!(covered * 100 >= runs * 95, "{covered} of {runs} cover the true {true_error:.4} pp");
    }
}
