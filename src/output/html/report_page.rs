//! `report.html`: one self-contained page per result, for people.
//!
//! What a researcher checks first — the result's warnings (stray pixels,
//! unlabelled texels, colour damage, resolution dependence) and failed
//! files — then the numbers docs/science.md says to quote (angular area and
//! exposure per part; legible time where a placement result lies beside),
//! then the summary, the scenario and rig with the map, the paper-compatible
//! per-texel count table (the paper's top-5 union marked), the views, the
//! heatmap texture and links to the vehicle with the heatmap on it
//! (`heatmap.glb`) and the machine-readable files, and the settings.
//!
//! No script, no network: the page links only files beside it (its
//! pictures are not embedded: the heatmap alone can be tens of megabytes),
//! and says so at its top — send the results folder (zipped), not the page.

use std::fmt::Write as _;
use std::path::Path;

use crate::archive::scenario_track::ScenarioTrack;
use crate::error::Result;
use crate::output::html::escape::escape;
use crate::output::html::placement_section::PlacementOnPage;
use crate::output::numbers::grouped;
use crate::result::part_stats::top_five_union;
use crate::{output::written_files::WrittenFiles, result::model::AnalysisResult};

/// Writes the report page for `result` into `path` (beside the other files).
/// `scenario` is what the archive's manifest says about the scenario (the
/// scenario section shows it); `placement`: the placement result found
/// beside it (or why it could not be read).
pub(crate) fn write_report(
    path: &Path,
    result: &AnalysisResult,
    files: &WrittenFiles,
    scenario: &ScenarioPage,
    placement: Option<&std::result::Result<PlacementOnPage, String>>,
) -> Result<()> {
    let inputs = PageInputs { result, files, scenario, placement };
    crate::files::write_bytes_atomically(path, render(&inputs).as_bytes())
}

/// The scenario section's content beyond the files: the manifest's track
/// (none without a manifest) and why there is no frame strip, if so.
#[derive(Default)]
pub(crate) struct ScenarioPage<'a> {
    pub track: Option<&'a ScenarioTrack>,
    pub strip_skipped: Option<String>,
}

fn file_name(path: &Path) -> String {
    escape(&path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default())
}

/// What the page is made from: the result and the files written beside it.
struct PageInputs<'a> {
    result: &'a AnalysisResult,
    files: &'a WrittenFiles,
    scenario: &'a ScenarioPage<'a>,
    placement: Option<&'a std::result::Result<PlacementOnPage, String>>,
}

/// One section of the page: appends its HTML (nothing when it has nothing
/// to show).
type Section = fn(&mut String, &PageInputs);

/// The page's sections, top to bottom: adding a section is adding its
/// function here (one line).
const SECTIONS: &[Section] = &[
    head,
    needs_its_folder,
    warnings,
    measures,
    placement,
    summary,
    resolution,
    scenario,
    plots,
    parts,
    vehicle_views,
    heatmap,
    files,
    settings,
    foot,
];

/// The words that say the page shows pictures from its folder.
pub const NEEDS_ITS_FOLDER: &str = "This page shows pictures and links files from its own folder";

/// The page is not a single file: it says so before anything else.
fn needs_its_folder(page: &mut String, _inputs: &PageInputs) {
    let _ = writeln!(
        page,
        "<p class=\"provenance\">{NEEDS_ITS_FOLDER} (<code>views.png</code>, <code>heatmap.png</code>, \
         <code>plots/</code>, …): keep it there, and send the whole results folder (zipped), not the page alone.</p>"
    );
}

fn render(inputs: &PageInputs) -> String {
    let mut page = String::new();
    for section in SECTIONS {
        section(&mut page, inputs);
    }
    page
}

/// The document head with its style sheet, the title and the provenance.
fn head(page: &mut String, inputs: &PageInputs) {
    let title = format!("UFCSR result: {}", escape(&inputs.result.settings.archive));
    let _ = write!(
        page,
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>{title}</title>\n<style>\
         body{{font-family:sans-serif;margin:2em;max-width:1100px;color:#222}}\
         table{{border-collapse:collapse;margin:0.5em 0}}td,th{{border:1px solid #ccc;padding:3px 8px;text-align:right}}\
         td:first-child,th:first-child,table.words td{{text-align:left}}tr.top{{background:#fff4d6}}\
         .swatch{{display:inline-block;width:0.9em;height:0.9em;border:1px solid #555;vertical-align:middle;margin-right:0.4em}}\
         .warn{{background:#fde8e8;border-left:4px solid #c00;padding:0.4em 0.8em;margin:0.3em 0}}\
         img{{max-width:100%;image-rendering:pixelated;border:1px solid #ccc}}img.plot{{image-rendering:auto}}\
         .provenance{{color:#555;font-size:0.9em}}</style></head><body>\n<h1>{title}</h1>\n"
    );
    let _ = writeln!(page, "{}", crate::output::html::provenance::paragraph());
}

/// Warnings first: what needs looking at before trusting the numbers.
fn warnings(page: &mut String, inputs: &PageInputs) {
    let result = inputs.result;
    let _ = writeln!(page, "<h2>Warnings</h2>");
    let mut warnings: Vec<String> = result.warnings.iter().map(|w| escape(w)).collect();
    if result.images.failed > 0 {
        warnings.push(format!(
            "{} images could not be read and were not counted (see <code>failures</code> in result.json)",
            result.images.failed
        ));
    }
    // Stray pixels, unlabelled counts and colour damage are in the result's
    // own warnings, as on stderr.
    if warnings.is_empty() {
        let _ = writeln!(page, "<p>None.</p>");
    }
    for warning in warnings {
        let _ = writeln!(page, "<div class=\"warn\">{warning}</div>");
    }
}

/// The scenario and the rig in words, and the map, when the archive's
/// manifest describes them.
fn scenario(page: &mut String, inputs: &PageInputs) {
    let Some(track) = inputs.scenario.track else { return };
    let _ = writeln!(page, "<h2>The scenario</h2>\n<table class=\"words\">");
    for (label, value) in &track.summary {
        let _ = writeln!(page, "<tr><th>{}</th><td>{}</td></tr>", escape(label), escape(value));
    }
    let _ = writeln!(page, "</table>");
    if let Some(map) = &inputs.files.map_png {
        let _ = writeln!(
            page,
            "<p>From above, north up: the vehicle's trajectory coloured by time, its footprint and the sightlines \
             from the eyes at five frames, the pedestrian (green), occluders (grey; moving ones blue).</p>\n\
             <img src=\"{0}\" alt=\"the scenario from above\" class=\"plot\">",
            file_name(map)
        );
    }
    if let Some(strip) = &inputs.files.frames_strip_png {
        let _ = writeln!(
            page,
            "<h3>What the pedestrian saw</h3>\n<p>Frames of one eye spread over the scenario, the vehicle in its \
             parts' colours (as in the parts table), everything else light grey.</p>\n\
             <img src=\"{0}\" alt=\"frames as the eye saw them, the vehicle coloured by part\" class=\"plot\">",
            file_name(strip)
        );
    } else if let Some(why) = &inputs.scenario.strip_skipped {
        let _ = writeln!(page, "<p>No frame strip: {}.</p>", escape(why));
    }
}

/// Tiles found, decoded, trimmed and failed (the pixel path's); texels seen
/// and the totals. A result of the exact measure read no images: it shows
/// its eye-frames and its definition instead of tile counts.
fn summary(page: &mut String, inputs: &PageInputs) {
    let result = inputs.result;
    let images = &result.images;
    let _ = writeln!(page, "<h2>Summary</h2>\n<table>");
    if result.measure == crate::format::result::CountMeasure::Unobstructed {
        let eye_frames = result.measures.as_ref().map_or("–".to_string(), |m| grouped(m.eye_frames));
        let _ = writeln!(
            page,
            "<tr><th>measure</th><td>unobstructed (exact: ray traced, no images read)</td></tr>\
             <tr><th>eye-frames</th><td>{eye_frames}</td></tr>"
        );
    } else {
        let _ = writeln!(
            page,
            "<tr><th>tiles found</th><td>{}</td></tr><tr><th>decoded</th><td>{}</td></tr>\
             <tr><th>trimmed (all background)</th><td>{}</td></tr><tr><th>failed</th><td>{}</td></tr>",
            grouped(images.found),
            grouped(images.decoded),
            grouped(images.trimmed),
            grouped(images.failed),
        );
    }
    let _ = writeln!(
        page,
        "<tr><th>texels seen</th><td>{}</td></tr><tr><th>grand total</th><td>{}</td></tr>\
         <tr><th>largest count of a texel</th><td>{}</td></tr></table>",
        grouped(result.texels_seen),
        grouped(result.grand_total),
        grouped(u64::from(result.max_count))
    );
}

/// The resolution diagnostics: does the count depend on pixels per degree?
fn resolution(page: &mut String, inputs: &PageInputs) {
    let Some(resolution) = &inputs.result.resolution else { return };
    let optional =
        |value: Option<f64>, digits: usize| value.map_or("–".to_string(), |v| format!("{v:.digits$}"));
    let _ = writeln!(
        page,
        "<h3>Does the count depend on resolution?</h3>\n<table><tr><th>pixels per degree</th><td>{}</td></tr>\
         <tr><th>texel size (mm)</th><td>{}</td></tr><tr><th>pixels per count</th><td>{:.2}</td></tr>\
         <tr><th>texels smaller than a pixel beyond (m)</th><td>{}</td></tr>\
         <tr><th>share of frames beyond that</th><td>{}</td></tr></table>",
        optional(resolution.pixels_per_degree, 2),
        optional(resolution.texel_size_mm, 2),
        resolution.pixels_per_count,
        optional(resolution.sub_pixel_distance_m, 1),
        resolution.sub_pixel_frame_share.map_or("–".to_string(), |s| format!("{:.0} %", 100.0 * s)),
    );
}

/// The parts table by total, with the paper's top-5 union highlighted.
fn parts(page: &mut String, inputs: &PageInputs) {
    let result = inputs.result;
    if result.parts.is_empty() {
        return;
    }
    let marked = top_five_union(&result.parts);
    let mut order: Vec<usize> = (0..result.parts.len()).collect();
    order.sort_by(|&a, &b| result.parts[b].total.cmp(&result.parts[a].total).then(a.cmp(&b)));
    let _ = writeln!(
        page,
        "<h2>Paper-compatible: the per-texel count per part</h2>\n<p>The paper's measure (a texel counts once per \
         image or eye-frame that shows it). It depends on resolution (docs/science.md: 27–59 pp from its exact \
         counterpart at 80 px/°): quote it only to compare with the paper, with its pixels per degree; quote the \
         measures above. Highlighted: the paper's table, the union of the five parts with the highest total, \
         peak and average.</p>\n<table><tr><th>part</th><th>texels</th><th>count total</th><th>count peak</th>\
         <th>count average</th><th>count share %</th><th>coverage %</th></tr>"
    );
    for index in order {
        let part = &result.parts[index];
        let swatch = part
            .color
            .map(|c| format!("<span class=\"swatch\" style=\"background:{c}\"></span>"))
            .unwrap_or_default();
        let _ = writeln!(
            page,
            "<tr{}><td>{swatch}{}</td><td>{}</td><td>{}</td><td>{}</td><td>{:.3}</td><td>{:.2}</td><td>{:.1}</td></tr>",
            if marked[index] { " class=\"top\"" } else { "" },
            escape(&part.name),
            grouped(part.texels),
            grouped(part.total),
            grouped(u64::from(part.peak)),
            part.average,
            part.share,
            part.coverage
        );
    }
    let _ = writeln!(page, "</table>");
}

/// The heatmap textures — `heatmap.png` (per-texel angular area, when
/// measured) and the paper-compatible count (`heatmap-count.png` then, else
/// `heatmap.png` itself) — and the link to the vehicle with `heatmap.png` on
/// it (`heatmap.glb`).
fn heatmap(page: &mut String, inputs: &PageInputs) {
    let (settings, files) = (&inputs.result.settings, inputs.files);
    let glb = match &files.heatmap_glb {
        Some(glb) => format!(
            " The vehicle with this heatmap on it: <a href=\"{}\">{}</a> (glTF; opens in Blender, three.js or any glTF viewer).",
            file_name(glb),
            file_name(glb)
        ),
        None => " (No vehicle model: give <code>--mesh</code> for heatmap.glb.)".to_string(),
    };
    let count_png = match &files.heatmap_count_png {
        Some(count) => {
            let _ = writeln!(
                page,
                "<h2>The heatmap texture: angular area per texel (deg²·s)</h2>\n<p>Each texel's visible angular area \
                 over time (deg²·s: the solid angle its pixels subtended, summed over the eye-frames, × seconds per \
                 frame / eyes; a part's texels add up to its angular area in the table of measures), laid out like the \
                 palette (the vehicle's UV layout; the views show it on the vehicle): plasma scale ({:?}) from 0 to {} per \
                 texel, texels never seen in neutral grey.{glb}</p>\n\
                 <img src=\"{}\" alt=\"angular-area heatmap texture\" width=\"384\">",
                settings.heatmap_scale,
                area_top(settings),
                file_name(&files.heatmap_png)
            );
            count
        }
        None => &files.heatmap_png,
    };
    let _ = writeln!(
        page,
        "<h2>The heatmap texture (paper-compatible count)</h2>\n<p>The paper's per-texel counts as a texture laid out \
         like the palette, for comparing with the paper (not a measure to quote: see docs/science.md): plasma scale \
         ({:?}{}), texels never seen in neutral grey.{}</p>\n\
         <img src=\"{}\" alt=\"heatmap texture\" width=\"384\">",
        settings.heatmap_scale,
        settings.heatmap_max.map(|m| format!(", top of scale {m} counts")).unwrap_or_default(),
        if files.area_first() { String::new() } else { glb },
        file_name(count_png)
    );
}

/// The top of the angular-area colour scale, in words.
fn area_top(settings: &crate::format::result::Settings) -> String {
    settings.heatmap_area_max.map_or_else(
        || "the largest texel's value (deg²·s)".to_string(),
        |max| format!("{max:.3e} deg²·s (--area-max)"),
    )
}

/// The eight views of the heatmap on the vehicle (`views.png`), when
/// written: per-texel angular area when measured, else the paper's count.
fn vehicle_views(page: &mut String, inputs: &PageInputs) {
    let Some(views) = &inputs.files.views_png else { return };
    let (result, settings) = (inputs.result, &inputs.result.settings);
    let (heading, what, top) = if inputs.files.area_first() {
        (
            "The heatmap on the vehicle: angular area per texel",
            "Each point's visible angular area over time (deg²·s per texel, the quoted measure; the paper's count \
             is in <code>heatmap-count.png</code> below).",
            area_top(settings),
        )
    } else {
        (
            "The heatmap on the vehicle (paper-compatible count)",
            "The paper's per-texel count (the analyzer measures angular area and exposure per part, not per \
             texel, without the eyes' projection and fps: see the table of measures above).",
            format!("{} counts", grouped(u64::from(settings.heatmap_max.unwrap_or(result.max_count)))),
        )
    };
    let _ = writeln!(
        page,
        "<h2>{heading}</h2>\n<p>{what} Front, front-left, left, rear-left (top row); rear, rear-right, \
         right, front-right (bottom row); seen from 15° above, one scale for all, shaded by a light from the upper \
         left. Colour bar: grey = never seen, then plasma from 0 to {top} ({:?} scale). The compass in each view's \
         corner shows where the pedestrian was (green) and the view's line of sight (black).{}</p>\n\
         <img src=\"{}\" alt=\"the heatmap on the vehicle from eight directions\">",
        settings.heatmap_scale,
        if inputs.files.single_views { " Each view is also in <code>views/</code>." } else { "" },
        file_name(views)
    );
}

/// The plots (visibility over time and distance, parts), when written.
fn plots(page: &mut String, inputs: &PageInputs) {
    let plots = &inputs.files.plots;
    if plots.is_empty() {
        return;
    }
    let _ = writeln!(
        page,
        "<h2>Plots</h2>\n<p>The angular area (deg², from the eyes' projection; pixels when the manifest gives none) \
         of each of the {} most visible parts per eye, by frame (both in <code>frames.csv</code>), \
         and the per-part bar chart (angular area and exposure when measured, then the paper's count). For a paper, \
         each plot is in <code>plots/</code> as PDF (vector, real text) and PNG (300 dpi), two columns wide \
         (181.9 mm, IEEE's text width, inside Elsevier's 190 mm), text at least 7 pt; <code>--figures all</code> \
         adds SVGs and one-column figures (88.9 mm, <code>NAME-1col.*</code>).</p>",
        crate::output::plots::TOP_PARTS
    );
    for plot in plots {
        let _ = writeln!(
            page,
            "<figure><a href=\"{vector}\"><img src=\"{shown}\" alt=\"{title}\" class=\"plot\"></a>\
             <figcaption>{scenario}: {title}.</figcaption></figure>",
            scenario = escape(&scenario_name(inputs)),
            vector = escape(&plot.vector),
            shown = escape(&plot.shown),
            title = escape(&plot.title)
        );
    }
}

/// The scenario's name for captions: the manifest's, else the archive's folder.
fn scenario_name(inputs: &PageInputs) -> String {
    let folder = Path::new(&inputs.result.settings.archive)
        .file_name()
        .map_or_else(|| inputs.result.settings.archive.clone(), |n| n.to_string_lossy().into_owned());
    inputs.scenario.track.and_then(|t| t.name.clone()).unwrap_or(folder)
}

/// The heading of the first table: the measures docs/science.md says to quote.
pub const QUOTED_HEADING: &str = "What to quote: angular area and exposure per part";

/// The resolution-independent measures per part, largest angular area first
/// (see [`crate::result::measures`]): the page's first table. Without them
/// (no manifest), the section says why and where the counts are.
fn measures(page: &mut String, inputs: &PageInputs) {
    let result = inputs.result;
    let _ = writeln!(page, "<h2>{QUOTED_HEADING}</h2>");
    let Some(measures) = &result.measures else {
        let _ = writeln!(
            page,
            "<div class=\"warn\">No angular area or exposure: the archive has no manifest with the eyes' \
             projection and frame rate (capture with <code>ufcsr capture</code>, or write one with \
             <code>ufcsr manifest</code>). Only the paper-compatible count below is available.</div>"
        );
        return;
    };
    let optional = |value: Option<f64>| value.map_or("–".to_string(), |v| format!("{v:.3}"));
    let _ = writeln!(
        page,
        "<p>The measures docs/science.md says to quote for eHMI placement: unlike the count they do not \
         depend on texel size, but they converge with pixels per degree and are not free of resolution error. \
         Per eye, averaged over {} eyes: visible angular area summed over time (deg²·s) and seconds seen \
         (exposure); {} eye-frames, {} s per captured frame, {} pixels per degree. \
         Definition: <code>{}</code>.</p>",
        measures.eyes,
        measures.eye_frames,
        optional(measures.seconds_per_frame),
        optional(measures.pixels_per_degree),
        escape(&measures.definition)
    );
    let _ = writeln!(
        page,
        "<div class=\"warn\">{}</div>",
        escape(&resolution_caution(measures.pixels_per_degree))
    );
    for note in &measures.notes {
        let _ = writeln!(page, "<div class=\"warn\">{}</div>", escape(note));
    }
    let mut order: Vec<&crate::result::measures::PartMeasure> = measures
        .parts
        .iter()
        .filter(|p| p.pixels > 0 || result.parts.iter().any(|q| q.name == p.name))
        .collect();
    let area = |p: &crate::result::measures::PartMeasure| p.angular_area_deg2_s.unwrap_or(-1.0);
    order.sort_by(|a, b| area(b).total_cmp(&area(a)).then(b.pixels.cmp(&a.pixels)).then(a.name.cmp(&b.name)));
    let _ = writeln!(
        page,
        "<table class=\"quoted\"><tr><th>part</th><th>angular area (deg²·s)</th><th>exposure (s)</th>\
         <th>eye-frames seen</th><th>pixels (all eye-frames)</th></tr>"
    );
    for part in order {
        let _ = writeln!(
            page,
            "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>",
            escape(&part.name),
            optional(part.angular_area_deg2_s),
            optional(part.exposure_s),
            grouped(part.eye_frames_seen),
            grouped(part.pixels)
        );
    }
    let _ = writeln!(page, "</table>");
}

/// Where the eHMI should go, when a placement result lies beside the result
/// ([`crate::output::html::placement_section`]).
fn placement(page: &mut String, inputs: &PageInputs) {
    match inputs.placement {
        Some(Ok(placement)) => crate::output::html::placement_section::section(page, placement),
        Some(Err(problem)) => {
            let _ = writeln!(
                page,
                "<h2>Where should the eHMI go?</h2>\n<div class=\"warn\">{}</div>",
                escape(problem)
            );
        }
        None => {}
    }
}

/// Links to the machine-readable files beside the page.
fn files(page: &mut String, inputs: &PageInputs) {
    let files = inputs.files;
    let _ = writeln!(page, "<h2>Files</h2>\n<ul>");
    let listed = [
        Some(&files.result_json),
        files.parts_csv.as_ref(),
        Some(&files.heatmap_png),
        files.heatmap_count_png.as_ref(),
        files.heatmap_glb.as_ref(),
        Some(&files.timings_json),
        files.frames_csv.as_ref(),
        files.views_png.as_ref(),
        files.views_pdf.as_ref(),
        files.map_png.as_ref(),
        files.frames_strip_png.as_ref(),
    ];
    for file in listed.into_iter().flatten() {
        let _ = writeln!(page, "<li><a href=\"{0}\">{0}</a></li>", file_name(file));
    }
    let _ = writeln!(page, "</ul>");
}

/// The settings the counts were made with: the pixel path's (background,
/// dedupe, trimming), or the exact measure's (its definition and notes).
fn settings(page: &mut String, inputs: &PageInputs) {
    let settings = &inputs.result.settings;
    let _ = writeln!(
        page,
        "<h2>Settings</h2>\n<table><tr><th>archive</th><td>{}</td></tr><tr><th>palette</th><td>{} {}×{}</td></tr>\
         <tr><th>PIdT</th><td>{}</td></tr><tr><th>legend</th><td>{}</td></tr>",
        escape(&settings.archive),
        escape(&settings.palette.kind),
        settings.palette.width,
        settings.palette.height,
        escape(settings.pidt.as_deref().unwrap_or("–")),
        escape(settings.parts.as_deref().unwrap_or("–")),
    );
    if inputs.result.measure == crate::format::result::CountMeasure::Unobstructed {
        let measures = inputs.result.measures.as_ref();
        let _ = writeln!(
            page,
            "<tr><th>one count means</th><td>an eye-frame in which the texel's point is in view, faces the eye \
             and nothing is in between</td></tr><tr><th>definition</th><td>{}</td></tr>",
            escape(measures.map_or("–", |m| m.definition.as_str()))
        );
        for note in measures.map(|m| m.notes.as_slice()).unwrap_or_default() {
            let _ = writeln!(page, "<tr><th>note</th><td>{}</td></tr>", escape(note));
        }
    } else {
        let _ = writeln!(
            page,
            "<tr><th>background</th><td>{}</td></tr><tr><th>one count means</th><td>{:?}</td></tr>\
             <tr><th>trimming</th><td>{}</td></tr>",
            settings.background.iter().map(|c| c.to_string()).collect::<Vec<_>>().join(", "),
            settings.dedupe,
            escape(&settings.trim.mode),
        );
    }
    let _ = writeln!(
        page,
        "<tr><th>shard</th><td>{}</td></tr></table>",
        settings.shard.map_or("whole archive".to_string(), |s| s.to_string())
    );
}

/// The version line and the end of the document.
fn foot(page: &mut String, _inputs: &PageInputs) {
    let _ = writeln!(page, "<p><small>ufcsr {}</small></p>\n</body></html>", env!("CARGO_PKG_VERSION"));
}

/// The angular-area share L1 measured on demo A–D against the exact solid
/// angle (`docs/science.md`, "Measured convergence on demo A–D", every 30th
/// frame as the middle of its step): the worst of the four scenarios at 5, 10,
/// 20, 40 and 80 px/°, pp (C, B, C, B, C).
const DEMO_CONVERGENCE: [(f64, f64); 5] =
    [(5.0, 7.45), (10.0, 2.15), (20.0, 1.30), (40.0, 0.46), (80.0, 0.19)];

/// The slowest rate fitted on the demo (scenario D, ppd^-1.26): how the
/// envelope is carried below 5 and above 80 px/°.
const DEMO_SLOWEST_RATE: f64 = -1.26;

/// The angular-area share error to expect at `ppd` from the demo's measured
/// convergence: the worst scenario's, interpolated on log–log between the
/// measured resolutions and carried at the slowest fitted rate outside them.
pub(crate) fn demo_share_error_pp(ppd: f64) -> f64 {
    let (first, last) = (DEMO_CONVERGENCE[0], DEMO_CONVERGENCE[DEMO_CONVERGENCE.len() - 1]);
    let along = |(p0, e0): (f64, f64), rate: f64| e0 * (ppd / p0).powf(rate);
    if ppd <= first.0 {
        return along(first, DEMO_SLOWEST_RATE);
    }
    for pair in DEMO_CONVERGENCE.windows(2) {
        let ((p0, e0), (p1, e1)) = (pair[0], pair[1]);
        if ppd <= p1 {
            return along((p0, e0), (e1 / e0).ln() / (p1 / p0).ln());
        }
    }
    along(last, DEMO_SLOWEST_RATE)
}

/// What a reader should know of the resolution error before quoting the
/// measures (issue 42 §5: the page once said they "do not depend on
/// resolution"): the demo's measured error at this archive's px/°, and that
/// only `ufcsr-capture study` measures it for this scene.
pub(crate) fn resolution_caution(pixels_per_degree: Option<f64>) -> String {
    let run = "This analysis carries no interval for it: to measure the error for this vehicle and scenario, \
               run `ufcsr study` (it compares resolutions and frame steps with the exact measure).";
    match pixels_per_degree.filter(|p| p.is_finite() && *p > 0.0) {
        Some(ppd) => {
            let [(p5, e5), _, (p20, e20), _, (p80, e80)] = DEMO_CONVERGENCE;
            format!(
                "Resolution error: at {ppd:.3} px/° the angular-area share of the demo truck (scenarios A–D) is \
                 up to {:.2} pp off the exact solid angle (measured {e5:.2} pp at {p5} px/°, {e20:.2} at {p20}, \
                 {e80:.2} at {p80}, falling like ppd^{DEMO_SLOWEST_RATE} or faster; docs/science.md). Exposure \
                 counts an eye-frame in which one pixel shows the part, so a part smaller than a pixel at this \
                 resolution reads as unseen. {run}",
                demo_share_error_pp(ppd)
            )
        }
        None => format!("Resolution error: the archive records no pixels per degree. {run}"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::PathBuf;

    #[test]
    fn the_page_states_the_demos_resolution_error_at_the_archives_ppd_and_says_to_run_study() {
        // The measured points themselves, and between them on log–log.
        for (ppd, pp) in DEMO_CONVERGENCE {
            assert!((demo_share_error_pp(ppd) - pp).abs() < 1e-12, "{ppd}");
        }
        // 6 px/° (the bundled example): 7.45 · 1.2^(ln(2.15/7.45)/ln 2) = 5.37 pp.
        let six = 7.45 * 1.2f64.powf((2.15f64 / 7.45).ln() / 2f64.ln());
        assert!((demo_share_error_pp(6.0) - six).abs() < 1e-9 && (six - 5.37).abs() < 5e-3, "{six}");
        // Outside the measured range at the slowest rate: 2.5 px/° is 7.45 · 2^1.26.
        assert!((demo_share_error_pp(2.5) - 7.45 * 2f64.powf(1.26)).abs() < 1e-9);
        assert!(demo_share_error_pp(160.0) < 0.19);
        let mut result = example_result();
        let ppd = result.measures.as_ref().unwrap().pixels_per_degree.unwrap();
        let page = page_of(&result);
        assert!(!page.contains("do not depend on resolution"));
        assert!(page.contains(&format!("up to {:.2} pp off", demo_share_error_pp(ppd))), "at {ppd} px/°");
        assert!(page.contains("run `ufcsr study`"));
        result.measures.as_mut().unwrap().pixels_per_degree = None;
        assert!(page_of(&result).contains("records no pixels per degree"));
    }

    fn example_result() -> AnalysisResult {
        let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/reference/example-result.json");
        crate::result::result_json::read_result_summary(&path).unwrap()
    }

    fn page_of(result: &AnalysisResult) -> String {
        let files = WrittenFiles {
            result_json: "result.json".into(),
            parts_csv: None,
            heatmap_png: "heatmap.png".into(),
            heatmap_count_png: None,
            texel_area: None,
            texel_area_units: None,
            views_pdf: None,
            timings_json: "timings.json".into(),
            heatmap_glb: None,
            report_html: "report.html".into(),
            views_png: None,
            frames_csv: None,
            map_png: None,
            frames_strip_png: None,
            single_views: false,
            plots: Vec::new(),
        };
        let scenario = ScenarioPage::default();
        render(&PageInputs { result, files: &files, scenario: &scenario, placement: None })
    }

    #[test]
    fn an_exact_measure_result_shows_its_own_settings_not_the_pixel_paths() {
        let mut result = example_result();
        let pixel_page = page_of(&result);
        assert!(pixel_page.contains("<th>trimming</th>") && pixel_page.contains("<th>decoded</th>"));
        result.measure = crate::format::result::CountMeasure::Unobstructed;
        let page = page_of(&result);
        for pixel_only in
            ["<th>trimming</th>", "<th>decoded</th>", "trimmed (all background)", "<th>background</th>"]
        {
            assert!(!page.contains(pixel_only), "an exact result's page shows {pixel_only}");
        }
        assert!(page.contains("no images read") && page.contains("<th>definition</th>"));
    }
}
