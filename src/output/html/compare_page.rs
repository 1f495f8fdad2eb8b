//! The comparison page: one `report.html` for several results (scenarios,
//! resolutions, dedupe rules) side by side — `ufcsr report A B ...`.
//!
//! Settings side by side; first the measure docs/science.md says to quote —
//! each part's angular area and exposure in every result, ranked by the
//! first result's angular area, and every result's ranking against the
//! first's by angular area ([`crate::result::compare::compare_angular_areas`])
//! — then, labelled paper-compatible, each part's share of the count (the
//! paper's top-5 union of each marked) and the count's ranking differences
//! ([`crate::compare_parts`]: share L1 and largest difference, Kendall τ-b by
//! total and by average with ties, top-5 overlap); and the heatmaps on the
//! vehicle (`views.png`, else the texture) side by side, by default drawn
//! again on ONE colour scale (the page says so), with `--own-scales` as each
//! result drew them. The heatmaps show the measure to quote, per-texel
//! angular area (deg²·s, from each result's `texel-area.f32`, 0 to the
//! largest texel of any result), when every result has it, else the
//! paper-compatible count (0 to the largest count of any result); the
//! heading says which. Columns are labelled by `--label` (else the result
//! folders' names).
//!
//! The images are written next to the page, so the folder is self-contained
//! like a single result's. Placement folders among the inputs add the
//! placement section (thresholds, ranking, best sets, picture).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use crate::error::{Error, Result};
use crate::output::html::placement_section::{PLACEMENT_PNG, PlacementOnPage, on_page, placement_folder};
use crate::{output::html::escape::escape, result::part_stats::top_five_union};
use crate::{result::model::AnalysisResult, result::result_json::read_result_summary};

/// What the page says when the heatmaps share one colour scale.
pub const SHARED_SCALE: &str = "All heatmaps share one colour scale";
/// What the page says when each heatmap keeps its own scale (`--own-scales`).
pub const OWN_SCALES: &str = "Each heatmap is on its own colour scale";

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

/// How the comparison page is written (`ufcsr report`).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct ComparisonOptions {
    /// Column labels, one per result in order (`--label`); results beyond
    /// them are labelled by their folders' names.
    pub labels: Vec<String>,
    /// Show each result's pictures as it drew them, each on its own colour
    /// scale (`--own-scales`); by default they are drawn again on one.
    pub own_scales: bool,
}

/// [`write_comparison_with`] with the default options (one colour scale,
/// folder names as labels).
pub fn write_comparison(paths: &[PathBuf], out_dir: &Path) -> Result<PathBuf> {
    write_comparison_with(paths, out_dir, &ComparisonOptions::default()).map(|written| written.page)
}

/// What [`write_comparison_with`] wrote.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct WrittenComparison {
    /// `report.html`.
    pub page: PathBuf,
    /// Every file written, in the order written, the page last: the pictures
    /// beside it (`result-N-heatmap.png`, or `result-N/views.png` and its
    /// eight views; `placement-N.png`), so `--json`'s `written` is complete.
    pub files: Vec<PathBuf>,
}

/// Writes `out_dir/report.html` comparing the results at `paths` (result
/// folders or `result.json` files; the first is the reference of the ranking
/// comparison). Returns the page's path and every file written.
///
/// A path that is a placement folder (holding `placement.json`, written by
/// `ufcsr placement`) or that file adds the placement section
/// ([`crate::output::html::placement_section`]) with its picture copied
/// beside the page; then one result is enough.
pub fn write_comparison_with(
    paths: &[PathBuf],
    out_dir: &Path,
    options: &ComparisonOptions,
) -> Result<WrittenComparison> {
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
    if options.labels.len() > paths.len() {
        return Err(Error::BadOptions(format!(
            "{} labels (--label) for {} results: give at most one label per result, in order",
            options.labels.len(),
            paths.len()
        )));
    }
    let mut entries = Vec::with_capacity(paths.len());
    let mut inputs: Vec<PathBuf> = paths.iter().map(|path| result_json(path)).collect();
    let mut files = Vec::new();
    let placements = copy_placements(&placement_paths, out_dir, &mut inputs, &mut files)?;
    for (index, path) in paths.iter().enumerate() {
        let json = result_json(path);
        let result = read_result_summary(&json)?;
        let mut label = options.labels.get(index).cloned().unwrap_or_else(|| label_of(&json));
        if entries.iter().any(|e: &Entry| e.label == label) {
            label = format!("{label} ({})", index + 1);
        }
        entries.push(Entry { label, result, image: None });
    }
    // The measure to quote where every result kept its per-texel values
    // (`texel-area.f32`); else the paper-compatible count.
    let areas = read_areas(paths, &entries)?;
    if areas.is_some() {
        inputs.extend(paths.iter().map(|p| area_file(&result_json(p))));
    }
    let scale = (!options.own_scales).then(|| match &areas {
        Some(values) => {
            let largest = values.iter().map(|v| crate::output::heatmap::largest_area(v)).fold(0f32, f32::max);
            HeatmapScale::Area(largest)
        }
        None => HeatmapScale::Count(entries.iter().map(|e| e.result.max_count).max().unwrap_or(0)),
    });
    for (index, (path, entry)) in paths.iter().zip(&mut entries).enumerate() {
        let json = result_json(path);
        entry.image = match scale {
            Some(scale) => {
                let area = areas.as_ref().map(|values| &values[index][..]);
                let on = OneScale { result: &entry.result, index, scale, area };
                shared_scale_image(&json, &on, out_dir, &inputs, &mut files)?
            }
            None => {
                // Checked as the shared scale checks it (palette kind, encoding), though
                // the counts are not drawn again: a damaged result is refused either way.
                crate::result::result_json::read_texel_counts(&json)?;
                copy_image(&json, (index, out_dir), &mut inputs, areas.is_some(), &mut files)?
            }
        };
    }
    let page = out_dir.join("report.html");
    crate::files::refuse_overwriting_inputs(std::slice::from_ref(&page), &inputs)?;
    crate::files::write_bytes_atomically(
        &page,
        render(&entries, &placements, scale, areas.is_some()).as_bytes(),
    )?;
    files.push(page.clone());
    Ok(WrittenComparison { page, files })
}

/// `texel-area.f32` beside a result's `result.json`.
fn area_file(json: &Path) -> PathBuf {
    json.parent().unwrap_or(Path::new(".")).join(crate::result::texel_area_file::TEXEL_AREA_FILE)
}

/// Every result's per-texel angular area (`texel-area.f32` beside its
/// `result.json`), when every result has one; `None` when any lacks it (the
/// page then compares the count's heatmaps and says why). A file that is
/// there but wrong, or no regular file, is an error naming it.
fn read_areas(paths: &[PathBuf], entries: &[Entry]) -> Result<Option<Vec<Vec<f32>>>> {
    let mut areas = Vec::with_capacity(paths.len());
    for (path, entry) in paths.iter().zip(entries) {
        let json = result_json(path);
        let dir = json.parent().unwrap_or(Path::new("."));
        let palette = &entry.result.settings.palette;
        match crate::result::texel_area_file::read_texel_area_in(dir, palette.width, palette.height)? {
            Some(area) => areas.push(area),
            None => return Ok(None),
        }
    }
    Ok(Some(areas))
}

/// The one colour scale of the page's heatmaps: its top, in the measure shown.
#[derive(Debug, Clone, Copy)]
enum HeatmapScale {
    /// Per-texel angular area, deg²·s (the largest texel of any result).
    Area(f32),
    /// The paper-compatible count (the largest of any result).
    Count(u32),
}

/// One result drawn again on the page's scale.
struct OneScale<'a> {
    result: &'a AnalysisResult,
    index: usize,
    scale: HeatmapScale,
    /// Its per-texel angular area, when the page shows area.
    area: Option<&'a [f32]>,
}

/// The result's own picture of the measure the page shows, copied beside
/// the page as `result-N-NAME` (added to `written`): with `area`, the views
/// on the vehicle when rendered, else the texture (`heatmap.png`, or an
/// earlier version's `heatmap-area.png`); without, the count texture
/// `heatmap-count.png` of a result whose `heatmap.png` and views show the
/// area, else the views or `heatmap.png`. `(index, out_dir)`: the result's place on the page and the
/// page's folder.
fn copy_image(
    json: &Path,
    (index, out_dir): (usize, &Path),
    inputs: &mut Vec<PathBuf>,
    area: bool,
    written: &mut Vec<PathBuf>,
) -> Result<Option<String>> {
    let dir = json.parent().unwrap_or(Path::new("."));
    use crate::output::heatmap::{COUNT_HEATMAP_FILE, EARLIER_AREA_HEATMAP_FILE, HEATMAP_FILE};
    let candidates = if area {
        vec!["views.png", EARLIER_AREA_HEATMAP_FILE, HEATMAP_FILE]
    } else if dir.join(COUNT_HEATMAP_FILE).is_file() {
        vec![COUNT_HEATMAP_FILE]
    } else {
        vec!["views.png", HEATMAP_FILE]
    };
    let Some(source) = candidates.into_iter().map(|name| dir.join(name)).find(|p| p.is_file()) else {
        return Ok(None);
    };
    let name = format!("result-{}-{}", index + 1, source.file_name().unwrap_or_default().to_string_lossy());
    let target = out_dir.join(&name);
    inputs.push(source.clone());
    crate::files::refuse_overwriting_inputs(std::slice::from_ref(&target), inputs)?;
    let bytes = crate::files::read_limited(&source, crate::files::IMAGE_LIMIT)?;
    crate::files::write_bytes_atomically(&target, &bytes)?;
    written.push(target);
    Ok(Some(name))
}

/// The result's heatmap drawn again with the colour scale's top shared by
/// every result on the page: the views on the vehicle
/// (`result-N/views.png`) when the result has views and its archive's
/// vehicle model is found, else the texture (`result-N-heatmap.png`); the
/// files are added to `written`.
fn shared_scale_image(
    json: &Path,
    on: &OneScale,
    out_dir: &Path,
    inputs: &[PathBuf],
    written: &mut Vec<PathBuf>,
) -> Result<Option<String>> {
    let (result, index) = (on.result, on.index);
    let (levels, max, quantum, width, height) = match (on.scale, on.area) {
        (HeatmapScale::Area(largest), Some(values)) => {
            let levels = crate::output::heatmap::AreaLevels::with_top(values, largest);
            let top = levels.level_of(largest);
            let palette = &result.settings.palette;
            (levels.levels, Some(top), Some(levels.quantum), palette.width, palette.height)
        }
        (scale, _) => {
            // Area without values cannot happen (the page draws area only
            // when every result has them); its count then takes its own top.
            let stored = crate::result::result_json::read_texel_counts(json)?;
            let max = if let HeatmapScale::Count(max) = scale { Some(max) } else { None };
            (stored.texel_counts, max, None, stored.width, stored.height)
        }
    };
    let options = crate::archive::options::HeatmapOptions { scale: result.settings.heatmap_scale, max };
    let had_views = json.parent().unwrap_or(Path::new(".")).join("views.png").is_file();
    if let Some((model, manifest)) = had_views.then(|| vehicle_of(result)).flatten() {
        let folder = out_dir.join(format!("result-{}", index + 1));
        crate::files::refuse_overwriting_inputs(&[folder.join("views.png")], inputs)?;
        let track = manifest.as_ref().and_then(crate::archive::scenario_track::ScenarioTrack::from_manifest);
        let scenario = track.as_ref().and_then(|t| t.name.as_deref());
        let (caption, unit) = match quantum {
            Some(_) => (
                crate::output::heatmap_views::area_views_caption(scenario),
                crate::output::heatmap_views::AREA_UNIT.to_string(),
            ),
            None => (
                crate::output::heatmap_views::views_caption(
                    result.measure,
                    &result.settings.archive,
                    scenario,
                ),
                crate::output::heatmap_views::measure_unit(result.measure).to_string(),
            ),
        };
        let texture = crate::output::heatmap_views::ViewTexture {
            counts: &levels,
            width,
            height,
            options,
            caption,
            unit,
            quantum,
            views_scale: crate::output::heatmap_views::DEFAULT_VIEWS_SCALE,
            pedestrian_azimuths_deg: track.map_or_else(Vec::new, |t| {
                t.frames.iter().filter_map(|f| f.pedestrian_azimuth_deg()).collect()
            }),
        };
        let views = crate::output::view_sheet::write_views(&model, &texture, &folder)?;
        written.extend(views.views);
        written.push(views.contact_sheet);
        written.push(views.pdf);
        return Ok(Some(format!("result-{}/views.png", index + 1)));
    }
    let name = format!(
        "result-{}-{}",
        index + 1,
        if quantum.is_some() { "heatmap.png" } else { "heatmap-count.png" }
    );
    let target = out_dir.join(&name);
    crate::files::refuse_overwriting_inputs(std::slice::from_ref(&target), inputs)?;
    let rgb = crate::output::heatmap::render(&levels, width, options);
    crate::files::write_rgb_png(&target, [width, height], &rgb, png::Compression::Fast)?;
    written.push(target);
    Ok(Some(name))
}

/// The vehicle model the result's archive manifest names, with the manifest.
fn vehicle_of(
    result: &AnalysisResult,
) -> Option<(crate::archive::vehicle_model::VehicleModel, Option<crate::archive::manifest::Manifest>)> {
    if !result.settings.manifest {
        return None;
    }
    let root = PathBuf::from(&result.settings.archive);
    let manifest = crate::archive::manifest::Manifest::load_from_dir(&root).ok()??;
    let path = root.join(manifest.vehicle.as_ref()?);
    let model = crate::archive::vehicle_model::VehicleModel::read(&path).ok()?;
    Some((model, Some(manifest)))
}

/// Each placement folder's document, its picture copied beside the page as
/// `placement-N.png` (added to `written`).
fn copy_placements(
    folders: &[PathBuf],
    out_dir: &Path,
    inputs: &mut Vec<PathBuf>,
    written: &mut Vec<PathBuf>,
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
            written.push(target);
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

fn render(
    entries: &[Entry],
    placements: &[PlacementOnPage],
    scale: Option<HeatmapScale>,
    area: bool,
) -> String {
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
    render_measures(&mut page, entries, &header("part (deg²·s / exposure s)"));
    render_area_rankings(&mut page, entries);
    render_shares(&mut page, entries, &header("part (count share %)"));
    render_rankings(&mut page, entries);

    render_heatmap_heading(&mut page, scale, area);
    let _ = writeln!(page, "<div class=\"sheets\">");
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

/// `value` for a result of the pixel path; a dash for the exact measure,
/// which reads no images (its own settings are its measure and definition).
fn pixel_path_only(result: &AnalysisResult, value: String) -> String {
    if result.measure == crate::format::result::CountMeasure::Unobstructed {
        "– (exact)".to_string()
    } else {
        value
    }
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
        ("trimming", &|r| pixel_path_only(r, escape(&r.settings.trim.mode))),
        ("pixels per degree", &|r| optional(r.resolution.as_ref().and_then(|s| s.pixels_per_degree), 2)),
        ("texel size (mm)", &|r| optional(r.resolution.as_ref().and_then(|s| s.texel_size_mm), 2)),
        ("images decoded", &|r| pixel_path_only(r, r.images.decoded.to_string())),
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
        let _ = writeln!(
            page,
            "<h2>Paper-compatible: count shares</h2>\n<p>No result has a parts table (no PIdT).</p>"
        );
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
        "<h2>Paper-compatible: count shares</h2>\n<p>The paper's per-texel count (it depends on resolution: \
         quote the measures above). Share of the grand total per part, percent. Highlighted: the paper's table of each \
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
        "<h2>Paper-compatible: count ranking differences against {}</h2>\n<p>Share L1 = Σ |share difference| (percentage points); \
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

/// What the page says above the heatmaps: which measure, which scale.
fn render_heatmap_heading(page: &mut String, scale: Option<HeatmapScale>, area: bool) {
    let _ = if area {
        writeln!(page, "<h2>The heatmaps side by side: {AREA_HEATMAPS}</h2>")
    } else {
        writeln!(
            page,
            "<h2>The heatmaps side by side: {COUNT_HEATMAPS}</h2>\n<p>Not every result has its per-texel angular \
             area (<code>texel-area.f32</code>, written by an analysis with the eyes' projection and fps), so the \
             heatmaps show the paper's count.</p>"
        )
    };
    let _ = match scale {
        Some(HeatmapScale::Area(largest)) => writeln!(
            page,
            "<p>{SHARED_SCALE}: plasma from 0 to {largest:.3e} deg²·s per texel (the largest texel of any result), \
             never-seen texels grey; colours compare across results. (<code>--own-scales</code> shows each \
             result's own pictures.)</p>"
        ),
        Some(HeatmapScale::Count(max)) => writeln!(
            page,
            "<p>{SHARED_SCALE}: plasma from 0 to {max} (the largest count of any result), never-seen texels grey; \
             colours compare across results. (<code>--own-scales</code> shows each result's own pictures.)</p>"
        ),
        None => writeln!(
            page,
            "<p>{OWN_SCALES}: each runs from 0 to that result's own largest value, so the same colour means \
             different values in different results.</p>"
        ),
    };
}

/// The heatmaps' heading when they show the measure to quote.
pub const AREA_HEATMAPS: &str = "visible angular area over time (deg²·s per texel, the quoted measure)";
/// The heatmaps' heading when some result lacks per-texel angular area.
pub const COUNT_HEATMAPS: &str = "the paper-compatible count";

/// The heading of the comparison's first table of parts.
pub const RANKED_HEADING: &str = "Ranked by angular area: the measures to quote";

/// Every result against the first by angular area
/// ([`crate::result::compare::compare_angular_areas`]), where all have it.
fn render_area_rankings(page: &mut String, entries: &[Entry]) {
    let Some(measures): Option<Vec<_>> = entries.iter().map(|e| e.result.measures.as_ref()).collect() else {
        let _ = writeln!(
            page,
            "<h2>{RANKED_HEADING}</h2>\n<div class=\"warn\">Not every result has angular areas (a manifest \
             with the eyes' projection and fps): only the paper-compatible count compares below.</div>"
        );
        return;
    };
    let _ = writeln!(
        page,
        "<h3>Ranking by angular area against {}</h3>\n<p>Share L1 = Σ |difference of the parts' shares of the \
         angular area| (percentage points); Kendall τ-b of the rankings by angular area (pairs tied in either \
         left out); top-{TOP_K} overlap.</p>\n<table><tr><th>result</th><th>share L1 (pp)</th><th>largest (pp)</th>\
         <th>of part</th><th>τ (ties)</th><th>top-{TOP_K} overlap</th></tr>",
        escape(&entries[0].label)
    );
    for (entry, measure) in entries.iter().zip(&measures).skip(1) {
        match crate::result::compare::compare_angular_areas(measures[0], measure, TOP_K) {
            Some(c) => {
                let _ = writeln!(
                    page,
                    "<tr><td>{}</td><td>{:.2}</td><td>{:.2}</td><td>{}</td><td>{:.3} ({})</td><td>{} / {}</td></tr>",
                    escape(&entry.label),
                    c.share_l1_pp,
                    c.share_max_pp,
                    escape(&c.share_max_part),
                    c.kendall_tau,
                    c.tied_pairs,
                    c.top_k_overlap,
                    c.top_k
                );
            }
            None => {
                let _ = writeln!(
                    page,
                    "<tr><td>{}</td><td colspan=\"5\">no angular areas (no fps or projection)</td></tr>",
                    escape(&entry.label)
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
        "<h2>{RANKED_HEADING}</h2>\n<p>The measures docs/science.md says to quote, ranked by the first result's \
         angular area. Per part: visible angular area over time (deg²·s) / seconds seen (exposure), per eye. \
         These do not change meaning with pixels per degree, unlike the counts.</p>\n\
         <table>{header}"
    );
    let optional = |value: Option<f64>| value.map_or("–".to_string(), |v| format!("{v:.2}"));
    let mut names: Vec<&str> =
        measures[0].parts.iter().filter(|p| p.pixels > 0).map(|p| p.name.as_str()).collect();
    let area = |name: &str| measures[0].part(name).and_then(|p| p.angular_area_deg2_s).unwrap_or(-1.0);
    names.sort_by(|a, b| area(b).total_cmp(&area(a)).then(a.cmp(b)));
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
