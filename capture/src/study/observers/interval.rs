//! What the observers say about the population: the mean, its 95 % interval
//! and the spread over people.
//!
//! For independently drawn observers the interval of the population mean
//! is the Student-t interval `mean ± t(0.975, n−1) · s/√n` (the Monte Carlo
//! part, shrinking like 1/√n as observers are added), widened on both sides
//! by the mean of the observers' own resolution bounds (each observer's
//! rendered value is within its bound of its exact value, so the mean of
//! the rendered values is within the mean bound of the mean of the exact
//! ones). A grid gets no interval: its error is a quadrature error, not a
//! spread. The spread over people is the 2.5th–97.5th percentile of the
//! observers' values. `capture/tests/it/observers.rs` measures the
//! interval's coverage against a population mean known from a dense
//! quadrature (`docs/science.md` states it).

use ufcsr::format::PopulationValue;

/// Which interval the sampling supports.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum IntervalKind {
    /// Independent draws: the Student-t interval of the mean.
    MonteCarlo,
    /// A deterministic grid: no interval.
    None,
}

use ufcsr::t975;

/// Percentile `q` (0–1) of sorted values, interpolated linearly between
/// order statistics (Hyndman & Fan type 7, as R's and NumPy's default).
pub fn percentile(sorted: &[f64], q: f64) -> f64 {
    let position = q * (sorted.len() - 1) as f64;
    let below = position.floor() as usize;
    let above = (below + 1).min(sorted.len() - 1);
    sorted[below] + (sorted[above] - sorted[below]) * (position - below as f64)
}

/// The value over the observers: mean, 95 % interval of the population
/// mean (with `bounds`, each observer's resolution bound, folded in; cut
/// at 0 when no value is negative) and the spread. `values` must not be empty.
pub fn population_value(values: &[f64], bounds: Option<&[f64]>, kind: IntervalKind) -> PopulationValue {
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    let resolution_bound = bounds.map(|b| b.iter().sum::<f64>() / b.len().max(1) as f64);
    let monte_carlo_half_width = match kind {
        IntervalKind::MonteCarlo if values.len() >= 2 => {
            let variance = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
            Some(t975(values.len() - 1) * (variance / n).sqrt())
        }
        _ => None,
    };
    // The mean of values that cannot be negative cannot be: such an interval starts at 0 at the lowest.
    let floor = if sorted[0] >= 0.0 { 0.0 } else { f64::NEG_INFINITY };
    let mean_ci95 = monte_carlo_half_width.map(|h| {
        let half = h + resolution_bound.unwrap_or(0.0);
        [(mean - half).max(floor), mean + half]
    });
    PopulationValue {
        mean,
        mean_ci95,
        monte_carlo_half_width,
        resolution_bound,
        p2_5: percentile(&sorted, 0.025),
        p97_5: percentile(&sorted, 0.975),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_interval_of_known_values_is_mean_plus_minus_t_s_over_root_n_plus_the_mean_bound() {
        // 1, 2, 3, 4: mean 2.5, s² = 5/3, t(0.975, 3) = 3.182.
        let values = [1.0, 2.0, 3.0, 4.0];
        let half = 3.182 * (5.0_f64 / 3.0 / 4.0).sqrt();
        let plain = population_value(&values, None, IntervalKind::MonteCarlo);
        assert!(
            (plain.mean - 2.5).abs() < 1e-12 && (plain.monte_carlo_half_width.unwrap() - half).abs() < 1e-12
        );
        assert_eq!(plain.mean_ci95, Some([2.5 - half, 2.5 + half]));
        // Linear percentiles: 2.5 % of the way from the first to the last of 4 is 1.075.
        assert!((plain.p2_5 - 1.075).abs() < 1e-12 && (plain.p97_5 - 3.925).abs() < 1e-12);
        let bounded = population_value(&values, Some(&[0.1, 0.3, 0.2, 0.2]), IntervalKind::MonteCarlo);
        assert!((bounded.resolution_bound.unwrap() - 0.2).abs() < 1e-12);
        let [low, high] = bounded.mean_ci95.unwrap();
        assert!((low - (2.5 - half - 0.2)).abs() < 1e-12 && (high - (2.5 + half + 0.2)).abs() < 1e-12);
        // Values that cannot be negative: the interval starts at 0 at the lowest.
        let wide = population_value(&[0.0, 10.0], None, IntervalKind::MonteCarlo);
        assert_eq!(wide.mean_ci95.unwrap()[0], 0.0);
        let signed = population_value(&[-1.0, 10.0], None, IntervalKind::MonteCarlo);
        assert!(signed.mean_ci95.unwrap()[0] < -50.0);
        // A grid, or one observer: no interval claimed.
        let grid = population_value(&values, None, IntervalKind::None);
        assert_eq!((grid.mean_ci95, grid.monte_carlo_half_width), (None, None));
        assert_eq!(population_value(&[7.0], None, IntervalKind::MonteCarlo).mean_ci95, None);
    }
}
