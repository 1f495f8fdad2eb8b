//! The console report: image bookkeeping and the headline part table.

use crate::result::model::AnalysisResult;
use crate::result::part_stats::{PartStats, ratio};

/// The parts shown in the console table: the union of the five highest by
/// total, by peak and by average (the paper's way), ordered by total.
pub fn headline_parts(parts: &[PartStats]) -> Vec<usize> {
    let top = |key: &dyn Fn(&PartStats) -> f64| {
        let mut order: Vec<usize> = (0..parts.len()).collect();
        order.sort_by(|&a, &b| key(&parts[b]).total_cmp(&key(&parts[a])).then(a.cmp(&b)));
        order.truncate(5);
        order
    };
    let mut chosen: Vec<usize> = top(&|p| p.total as f64);
    chosen.extend(top(&|p| f64::from(p.peak)));
    chosen.extend(top(&|p| p.average));
    chosen.sort_by(|&a, &b| parts[b].total.cmp(&parts[a].total).then(a.cmp(&b)));
    chosen.dedup();
    chosen
}

/// The console report: image bookkeeping and the headline part table.
pub fn format_table(result: &AnalysisResult) -> String {
    let images = &result.images;
    let mut out = format!(
        "images: {} found, {} trimmed (empty), {} decoded, {} failed\n",
        images.found, images.trimmed, images.decoded, images.failed
    );
    out.push_str(&format!(
        "pixels: {} decoded, {} background, {} stray ({} distinct stray colours)\n",
        result.pixels.decoded, result.background_pixels, result.stray_pixels, result.stray_colors
    ));
    out + &format_parts(result)
}

/// [`format_table`] of a capture counted straight from the renderer
/// (`--count`): the same numbers, named for what happened (nothing was
/// decoded, no image was written).
pub fn format_counted_table(result: &AnalysisResult) -> String {
    let images = &result.images;
    let mut out = format!(
        "tiles: {} in the capture, {} counted from the renderer, {} empty or not rendered\n",
        images.found, images.decoded, images.trimmed
    );
    out.push_str(&format!(
        "pixels: {} counted, {} background, {} stray ({} distinct stray colours)\n",
        result.pixels.decoded, result.background_pixels, result.stray_pixels, result.stray_colors
    ));
    out + &format_parts(result)
}

/// Texels seen, the dedupe note and the headline part table.
fn format_parts(result: &AnalysisResult) -> String {
    let mut out = String::new();
    out.push_str(&format!("texels seen: {}, max count: {}\n", result.texels_seen, result.max_count));
    if let Some(dedupe) = &result.dedupe {
        out.push_str(&format!(
            "dedupe per eye-frame: grand total {} vs {} per image ({:+.2}%)\n",
            dedupe.grand_total_per_frame, dedupe.grand_total_per_image, dedupe.change_percent
        ));
    }
    if result.parts.is_empty() {
        out.push_str(&format!("grand total (all texels): {}\n", result.grand_total));
        return out;
    }
    let header = format!(
        "\n{:<28} {:>10} {:>12} {:>7} {:>10} {:>8} {:>9}\n",
        "part", "texels", "total", "peak", "average", "share %", "covered %"
    );
    out.push_str(&header);
    out.push_str(&format!("{}\n", "-".repeat(header.trim().len())));
    let row = |name: &str, texels: u64, total: u64, peak: u32, seen: u64| {
        format!(
            "{:<28} {:>10} {:>12} {:>7} {:>10.3} {:>8.3} {:>9.2}\n",
            truncate(name, 28),
            texels,
            total,
            peak,
            ratio(total, texels),
            100.0 * ratio(total, result.grand_total),
            100.0 * ratio(seen, texels)
        )
    };
    let chosen = headline_parts(&result.parts);
    for &index in &chosen {
        let part = &result.parts[index];
        out.push_str(&row(&part.name, part.texels, part.total, part.peak, part.texels_seen));
    }
    let others: Vec<&PartStats> =
        result.parts.iter().enumerate().filter(|(i, _)| !chosen.contains(i)).map(|(_, p)| p).collect();
    if !others.is_empty() {
        let sum = |f: &dyn Fn(&PartStats) -> u64| others.iter().map(|p| f(p)).sum::<u64>();
        out.push_str(&row(
            &format!("(other {} parts)", others.len()),
            sum(&|p| p.texels),
            sum(&|p| p.total),
            others.iter().map(|p| p.peak).max().unwrap_or(0),
            sum(&|p| p.texels_seen),
        ));
    }
    out.push_str(&format!("{:<28} {:>10} {:>12}\n", "grand total", "", result.grand_total));
    if let Some(unlabelled) = &result.unlabelled {
        out.push_str(&format!(
            "unlabelled texels: {} (total {}, not in the grand total)\n",
            unlabelled.texels, unlabelled.total
        ));
    }
    out
}

fn truncate(text: &str, width: usize) -> String {
    if text.chars().count() <= width {
        text.to_string()
    } else {
        let mut short: String = text.chars().take(width - 1).collect();
        short.push('…');
        short
    }
}
