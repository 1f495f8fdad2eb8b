//! How far a rendered setting is from the exact measure of the same
//! quantity, eye-frame by eye-frame, with a 95 % interval: what `study`
//! recommends by.
//!
//! Both sides are tables of per-part values per eye-frame ([`PerEyeFrame`]):
//! the rendered one from `frames.csv` (texels seen per eye-frame for the
//! count, the pixels' solid angle for the angular area), the exact one from
//! the ray casts (sampled texels visible, their solid angle; scaled by
//! texels / sampled texels per part under `--exact-sample`). A setting is
//! compared on its own eye-frames only ([`share_error`] of the sums over
//! them). The interval is a seeded bootstrap: when the frame step subsamples
//! the scenario, each replicate draws the setting's eye-frames with
//! replacement (the same draws on both sides), and when the exact measure
//! sampled the texels, it scales each part's exact total by a normal draw of
//! its relative standard error (from [`super::estimator`]); the 2.5 and 97.5
//! percentiles of the replicates' share L1 are the interval.

use serde::Serialize;

/// Per-part values of every eye-frame, keyed by `(frame, eye)`.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PerEyeFrame {
    pub parts: Vec<String>,
    /// `(frame, eye, one value per part)`, in eye-frame order.
    pub rows: Vec<(u32, String, Vec<f64>)>,
}

impl PerEyeFrame {
    /// The rows of `frames`, in their order; `None` when one is missing.
    pub fn select(&self, frames: &[u32]) -> Option<Vec<&[f64]>> {
        let mut selected = Vec::with_capacity(frames.len() * 2);
        for &frame in frames {
            let rows: Vec<&[f64]> =
                self.rows.iter().filter(|(f, _, _)| *f == frame).map(|(_, _, v)| v.as_slice()).collect();
            if rows.is_empty() {
                return None;
            }
            selected.extend(rows);
        }
        Some(selected)
    }

    /// The row of `(frame, eye)`.
    pub fn row(&self, frame: u32, eye: &str) -> Option<&[f64]> {
        self.rows.iter().find(|(f, e, _)| *f == frame && e == eye).map(|(_, _, v)| v.as_slice())
    }
}

/// Part totals: the sum of `rows` (each one value per part).
pub fn totals(rows: &[&[f64]], parts: usize) -> Vec<f64> {
    let mut sum = vec![0.0; parts];
    for row in rows {
        sum.iter_mut().zip(row.iter()).for_each(|(s, v)| *s += v);
    }
    sum
}

/// The share error of `candidate` against `reference` (part totals of the
/// same parts, in the same order).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ShareError {
    /// Σ |share difference| over parts, percentage points.
    pub share_l1_pp: f64,
    /// Largest |share difference| of one part, percentage points.
    pub share_max_pp: f64,
    pub share_max_part: String,
    /// Kendall's τ-b between the rankings by total.
    pub kendall_tau_b: f64,
    /// Parts in both top-5 lists by total, out of 5 (or fewer parts).
    pub top5_overlap: usize,
}

fn shares(values: &[f64]) -> Vec<f64> {
    let sum: f64 = values.iter().sum();
    values.iter().map(|v| if sum > 0.0 { 100.0 * v / sum } else { 0.0 }).collect()
}

/// Share L1 alone (for the bootstrap).
pub fn share_l1_pp(reference: &[f64], candidate: &[f64]) -> f64 {
    shares(reference).iter().zip(shares(candidate)).map(|(a, b)| (a - b).abs()).sum()
}

fn top5(names: &[String], values: &[f64]) -> Vec<usize> {
    let mut order: Vec<usize> = (0..values.len()).collect();
    order.sort_by(|&a, &b| values[b].total_cmp(&values[a]).then_with(|| names[a].cmp(&names[b])));
    order.truncate(5);
    order
}

/// Compares part totals (see [`ShareError`]).
pub fn share_error(names: &[String], reference: &[f64], candidate: &[f64]) -> ShareError {
    let (a, b) = (shares(reference), shares(candidate));
    let (mut share_max_pp, mut share_max_part) = (0.0f64, String::new());
    for ((x, y), name) in a.iter().zip(&b).zip(names) {
        if (x - y).abs() > share_max_pp {
            share_max_pp = (x - y).abs();
            share_max_part = name.clone();
        }
    }
    let pairs: Vec<(f64, f64)> = reference.iter().copied().zip(candidate.iter().copied()).collect();
    let (top_a, top_b) = (top5(names, reference), top5(names, candidate));
    ShareError {
        share_l1_pp: share_l1_pp(reference, candidate),
        share_max_pp,
        share_max_part,
        kendall_tau_b: ufcsr::kendall_tau_b(&pairs).0,
        top5_overlap: top_a.iter().filter(|p| top_b.contains(p)).count(),
    }
}

/// What the bootstrap varies.
#[derive(Debug, Clone)]
pub struct Resampling<'a> {
    /// Draw the eye-frames with replacement (the frame step subsamples).
    pub eye_frames: bool,
    /// Per part, the exact total's relative standard error (texel sampling;
    /// empty or zeros when every texel was measured).
    pub relative_error: &'a [f64],
    pub replicates: u32,
    pub seed: u64,
}

/// A small deterministic generator (SplitMix64): the interval must not
/// change from run to run.
pub(crate) struct SplitMix(pub(crate) u64);

impl SplitMix {
    pub(crate) fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in (0, 1).
    pub(crate) fn uniform(&mut self) -> f64 {
        ((self.next() >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    }

    /// Standard normal (Box–Muller).
    pub(crate) fn normal(&mut self) -> f64 {
        let (u, v) = (self.uniform(), self.uniform());
        (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
    }
}

/// The 95 % interval `[low, high]` of the share L1 between `candidate` and
/// `reference` rows (paired eye-frames), and the replicates drawn (0 when
/// nothing varies: then the interval is the point value).
pub fn share_l1_interval(
    reference: &[&[f64]],
    candidate: &[&[f64]],
    resampling: &Resampling,
) -> ([f64; 2], u32) {
    let parts = reference.first().map_or(0, |row| row.len());
    let point = share_l1_pp(&totals(reference, parts), &totals(candidate, parts));
    let texels_vary = resampling.relative_error.iter().any(|e| *e > 0.0);
    if !(resampling.eye_frames || texels_vary) || resampling.replicates == 0 || reference.is_empty() {
        return ([point, point], 0);
    }
    let mut random = SplitMix(resampling.seed);
    let mut values = Vec::with_capacity(resampling.replicates as usize);
    let n = reference.len();
    for _ in 0..resampling.replicates {
        let (mut a, mut b) = (vec![0.0; parts], vec![0.0; parts]);
        for draw in 0..n {
            let i = if resampling.eye_frames { (random.next() % n as u64) as usize } else { draw };
            a.iter_mut().zip(reference[i]).for_each(|(s, v)| *s += v);
            b.iter_mut().zip(candidate[i]).for_each(|(s, v)| *s += v);
        }
        for (value, error) in a.iter_mut().zip(resampling.relative_error) {
            if *error > 0.0 {
                *value = (*value * (1.0 + error * random.normal())).max(0.0);
            }
        }
        values.push(share_l1_pp(&a, &b));
    }
    values.sort_by(f64::total_cmp);
    let at = |q: f64| values[((q * (values.len() - 1) as f64).round() as usize).min(values.len() - 1)];
    ([at(0.025).min(point), at(0.975).max(point)], resampling.replicates)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names(n: usize) -> Vec<String> {
        (0..n).map(|i| format!("p{i}")).collect()
    }

    #[test]
    fn share_error_of_known_totals() {
        // Shares 50/30/20 against 40/40/20: L1 20 pp, largest 10 pp (p0).
        let e = share_error(&names(3), &[5.0, 3.0, 2.0], &[4.0, 4.0, 2.0]);
        assert!((e.share_l1_pp - 20.0).abs() < 1e-12);
        assert!((e.share_max_pp - 10.0).abs() < 1e-12);
        assert_eq!(e.share_max_part, "p0");
        assert_eq!(e.top5_overlap, 3);
        // Scale does not matter: shares only.
        assert!(share_error(&names(3), &[5.0, 3.0, 2.0], &[50.0, 30.0, 20.0]).share_l1_pp < 1e-12);
        assert_eq!(share_error(&names(3), &[1.0, 2.0, 3.0], &[3.0, 2.0, 1.0]).kendall_tau_b, -1.0);
    }

    #[test]
    fn the_interval_is_the_point_when_nothing_varies_and_brackets_it_otherwise() {
        let a: Vec<Vec<f64>> = (0..40).map(|i| vec![1.0 + (i % 3) as f64, 2.0, 0.5]).collect();
        let b: Vec<Vec<f64>> = (0..40).map(|i| vec![1.0, 2.0 + (i % 5) as f64, 0.5]).collect();
        let (ra, rb): (Vec<&[f64]>, Vec<&[f64]>) =
            (a.iter().map(Vec::as_slice).collect(), b.iter().map(Vec::as_slice).collect());
        let point = share_l1_pp(&totals(&ra, 3), &totals(&rb, 3));
        let fixed = Resampling { eye_frames: false, relative_error: &[], replicates: 200, seed: 1 };
        assert_eq!(share_l1_interval(&ra, &rb, &fixed), ([point, point], 0));
        let drawn = Resampling { eye_frames: true, ..fixed.clone() };
        let ([low, high], replicates) = share_l1_interval(&ra, &rb, &drawn);
        assert_eq!(replicates, 200);
        assert!(low < point && point < high, "{low} {point} {high}");
        // Same seed, same interval.
        assert_eq!(share_l1_interval(&ra, &rb, &drawn).0, [low, high]);
        // Identical sides under texel noise only: the interval starts at 0 and is as wide as the noise.
        let noisy = Resampling { eye_frames: false, relative_error: &[0.1, 0.1, 0.1], ..fixed };
        let ([low, high], _) = share_l1_interval(&ra, &ra, &noisy);
        assert_eq!(low, 0.0);
        assert!(high > 1.0 && high < 30.0, "{high}");
    }

    #[test]
    fn a_normal_draw_has_unit_variance() {
        let mut random = SplitMix(7);
        let draws: Vec<f64> = (0..20_000).map(|_| random.normal()).collect();
        let mean = draws.iter().sum::<f64>() / draws.len() as f64;
        let variance = draws.iter().map(|d| (d - mean).powi(2)).sum::<f64>() / draws.len() as f64;
        assert!(mean.abs() < 0.03 && (variance - 1.0).abs() < 0.05, "{mean} {variance}");
    }
}
