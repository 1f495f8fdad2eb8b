//! The merged result's files: `design.json` (the typed
//! `ufcsr-design-result/2`), `design.csv` (one row per group and
//! candidate) and `design.html`, the report page: the answer first ("for a
//! sedan: …; across all: …"), then the best placements with P(best), the
//! main effects and every group's table, each text through the analyzer's
//! HTML escape.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use ufcsr::{
    format::DesignResult, format::GroupSummary, format::MainEffect, format::MeanInterval,
    output::html_escape as esc,
};

use crate::error::{CaptureError, Result};

/// Candidates per group shown on the page (all are in the CSV).
const PAGE_ROWS: usize = 12;

fn interval_text(v: &MeanInterval) -> String {
    match v.ci95 {
        Some([lo, hi]) => format!("{:.2} [{lo:.2}–{hi:.2}]", v.mean),
        None => format!("{:.2} (n = {})", v.mean, v.n),
    }
}

/// ` [lo–hi]` with signs, or nothing without an interval.
fn bracket(v: &MeanInterval) -> String {
    v.ci95.map_or_else(String::new, |[lo, hi]| format!(" [{lo:+.2} to {hi:+.2}]"))
}

fn group_table(page: &mut String, group: &GroupSummary) {
    let _ = write!(
        page,
        "<h3>{}</h3><table><tr><th>candidate</th><th>kind</th><th>legible s [95 %]</th>\
         <th>in the decision window, s [95 %]</th><th>angular area deg²·s [95 %]</th></tr>",
        esc(&group.group)
    );
    for c in group.candidates.iter().take(PAGE_ROWS) {
        let _ = write!(
            page,
            "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>",
            esc(&c.name),
            esc(&c.kind),
            interval_text(&c.legible_s),
            interval_text(&c.decision_window_legible_s),
            interval_text(&c.angular_area_deg2_s)
        );
    }
    page.push_str("</table>");
}

/// One main-effects table (`within` names the body for a display's).
fn effects_table(page: &mut String, effects: &[MainEffect]) {
    let within = effects.iter().any(|e| e.within_vehicle.is_some());
    let _ = write!(
        page,
        "<table><tr>{}<th>factor</th><th>candidate</th><th>range s [95 %]</th>\
         <th>per level: mean s [95 %]; effect s [95 %]</th></tr>",
        if within { "<th>within vehicle</th>" } else { "" }
    );
    for e in effects {
        let levels: Vec<String> = e
            .levels
            .iter()
            .map(|l| {
                format!(
                    "{}: {}; {:+.2}{}",
                    l.level,
                    interval_text(&l.mean_s),
                    l.effect_s.mean,
                    bracket(&l.effect_s)
                )
            })
            .collect();
        let body = e.within_vehicle.as_deref().map_or_else(String::new, |v| format!("<td>{}</td>", esc(v)));
        let _ = write!(
            page,
            "<tr>{body}<td>{}</td><td>{}</td><td>{} ({} − {})</td><td>{}</td></tr>",
            esc(&e.factor),
            esc(&e.candidate),
            interval_text(&e.range_s),
            esc(&e.highest),
            esc(&e.lowest),
            esc(&levels.join(" | "))
        );
    }
    page.push_str("</table>");
}

/// The report page.
pub(crate) fn page(result: &DesignResult) -> String {
    let mut page = format!(
        "<!doctype html><meta charset=utf-8><title>{0}</title><style>body{{font-family:sans-serif;max-width:70em}}\
         td,th{{padding:0 .6em;text-align:left}}</style><h1>Design {0}</h1><h2>Answer</h2><ul>",
        esc(&result.design)
    );
    for line in &result.answer {
        let _ = write!(page, "<li>{}</li>", esc(line));
    }
    let _ = write!(page, "</ul><p>{}</p><h2>Best placements</h2>", esc(&result.interval));
    page.push_str("<table><tr><th>group</th><th>rank</th><th>kind</th><th>candidate</th><th>legible s [95 %]</th><th>P(best)</th><th>P(within 0.05 s)</th><th>tied with</th></tr>");
    for group in result.vehicles.iter().chain([&result.overall]) {
        for b in &group.best {
            let _ = write!(
                page,
                "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>",
                esc(&group.group),
                b.rank,
                esc(&b.kind),
                esc(&b.name),
                interval_text(&b.legible_s),
                b.p_best
                    .map_or_else(|| esc(b.p_best_note.as_deref().unwrap_or("n/a")), |p| format!("{p:.2}")),
                b.p_within_epsilon.map_or_else(|| "–".to_string(), |p| format!("{p:.2}")),
                esc(&b.tied_with.join(", "))
            );
        }
    }
    page.push_str("</table>");
    let left_out = super::stats::left_out_line(result.vehicles.iter().chain([&result.overall]));
    if !left_out.is_empty() {
        let _ = write!(
            page,
            "<p>{}. One rule for every command: a display is never placed on wheels or glass, and a whole part \
             is legible only through a display patch that fits on it (docs/placement.md).</p>",
            esc(&left_out)
        );
    }
    page.push_str(
        "<h2>Main effects</h2><p>Per factor and candidate: the range (largest level mean minus \
         smallest, with the interval of the per-unit difference of those two levels) and each level's mean \
         legible time with its effect (the level's mean minus the mean over the levels), each with its 95 % \
         interval over the random units.</p>",
    );
    effects_table(&mut page, &result.main_effects);
    if !result.display_main_effects.is_empty() {
        page.push_str(
            "<h3>Displays, within one body</h3><p>Each vehicle's best displays, over that vehicle's cells \
             only: a display patch's name carries its place on one body, so these compare the other \
             factors' levels on that body and say nothing across body types (no vehicle effect).</p>",
        );
        effects_table(&mut page, &result.display_main_effects);
    }
    page.push_str("<h2>Groups</h2>");
    for group in result.vehicles.iter().chain([&result.overall]).chain(&result.cells) {
        group_table(&mut page, group);
    }
    let _ = write!(page, "<p>{} tasks, design hash {}</p>", result.tasks, esc(&result.design_hash));
    page
}

/// One value with its interval and n as CSV fields: `mean,low,high`.
fn csv_interval(v: &MeanInterval) -> String {
    let end = |i: usize| v.ci95.map_or_else(String::new, |c| format!("{:.6}", c[i]));
    format!("{:.6},{},{}", v.mean, end(0), end(1))
}

/// The CSV's columns: the legible, decision-window and angular-area triples (mean, 95 % low, high) and n.
const CSV_HEADER: &str = "group,candidate,kind,legible_s,legible_s_low,legible_s_high,decision_window_legible_s,\
     decision_window_low,decision_window_high,angular_area_deg2_s,angular_area_low,angular_area_high,n\n";

/// One row per group and candidate; then the main effects, one row per factor, candidate and
/// level (`kind` `level-mean` or `level-effect`, `group` `FACTOR=LEVEL`) and one for the range
/// (`kind` `range`, `group` `FACTOR: HIGHEST - LOWEST`), their seconds in the legible columns;
/// a display's, over one vehicle's cells, with `group` prefixed `within vehicle NAME: `.
pub(crate) fn csv(result: &DesignResult) -> String {
    let mut text = String::from(CSV_HEADER);
    for group in result.cells.iter().chain(&result.vehicles).chain([&result.overall]) {
        for c in &group.candidates {
            let _ = writeln!(
                text,
                "{},{},{},{},{},{},{}",
                ufcsr::output::csv_field(&group.group),
                ufcsr::output::csv_field(&c.name),
                c.kind,
                csv_interval(&c.legible_s),
                csv_interval(&c.decision_window_legible_s),
                csv_interval(&c.angular_area_deg2_s),
                c.legible_s.n
            );
        }
    }
    for e in result.main_effects.iter().chain(&result.display_main_effects) {
        let within = e.within_vehicle.as_ref().map_or_else(String::new, |v| format!("within vehicle {v}: "));
        let mut row = |group: String, kind: &str, v: &MeanInterval| {
            let _ = writeln!(
                text,
                "{},{},{kind},{},,,,,,,{}",
                ufcsr::output::csv_field(&group),
                ufcsr::output::csv_field(&e.candidate),
                csv_interval(v),
                v.n
            );
        };
        row(format!("{within}{}: {} - {}", e.factor, e.highest, e.lowest), "range", &e.range_s);
        for l in &e.levels {
            row(format!("{within}{}={}", e.factor, l.level), "level-mean", &l.mean_s);
            row(format!("{within}{}={}", e.factor, l.level), "level-effect", &l.effect_s);
        }
    }
    text
}

/// Writes `design.json`, `design.csv` and `design.html` into `dir`, never over one of `inputs`.
pub fn write_result(result: &DesignResult, dir: &Path, inputs: &[PathBuf]) -> Result<Vec<PathBuf>> {
    ufcsr::files::create_output_dir(dir)?;
    let files = ["design.json", "design.csv", "design.html"].map(|f| dir.join(f));
    ufcsr::files::refuse_overwriting_inputs(&files, inputs)?;
    let json =
        serde_json::to_vec_pretty(result).map_err(|e| CaptureError::bad_file(&files[0], e.to_string()))?;
    ufcsr::files::write_bytes_atomically(&files[0], &json)?;
    ufcsr::files::write_bytes_atomically(&files[1], csv(result).as_bytes())?;
    ufcsr::files::write_bytes_atomically(&files[2], page(result).as_bytes())?;
    Ok(files.to_vec())
}
