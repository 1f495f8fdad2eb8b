//! Per-part statistics: the join of per-texel counts with the PIdT and
//! legend ([`join_parts`]), and which parts the headlines show.

use rayon::prelude::*;

use crate::archive::labels::{Legend, Pidt, UNLABELLED};
use crate::color::Color;

pub use crate::format::result::PartStats;

/// Raw sums gathered per part during the join.
#[derive(Debug, Clone, Copy, Default)]
struct Sums {
    texels: u64,
    total: u64,
    peak: u32,
    seen: u64,
}

impl Sums {
    fn add(&mut self, count: u32) {
        self.texels += 1;
        self.total += u64::from(count);
        self.peak = self.peak.max(count);
        self.seen += u64::from(count > 0);
    }
    fn merge(mut self, other: Sums) -> Sums {
        self.texels += other.texels;
        self.total += other.total;
        self.peak = self.peak.max(other.peak);
        self.seen += other.seen;
        self
    }
}

/// The per-part table and the unlabelled remainder.
#[derive(Debug, Clone, PartialEq)]
pub struct PartTable {
    pub parts: Vec<PartStats>,
    pub unlabelled: PartStats,
    /// Sum of totals over legend parts (the paper's "grand total").
    pub grand_total: u64,
}

/// Joins per-texel counts with the PIdT (in parallel, exact integer sums).
pub fn join_parts(texel_counts: &[u32], pidt: &Pidt, legend: &Legend) -> PartTable {
    let slots = legend.parts.len() + 1; // last slot: unlabelled
    let sums = texel_counts
        .par_chunks(1 << 16)
        .zip(pidt.part_of_texel.par_chunks(1 << 16))
        .fold(
            || vec![Sums::default(); slots],
            |mut sums, (counts, parts)| {
                for (&count, &part) in counts.iter().zip(parts) {
                    let slot = if part == UNLABELLED { slots - 1 } else { usize::from(part) };
                    sums[slot].add(count);
                }
                sums
            },
        )
        .reduce(
            || vec![Sums::default(); slots],
            |a, b| a.into_iter().zip(b).map(|(x, y)| x.merge(y)).collect(),
        );
    let grand_total: u64 = sums[..slots - 1].iter().map(|s| s.total).sum();
    let stats = |name: &str, color: Option<Color>, sums: &Sums| PartStats {
        name: name.to_string(),
        color,
        texels: sums.texels,
        total: sums.total,
        peak: sums.peak,
        average: ratio(sums.total, sums.texels),
        share: 100.0 * ratio(sums.total, grand_total),
        coverage: 100.0 * ratio(sums.seen, sums.texels),
        texels_seen: sums.seen,
    };
    let parts =
        legend.parts.iter().zip(&sums).map(|(part, s)| stats(&part.name, Some(part.color), s)).collect();
    let unlabelled = stats("(unlabelled)", None, &sums[slots - 1]);
    PartTable { parts, unlabelled, grand_total }
}

/// `numerator / denominator`, 0 when the denominator is 0.
pub(crate) fn ratio(numerator: u64, denominator: u64) -> f64 {
    if denominator == 0 { 0.0 } else { numerator as f64 / denominator as f64 }
}

/// Parts in the paper's table: the union of the top five by total, by peak
/// and by average.
pub(crate) fn top_five_union(parts: &[PartStats]) -> Vec<bool> {
    let mut marked = vec![false; parts.len()];
    let mut order: Vec<usize> = (0..parts.len()).collect();
    let mut mark = |key: &dyn Fn(&PartStats) -> f64| {
        order.sort_by(|&a, &b| key(&parts[b]).total_cmp(&key(&parts[a])).then(a.cmp(&b)));
        for &index in order.iter().take(5) {
            if key(&parts[index]) > 0.0 {
                marked[index] = true;
            }
        }
    };
    mark(&|p| p.total as f64);
    mark(&|p| f64::from(p.peak));
    mark(&|p| p.average);
    marked
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::*;
    use crate::archive::labels::Part;

    fn legend() -> Legend {
        Legend::new(
            Path::new("parts.csv"),
            vec![
                Part { name: "Hood".into(), color: Color::from_packed(0xFF0000) },
                Part { name: "Roof".into(), color: Color::from_packed(0x00FF00) },
                Part { name: "Ghost".into(), color: Color::from_packed(0x0000FF) },
            ],
        )
        .unwrap()
    }

    #[test]
    fn joins_hand_computed_table() {
        let legend = legend();
        // 2×3 PIdT: Hood, Hood, Roof, Roof, unlabelled, unlabelled.
        let pidt =
            Pidt::from_colors([2, 3], &[0xFF0000, 0xFF0000, 0x00FF00, 0x00FF00, 0x0A0000, 0x0A0000], &legend);
        assert_eq!(pidt.part_texels, vec![2, 2, 0]);
        assert_eq!(pidt.unlabelled_colors[&Color::from_packed(0x0A0000)], 2);
        let table = join_parts(&[3, 1, 0, 4, 5, 0], &pidt, &legend);
        assert_eq!(table.grand_total, 8);
        let hood = &table.parts[0];
        assert_eq!((hood.texels, hood.total, hood.peak), (2, 4, 3));
        assert_eq!((hood.average, hood.share, hood.coverage), (2.0, 50.0, 100.0));
        let roof = &table.parts[1];
        assert_eq!((roof.total, roof.peak, roof.coverage), (4, 4, 50.0));
        let ghost = &table.parts[2];
        assert_eq!((ghost.texels, ghost.average, ghost.share), (0, 0.0, 0.0));
        assert_eq!((table.unlabelled.texels, table.unlabelled.total), (2, 5));
    }
}
