//! The pages' placement section ("Where should the eHMI go?"), from a
//! `placement.json` written by `ufcsr-analyze placement`: the legibility
//! thresholds with the source of each, the candidates ranked by legible
//! seconds (visible seconds, first legible sighting, legible seconds in the
//! decision window), the best sets of 1 to k with their share of the time
//! and worst case, and the picture of the chosen placements on the vehicle
//! (`placement.png`). The report of one result shows it when a placement
//! folder lies beside the result (`placement/` in the result folder);
//! `ufcsr-analyze report` when it is given a placement folder.
//!
//! The section reads placement.json as JSON (schema `ufcsr-placement/1`),
//! so the pages do not depend on the placement search's code.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use serde_json::Value;

use crate::error::{Error, Result};
use crate::output::html::escape::escape;

/// The file the section is made from.
pub const PLACEMENT_JSON: &str = "placement.json";
/// The picture beside it.
pub const PLACEMENT_PNG: &str = "placement.png";
/// Candidates listed per kind.
const LISTED: usize = 15;

/// A placement result to show: its document and the picture's address
/// relative to the page (when there is a picture).
#[derive(Debug, Clone)]
pub struct PlacementOnPage {
    pub label: String,
    pub document: Value,
    pub picture: Option<String>,
}

/// The placement folder `path` names: the folder holding placement.json, or
/// the file itself; `None` when it is neither.
pub fn placement_folder(path: &Path) -> Option<PathBuf> {
    if path.is_dir() && path.join(PLACEMENT_JSON).is_file() {
        return Some(path.to_path_buf());
    }
    let named = path.file_name().is_some_and(|n| n == PLACEMENT_JSON) && path.is_file();
    named.then(|| path.parent().unwrap_or(Path::new(".")).to_path_buf())
}

/// The placement folder beside a result in `result_dir`: `placement/` in it,
/// or the folder itself.
pub fn placement_beside(result_dir: &Path) -> Option<PathBuf> {
    [result_dir.join("placement"), result_dir.to_path_buf()]
        .into_iter()
        .find_map(|dir| placement_folder(&dir))
}

/// Reads `dir/placement.json`, checking its schema.
pub fn read_placement(dir: &Path) -> Result<Value> {
    let path = dir.join(PLACEMENT_JSON);
    let bytes = crate::files::read_limited(&path, crate::files::SMALL_INPUT_LIMIT)?;
    let document: Value =
        serde_json::from_slice(&bytes).map_err(|e| Error::bad_file(&path, format!("not JSON: {e}")))?;
    match document["schema"].as_str() {
        Some(schema) if schema.starts_with("ufcsr-placement/") => Ok(document),
        _ => Err(Error::bad_file(&path, "not a placement result (no schema \"ufcsr-placement/1\")")),
    }
}

fn number(value: &Value, digits: usize) -> String {
    value.as_f64().map_or("–".to_string(), |v| format!("{v:.digits$}"))
}

/// Appends the section for `placement`.
pub fn section(page: &mut String, placement: &PlacementOnPage) {
    let document = &placement.document;
    let _ = writeln!(
        page,
        "<h2>Where should the eHMI go? ({})</h2>\n<p>From <code>placement.json</code> (<code>ufcsr-analyze \
         placement</code>, docs/placement.md) over {} archive(s): a candidate is <em>legible</em> in an eye-frame \
         when all three thresholds hold; seconds are means over the archives.</p>",
        escape(&placement.label),
        document["archives"].as_array().map_or(0, Vec::len)
    );
    thresholds(page, &document["thresholds"]);
    combinations(page, document["combinations"].as_array().map_or(&[][..], Vec::as_slice));
    candidates(page, document["candidates"].as_array().map_or(&[][..], Vec::as_slice));
    match &placement.picture {
        Some(picture) => {
            let _ = writeln!(
                page,
                "<h3>The chosen placements on the vehicle</h3>\n<p>Per row one chosen set (the best 1, 2 and 3 \
                 parts, then display patches), seen from the eight directions; a left/right pair shares a \
                 colour.</p>\n<img src=\"{}\" alt=\"the chosen placements on the vehicle\" class=\"plot\">",
                escape(picture)
            );
        }
        None => {
            let _ = writeln!(
                page,
                "<p>No picture: the placement had no vehicle model (give it <code>--mesh</code>).</p>"
            );
        }
    }
}

fn thresholds(page: &mut String, thresholds: &Value) {
    let _ = writeln!(
        page,
        "<h3>Thresholds</h3>\n<table><tr><th>threshold</th><th>value</th><th>source</th></tr>"
    );
    for (key, name) in [
        ("min_angular_height_arcmin", "visible angular height ≥ (arcmin)"),
        ("min_visible_fraction", "visible fraction ≥"),
        ("max_view_angle_deg", "view angle ≤ (°)"),
        ("decision_window_s", "decision window (s)"),
    ] {
        let source = thresholds["sources"][key].as_str().unwrap_or("");
        let _ = writeln!(
            page,
            "<tr><td>{name}</td><td>{}</td><td style=\"text-align:left\">{}</td></tr>",
            number(&thresholds[key], 2),
            escape(source)
        );
    }
    let _ = writeln!(
        page,
        "<tr><td>eyes</td><td>{}</td><td style=\"text-align:left\">legible to either eye (any) or both</td></tr>\
         <tr><td>a left/right pair is one choice</td><td>{}</td><td></td></tr></table>",
        escape(thresholds["eyes"].as_str().unwrap_or("–")),
        thresholds["symmetric"].as_bool().map_or("–", |s| if s { "yes" } else { "no" })
    );
}

fn combinations(page: &mut String, combinations: &[Value]) {
    let _ = writeln!(
        page,
        "<h3>The best sets</h3>\n<table><tr><th>k</th><th>kind</th><th>objective</th><th>method</th>\
         <th>candidates</th><th>legible s (at least one)</th><th>share of time %</th><th>worst case s</th>\
         <th>bound s</th></tr>"
    );
    for c in combinations {
        let members: Vec<&str> =
            c["candidates"].as_array().map_or(Vec::new(), |m| m.iter().filter_map(Value::as_str).collect());
        let _ = writeln!(
            page,
            "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td style=\"text-align:left\">{}</td><td>{}</td>\
             <td>{:.1}</td><td>{}</td><td>{}</td></tr>",
            c["k"],
            escape(c["kind"].as_str().unwrap_or("")),
            escape(c["objective"].as_str().unwrap_or("")),
            escape(c["method"].as_str().unwrap_or("")),
            escape(&members.join(" + ")),
            number(&c["legible_s"], 3),
            100.0 * c["share_of_time"].as_f64().unwrap_or(0.0),
            number(&c["worst_case_s"], 3),
            number(&c["upper_bound_s"], 3)
        );
    }
    let _ = writeln!(page, "</table>");
}

fn candidates(page: &mut String, candidates: &[Value]) {
    let _ = writeln!(
        page,
        "<h3>Candidates ranked by legible seconds</h3>\n<p>Every part, and the {LISTED} best display patches \
         (placement.csv lists all).</p>\n<table><tr><th>candidate</th><th>kind</th><th>legible s</th><th>visible s</th>\
         <th>first legible s</th><th>first legible at m</th><th>legible s in the decision window</th>\
         <th>worst case legible s</th></tr>"
    );
    let mut patches = 0;
    for c in candidates {
        if c["kind"] == "patch" {
            patches += 1;
            if patches > LISTED {
                continue;
            }
        }
        let _ = writeln!(
            page,
            "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>",
            escape(c["name"].as_str().unwrap_or("")),
            escape(c["kind"].as_str().unwrap_or("")),
            number(&c["legible_s"], 3),
            number(&c["visible_s"], 3),
            c["first_legible_s"].as_f64().map_or("never".to_string(), |v| format!("{v:.3}")),
            number(&c["first_legible_distance_m"], 1),
            number(&c["decision_window_legible_s"], 3),
            number(&c["worst_case_legible_s"], 3)
        );
    }
    let _ = writeln!(page, "</table>");
}

/// The placement in `folder` as shown on a page in `page_dir`: the picture
/// addressed relative to the page when it lies below it.
pub fn on_page(folder: &Path, page_dir: &Path, label: &str) -> Result<PlacementOnPage> {
    let document = read_placement(folder)?;
    let picture = folder.join(PLACEMENT_PNG);
    let picture = picture
        .is_file()
        .then(|| picture.strip_prefix(page_dir).ok().map(|p| p.to_string_lossy().into_owned()))
        .flatten();
    Ok(PlacementOnPage { label: label.to_string(), document, picture })
}
