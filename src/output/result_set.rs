//! The result set: every file of one analysis written into its folder at
//! once (staged, then moved into place), never over one of its inputs.

use std::path::{Path, PathBuf};
use std::time::Instant;

use crate::archive::labels::{Legend, LoadedLabels, Pidt};
use crate::archive::manifest::Manifest;
use crate::archive::options::HeatmapOptions;
use crate::archive::scenario_track::ScenarioTrack;
use crate::archive::vehicle_model::VehicleModel;
use crate::error::Result;
use crate::files::{IMAGE_LIMIT, Staging, read_limited, refuse_overwriting_inputs};
use crate::output::csv::{CsvStyle, write_frames_csv, write_parts_table};
use crate::output::frame_strip::{FRAME_STRIP_FILE, StripInputs, frame_strip_skipped, write_frame_strip};
use crate::output::heatmap::{
    AreaLevels, COUNT_HEATMAP_FILE, EARLIER_AREA_HEATMAP_FILE, HEATMAP_FILE, write_area_heatmap,
};
use crate::output::heatmap_views::{
    AREA_UNIT, DEFAULT_VIEWS_SCALE, DIRECTIONS, ViewTexture, area_views_caption, measure_unit, views_caption,
};
use crate::output::html::placement_section::PlacementOnPage;
use crate::output::html::report_page::ScenarioPage;
use crate::output::plots::{PLOTS_DIR, Plot, PlotFiles, font_available, plot_file_names, write_plots};
use crate::output::scenario_map::{MapContent, SceneShapes, write_scenario_map};
use crate::output::view_sheet::{SingleViews, VIEWS_PDF_FILE, write_sheet_and_views};
use crate::output::written_files::WrittenFiles;
use crate::result::frames::FRAMES_FILE;
use crate::result::model::Analysis;
use crate::result::result_json::{write_result_json, write_timings_json};
use crate::result::texel_area_file::{TEXEL_AREA_FILE, TEXEL_AREA_UNITS_FILE, write_texel_area};

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
        files.heatmap_count_png.as_ref(),
        files.texel_area.as_ref(),
        Some(&files.timings_json),
        files.heatmap_glb.as_ref(),
        Some(&files.report_html),
        files.views_png.as_ref(),
        files.views_pdf.as_ref(),
        files.frames_csv.as_ref(),
        files.map_png.as_ref(),
        files.frames_strip_png.as_ref(),
    ];
    outputs.into_iter().flatten().cloned().chain(files.views()).collect()
}

/// Writes `result.json`, `parts.csv` (with a PIdT), `heatmap.png` and
/// `timings.json` into `out_dir` (created if needed), each atomically. The
/// heatmap uses the scale recorded in the result's settings.
///
/// The set is written into a staging folder inside `out_dir` and moved into
/// place only when every file was written: a failure (a full disk, a bad
/// vehicle model) or an interruption leaves the previous result set whole.
pub fn write_results(analysis: &mut Analysis, out_dir: &Path) -> Result<WrittenFiles> {
    write_results_with(analysis, out_dir, &ResultSetOptions::default())
}

/// How a result set is written, beyond the analysis itself.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ResultSetOptions {
    /// Columns of `parts.csv` (`--csv-style`).
    pub csv_style: CsvStyle,
    /// Each view is 400×300 pixels times this (`--views-scale`).
    pub views_scale: u32,
    /// Whether the figures are drawn (`--figures`).
    pub figures: Figures,
}

/// Whether a result set has its figures (`--figures on|all|off`): the plots,
/// the views (`views.png`, `views.pdf`), the scenario map and the frame
/// strip. Drawing them is most of a small analysis (issue 44 §3): batch runs
/// and notebooks that want the tables leave them out. The tables, the
/// heatmaps, `heatmap.glb` and `report.html` are written either way, and the
/// tables are the same.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Figures {
    /// Every figure the analysis allows, each once (the default): a plot as
    /// two-column PNG and PDF, the views as their sheet (`views.png`, `views.pdf`).
    All,
    /// [`Figures::All`] and the variants (issue 45 §5): each plot also as
    /// SVG and at one column (`plots/NAME-1col.*`), each view alone (`views/NAME.png`).
    WithVariants,
    /// No figures.
    None,
}

impl Default for ResultSetOptions {
    fn default() -> Self {
        ResultSetOptions {
            csv_style: CsvStyle::Report,
            views_scale: DEFAULT_VIEWS_SCALE,
            figures: Figures::All,
        }
    }
}

/// [`write_results`] with `options` (`--csv-style`, `--views-scale`).
pub fn write_results_with(
    analysis: &mut Analysis,
    out_dir: &Path,
    options: &ResultSetOptions,
) -> Result<WrittenFiles> {
    crate::files::create_output_dir(out_dir)?;
    let mut files = planned_files(analysis, out_dir, options.figures);
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
    let figures = write_results_into(analysis, staging.path(), options, placement.as_ref())?;
    files.plots = figures.plots;
    files.map_png = files.map_png.filter(|_| figures.map);
    files.frames_strip_png = files.frames_strip_png.filter(|_| figures.frames_strip);
    let members = result_set_members();
    staging.commit(out_dir, &members.iter().map(String::as_str).collect::<Vec<_>>())?;
    Ok(files)
}

/// Every file a result set can have, relative to its folder (plots and
/// views included): a run that writes fewer (no vehicle model,
/// `--frames-csv off`) removes the rest of an earlier run, so the folder
/// never holds a mixed set.
pub(crate) fn result_set_members() -> Vec<String> {
    let mut members: Vec<String> = [
        "result.json",
        "parts.csv",
        HEATMAP_FILE,
        COUNT_HEATMAP_FILE,
        EARLIER_AREA_HEATMAP_FILE,
        TEXEL_AREA_FILE,
        "timings.json",
        "heatmap.glb",
        "report.html",
        "views.png",
        VIEWS_PDF_FILE,
        MAP_FILE,
        FRAME_STRIP_FILE,
    ]
    .iter()
    .map(|name| (*name).to_string())
    .collect();
    members.push(FRAMES_FILE.to_string());
    members.extend(plot_file_names().iter().map(|name| format!("{PLOTS_DIR}/{name}")));
    members.extend(DIRECTIONS.iter().map(|(name, _)| format!("views/{name}.png")));
    members
}

/// The files [`write_results`] writes into `out_dir` (the figures only with
/// `figures`).
fn planned_files(analysis: &Analysis, out_dir: &Path, figures: Figures) -> WrittenFiles {
    let drawn = figures != Figures::None;
    let model = analysis.vehicle_model.as_ref().filter(|_| drawn);
    let manifest = analysis.result.settings.manifest && drawn;
    WrittenFiles {
        result_json: out_dir.join("result.json"),
        parts_csv: (!analysis.result.parts.is_empty()).then(|| out_dir.join("parts.csv")),
        heatmap_png: out_dir.join(HEATMAP_FILE),
        heatmap_count_png: analysis.texel_angular_area.as_ref().map(|_| out_dir.join(COUNT_HEATMAP_FILE)),
        texel_area: analysis.texel_angular_area.as_ref().map(|_| out_dir.join(TEXEL_AREA_FILE)),
        texel_area_units: analysis.texel_area_units.as_ref().map(|_| out_dir.join(TEXEL_AREA_UNITS_FILE)),
        timings_json: out_dir.join("timings.json"),
        heatmap_glb: analysis.vehicle_model.as_ref().map(|_| out_dir.join("heatmap.glb")),
        report_html: out_dir.join("report.html"),
        views_png: model.map(|_| out_dir.join("views.png")),
        views_pdf: model.map(|_| out_dir.join(VIEWS_PDF_FILE)),
        frames_csv: analysis.frames.as_ref().map(|_| out_dir.join(FRAMES_FILE)),
        map_png: manifest.then(|| out_dir.join(MAP_FILE)),
        frames_strip_png: manifest.then(|| out_dir.join(FRAME_STRIP_FILE)),
        single_views: figures == Figures::WithVariants,
        plots: Vec::new(),
    }
}

/// The figures that depend on what the analysis had.
struct FiguresWritten {
    plots: Vec<Plot>,
    /// Whether `map.png` was written.
    map: bool,
    /// Whether `frames-strip.png` was written.
    frames_strip: bool,
    /// Seconds per figure ([`crate::archive::options::Timings::figure_seconds`]).
    seconds: std::collections::BTreeMap<String, f64>,
}

/// The scenario map's file name in a result set.
pub const MAP_FILE: &str = "map.png";

/// Writes the whole result set into `out_dir` (a staging folder); returns
/// the figures written there. `placement`: a placement result found beside
/// the set, for the page.
fn write_results_into(
    analysis: &mut Analysis,
    out_dir: &Path,
    options: &ResultSetOptions,
    placement: Option<&std::result::Result<PlacementOnPage, String>>,
) -> Result<FiguresWritten> {
    let files = planned_files(analysis, out_dir, options.figures);
    let stage = Instant::now();
    let inputs = FigureInputs::read(analysis)?;
    let written = write_side_by_side(analysis, &files, options, &inputs, out_dir)?;
    let side_by_side_seconds = stage.elapsed().as_secs_f64();
    analysis.timings.heatmap_seconds = written.heatmap_seconds;
    analysis.timings.write_seconds = written.tables_seconds;
    let timings_json = files.timings_json.clone();
    let mut figures =
        write_figures(analysis, out_dir, files, placement, &inputs, written.strip_skipped, options.figures)?;
    let timings = &mut analysis.timings;
    timings.total_seconds += side_by_side_seconds + figures.seconds.values().sum::<f64>();
    figures.seconds.insert("frames_strip".to_string(), written.strip_seconds);
    figures.seconds.insert("views".to_string(), written.views_seconds);
    timings.figure_seconds = figures.seconds.clone();
    write_timings_json(&timings_json, timings)?;
    Ok(figures)
}

/// What the figures are drawn from besides the analysis, read once.
struct FigureInputs {
    /// The archive's manifest: what it says about the scenario, for the
    /// views, the map and the strip.
    manifest: Option<Manifest>,
    track: Option<ScenarioTrack>,
    model: Option<VehicleModel>,
}

impl FigureInputs {
    fn read(analysis: &Analysis) -> Result<FigureInputs> {
        let settings = &analysis.result.settings;
        let archive = Path::new(&settings.archive);
        let manifest = settings.manifest.then(|| Manifest::load_from_dir(archive).ok().flatten()).flatten();
        let track = manifest.as_ref().and_then(ScenarioTrack::from_manifest);
        let model = analysis.vehicle_model.as_deref().map(VehicleModel::read).transpose()?;
        Ok(FigureInputs { manifest, track, model })
    }
}

/// What [`write_side_by_side`] wrote, and each one's seconds.
struct SideBySide {
    heatmap_seconds: f64,
    tables_seconds: f64,
    strip_seconds: f64,
    views_seconds: f64,
    /// Why there is no frame strip (`None`: written, or no manifest).
    strip_skipped: Option<String>,
}

/// Writes the files that need only the analysis side by side, as each is
/// largely one thread's work (encoding `heatmap.png`, formatting
/// `result.json`'s counts, decoding the strip's tiles): the heatmap, the
/// tables (`result.json`, `parts.csv`, `frames.csv`), the frame strip and
/// the views of the vehicle model. The first error, in that order, is the
/// one returned.
fn write_side_by_side(
    analysis: &Analysis,
    files: &WrittenFiles,
    options: &ResultSetOptions,
    inputs: &FigureInputs,
    out_dir: &Path,
) -> Result<SideBySide> {
    fn timed<T>(write: impl FnOnce() -> Result<T>) -> Result<(T, f64)> {
        let stage = Instant::now();
        write().map(|value| (value, stage.elapsed().as_secs_f64()))
    }
    let strip = || match (&inputs.manifest, &files.frames_strip_png) {
        (Some(manifest), Some(path)) => write_strip(path, manifest, analysis),
        _ => Ok(None),
    };
    // `heatmap.png` and the views show per-texel angular area when it was
    // measured; `heatmap-count.png` then keeps the paper's count.
    let area = analysis.texel_angular_area.as_deref().map(AreaLevels::new);
    let views = || match (&inputs.model, &files.views_png) {
        (Some(model), Some(_)) => {
            let texture = view_texture(analysis, area.as_ref(), inputs.track.as_ref(), options);
            let singles = if files.single_views { SingleViews::Written } else { SingleViews::Omitted };
            write_sheet_and_views(model, &texture, out_dir, singles).map(drop)
        }
        _ => Ok(()),
    };
    let heatmaps = || {
        let settings = &analysis.result.settings;
        let size = [settings.palette.width, settings.palette.height];
        match &area {
            Some(area) => {
                write_area_heatmap(
                    &files.heatmap_png,
                    area,
                    size,
                    settings.heatmap_scale,
                    settings.heatmap_area_max,
                )?;
                if let Some(path) = &files.heatmap_count_png {
                    write_count_heatmap(analysis, path)?;
                }
            }
            None => write_count_heatmap(analysis, &files.heatmap_png)?,
        }
        if let (Some(values), Some(path)) = (&analysis.texel_angular_area, &files.texel_area) {
            let palette = &analysis.result.settings.palette;
            write_texel_area(path, palette.width, palette.height, values)?;
        }
        if let (Some(units), Some(path)) = (&analysis.texel_area_units, &files.texel_area_units) {
            let palette = &analysis.result.settings.palette;
            units.write(path, palette.width, palette.height)?;
        }
        Ok(())
    };
    let ((heatmap, tables), (strip, views)) = rayon::join(
        || rayon::join(|| timed(heatmaps), || timed(|| write_tables(analysis, files, options))),
        || rayon::join(|| timed(strip), || timed(views)),
    );
    let ((), heatmap_seconds) = heatmap?;
    let ((), tables_seconds) = tables?;
    let (strip_skipped, strip_seconds) = strip?;
    let ((), views_seconds) = views?;
    Ok(SideBySide { heatmap_seconds, tables_seconds, strip_seconds, views_seconds, strip_skipped })
}

/// The heatmap as the views paint it, captioned for this analysis: the
/// per-texel angular area (`area`) when measured, else the paper's count.
fn view_texture<'a>(
    analysis: &'a Analysis,
    area: Option<&'a AreaLevels>,
    track: Option<&ScenarioTrack>,
    options: &ResultSetOptions,
) -> ViewTexture<'a> {
    let settings = &analysis.result.settings;
    let measure = analysis.result.measure;
    let scenario = track.and_then(|t| t.name.as_deref());
    let (counts, max, caption, unit, quantum) = match area {
        Some(area) => (
            &area.levels[..],
            area.top(settings.heatmap_area_max),
            area_views_caption(scenario),
            AREA_UNIT.to_string(),
            Some(area.quantum),
        ),
        None => (
            &analysis.texel_counts[..],
            settings.heatmap_max,
            views_caption(measure, &settings.archive, scenario),
            measure_unit(measure).to_string(),
            None,
        ),
    };
    ViewTexture {
        counts,
        width: settings.palette.width,
        height: settings.palette.height,
        options: HeatmapOptions { scale: settings.heatmap_scale, max },
        caption,
        unit,
        quantum,
        views_scale: options.views_scale,
        pedestrian_azimuths_deg: pedestrian_azimuths(track),
    }
}

/// Writes the paper's count heatmap (`heatmap.png` without per-texel area,
/// else `heatmap-count.png`) with the scale recorded in the result's settings.
fn write_count_heatmap(analysis: &Analysis, path: &Path) -> Result<()> {
    let settings = &analysis.result.settings;
    let heatmap = HeatmapOptions { scale: settings.heatmap_scale, max: settings.heatmap_max };
    let (width, height) = (settings.palette.width, settings.palette.height);
    crate::output::heatmap::write_heatmap(path, &analysis.texel_counts, width, height, heatmap)
}

/// Writes `result.json`, `parts.csv` (with parts) and `frames.csv` (with
/// per-frame tallies).
fn write_tables(analysis: &Analysis, files: &WrittenFiles, options: &ResultSetOptions) -> Result<()> {
    write_result_json(&files.result_json, &analysis.result, &analysis.texel_counts)?;
    if let Some(path) = &files.parts_csv {
        write_parts_table(
            path,
            &analysis.result.parts,
            analysis.result.measures.as_ref(),
            options.csv_style,
        )?;
    }
    if let (Some(frames), Some(path)) = (&analysis.frames, &files.frames_csv) {
        write_frames_csv(path, frames)?;
    }
    Ok(())
}

/// Seconds per stage: each [`StageClock::lap`] records the time since the last.
struct StageClock {
    last: Instant,
    seconds: std::collections::BTreeMap<String, f64>,
}

impl StageClock {
    fn start() -> StageClock {
        StageClock { last: Instant::now(), seconds: Default::default() }
    }

    fn lap(&mut self, stage: &str) {
        let now = Instant::now();
        *self.seconds.entry(stage.to_string()).or_default() += (now - self.last).as_secs_f64();
        self.last = now;
    }
}

/// Writes the figures left after [`write_side_by_side`] (`heatmap.glb`,
/// which embeds `heatmap.png`, the map, the plots) and the report page that
/// shows them all (with `placement`, if found beside). `strip_skipped`:
/// why there is no frame strip, for the page.
fn write_figures(
    analysis: &Analysis,
    out_dir: &Path,
    mut files: WrittenFiles,
    placement: Option<&std::result::Result<PlacementOnPage, String>>,
    inputs: &FigureInputs,
    strip_skipped: Option<String>,
    figures: Figures,
) -> Result<FiguresWritten> {
    let mut clock = StageClock::start();
    let archive = Path::new(&analysis.result.settings.archive);
    let FigureInputs { manifest, track, model } = inputs;
    if let (Some(model), Some(glb)) = (model, &files.heatmap_glb) {
        // heatmap.png: angular area when measured, else the count.
        let png = read_limited(&files.heatmap_png, IMAGE_LIMIT)?;
        model.write_glb(glb, Some(("heatmap", &png)))?;
    }
    clock.lap("heatmap_glb");
    files.map_png = match (track, files.map_png) {
        (Some(track), Some(path)) if font_available() => {
            write_map(&path, track, model.as_ref(), archive)?;
            Some(path)
        }
        _ => None,
    };
    clock.lap("map");
    if strip_skipped.is_some() || manifest.is_none() {
        files.frames_strip_png = None;
    }
    if figures != Figures::None {
        let which =
            if figures == Figures::WithVariants { PlotFiles::WithVariants } else { PlotFiles::Default };
        files.plots = write_plots(
            out_dir,
            &analysis.result.parts,
            analysis.frames.as_ref(),
            analysis.result.measures.as_ref(),
            measure_unit(analysis.result.measure),
            which,
        )?;
    }
    clock.lap("plots");
    let scenario_page = ScenarioPage { track: track.as_ref(), strip_skipped };
    crate::output::html::report_page::write_report(
        &files.report_html,
        &analysis.result,
        &files,
        &scenario_page,
        placement,
    )?;
    clock.lap("report");
    Ok(FiguresWritten {
        plots: files.plots,
        map: files.map_png.is_some(),
        frames_strip: files.frames_strip_png.is_some(),
        seconds: clock.seconds,
    })
}

/// Writes the frame strip, or says why there is none.
fn write_strip(path: &Path, manifest: &Manifest, analysis: &Analysis) -> Result<Option<String>> {
    let settings = &analysis.result.settings;
    let canonical = settings.palette.kind == "canonical";
    if let Some(why) = frame_strip_skipped(manifest, canonical) {
        return Ok(Some(why.to_string()));
    }
    let (Some(pidt), Some(legend)) = (&settings.pidt, &settings.parts) else {
        return Ok(Some("the analysis had no PIdT, so parts have no colours: no frame strip".into()));
    };
    // The analysis's own labels; a merge's are read from the files it names.
    let labels = match &analysis.labels {
        Some(labels) => labels.clone(),
        None => {
            let legend = Legend::load(Path::new(legend))?;
            let (width, height) = (settings.palette.width, settings.palette.height);
            let pidt = Pidt::load(Path::new(pidt), &legend, [width, height])?;
            LoadedLabels { legend, pidt: pidt.into() }
        }
    };
    let inputs = StripInputs {
        archive: Path::new(&settings.archive),
        manifest,
        labels: &labels,
        background: &settings.background,
    };
    write_frame_strip(path, &inputs)?;
    Ok(None)
}

/// Writes the scenario map of `track`, with the archive's `scene.glb` when
/// it has one (a broken one is said on the map, not fatal).
fn write_map(
    path: &Path,
    track: &ScenarioTrack,
    vehicle: Option<&VehicleModel>,
    archive: &Path,
) -> Result<()> {
    let scene_file = archive.join("scene.glb");
    let scene = if scene_file.is_file() {
        SceneShapes::read(&scene_file).map_err(|error| format!("{error}"))
    } else {
        Ok(SceneShapes { occluders: Vec::new() })
    };
    // No folder name in a figure (issue 35): the page's caption says the scenario.
    let title = match &track.name {
        Some(name) => format!("Scenario {name} from above"),
        None => "The scenario from above".to_string(),
    };
    write_scenario_map(path, &MapContent { track, scene, vehicle, title })?;
    Ok(())
}

/// Every frame's direction of the pedestrian seen from the vehicle.
pub(crate) fn pedestrian_azimuths(track: Option<&ScenarioTrack>) -> Vec<f64> {
    track.map_or_else(Vec::new, |track| {
        track.frames.iter().filter_map(|f| f.pedestrian_azimuth_deg()).collect()
    })
}
