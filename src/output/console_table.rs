//! The console report: image bookkeeping, the measure to quote (angular
//! area and exposure per part, when the archive has the eyes' projection)
//! and the paper-compatible headline count table.

use crate::result::model::AnalysisResult;
use crate::result::part_stats::{PartStats, ratio};

/// The parts shown in the console table: the union of the five highest by
/// total, by peak and by average (the paper's way), ordered by total.
pub(crate) fn headline_parts(parts: &[PartStats]) -> Vec<usize> {
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

/// Parts shown by name in the console's table of measures; the rest are
/// summed in one "(other N parts)" row.
const MEASURED_PARTS_SHOWN: usize = 8;

/// The measure to quote, first (issue 43 §1): angular area over time
/// (deg²·s) and exposure (s) per part, largest area first, as the report's
/// first table; empty without the measures or without angular area.
fn format_measures(result: &AnalysisResult) -> String {
    let Some(measures) = &result.measures else { return String::new() };
    let mut parts: Vec<&crate::format::result::PartMeasure> =
        measures.parts.iter().filter(|p| p.angular_area_deg2_s.is_some()).collect();
    if parts.is_empty() {
        return String::new();
    }
    let area = |p: &crate::format::result::PartMeasure| p.angular_area_deg2_s.unwrap_or(0.0);
    parts.sort_by(|a, b| area(b).total_cmp(&area(a)).then(a.name.cmp(&b.name)));
    let total: f64 = parts.iter().map(|p| area(p)).sum();
    let share = |value: f64| if total > 0.0 { 100.0 * value / total } else { 0.0 };
    let header = format!("\n{:<28} {:>14} {:>8} {:>12}\n", "part", "area deg²·s", "share %", "exposure s");
    let mut out =
        String::from("\nwhat to quote: visible angular area over time and exposure per part (per eye)");
    out.push_str(&header);
    out.push_str(&format!("{}\n", "-".repeat(header.trim().chars().count())));
    let row = |name: &str, value: f64, exposure: String| {
        format!("{:<28} {:>14.4} {:>8.3} {:>12}\n", truncate(name, 28), value, share(value), exposure)
    };
    for part in parts.iter().take(MEASURED_PARTS_SHOWN) {
        let exposure = part.exposure_s.map_or("–".to_string(), |s| format!("{s:.3}"));
        out.push_str(&row(&part.name, area(part), exposure));
    }
    if parts.len() > MEASURED_PARTS_SHOWN {
        let rest: f64 = parts[MEASURED_PARTS_SHOWN..].iter().map(|p| area(p)).sum();
        let name = format!("(other {} parts)", parts.len() - MEASURED_PARTS_SHOWN);
        out.push_str(&row(&name, rest, String::new()));
    }
    out.push_str(&format!("{:<28} {:>14.4}\n", "all parts", total));
    out.push_str("\npaper-compatible count (to compare with the paper, not to quote: docs/science.md)\n");
    out
}

/// The measures to quote, then texels seen, the dedupe note and the
/// headline part table of counts.
fn format_parts(result: &AnalysisResult) -> String {
    let mut out = format_measures(result);
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

#[cfg(test)]
mod tests {
    use super::*;

    fn example_result() -> AnalysisResult {
        let path =
            std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/reference/example-result.json");
        crate::result::result_json::read_result_summary(&path).unwrap()
    }

    #[test]
    fn the_console_leads_with_the_angular_area_and_keeps_the_count_below() {
        let mut result = example_result();
        let measures = result.measures.as_mut().unwrap();
        // Two parts ranked oppositely by area and by count: the area decides the order.
        for part in &mut measures.parts {
            part.angular_area_deg2_s = Some(0.0);
        }
        measures.parts[0].angular_area_deg2_s = Some(1.0);
        measures.parts[1].angular_area_deg2_s = Some(3.0);
        let (first, second) = (measures.parts[0].name.clone(), measures.parts[1].name.clone());
        let table = format_table(&result);
        let quoted = table.find("what to quote").expect("no table of the measure to quote");
        let count = table.find("paper-compatible count").expect("the count is not labelled");
        assert!(quoted < count && count < table.find("grand total").unwrap(), "{table}");
        let rows: Vec<&str> = table[quoted..count].lines().skip(3).collect();
        assert!(rows[0].starts_with(&second[..second.len().min(27)]), "{table}");
        assert!(rows[0].contains("3.0000") && rows[0].contains("75.000"), "{table}");
        assert!(rows[1].starts_with(&first[..first.len().min(27)]), "{table}");
        assert!(table[quoted..count].contains("4.0000"), "the parts' sum: {table}");
        // Without the measures the table is the paper's alone, as before.
        result.measures = None;
        let table = format_table(&result);
        assert!(!table.contains("what to quote") && !table.contains("paper-compatible"), "{table}");
    }
}
