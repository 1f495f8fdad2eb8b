//! The pages' placement section ("Where should the eHMI go?"), from a
//! `placement.json` written by `ufcsr placement`: the legibility
//! rule with the source of each default, the best sets of at most k
//! physical displays with their interval, P(best) and runners-up (members
//! that add no legible time marked), the thresholds whose one-step change
//! changes a best set, the candidates ranked by legible seconds, and the
//! picture of the chosen placements on the vehicle (`placement.png`). The
//! report of one result shows it when a placement folder lies beside the
//! result (`placement/` in the result folder); `ufcsr report` when
//! it is given a placement folder.
//!
//! The section reads placement.json through its type
//! ([`PlacementDocument`], `src/format/placement.rs`), so a file of another
//! version is an error naming it; every string from the file is
//! HTML-escaped (a name is data, never markup).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use crate::error::{Error, Result};
use crate::format::placement::{
    CandidateKind, CandidateRecord, CharacterHeight, CombinationRecord, PLACEMENT_SCHEMA, PlacementDocument,
    ThresholdsRecord,
};
use crate::output::html::escape::escape;

/// The file the section is made from.
pub(crate) const PLACEMENT_JSON: &str = "placement.json";
/// The picture beside it.
pub(crate) const PLACEMENT_PNG: &str = "placement.png";
/// Candidates listed per kind.
const LISTED: usize = 15;

/// A placement result to show: its document and the picture's address
/// relative to the page (when there is a picture).
#[derive(Debug, Clone)]
pub(crate) struct PlacementOnPage {
    pub label: String,
    pub document: PlacementDocument,
    pub picture: Option<String>,
}

/// The placement folder `path` names: the folder holding placement.json, or
/// the file itself; `None` when it is neither.
pub(crate) fn placement_folder(path: &Path) -> Option<PathBuf> {
    if path.is_dir() && path.join(PLACEMENT_JSON).is_file() {
        return Some(path.to_path_buf());
    }
    let named = path.file_name().is_some_and(|n| n == PLACEMENT_JSON) && path.is_file();
    named.then(|| path.parent().unwrap_or(Path::new(".")).to_path_buf())
}

/// The placement folder beside a result in `result_dir`: `placement/` in it,
/// or the folder itself.
pub(crate) fn placement_beside(result_dir: &Path) -> Option<PathBuf> {
    [result_dir.join("placement"), result_dir.to_path_buf()]
        .into_iter()
        .find_map(|dir| placement_folder(&dir))
}

/// Reads `dir/placement.json` through its type, checking its schema.
pub(crate) fn read_placement(dir: &Path) -> Result<PlacementDocument> {
    let path = dir.join(PLACEMENT_JSON);
    let bytes = crate::files::read_limited(&path, crate::files::SMALL_INPUT_LIMIT)?;
    #[derive(serde::Deserialize)]
    struct Versioned {
        schema: Option<String>,
    }
    let version: Versioned =
        serde_json::from_slice(&bytes).map_err(|e| Error::bad_file(&path, format!("not JSON: {e}")))?;
    if version.schema.as_deref() != Some(PLACEMENT_SCHEMA) {
        return Err(Error::bad_file(
            &path,
            format!(
                "not a placement result of this version (schema {:?}, expected {PLACEMENT_SCHEMA:?}): run \
                 `ufcsr placement` again",
                version.schema.unwrap_or_default()
            ),
        ));
    }
    serde_json::from_slice(&bytes)
        .map_err(|e| Error::bad_file(&path, format!("not a {PLACEMENT_SCHEMA} document: {e}")))
}

fn probability(value: Option<f64>) -> String {
    value.map_or("–".to_string(), |v| format!("{v:.2}"))
}

/// Appends the section for `placement`.
pub(crate) fn section(page: &mut String, placement: &PlacementOnPage) {
    let document = &placement.document;
    let _ = writeln!(
        page,
        "<h2>Where should the eHMI go? ({})</h2>\n<p>From <code>placement.json</code> (<code>ufcsr analyze \
         placement</code>, docs/placement.md) over {} archive(s): a candidate is <em>legible</em> in an eye-frame \
         when its characters pass every threshold below, in a run of at least the dwell; seconds are means over \
         the archives; <strong>k counts physical displays</strong> (a symmetric pair is two).</p>",
        escape(&placement.label),
        document.archives.len()
    );
    thresholds(page, &document.thresholds);
    combinations(page, document);
    sensitivity(page, document);
    candidates(page, &document.candidates);
    match &placement.picture {
        Some(picture) => {
            let _ = writeln!(
                page,
                "<h3>The chosen placements on the vehicle</h3>\n<p>Per row one chosen set (the best parts, then \
                 display patches, of at most 1, 2 and 3 displays), seen from the eight directions; a left/right \
                 pair shares a colour.</p>\n<img src=\"{}\" alt=\"the chosen placements on the vehicle\" \
                 class=\"plot\">",
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

fn thresholds(page: &mut String, t: &ThresholdsRecord) {
    let _ = writeln!(
        page,
        "<h3>Thresholds</h3>\n<table><tr><th>threshold</th><th>value</th><th>source</th></tr>"
    );
    let character_height = match t.character_height {
        CharacterHeight::Fraction(f) => format!("{f:.2} of the display height"),
        CharacterHeight::Metres(m) => format!("{m:.3} m"),
    };
    let sources = &t.sources;
    let rows = [
        (
            "character angular height ≥ (arcmin)",
            format!("{:.2}", t.min_character_height_arcmin),
            &sources.min_character_height_arcmin,
        ),
        ("character height", character_height, &sources.character_height),
        (
            "characters across the foreshortened width ≥",
            t.min_characters.to_string(),
            &sources.min_characters,
        ),
        ("visible fraction ≥", format!("{:.2}", t.min_visible_fraction), &sources.min_visible_fraction),
        ("view angle ≤ (°)", format!("{:.1}", t.max_view_angle_deg), &sources.max_view_angle_deg),
        ("dwell: legible runs at least (s)", format!("{:.2}", t.min_dwell_s), &sources.min_dwell_s),
        ("decision window (s)", format!("{:.2}", t.decision_window_s), &sources.decision_window_s),
        ("not mountable (never chosen)", t.not_mountable.join(", "), &sources.not_mountable),
        ("one region: patches within (m)", format!("{:.2}", t.region_radius_m), &sources.region_radius_m),
    ];
    for (name, value, source) in rows {
        let _ = writeln!(
            page,
            "<tr><td>{name}</td><td>{}</td><td style=\"text-align:left\">{}</td></tr>",
            escape(&value),
            escape(source)
        );
    }
    let _ = writeln!(
        page,
        "<tr><td>eyes</td><td>{}</td><td style=\"text-align:left\">legible to either eye (any) or both</td></tr>\
         <tr><td>a left/right pair is chosen together (two displays)</td><td>{}</td><td></td></tr></table>",
        escape(t.eyes.name()),
        if t.symmetric { "yes" } else { "no" }
    );
}

fn combination_row(page: &mut String, c: &CombinationRecord) {
    let interval = c.interval_s.map_or("–".to_string(), |[low, high]| format!("{low:.3}–{high:.3}"));
    let _ = writeln!(
        page,
        "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td style=\"text-align:left\">{}</td>\
         <td>{:.3}</td><td>{}</td><td>{}</td><td>{}</td><td>{:.1}</td><td>{:.3}</td><td>{:.3}</td></tr>",
        c.k,
        c.displays,
        escape(c.kind.name()),
        escape(c.objective.name()),
        escape(c.method.name()),
        escape(&c.members_text()),
        c.legible_s,
        interval,
        c.p_best_note.as_deref().map_or_else(|| probability(c.p_best), escape),
        probability(c.p_within_epsilon),
        100.0 * c.share_of_time,
        c.worst_case_s,
        c.upper_bound_s
    );
    for r in &c.runners_up {
        let _ = writeln!(
            page,
            "<tr><td></td><td>{}</td><td colspan=\"3\">runner-up</td><td style=\"text-align:left\">{}</td>\
             <td>{:.3}</td><td></td><td>{}</td><td colspan=\"4\"></td></tr>",
            r.displays,
            escape(&r.candidates.join(" + ")),
            r.legible_s,
            probability(r.p_best)
        );
    }
}

fn combinations(page: &mut String, document: &PlacementDocument) {
    let u = &document.uncertainty;
    let _ = writeln!(
        page,
        "<h3>The best sets</h3>\n<p>k: at most this many physical displays; <em>[adds 0 s]</em>: a member that \
         adds no legible time to the others. {:.0} % interval over the {} archive(s) (the random units); P(best) \
         and P(within {:.2} s) from {} bootstrap replicates over the archives; runners-up: other sets inside the \
         interval. {}</p>\n<table><tr><th>k</th><th>displays</th><th>kind</th><th>objective</th><th>method</th>\
         <th>members</th><th>legible s (at least one)</th><th>interval s</th><th>P(best)</th><th>P(within ε)</th>\
         <th>share of time %</th><th>worst case s</th><th>bound s</th></tr>",
        100.0 * u.confidence,
        u.archives,
        u.epsilon_s,
        u.replicates,
        escape(&u.method)
    );
    for c in &document.combinations {
        combination_row(page, c);
    }
    let _ = writeln!(page, "</table>");
    let tied: Vec<String> = document
        .combinations
        .iter()
        .filter(|c| !c.tied_with.is_empty())
        .map(|c| {
            let sets: Vec<String> = c.tied_with.iter().map(|s| s.join(" & ")).collect();
            format!("k={} {}: {} ties with {}", c.k, c.kind.name(), c.members_text(), sets.join("; "))
        })
        .collect();
    if !tied.is_empty() {
        let _ = writeln!(
            page,
            "<p>Exact ties (the answer is the tied set; P(best) is shared, 1/t each): {}</p>",
            escape(&tied.join(". "))
        );
    }
    for warning in crate::format::placement::warning_lines(&document.archives) {
        let _ = writeln!(page, "<p><strong>{}</strong></p>", escape(&warning));
    }
    let excluded = crate::format::placement::excluded_line(&document.excluded);
    if !excluded.is_empty() {
        let _ = writeln!(
            page,
            "<p>{}. A whole part is legible only through a display patch that fits on it (docs/placement.md).</p>",
            escape(&excluded)
        );
    }
}

fn sensitivity(page: &mut String, document: &PlacementDocument) {
    let mut rows = String::new();
    for step in &document.sensitivity {
        for s in step.sets.iter().filter(|s| !s.same_set) {
            let _ = writeln!(
                rows,
                "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td style=\"text-align:left\">{}</td><td>{:.3}</td>\
                 <td>{:.3}</td></tr>",
                escape(&step.threshold),
                step.value,
                escape(s.kind.name()),
                s.k,
                escape(&s.candidates.join(" + ")),
                s.legible_s,
                s.reported_set_legible_s
            );
        }
    }
    let steps = document.sensitivity.len();
    if rows.is_empty() {
        let _ = writeln!(
            page,
            "<h3>Sensitivity to the thresholds</h3>\n<p>With each threshold one step down and up ({steps} runs), \
             every best set (by the mean) stays the same place.</p>"
        );
        return;
    }
    let _ = writeln!(
        page,
        "<h3>Sensitivity to the thresholds</h3>\n<p>Of {steps} runs with one threshold one step down or up, these \
         change a best set (by the mean):</p>\n<table><tr><th>threshold</th><th>moved to</th><th>kind</th><th>k</th>\
         <th>best set then</th><th>its legible s</th><th>the reported set's legible s then</th></tr>\n{rows}</table>"
    );
}

fn candidates(page: &mut String, candidates: &[CandidateRecord]) {
    let _ = writeln!(
        page,
        "<h3>Candidates ranked by legible seconds</h3>\n<p>Every part, and the {LISTED} best display regions \
         (placement.csv lists every patch, not-mountable ones too); <em>not mountable</em> parts are scored, never \
         chosen.</p>\n\
         <table><tr><th>candidate</th><th>kind</th><th>region of</th><th>mountable</th><th>legible s</th>\
         <th>visible s</th><th>first legible s</th><th>first legible at m</th>\
         <th>legible s in the decision window</th><th>worst case legible s</th></tr>"
    );
    let mut patches = 0;
    for c in
        candidates.iter().filter(|c| c.region.is_none() && (c.mountable || c.kind == CandidateKind::Part))
    {
        if c.kind == CandidateKind::Patch {
            patches += 1;
            if patches > LISTED {
                continue;
            }
        }
        let _ = writeln!(
            page,
            "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{:.3}</td><td>{:.3}</td><td>{}</td><td>{}</td>\
             <td>{:.3}</td><td>{:.3}</td></tr>",
            escape(&c.name),
            escape(c.kind.name()),
            c.region_members,
            if c.mountable { "yes" } else { "no" },
            c.legible_s,
            c.visible_s,
            c.first_legible_s.map_or("never".to_string(), |v| format!("{v:.3}")),
            c.first_legible_distance_m.map_or("–".to_string(), |v| format!("{v:.1}")),
            c.decision_window_legible_s,
            c.worst_case_legible_s
        );
    }
    let _ = writeln!(page, "</table>");
}

/// The placement in `folder` as shown on a page in `page_dir`: the picture
/// addressed relative to the page when it lies below it.
pub(crate) fn on_page(folder: &Path, page_dir: &Path, label: &str) -> Result<PlacementOnPage> {
    let document = read_placement(folder)?;
    let picture = folder.join(PLACEMENT_PNG);
    let picture = picture
        .is_file()
        .then(|| picture.strip_prefix(page_dir).ok().map(|p| p.to_string_lossy().into_owned()))
        .flatten();
    Ok(PlacementOnPage { label: label.to_string(), document, picture })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::format::placement::*;

    const HOSTILE: &str = "<script>alert(1)</script>\"'&";

    fn hostile_thresholds() -> ThresholdsRecord {
        let text = || HOSTILE.to_string();
        ThresholdsRecord {
            min_character_height_arcmin: 16.0,
            character_height: CharacterHeight::Fraction(0.5),
            min_characters: 4,
            character_pitch: 0.85,
            min_visible_fraction: 0.8,
            max_view_angle_deg: 60.0,
            min_dwell_s: 1.0,
            decision_window_s: 6.0,
            eyes: EyeRule::Any,
            min_solid_angle_sr: None,
            symmetric: true,
            not_mountable: vec![text()],
            region_radius_m: 0.25,
            sources: Sources {
                min_character_height_arcmin: text(),
                character_height: text(),
                min_characters: text(),
                min_visible_fraction: text(),
                max_view_angle_deg: text(),
                min_dwell_s: text(),
                decision_window_s: text(),
                not_mountable: text(),
                region_radius_m: text(),
            },
        }
    }

    fn hostile_document() -> PlacementDocument {
        let text = || HOSTILE.to_string();
        let member = MemberRecord { candidates: vec![text()], displays: 1, adds_s: 0.0, adds_no_time: true };
        PlacementDocument {
            schema: PLACEMENT_SCHEMA.into(),
            archives: vec![hostile_archive()],
            thresholds: hostile_thresholds(),
            uncertainty: UncertaintyRecord {
                units: text(),
                archives: 1,
                confidence: 0.95,
                replicates: 10,
                seed: 1,
                epsilon_s: 0.05,
                method: text(),
            },
            candidates: vec![CandidateRecord {
                name: text(),
                kind: CandidateKind::Part,
                display_size_m: None,
                mountable: true,
                region: None,
                region_members: 1,
                legible_s: 1.0,
                visible_s: 1.0,
                first_legible_s: None,
                first_legible_distance_m: None,
                decision_window_legible_s: 0.0,
                worst_case_legible_s: 0.0,
                texel_sample_interval_s: None,
                per_archive: Vec::new(),
                legible_through: Some(text()),
            }],
            combinations: vec![CombinationRecord {
                k: 1,
                displays: 1,
                kind: CandidateKind::Part,
                objective: Objective::Mean,
                method: Method::Exhaustive,
                members: vec![member],
                legible_s: 1.0,
                interval_s: Some([0.5, 1.5]),
                p_best: Some(0.9),
                p_within_epsilon: Some(0.95),
                share_of_time: 0.5,
                worst_case_s: 1.0,
                per_archive_s: vec![1.0],
                upper_bound_s: 1.0,
                gap_s: 0.0,
                runners_up: vec![RunnerUpRecord {
                    candidates: vec![text()],
                    displays: 1,
                    legible_s: 0.9,
                    p_best: Some(0.1),
                }],
                tied_with: vec![vec![text()]],
                p_best_note: None,
            }],
            sensitivity: vec![SensitivityRecord {
                threshold: text(),
                value: 1.0,
                sets: vec![SensitivitySet {
                    kind: CandidateKind::Part,
                    k: 1,
                    same_set: false,
                    candidates: vec![text()],
                    legible_s: 1.0,
                    reported_set_legible_s: 0.5,
                }],
            }],
            notes: vec![text()],
            excluded: vec![hostile_excluded()],
        }
    }

    fn hostile_archive() -> ArchiveRecord {
        let text = || HOSTILE.to_string();
        ArchiveRecord {
            table: text(),
            frames: 1,
            eyes: vec![text()],
            seconds_per_frame: 0.1,
            duration_s: 0.1,
            arrival_s: 0.0,
            decision_window_s: [0.0, 0.0],
            warning: Some(text()),
        }
    }

    fn hostile_excluded() -> crate::format::placement::ExcludedRecord {
        crate::format::placement::ExcludedRecord {
            candidate: HOSTILE.into(),
            kind: CandidateKind::Part,
            reason: crate::format::placement::ExclusionReason::NotMountable,
            detail: HOSTILE.into(),
        }
    }

    #[test]
    fn every_string_from_the_file_is_escaped_on_the_page() {
        let dir = tempfile::tempdir().unwrap();
        let document = hostile_document();
        let json = serde_json::to_string(&document).unwrap();
        std::fs::write(dir.path().join(PLACEMENT_JSON), json).unwrap();
        let read = read_placement(dir.path()).unwrap();
        assert_eq!(read, document, "the file reads back to the same document");
        let placement =
            PlacementOnPage { label: HOSTILE.into(), document: read, picture: Some(HOSTILE.into()) };
        let mut page = String::new();
        section(&mut page, &placement);
        assert!(!page.contains("<script>"), "raw markup on the page");
        assert!(!page.contains("\"'&<"), "an unescaped quote or ampersand");
        // Every hostile string appears escaped: the label, the picture, members, runners-up, the
        // threshold moved, sources, the not-mountable list and candidate names.
        let escaped = escape(HOSTILE);
        assert!(page.matches(&escaped).count() >= 14, "{}", page.matches(&escaped).count());
        // The member that adds nothing is marked, and k is stated as displays.
        assert!(page.contains("[adds 0 s]") && page.contains("k counts physical displays"));
    }

    #[test]
    fn a_placement_of_another_version_or_shape_is_an_error_naming_the_file() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join(PLACEMENT_JSON);
        std::fs::write(&path, r#"{"schema": "ufcsr-placement/1", "combinations": []}"#).unwrap();
        let error = read_placement(dir.path()).unwrap_err().to_string();
        assert!(error.contains("placement.json") && error.contains("ufcsr-placement/1"), "{error}");
        let mut document = serde_json::to_value(hostile_document()).unwrap();
        document["combinations"][0]["k"] = serde_json::json!("<b>1</b>");
        std::fs::write(&path, document.to_string()).unwrap();
        let error = read_placement(dir.path()).unwrap_err().to_string();
        assert!(error.contains("not a ufcsr-placement/2 document"), "{error}");
    }
}
