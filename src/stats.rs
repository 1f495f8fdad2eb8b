//! Small statistics both crates need, defined once: Student's t quantile
//! for 95 % intervals ([`t975`]: the placement's bootstrap intervals, the
//! observers' and the design's intervals in the capture) and a seeded
//! random generator ([`SplitMix64`]: bootstrap draws, observer and offset
//! draws, the street's other vehicles, synthetic archives, test
//! populations), so a seed means the same sequence everywhere.

/// t(0.975, df) for df = 1…30.
const T975: [f64; 30] = [
    12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262, 2.228, 2.201, 2.179, 2.160, 2.145, 2.131,
    2.120, 2.110, 2.101, 2.093, 2.086, 2.080, 2.074, 2.069, 2.064, 2.060, 2.056, 2.052, 2.048, 2.045, 2.042,
];

/// The 97.5th percentile of Student's t with `df` degrees of freedom: the
/// table to 30, then the Cornish–Fisher expansion about the normal's 1.96
/// (within 1e-4 of the exact value above 30); infinite for 0.
pub fn t975(df: usize) -> f64 {
    match df {
        0 => f64::INFINITY,
        1..=30 => T975[df - 1],
        _ => {
            let (z, n): (f64, f64) = (1.959_964, df as f64);
            z + (z.powi(3) + z) / (4.0 * n) + (5.0 * z.powi(5) + 16.0 * z.powi(3) + 3.0 * z) / (96.0 * n * n)
        }
    }
}

/// SplitMix64 (Steele, Lea & Flood 2014): a small deterministic generator,
/// the same sequence on every platform, no dependency. The field is the
/// state; `SplitMix64(seed)` starts one.
#[derive(Debug, Clone)]
pub struct SplitMix64(pub u64);

impl SplitMix64 {
    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// An integer in `[0, n)` (0 when `n` is 0).
    pub fn below(&mut self, n: u64) -> u64 {
        self.next_u64() % n.max(1)
    }

    /// Uniform in `[0, 1)`, on 53 bits.
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in the open `(0, 1)`, on 53 bits (a logarithm of it is finite).
    pub fn uniform(&mut self) -> f64 {
        ((self.next_u64() >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    }

    /// Standard normal (Box–Muller on two [`uniform`](Self::uniform) draws).
    pub fn normal(&mut self) -> f64 {
        let (u, v) = (self.uniform(), self.uniform());
        (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn t_quantiles_match_the_table_and_approach_the_normal() {
        assert_eq!(t975(1), 12.706);
        assert_eq!(t975(3), 3.182);
        assert_eq!(t975(15), 2.131);
        assert_eq!(t975(0), f64::INFINITY);
        // Exact: t(0.975, 40) = 2.0211, 60: 2.0003, 120: 1.9799; the normal's 1.95996 far out.
        for (df, exact) in [(40, 2.0211), (60, 2.0003), (120, 1.9799), (100_000, 1.95996)] {
            assert!((t975(df) - exact).abs() < 2e-4, "{df}: {}", t975(df));
        }
    }

    #[test]
    fn split_mix_gives_the_published_sequence_and_standard_normals() {
        // The reference implementation's first outputs from seed 1234567.
        let mut random = SplitMix64(1_234_567);
        assert_eq!(random.next_u64(), 6_457_827_717_110_365_317);
        assert_eq!(random.next_u64(), 3_203_168_211_198_807_973);
        let mut random = SplitMix64(7);
        let draws: Vec<f64> = (0..20_000).map(|_| random.normal()).collect();
        let mean = draws.iter().sum::<f64>() / draws.len() as f64;
        let variance = draws.iter().map(|d| (d - mean).powi(2)).sum::<f64>() / draws.len() as f64;
        assert!(mean.abs() < 0.03 && (variance - 1.0).abs() < 0.05, "{mean} {variance}");
        assert!((0..1000).all(|_| (0.0..1.0).contains(&random.unit()) && random.below(3) < 3));
    }
}
