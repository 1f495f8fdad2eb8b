//! The pieces `study` compares a rendered setting with the exact measure
//! of the same quantity by: per-part values per eye-frame
//! ([`PerEyeFrame`]; the rendered one from `frames.csv`, texels seen per
//! eye-frame for the count and the pixels' solid angle for the angular
//! area; the exact one from the ray casts), their part totals, the share
//! error of two sets of totals ([`share_error`]) and a seeded generator.
//! The study's interval over frame offsets is `crate::study::offsets`.

/// Per-part values of every eye-frame, keyed by `(frame, eye)`.
#[derive(Debug, Clone, Default, PartialEq)]
pub(crate) struct PerEyeFrame {
    pub parts: Vec<String>,
    /// `(frame, eye, one value per part)`, in eye-frame order.
    pub rows: Vec<(u32, String, Vec<f64>)>,
}

impl PerEyeFrame {
    /// The rows of `frames`, in their order; `None` when one is missing.
    pub(crate) fn select(&self, frames: &[u32]) -> Option<Vec<&[f64]>> {
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
}

/// Part totals: the sum of `rows` (each one value per part).
pub(crate) fn totals(rows: &[&[f64]], parts: usize) -> Vec<f64> {
    let mut sum = vec![0.0; parts];
    for row in rows {
        sum.iter_mut().zip(row.iter()).for_each(|(s, v)| *s += v);
    }
    sum
}

/// The share error of `candidate` against `reference` (part totals of the
/// same parts, in the same order); the type is `study.json`'s.
pub(crate) use ufcsr::format::ShareError;

fn shares(values: &[f64]) -> Vec<f64> {
    let sum: f64 = values.iter().sum();
    values.iter().map(|v| if sum > 0.0 { 100.0 * v / sum } else { 0.0 }).collect()
}

/// Share L1 alone (for the bootstrap).
pub(crate) fn share_l1_pp(reference: &[f64], candidate: &[f64]) -> f64 {
    shares(reference).iter().zip(shares(candidate)).map(|(a, b)| (a - b).abs()).sum()
}

fn top5(names: &[String], values: &[f64]) -> Vec<usize> {
    let mut order: Vec<usize> = (0..values.len()).collect();
    order.sort_by(|&a, &b| values[b].total_cmp(&values[a]).then_with(|| names[a].cmp(&names[b])));
    order.truncate(5);
    order
}

/// Compares part totals (see [`ShareError`]).
pub(crate) fn share_error(names: &[String], reference: &[f64], candidate: &[f64]) -> ShareError {
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
}
