//! The `--sample` estimator: per-part totals of a seeded random share of the
//! texels, scaled to the whole part with finite-population standard errors.
//!
//! Both the count (eye-frames per texel) and the solid angle (sr·eye-frames
//! per texel) are estimated the same way: N · mean of the sample, standard
//! error `N · sqrt((1 − f) · s² / n)` with N texels in the part, n sampled,
//! f = n / N's design fraction and s² the sample variance.

use super::types::{SurfaceSamples, TexelVisibility};

/// Sums of one per-texel quantity over a part's sample.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(crate) struct SampleSums {
    pub sum: f64,
    pub sum_of_squares: f64,
}

impl SampleSums {
    fn add(&mut self, value: f64) {
        self.sum += value;
        self.sum_of_squares += value * value;
    }

    /// The estimated part total and its standard error.
    fn estimate(&self, texels: u64, sampled: u64, fraction: f64) -> Estimate {
        if sampled == 0 {
            return Estimate::default();
        }
        let n = sampled as f64;
        let mean = self.sum / n;
        let variance =
            if sampled > 1 { (self.sum_of_squares - n * mean * mean).max(0.0) / (n - 1.0) } else { 0.0 };
        Estimate {
            total: texels as f64 * mean,
            standard_error: texels as f64 * ((1.0 - fraction).max(0.0) * variance / n).sqrt(),
        }
    }
}

/// An estimated total with its standard error.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(crate) struct Estimate {
    pub total: f64,
    pub standard_error: f64,
}

/// What the sample of one part holds.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(crate) struct PartSample {
    pub sampled: u64,
    pub counts: SampleSums,
    pub solid_angle_sr: SampleSums,
}

/// A part's totals estimated from the sample (one row of
/// `unobstructed-parts.csv`).
#[derive(Debug, Clone, serde::Serialize)]
pub struct PartEstimate {
    pub part: String,
    /// Texels with a footprint on the mesh.
    pub texels: u64,
    pub sampled: u64,
    /// The count summed over the sampled texels.
    pub sampled_total: u64,
    /// The count's part total estimated from the sample, and its standard error.
    pub estimated_total: f64,
    pub standard_error: f64,
    /// Solid angle summed over the eye-frames (sr), estimated, and its standard error.
    pub estimated_solid_angle_sr: f64,
    pub solid_angle_standard_error_sr: f64,
}

/// Per-part estimates of the sampled texels' visibility.
pub fn estimate_parts(
    part_names: &[String],
    samples: &SurfaceSamples,
    visibility: &TexelVisibility,
    fraction: f64,
) -> Vec<PartEstimate> {
    let mut per_part = vec![PartSample::default(); part_names.len()];
    for ((texel, &count), &solid_angle) in
        samples.texels.iter().zip(&visibility.counts).zip(&visibility.solid_angle_sr)
    {
        let part = &mut per_part[texel.part as usize];
        part.sampled += 1;
        part.counts.add(f64::from(count));
        part.solid_angle_sr.add(solid_angle);
    }
    part_names
        .iter()
        .zip(per_part)
        .zip(&samples.texels_per_part)
        .map(|((name, sample), &texels)| {
            let count = sample.counts.estimate(texels, sample.sampled, fraction);
            let solid_angle = sample.solid_angle_sr.estimate(texels, sample.sampled, fraction);
            PartEstimate {
                part: name.clone(),
                texels,
                sampled: sample.sampled,
                sampled_total: sample.counts.sum as u64,
                estimated_total: count.total,
                standard_error: count.standard_error,
                estimated_solid_angle_sr: solid_angle.total,
                solid_angle_standard_error_sr: solid_angle.standard_error,
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_full_sample_estimates_its_own_total_without_error() {
        let sums = SampleSums { sum: 12.0, sum_of_squares: 50.0 };
        let whole = sums.estimate(4, 4, 1.0);
        assert_eq!(whole, Estimate { total: 12.0, standard_error: 0.0 });
        // Half the texels: twice the mean total, with an error.
        let half = sums.estimate(8, 4, 0.5);
        assert_eq!(half.total, 24.0);
        // s² = (50 − 4·9)/3 = 14/3; SE = 8·sqrt(0.5 · 14/3 / 4).
        assert!((half.standard_error - 8.0 * (0.5f64 * 14.0 / 3.0 / 4.0).sqrt()).abs() < 1e-12);
    }
}
