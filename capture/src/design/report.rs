//! The merged result's files: `design.json` (the typed
//! `ufcsr-design-result/1`), `design.csv` (one row per group and
//! candidate) and `design.html`, the report page: the answer first ("for a
//! sedan: …; across all: …"), then the best placements with P(best), the
//! main effects and every group's table, each text through the analyzer's
//! HTML escape.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use ufcsr::{DesignResult, GroupSummary, MeanInterval, html_escape as esc};

use crate::error::{CaptureError, Result};

/// Candidates per group shown on the page (all are in the CSV).
const PAGE_ROWS: usize = 12;

fn interval_text(v: &MeanInterval) -> String {
    match v.ci95 {
        Some([lo, hi]) => format!("{:.2} [{lo:.2}–{hi:.2}]", v.mean),
        None => format!("{:.2} (n = {})", v.mean, v.n),
    }
}

fn group_table(page: &mut String, group: &GroupSummary) {
    let _ = write!(
        page,
        "<h3>{}</h3><table><tr><th>candidate</th><th>kind</th><th>legible s [95 %]</th>\
         <th>angular area deg²·s [95 %]</th></tr>",
        esc(&group.group)
    );
    for c in group.candidates.iter().take(PAGE_ROWS) {
        let _ = write!(
            page,
            "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>",
            esc(&c.name),
            esc(&c.kind),
            interval_text(&c.legible_s),
            interval_text(&c.angular_area_deg2_s)
        );
    }
    page.push_str("</table>");
}

/// The report page.
pub fn page(result: &DesignResult) -> String {
    let mut page = format!(
        "<!doctype html><meta charset=utf-8><title>{0}</title><style>body{{font-family:sans-serif;max-width:70em}}\
         td,th{{padding:0 .6em;text-align:left}}</style><h1>Design {0}</h1><h2>Answer</h2><ul>",
        esc(&result.design)
    );
    for line in &result.answer {
        let _ = write!(page, "<li>{}</li>", esc(line));
    }
    let _ = write!(page, "</ul><p>{}</p><h2>Best placements</h2>", esc(&result.interval));
    page.push_str("<table><tr><th>group</th><th>rank</th><th>kind</th><th>candidate</th><th>legible s [95 %]</th><th>P(best)</th></tr>");
    for group in result.vehicles.iter().chain([&result.overall]) {
        for b in &group.best {
            let _ = write!(
                page,
                "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{:.2}</td></tr>",
                esc(&group.group),
                b.rank,
                esc(&b.kind),
                esc(&b.name),
                interval_text(&b.legible_s),
                b.p_best
            );
        }
    }
    page.push_str("</table><h2>Main effects</h2><table><tr><th>factor</th><th>candidate</th><th>range s</th><th>mean per level, s</th></tr>");
    for e in &result.main_effects {
        let levels: Vec<String> = e.level_means_s.iter().map(|(l, m)| format!("{l}: {m:.2}")).collect();
        let _ = write!(
            page,
            "<tr><td>{}</td><td>{}</td><td>{:.2}</td><td>{}</td></tr>",
            esc(&e.factor),
            esc(&e.candidate),
            e.range_s,
            esc(&levels.join(", "))
        );
    }
    page.push_str("</table><h2>Groups</h2>");
    for group in result.vehicles.iter().chain([&result.overall]).chain(&result.cells) {
        group_table(&mut page, group);
    }
    let _ = write!(page, "<p>{} tasks, design hash {}</p>", result.tasks, esc(&result.design_hash));
    page
}

/// One row per group and candidate.
pub fn csv(result: &DesignResult) -> String {
    let mut text = String::from(
        "group,candidate,kind,legible_s,legible_s_low,legible_s_high,angular_area_deg2_s,angular_area_low,angular_area_high,n\n",
    );
    let cell = |v: Option<[f64; 2]>, i: usize| v.map_or_else(String::new, |c| format!("{:.6}", c[i]));
    for group in result.cells.iter().chain(&result.vehicles).chain([&result.overall]) {
        for c in &group.candidates {
            let _ = writeln!(
                text,
                "{},{},{},{:.6},{},{},{:.6},{},{},{}",
                ufcsr::csv_field(&group.group),
                ufcsr::csv_field(&c.name),
                c.kind,
                c.legible_s.mean,
                cell(c.legible_s.ci95, 0),
                cell(c.legible_s.ci95, 1),
                c.angular_area_deg2_s.mean,
                cell(c.angular_area_deg2_s.ci95, 0),
                cell(c.angular_area_deg2_s.ci95, 1),
                c.legible_s.n
            );
        }
    }
    text
}

/// Writes `design.json`, `design.csv` and `design.html` into `dir`, never over one of `inputs`.
pub fn write_result(result: &DesignResult, dir: &Path, inputs: &[PathBuf]) -> Result<Vec<PathBuf>> {
    ufcsr::create_output_dir(dir)?;
    let files = ["design.json", "design.csv", "design.html"].map(|f| dir.join(f));
    ufcsr::refuse_overwriting_inputs(&files, inputs)?;
    let json =
        serde_json::to_vec_pretty(result).map_err(|e| CaptureError::bad_file(&files[0], e.to_string()))?;
    ufcsr::write_bytes_atomically(&files[0], &json)?;
    ufcsr::write_bytes_atomically(&files[1], csv(result).as_bytes())?;
    ufcsr::write_bytes_atomically(&files[2], page(result).as_bytes())?;
    Ok(files.to_vec())
}
