//! The result set: every file of one analysis written into its folder at
//! once (staged, then moved into place), never over one of its inputs.

use std::path::{Path, PathBuf};
use std::time::Instant;

use crate::error::{Error, Result};
use crate::files::{IMAGE_LIMIT, Staging, read_limited, refuse_overwriting_inputs};
use crate::input::options::HeatmapOptions;
use crate::output::csv::{CsvStyle, write_frames_csv, write_parts_table};
use crate::output::heatmap_views::{DIRECTIONS, ViewTexture, views_caption, write_views};
use crate::output::html::placement_section::PlacementOnPage;
use crate::output::plots::{PLOT_NAMES, PLOTS_DIR, Plot, write_plots};
use crate::output::vehicle_model::VehicleModel;
use crate::output::written_files::WrittenFiles;
use crate::result::frames::FRAMES_FILE;
use crate::result::model::Analysis;
use crate::result::result_json::{write_result_json, write_timings_json};

/// The default output folder for an archive: `<archive>/results` (excluded
/// from the images when the archive has no manifest).
pub fn default_output_dir(archive: &Path) -> PathBuf {
    archive.join("results")
}

/// Every file `files` names, for [`crate::files::refuse_overwriting_inputs`].
fn output_paths(files: &WrittenFiles) -> Vec<PathBuf> {
    let outputs = [
        Some(&files.result_json),
        files.parts_csv.as_ref(),
        Some(&files.heatmap_png),
        Some(&files.timings_json),
        files.heatmap_glb.as_ref(),
        Some(&files.report_html),
        files.views_png.as_ref(),
        files.frames_csv.as_ref(),
    ];
    outputs.into_iter().flatten().cloned().collect()
}

/// Writes `result.json`, `parts.csv` (with a PIdT), `heatmap.png` and
/// `timings.json` into `out_dir` (created if needed), each atomically. The
/// heatmap uses the scale recorded in the result's settings.
///
/// The set is written into a staging folder inside `out_dir` and moved into
/// place only when every file was written: a failure (a full disk, a bad
/// vehicle model) or an interruption leaves the previous result set whole.
pub fn write_results(analysis: &mut Analysis, out_dir: &Path) -> Result<WrittenFiles> {
    write_results_with(analysis, out_dir, CsvStyle::Report)
}

/// [`write_results`] with `parts.csv` in `csv` style (`--csv-style`).
pub fn write_results_with(analysis: &mut Analysis, out_dir: &Path, csv: CsvStyle) -> Result<WrittenFiles> {
    std::fs::create_dir_all(out_dir).map_err(|e| Error::io(out_dir, e))?;
    let mut files = planned_files(analysis, out_dir);
    let mut outputs = output_paths(&files);
    outputs.extend(result_set_members().iter().map(|name| out_dir.join(name)));
    refuse_overwriting_inputs(&outputs, &analysis.input_files)?;
    let staging = Staging::new(out_dir)?;
    // Plot paths are relative to the output folder: the same after the move.
    // A placement result already in the folder shows on the page.
    let placement = crate::output::html::placement_section::placement_beside(out_dir).map(|folder| {
        crate::output::html::placement_section::on_page(&folder, out_dir, "beside this result")
            .map_err(|e| e.to_string())
    });
    files.plots = write_results_into(analysis, staging.path(), csv, placement.as_ref())?;
    let members = result_set_members();
    staging.commit(out_dir, &members.iter().map(String::as_str).collect::<Vec<_>>())?;
    Ok(files)
}

/// Every file a result set can have, relative to its folder (plots and
/// views included): a run that writes fewer (no vehicle model,
/// `--frames-csv off`) removes the rest of an earlier run, so the folder
/// never holds a mixed set.
pub fn result_set_members() -> Vec<String> {
    let mut members: Vec<String> = [
        "result.json",
        "parts.csv",
        "heatmap.png",
        "timings.json",
        "heatmap.glb",
        "report.html",
        "views.png",
    ]
    .iter()
    .map(|name| (*name).to_string())
    .collect();
    members.push(FRAMES_FILE.to_string());
    for plot in PLOT_NAMES {
        members.extend(["svg", "png"].iter().map(|ext| format!("{PLOTS_DIR}/{plot}.{ext}")));
    }
    members.extend(DIRECTIONS.iter().map(|(name, _)| format!("views/{name}.png")));
    members
}

/// The files [`write_results`] writes into `out_dir`.
fn planned_files(analysis: &Analysis, out_dir: &Path) -> WrittenFiles {
    WrittenFiles {
        result_json: out_dir.join("result.json"),
        parts_csv: (!analysis.result.parts.is_empty()).then(|| out_dir.join("parts.csv")),
        heatmap_png: out_dir.join("heatmap.png"),
        timings_json: out_dir.join("timings.json"),
        heatmap_glb: analysis.vehicle_model.as_ref().map(|_| out_dir.join("heatmap.glb")),
        report_html: out_dir.join("report.html"),
        views_png: analysis.vehicle_model.as_ref().map(|_| out_dir.join("views.png")),
        frames_csv: analysis.frames.as_ref().map(|_| out_dir.join(FRAMES_FILE)),
        plots: Vec::new(),
    }
}

/// Writes the whole result set into `out_dir` (a staging folder); returns
/// the plots written there.
fn write_results_into(
    analysis: &mut Analysis,
    out_dir: &Path,
    csv: CsvStyle,
    placement: Option<&std::result::Result<PlacementOnPage, String>>,
) -> Result<Vec<Plot>> {
    let files = planned_files(analysis, out_dir);
    let palette = &analysis.result.settings.palette;
    let (width, height) = (palette.width, palette.height);
    let settings = &analysis.result.settings;
    let heatmap = HeatmapOptions { scale: settings.heatmap_scale, max: settings.heatmap_max };
    let stage = Instant::now();
    crate::output::heatmap::write_heatmap(
        &files.heatmap_png,
        &analysis.texel_counts,
        width,
        height,
        heatmap,
    )?;
    analysis.timings.heatmap_seconds = stage.elapsed().as_secs_f64();
    let stage = Instant::now();
    write_result_json(&files.result_json, &analysis.result, &analysis.texel_counts)?;
    if let Some(path) = &files.parts_csv {
        write_parts_table(path, &analysis.result.parts, analysis.result.measures.as_ref(), csv)?;
    }
    if let (Some(frames), Some(path)) = (&analysis.frames, &files.frames_csv) {
        write_frames_csv(path, frames)?;
    }
    analysis.timings.write_seconds = stage.elapsed().as_secs_f64();
    analysis.timings.total_seconds += analysis.timings.heatmap_seconds + analysis.timings.write_seconds;
    write_timings_json(&files.timings_json, &analysis.timings)?;
    if let (Some(model), Some(glb)) = (&analysis.vehicle_model, &files.heatmap_glb) {
        let png = read_limited(&files.heatmap_png, IMAGE_LIMIT)?;
        let model = VehicleModel::read(model)?;
        model.write_glb(glb, Some(("heatmap", &png)))?;
        let texture = ViewTexture {
            counts: &analysis.texel_counts,
            width,
            height,
            options: heatmap,
            caption: views_caption(&analysis.result.measure, &analysis.result.settings.archive),
        };
        write_views(&model, &texture, out_dir)?;
    }
    let mut files = files;
    let scenario = archive_name(&analysis.result.settings.archive);
    files.plots = write_plots(out_dir, &analysis.result.parts, analysis.frames.as_ref(), &scenario)?;
    crate::output::html::report_page::write_report(&files.report_html, &analysis.result, &files, placement)?;
    Ok(files.plots)
}

/// The archive's folder name (the scenario's, for a capture of one), for titles.
fn archive_name(archive: &str) -> String {
    Path::new(archive)
        .file_name()
        .map_or_else(|| archive.to_string(), |name| name.to_string_lossy().into_owned())
}
