//! The comparison page: one `report.html` for several results (scenarios,
//! resolutions, dedupe rules) side by side — `ufcsr-analyze report A B ...`.
//!
//! Settings side by side, each part's share in every result (the paper's
//! top-5 union of each marked), the ranking differences of every result
//! against the first ([`crate::compare_parts`]: share L1 and largest
//! difference, Kendall τ-b by total and by average with ties, top-5 overlap),
//! the resolution-independent measures where the results have them, and the
//! heatmaps on the vehicle (`views.png`, else the texture) side by side.
//! The images are copied next to the page, so the folder is self-contained
//! like a single result's. Placement folders among the inputs add the
//! placement section (thresholds, ranking, best sets, picture).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use crate::error::{Error, Result};
use crate::output::html::placement_section::{PLACEMENT_PNG, PlacementOnPage, on_page, placement_folder};
use crate::{output::html::escape::escape, result::part_stats::top_five_union};
use crate::{result::model::AnalysisResult, result::result_json::read_result_summary};

/// Parts in each top list compared ([`crate::Comparison::top_k`]).
const TOP_K: usize = 5;

/// One result on the page.
struct Entry {
    /// Short name shown in column headers: the result folder's name (or its
    /// parent's, for the default `ARCHIVE/results`).
    label: String,
    result: AnalysisResult,
    /// The image shown for it, relative to the page (copied beside it).
    image: Option<String>,
}

/// Where a result named on the command line keeps its `result.json`: the
/// path itself when it is a file, else `DIR/result.json`.
fn result_json(path: &Path) -> PathBuf {
    if path.is_dir() { path.join("result.json") } else { path.to_path_buf() }
}

/// A readable label for the result in `dir`: `scenario-a/results` → `scenario-a`.
fn label_of(json: &Path) -> String {
    let dir = json.parent().unwrap_or(Path::new("."));
    let name = |path: &Path| path.file_name().map(|n| n.to_string_lossy().into_owned());
    match name(dir) {
        Some(folder) if folder == "results" => dir.parent().and_then(name).unwrap_or(folder),
        Some(folder) => folder,
        None => json.display().to_string(),
    }
}

/// Writes `out_dir/report.html` comparing the results at `paths` (result
/// folders or `result.json` files; the first is the reference of the ranking
/// comparison). Returns the page's path.
///
/// A path that is a placement folder (holding `placement.json`, written by
/// `ufcsr-analyze placement`) or that file adds the placement section
/// ([`crate::output::html::placement_section`]) with its picture copied
/// beside the page; then one result is enough.
pub fn write_comparison(paths: &[PathBuf], out_dir: &Path) -> Result<PathBuf> {
    // A folder holding both a result and placement.json is both (issue 34:
    // `report R1 R2` used to drop R1 silently when it held a placement).
    let is_result = |path: &Path| {
        (path.is_dir() && path.join("result.json").is_file())
            || path.file_name().is_some_and(|n| n == "result.json")
    };
    let placement_paths: Vec<PathBuf> =
        paths.iter().filter(|p| placement_folder(p).is_some()).cloned().collect();
    let paths: Vec<PathBuf> =
        paths.iter().filter(|p| placement_folder(p).is_none() || is_result(p)).cloned().collect();
    if paths.len() < 2 && (paths.is_empty() || placement_paths.is_empty()) {
        return Err(Error::BadOptions(
            "report needs at least two results to compare, or a result and a placement folder".into(),
        ));
    }
    let paths = &paths[..];
    refuse_result_folders(paths, out_dir)?;
    crate::files::create_output_dir(out_dir)?;
    let mut entries = Vec::with_capacity(paths.len());
    let mut inputs: Vec<PathBuf> = paths.iter().map(|path| result_json(path)).collect();
    let placements = copy_placements(&placement_paths, out_dir, &mut inputs)?;
    for (index, path) in paths.iter().enumerate() {
        let json = result_json(path);
        let result = read_result_summary(&json)?;
        let mut label = label_of(&json);
        if entries.iter().any(|e: &Entry| e.label == label) {
            label = format!("{label} ({})", index + 1);
        }
        // The heatmap on the vehicle when it was rendered, else the texture.
        let dir = json.parent().unwrap_or(Path::new("."));
        let source =
            ["views.png", "heatmap.png"].into_iter().map(|name| dir.join(name)).find(|p| p.is_file());
        let image = match source {
            Some(source) => {
                let name = format!(
                    "result-{}-{}",
                    index + 1,
                    source.file_name().unwrap_or_default().to_string_lossy()
                );
                let target = out_dir.join(&name);
                inputs.push(source.clone());
                crate::files::refuse_overwriting_inputs(std::slice::from_ref(&target), &inputs)?;
                let bytes = crate::files::read_limited(&source, crate::files::IMAGE_LIMIT)?;
                crate::files::write_bytes_atomically(&target, &bytes)?;
                Some(name)
            }
            None => None,
        };
        entries.push(Entry { label, result, image });
    }
    let page = out_dir.join("report.html");
    crate::files::refuse_overwriting_inputs(std::slice::from_ref(&page), &inputs)?;
    crate::files::write_bytes_atomically(&page, render(&entries, &placements).as_bytes())?;
    Ok(page)
}

/// Each placement folder's document, its picture copied beside the page as
/// `placement-N.png`.
fn copy_placements(
    folders: &[PathBuf],
    out_dir: &Path,
    inputs: &mut Vec<PathBuf>,
) -> Result<Vec<PlacementOnPage>> {
    let mut placements = Vec::with_capacity(folders.len());
    for (index, path) in folders.iter().enumerate() {
        let folder = placement_folder(path).unwrap_or_else(|| path.clone());
        let label = folder
            .file_name()
            .map_or_else(|| folder.display().to_string(), |n| n.to_string_lossy().into_owned());
        let mut placement = on_page(&folder, out_dir, &label)?;
        let source = folder.join(PLACEMENT_PNG);
        placement.picture = None;
        if source.is_file() {
            let name = format!("placement-{}.png", index + 1);
            let target = out_dir.join(&name);
            inputs.push(source.clone());
            crate::files::refuse_overwriting_inputs(std::slice::from_ref(&target), inputs)?;
            let bytes = crate::files::read_limited(&source, crate::files::IMAGE_LIMIT)?;
            crate::files::write_bytes_atomically(&target, &bytes)?;
            placement.picture = Some(name);
        }
        placements.push(placement);
    }
    Ok(placements)
}

/// The page may not go into the folder of a result it compares: it would
/// replace that result's own `report.html` (and sit in its result set).
fn refuse_result_folders(paths: &[PathBuf], out_dir: &Path) -> Result<()> {
    for path in paths {
        let json = result_json(path);
        let dir = json.parent().filter(|d| !d.as_os_str().is_empty()).unwrap_or(Path::new("."));
        if crate::files::same_path(dir, out_dir) {
            return Err(Error::BadOptions(format!(
                "--out {} is the folder of the compared result {}: writing report.html there would \
                 replace that result's own report; choose another --out folder",
                out_dir.display(),
                json.display()
            )));
        }
    }
    Ok(())
}

fn render(entries: &[Entry], placements: &[PlacementOnPage]) -> String {
    let mut page = String::new();
    let title = format!(
        "UFCSR comparison: {}",
        entries.iter().map(|e| escape(&e.label)).collect::<Vec<_>>().join(" · ")
    );
    let _ = write!(
        page,
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>{title}</title>\n<style>\
         body{{font-family:sans-serif;margin:2em;color:#222}}\
         table{{border-collapse:collapse;margin:0.5em 0}}td,th{{border:1px solid #ccc;padding:3px 8px;text-align:right}}\
         td:first-child,th:first-child{{text-align:left}}td.top{{background:#fff4d6;font-weight:bold}}\
         .warn{{background:#fde8e8;border-left:4px solid #c00;padding:0.4em 0.8em;margin:0.3em 0}}\
         .sheets{{display:flex;flex-wrap:wrap;gap:1em}}.sheets figure{{margin:0;flex:1 1 400px}}\
         img{{max-width:100%;image-rendering:pixelated;border:1px solid #ccc}}</style></head><body>\n<h1>{title}</h1>\n"
    );
    let header = |first: &str| {
        let mut row = format!("<tr><th>{first}</th>");
        for entry in entries {
            let _ = write!(row, "<th>{}</th>", escape(&entry.label));
        }
        row.push_str("</tr>");
        row
    };
    render_settings(&mut page, entries, &header("setting"));
    render_shares(&mut page, entries, &header("part (share %)"));
    render_rankings(&mut page, entries);
    render_measures(&mut page, entries, &header("part (deg²·s / exposure s)"));

    let _ = writeln!(page, "<h2>The heatmaps side by side</h2>\n<div class=\"sheets\">");
    for entry in entries {
        match &entry.image {
            Some(image) => {
                let _ = writeln!(
                    page,
                    "<figure><img src=\"{}\" alt=\"heatmap of {label}\"><figcaption>{label}</figcaption></figure>",
                    escape(image),
                    label = escape(&entry.label)
                );
            }
            None => {
                let _ = writeln!(
                    page,
                    "<figure><p>{}: no heatmap image beside its result.json</p></figure>",
                    escape(&entry.label)
                );
            }
        }
    }
    let _ = writeln!(page, "</div>");
    for placement in placements {
        crate::output::html::placement_section::section(&mut page, placement);
    }
    let _ = writeln!(page, "<p><small>ufcsr {}</small></p>\n</body></html>", env!("CARGO_PKG_VERSION"));
    page
}

/// One row of the settings table: a result's value, as HTML.
type Setting = dyn Fn(&AnalysisResult) -> String;

/// A number with `digits` decimals, or a dash.
fn optional(value: Option<f64>, digits: usize) -> String {
    value.map_or("–".to_string(), |v| format!("{v:.digits$}"))
}

fn render_settings(page: &mut String, entries: &[Entry], header: &str) {
    let _ = writeln!(page, "<h2>Settings</h2>\n<table>{header}");
    let rows: [(&str, &Setting); 12] = [
        ("archive", &|r| escape(&r.settings.archive)),
        ("measure", &|r| escape(r.measure.name())),
        ("palette", &|r| {
            format!(
                "{} {}×{}",
                escape(&r.settings.palette.kind),
                r.settings.palette.width,
                r.settings.palette.height
            )
        }),
        ("one count means", &|r| format!("{:?}", r.settings.dedupe)),
        ("trimming", &|r| escape(&r.settings.trim.mode)),
        ("pixels per degree", &|r| optional(r.resolution.as_ref().and_then(|s| s.pixels_per_degree), 2)),
        ("texel size (mm)", &|r| optional(r.resolution.as_ref().and_then(|s| s.texel_size_mm), 2)),
        ("images decoded", &|r| r.images.decoded.to_string()),
        ("texels seen", &|r| r.texels_seen.to_string()),
        ("grand total", &|r| r.grand_total.to_string()),
        ("largest count", &|r| r.max_count.to_string()),
        ("warnings", &|r| r.warnings.len().to_string()),
    ];
    for (name, value) in rows {
        let _ = write!(page, "<tr><th>{name}</th>");
        for entry in entries {
            let _ = write!(page, "<td>{}</td>", value(&entry.result));
        }
        let _ = writeln!(page, "</tr>");
    }
    let _ = writeln!(page, "</table>");
    for entry in entries {
        for warning in &entry.result.warnings {
            let _ = writeln!(page, "<div class=\"warn\">{}: {}</div>", escape(&entry.label), escape(warning));
        }
    }
}

/// Every part's share in each result, in the first result's order of share.
fn render_shares(page: &mut String, entries: &[Entry], header: &str) {
    let mut names: Vec<&str> = Vec::new();
    for entry in entries {
        for part in &entry.result.parts {
            if !names.contains(&part.name.as_str()) {
                names.push(&part.name);
            }
        }
    }
    if names.is_empty() {
        let _ = writeln!(page, "<h2>Shares</h2>\n<p>No result has a parts table (no PIdT).</p>");
        return;
    }
    let share =
        |entry: &Entry, name: &str| entry.result.parts.iter().find(|p| p.name == name).map(|p| p.share);
    let first = &entries[0];
    names.sort_by(|a, b| {
        share(first, b).unwrap_or(-1.0).total_cmp(&share(first, a).unwrap_or(-1.0)).then(a.cmp(b))
    });
    let marked: Vec<Vec<bool>> = entries.iter().map(|e| top_five_union(&e.result.parts)).collect();
    let _ = writeln!(
        page,
        "<h2>Shares</h2>\n<p>Share of the grand total per part, percent. Highlighted: the paper's table of each \
         result (the union of its top five by total, peak and average).</p>\n<table>{header}"
    );
    for name in names {
        let _ = write!(page, "<tr><td>{}</td>", escape(name));
        for (entry, marks) in entries.iter().zip(&marked) {
            let index = entry.result.parts.iter().position(|p| p.name == name);
            match index {
                Some(index) => {
                    let class = if marks[index] { " class=\"top\"" } else { "" };
                    let _ = write!(page, "<td{class}>{:.2}</td>", entry.result.parts[index].share);
                }
                None => page.push_str("<td>–</td>"),
            }
        }
        let _ = writeln!(page, "</tr>");
    }
    let _ = writeln!(page, "</table>");
}

/// Every result against the first: [`crate::compare_parts`].
fn render_rankings(page: &mut String, entries: &[Entry]) {
    let reference = &entries[0];
    let _ = writeln!(
        page,
        "<h2>Ranking differences against {}</h2>\n<p>Share L1 = Σ |share difference| (percentage points); \
         Kendall τ-b of the part rankings (1 = same order), with the pairs tied in either ranking left out; \
         top-{TOP_K} overlap by total.</p>\n<table><tr><th>result</th><th>share L1 (pp)</th><th>largest (pp)</th>\
         <th>of part</th><th>τ by total (ties)</th><th>τ by average (ties)</th><th>top-{TOP_K} overlap</th>\
         <th>coverage difference (pp)</th></tr>",
        escape(&reference.label)
    );
    for entry in &entries[1..] {
        match crate::result::compare::compare_parts(&reference.result.parts, &entry.result.parts, TOP_K) {
            Ok(c) => {
                let _ = writeln!(
                    page,
                    "<tr><td>{}</td><td>{:.2}</td><td>{:.2}</td><td>{}</td><td>{:.3} ({})</td><td>{:.3} ({})</td>\
                     <td>{} / {}</td><td>{:+.2}</td></tr>",
                    escape(&entry.label),
                    c.share_l1_pp,
                    c.share_max_pp,
                    escape(&c.share_max_part),
                    c.kendall_tau_total,
                    c.tied_pairs_total,
                    c.kendall_tau_average,
                    c.tied_pairs_average,
                    c.top_k_overlap,
                    c.top_k,
                    c.coverage_difference_pp
                );
            }
            Err(error) => {
                let _ = writeln!(
                    page,
                    "<tr><td>{}</td><td colspan=\"7\">not comparable: {}</td></tr>",
                    escape(&entry.label),
                    escape(&error.to_string())
                );
            }
        }
    }
    let _ = writeln!(page, "</table>");
}

/// The resolution-independent measures, where every result has them.
fn render_measures(page: &mut String, entries: &[Entry], header: &str) {
    let Some(measures): Option<Vec<_>> = entries.iter().map(|e| e.result.measures.as_ref()).collect() else {
        return;
    };
    let _ = writeln!(
        page,
        "<h2>Resolution-independent measures</h2>\n<p>Per part: visible angular area over time (deg²·s) / seconds \
         seen, per eye (see the README). These do not change meaning with pixels per degree, unlike the counts.</p>\n\
         <table>{header}"
    );
    let optional = |value: Option<f64>| value.map_or("–".to_string(), |v| format!("{v:.2}"));
    let mut names: Vec<&str> =
        measures[0].parts.iter().filter(|p| p.pixels > 0).map(|p| p.name.as_str()).collect();
    names.sort_by_key(|name| std::cmp::Reverse(measures[0].part(name).map_or(0, |p| p.pixels)));
    for name in names {
        let _ = write!(page, "<tr><td>{}</td>", escape(name));
        for measure in &measures {
            match measure.part(name) {
                Some(part) => {
                    let _ = write!(
                        page,
                        "<td>{} / {}</td>",
                        optional(part.angular_area_deg2_s),
                        optional(part.exposure_s)
                    );
                }
                None => page.push_str("<td>–</td>"),
            }
        }
        let _ = writeln!(page, "</tr>");
    }
    let _ = writeln!(page, "</table>");
}
