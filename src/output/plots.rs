//! Plots for people and papers, under `--out/plots/`: the visibility of
//! the most visible parts against time and against the vehicle's distance
//! (from `frames.csv`), and the per-part bar chart — the measures to quote
//! (angular area, exposure) when the result has them, else the paper's
//! counts, the paper's top-5 union marked.
//!
//! Each plot is written for two journal columns (`NAME.png`, 300 dpi,
//! kerned text, and `NAME.pdf`, vector, real text; 181.9 mm) and, on
//! request ([`PlotFiles::WithVariants`]), also as SVG and for one column
//! (`NAME-1col.*`, 88.9 mm; see [`crate::output::figure`]), all text ≥ 7 pt
//! at the printed size. Series carry
//! the Okabe–Ito colours plus a marker and a dash each; every axis says
//! "quantity (unit)"; no figure carries the archive's folder name (the
//! page's captions say the scenario). Ticks of counts are whole numbers
//! with thousands separators, and the legend sits beside the plot (below
//! it at one column), never over a curve. Parts are named by
//! [`readable_part_name`].
//!
//! Labels need a TrueType font, looked up at run time (`UFCSR_FONT`, else
//! DejaVu Sans where Debian and most distributions put it) so that building
//! needs no fontconfig; without one the SVGs are drawn without text and no
//! PNG or PDF is written (the report then shows the SVGs).

use std::path::Path;

use plotters::coord::Shift;
use plotters::coord::ranged1d::SegmentValue;
use plotters::prelude::*;
use plotters::style::text_anchor;

use crate::error::{Error, Result};
use crate::output::figure::{
    DrawResult, FigureSize, KernedBitmap, draw_marker, draw_series_line, mm, pt, series_color, stroke,
    svg_in_millimetres, text_width,
};
use crate::output::numbers::tick;
use crate::output::part_names::readable_part_name;
use crate::output::pdf::{PdfBackend, PdfPage};
use crate::result::measures::Measures;
use crate::result::part_stats::PartStats;
use crate::{count::part_lookup::FrameLabel, result::frames::FrameTable};

/// Folder of the plots inside the output folder.
pub(crate) const PLOTS_DIR: &str = "plots";

/// Every plot a result set can have (`plots/NAME.svg`, `.png`, `.pdf`, and
/// the same with `-1col`).
pub(crate) const PLOT_NAMES: [&str; 3] = ["visibility-time", "visibility-distance", "parts"];

/// Every file name a plot can have, relative to [`PLOTS_DIR`].
pub(crate) fn plot_file_names() -> Vec<String> {
    let mut names = Vec::new();
    for plot in PLOT_NAMES {
        for size in FigureSize::ALL {
            names.extend(["svg", "png", "pdf"].iter().map(|ext| format!("{plot}{}.{ext}", size.suffix())));
        }
    }
    names
}

/// Parts drawn in the time and distance plots.
pub(crate) const TOP_PARTS: usize = 8;

/// Registers a sans-serif font with plotters once; false when none is found
/// (`ufcsr capture`'s study plot uses it too).
pub fn font_available() -> bool {
    crate::output::figure::font_bytes().is_some()
}

/// One plot as written: its name and the image to show (PNG when a font
/// was found, else SVG).
#[derive(Debug, Clone, PartialEq)]
pub struct Plot {
    /// What it shows, for the report's alt text and caption.
    pub title: String,
    /// The image to show, relative to the output folder (`plots/NAME.png`).
    pub shown: String,
    /// The vector figure the page links to, relative to the output folder:
    /// the two-column PDF (with a font), else the SVG.
    pub vector: String,
    /// Every file written for the plot, relative to the output folder.
    pub files: Vec<String>,
}

/// Which files of each plot are written (issue 45 §5: a default analysis
/// wrote 18 plot files).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum PlotFiles {
    /// Two columns as PNG (shown on the page) and PDF (for the paper); the
    /// SVG only without a font (then the only file that can be drawn).
    Default,
    /// Also the SVG, and all three at one column (`NAME-1col.*`).
    WithVariants,
}

/// Whether a plot's labels are drawn: they need a font, and without one the SVGs are drawn
/// without text and no PNG or PDF is written.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PlotText {
    Drawn,
    Omitted,
}

impl PlotText {
    /// Drawn when a font was found ([`font_available`]).
    pub fn available() -> PlotText {
        if font_available() { PlotText::Drawn } else { PlotText::Omitted }
    }
}

/// A plot drawn on any backend at a printed size (`text`: whether labels can be drawn).
trait Drawing {
    fn size(&self, size: FigureSize) -> (u32, u32);
    fn draw_svg(&self, root: &DrawingArea<SVGBackend, Shift>, size: FigureSize, text: PlotText)
    -> DrawResult;
    fn draw_png(&self, root: &DrawingArea<KernedBitmap, Shift>, size: FigureSize) -> DrawResult;
    fn draw_pdf(&self, root: &DrawingArea<PdfBackend, Shift>, size: FigureSize) -> DrawResult;
}

/// Implements [`Drawing`] for a type with a generic `draw(root, size, text)`.
macro_rules! drawing {
    ($type:ty, $size:expr) => {
        impl Drawing for $type {
            fn size(&self, size: FigureSize) -> (u32, u32) {
                #[allow(clippy::redundant_closure_call)]
                ($size)(self, size)
            }
            fn draw_svg(
                &self,
                root: &DrawingArea<SVGBackend, Shift>,
                size: FigureSize,
                text: PlotText,
            ) -> DrawResult {
                self.draw(root, size, text)
            }
            fn draw_png(&self, root: &DrawingArea<KernedBitmap, Shift>, size: FigureSize) -> DrawResult {
                self.draw(root, size, PlotText::Drawn)
            }
            fn draw_pdf(&self, root: &DrawingArea<PdfBackend, Shift>, size: FigureSize) -> DrawResult {
                self.draw(root, size, PlotText::Drawn)
            }
        }
    };
}

fn drawing_error(path: &Path, error: impl std::fmt::Display) -> Error {
    Error::bad_file(path, format!("drawing the plot: {error}"))
}

/// Writes `drawing` as `plots/NAME.png` and `.pdf` (two columns) with a
/// font, else `plots/NAME.svg`; with variants also the SVG and all three at
/// one column (`NAME-1col.*`).
fn write_plot(
    out_dir: &Path,
    name: &str,
    title: &str,
    drawing: &dyn Drawing,
    which: PlotFiles,
) -> Result<Plot> {
    let dir = out_dir.join(PLOTS_DIR);
    crate::files::real_dir(&dir)?;
    let text = PlotText::available();
    let sizes: &[FigureSize] =
        if which == PlotFiles::WithVariants { &FigureSize::ALL } else { &[FigureSize::TwoColumns] };
    let mut files = Vec::new();
    for &size in sizes {
        let (w, h) = drawing.size(size);
        let stem = format!("{name}{}", size.suffix());
        if which == PlotFiles::WithVariants || text == PlotText::Omitted {
            let path = dir.join(format!("{stem}.svg"));
            let mut svg = String::new();
            {
                let root = SVGBackend::with_string(&mut svg, (w, h)).into_drawing_area();
                drawing.draw_svg(&root, size, text).map_err(|e| drawing_error(&path, e))?;
                root.present().map_err(|e| drawing_error(&path, e))?;
            }
            crate::files::write_bytes_atomically(&path, svg_in_millimetres(&svg, size, h).as_bytes())?;
            files.push(format!("{PLOTS_DIR}/{stem}.svg"));
        }
        if text == PlotText::Omitted {
            continue;
        }
        let path = dir.join(format!("{stem}.png"));
        let mut rgb = vec![255u8; w as usize * h as usize * 3];
        {
            let root = KernedBitmap(BitMapBackend::with_buffer(&mut rgb, (w, h))).into_drawing_area();
            drawing.draw_png(&root, size).map_err(|e| drawing_error(&path, e))?;
            root.present().map_err(|e| drawing_error(&path, e))?;
        }
        crate::files::write_figure_png(&path, [w, h], &rgb, crate::output::figure::DPI)?;
        files.push(format!("{PLOTS_DIR}/{stem}.png"));
        let path = dir.join(format!("{stem}.pdf"));
        let mut page = PdfPage::new((w, h));
        {
            let root = page.backend().into_drawing_area();
            drawing.draw_pdf(&root, size).map_err(|e| drawing_error(&path, e))?;
        }
        crate::files::write_bytes_atomically(&path, &page.finish(title))?;
        files.push(format!("{PLOTS_DIR}/{stem}.pdf"));
    }
    let (shown, vector) = match text {
        PlotText::Drawn => ("png", "pdf"),
        PlotText::Omitted => ("svg", "svg"),
    };
    Ok(Plot {
        title: title.to_string(),
        shown: format!("{PLOTS_DIR}/{name}.{shown}"),
        vector: format!("{PLOTS_DIR}/{name}.{vector}"),
        files,
    })
}

/// Writes every plot the data allows into `out_dir/plots/`: the time and
/// distance plots need `frames` with eye-frames (a manifest), the bar chart
/// needs parts (and shows `measures` when the result has them); `which`
/// files of each.
pub(crate) fn write_plots(
    out_dir: &Path,
    parts: &[PartStats],
    frames: Option<&FrameTable>,
    measures: Option<&Measures>,
    count_unit: &str,
    which: PlotFiles,
) -> Result<Vec<Plot>> {
    let mut plots = Vec::new();
    if let Some(series) = frames.and_then(VisibilitySeries::new) {
        let by_time = Visibility { series: &series, against_distance: false };
        let what = series.quantity();
        plots.push(write_plot(
            out_dir,
            "visibility-time",
            &format!("{what} per eye of the top parts against time"),
            &by_time,
            which,
        )?);
        if series.has_distance {
            let by_distance = Visibility { series: &series, against_distance: true };
            plots.push(write_plot(
                out_dir,
                "visibility-distance",
                &format!("{what} per eye of the top parts against the vehicle's distance"),
                &by_distance,
                which,
            )?);
        }
    }
    if !parts.is_empty() {
        let bars = PartBars::new(parts, measures, count_unit);
        let title = if bars.quoted {
            "angular area, exposure and the paper's total count per part, the paper's top-5 union marked"
        } else {
            "the paper's total, average and peak count per part, its top-5 union marked"
        };
        plots.push(write_plot(out_dir, "parts", title, &bars, which)?);
    }
    Ok(plots)
}

/// Pixels per eye of the top parts at each captured frame.
struct VisibilitySeries {
    /// (time s, distance m) per frame, in frame order.
    frames: Vec<(f64, Option<f64>)>,
    /// (part name, per eye at each frame: deg² when `angular`, else pixels).
    parts: Vec<(String, Vec<f64>)>,
    has_distance: bool,
    /// True when every eye-frame has solid angles (the manifest gave the
    /// eyes' projection): the series are angular areas in deg², which do
    /// not depend on resolution; else pixels.
    angular: bool,
}

/// Square degrees in a steradian.
const SQUARE_DEGREES_PER_SR: f64 = (180.0 / std::f64::consts::PI) * (180.0 / std::f64::consts::PI);

impl VisibilitySeries {
    /// The series of a table with eye-frames and times; `None` otherwise.
    fn new(table: &FrameTable) -> Option<VisibilitySeries> {
        let angular = table.records.iter().all(|record| record.solid_angle_sr.is_some());
        // Frame number → (time, distance, eyes, deg² or pixels per part).
        let mut by_frame: std::collections::BTreeMap<u32, (f64, Option<f64>, f64, Vec<f64>)> =
            std::collections::BTreeMap::new();
        for record in &table.records {
            let FrameLabel::EyeFrame(eye_frame) = &record.label else { return None };
            let time = eye_frame.time_s?;
            let entry = by_frame
                .entry(eye_frame.frame)
                .or_insert_with(|| (time, eye_frame.distance_m, 0.0, vec![0.0; table.parts.len()]));
            entry.2 += 1.0;
            match (&record.solid_angle_sr, angular) {
                (Some(solid_angles), true) => {
                    for (sum, &solid_angle) in entry.3.iter_mut().zip(solid_angles) {
                        *sum += solid_angle * SQUARE_DEGREES_PER_SR;
                    }
                }
                _ => {
                    for (sum, &pixels) in entry.3.iter_mut().zip(&record.pixels) {
                        *sum += pixels as f64;
                    }
                }
            }
        }
        if by_frame.is_empty() {
            return None;
        }
        let mut totals: Vec<(usize, f64)> = (0..table.parts.len())
            .map(|part| (part, by_frame.values().map(|f| f.3[part]).sum::<f64>()))
            .filter(|(_, total)| *total > 0.0)
            .collect();
        totals.sort_by(|a, b| b.1.total_cmp(&a.1).then(a.0.cmp(&b.0)));
        totals.truncate(TOP_PARTS);
        let parts = totals
            .iter()
            .map(|&(part, _)| {
                (table.parts[part].clone(), by_frame.values().map(|f| f.3[part] / f.2.max(1.0)).collect())
            })
            .collect();
        let has_distance = by_frame.values().all(|f| f.1.is_some());
        Some(VisibilitySeries {
            frames: by_frame.values().map(|f| (f.0, f.1)).collect(),
            parts,
            has_distance,
            angular,
        })
    }

    /// The parts' names as the figures print them ([`readable_part_name`]).
    fn readable_names(&self) -> Vec<String> {
        self.parts.iter().map(|(name, _)| readable_part_name(name)).collect()
    }

    /// What the series measure, in words.
    fn quantity(&self) -> &'static str {
        if self.angular { "angular area (deg²)" } else { "pixels" }
    }
}

struct Visibility<'a> {
    series: &'a VisibilitySeries,
    against_distance: bool,
}

/// Where a time or distance plot puts its data panel and its legend:
/// beside the data at two columns, below it at one column (at 88.9 mm a
/// legend beside the data took more than half the width, issue 44 §2), in
/// one or two columns of entries. Figure pixels.
#[derive(Debug, Clone, Copy, PartialEq)]
struct VisibilityLayout {
    /// The whole figure.
    size: (u32, u32),
    /// The data panel (axes, ticks and curves): `[left, top, right, bottom]`.
    data: [i32; 4],
    /// The legend panel: `[left, top, right, bottom]`.
    legend: [i32; 4],
    /// Columns of legend entries.
    columns: usize,
}

/// Height of one legend row, figure pixels.
fn legend_row() -> i32 {
    (pt(LABEL_PT) * 1.3) as i32
}

impl VisibilityLayout {
    fn new(size: FigureSize, names: &[String]) -> VisibilityLayout {
        let width = size.width_px() as i32;
        let longest = names.iter().map(|n| text_width(n, pt(LABEL_PT))).max().unwrap_or(0);
        // Line, marker, gap and the name (never cut).
        let entry = longest + mm(12.0);
        match size {
            FigureSize::TwoColumns => {
                let height = width / 2;
                let legend = entry.min(width / 2);
                VisibilityLayout {
                    size: (width as u32, height as u32),
                    data: [0, 0, width - legend, height],
                    legend: [width - legend, 0, width, height],
                    columns: 1,
                }
            }
            FigureSize::OneColumn => {
                let columns = if 2 * entry <= width { 2 } else { 1 };
                let rows = names.len().div_ceil(columns) as i32;
                let data_height = (f64::from(width) * 0.62) as i32;
                let height = data_height + mm(2.0) + rows * legend_row();
                VisibilityLayout {
                    size: (width as u32, height as u32),
                    data: [0, 0, width, data_height],
                    legend: [0, data_height, width, height],
                    columns,
                }
            }
        }
    }

    /// Where entry `index` of the legend is centred vertically and begins,
    /// relative to the legend panel (entries fill rows left to right).
    fn entry_at(&self, index: usize) -> (i32, i32) {
        let column_width = (self.legend[2] - self.legend[0]) / self.columns as i32;
        let (column, row) = ((index % self.columns) as i32, (index / self.columns) as i32);
        let top = if self.columns == 1 && self.legend[1] == 0 { mm(6.0) } else { mm(1.0) + legend_row() / 2 };
        (column * column_width, top + row * legend_row())
    }
}

/// Tick labels and legend entries, in points.
const LABEL_PT: f64 = 7.5;
/// Axis titles, in points.
const AXIS_PT: f64 = 8.5;

/// The legend of the top parts in its own panel (beside or below the data,
/// so it never hides a curve): each series' line, dash and marker, and the
/// part's name.
fn draw_legend<B: DrawingBackend>(
    panel: &DrawingArea<B, Shift>,
    names: &[String],
    layout: &VisibilityLayout,
) -> DrawResult
where
    B::ErrorType: 'static,
{
    for (index, name) in names.iter().enumerate() {
        let (x, y) = layout.entry_at(index);
        draw_series_line(panel, index, &[(x + mm(1.0), y), (x + mm(8.0), y)])?;
        draw_marker(panel, index, (x + mm(4.5), y), mm(0.8))?;
        let style = TextStyle::from(("sans-serif", pt(LABEL_PT)).into_font())
            .pos(text_anchor::Pos::new(text_anchor::HPos::Left, text_anchor::VPos::Center));
        panel.draw(&Text::new(name.clone(), (x + mm(10.0), y), style))?;
    }
    Ok(())
}

/// Mesh lines, axes and labels in print sizes.
fn style_mesh<X, Y, B>(mesh: &mut plotters::chart::MeshStyle<'_, '_, X, Y, B>)
where
    X: plotters::coord::ranged1d::Ranged,
    Y: plotters::coord::ranged1d::Ranged,
    B: DrawingBackend,
{
    mesh.label_style(("sans-serif", pt(LABEL_PT)))
        .axis_desc_style(("sans-serif", pt(AXIS_PT)))
        .light_line_style(RGBColor(238, 238, 238).stroke_width(stroke(0.3)))
        .bold_line_style(RGBColor(210, 210, 210).stroke_width(stroke(0.4)))
        .axis_style(BLACK.stroke_width(stroke(0.6)))
        .set_all_tick_mark_size(mm(1.0));
}

impl Visibility<'_> {
    fn draw<B: DrawingBackend>(
        &self,
        root: &DrawingArea<B, Shift>,
        size: FigureSize,
        text: PlotText,
    ) -> DrawResult
    where
        B::ErrorType: 'static,
    {
        root.fill(&WHITE)?;
        let names = self.series.readable_names();
        let layout = VisibilityLayout::new(size, &names);
        let (plot_area, legend_area) = match text {
            PlotText::Omitted => (root.clone(), root.clone()),
            PlotText::Drawn if layout.legend[1] > 0 => root.split_vertically(layout.data[3]),
            PlotText::Drawn => root.split_horizontally(layout.data[2]),
        };
        let xs: Vec<f64> = self
            .series
            .frames
            .iter()
            .map(|&(time, distance)| if self.against_distance { distance.unwrap_or(0.0) } else { time })
            .collect();
        let (x_min, x_max) = xs.iter().fold((f64::MAX, f64::MIN), |(lo, hi), &x| (lo.min(x), hi.max(x)));
        let x_max = if x_max > x_min { x_max } else { x_min + 1.0 };
        let y_max =
            self.series.parts.iter().flat_map(|(_, ys)| ys.iter().copied()).fold(1.0, f64::max) * 1.08;
        let mut builder = ChartBuilder::on(&plot_area);
        builder.margin(mm(2.5));
        if text == PlotText::Drawn {
            builder.x_label_area_size(mm(10.0)).y_label_area_size(mm(13.0));
        }
        let mut chart = builder.build_cartesian_2d(x_min..x_max, 0.0..y_max)?;
        let mut mesh = chart.configure_mesh();
        let x_span = x_max - x_min;
        let x_tick = move |v: &f64| tick(*v, x_span);
        let y_tick = move |v: &f64| tick(*v, y_max);
        style_mesh(&mut mesh);
        let ticks = if size == FigureSize::OneColumn { 5 } else { 9 };
        if text == PlotText::Drawn {
            mesh.x_desc(if self.against_distance { "vehicle distance (m)" } else { "time (s)" })
                .y_desc(if self.series.angular {
                    "angular area per eye (deg²)"
                } else {
                    "part's pixels per eye (px)"
                })
                .x_labels(ticks)
                .y_labels(6)
                .x_label_formatter(&x_tick)
                .y_label_formatter(&y_tick);
        } else {
            mesh.x_labels(0).y_labels(0);
        }
        mesh.draw()?;
        let markers = if size == FigureSize::OneColumn { 6 } else { 10 };
        for (index, (_, ys)) in self.series.parts.iter().enumerate() {
            let mut points: Vec<(f64, f64)> = xs.iter().copied().zip(ys.iter().copied()).collect();
            if self.against_distance {
                // Distance need not change monotonically: points, joined in distance order.
                points.sort_by(|a, b| a.0.total_cmp(&b.0));
            }
            let pixels: Vec<(i32, i32)> = points.iter().map(|p| chart.backend_coord(p)).collect();
            draw_series_line(root, index, &pixels)?;
            // A few markers per curve (offset per series so they do not stack):
            // one per frame would thicken it into a band at 181 frames.
            let step = (pixels.len() / markers).max(1);
            for at in pixels.iter().skip((index * step) / TOP_PARTS).step_by(step) {
                draw_marker(root, index, *at, mm(0.8))?;
            }
        }
        if text == PlotText::Drawn {
            draw_legend(&legend_area, &names, &layout)?;
        }
        root.present()?;
        Ok(())
    }
}

drawing!(Visibility<'_>, |plot: &Visibility<'_>, size: FigureSize| {
    VisibilityLayout::new(size, &plot.series.readable_names()).size
});

/// One panel of the bar chart: its axis title and a value per part.
struct BarPanel {
    label: String,
    values: Vec<f64>,
}

/// Horizontal bars per part (sorted by the first panel): angular area,
/// exposure and the paper's total count when the result has measures; else
/// the paper's total, average and peak count.
struct PartBars {
    names: Vec<String>,
    /// The paper's top-5 union, per part.
    marked: Vec<bool>,
    panels: Vec<BarPanel>,
    /// Whether the first panels are the measures to quote.
    quoted: bool,
}

impl PartBars {
    fn new(parts: &[PartStats], measures: Option<&Measures>, unit: &str) -> PartBars {
        let marked = crate::result::part_stats::top_five_union(parts);
        let totals = parts.iter().map(|p| p.total as f64).collect();
        let total = BarPanel { label: format!("paper's count, total ({unit})"), values: totals };
        let measure = |value: fn(&crate::result::measures::PartMeasure) -> Option<f64>| -> Option<Vec<f64>> {
            let measures = measures?;
            parts
                .iter()
                .map(|p| measures.parts.iter().find(|m| m.name == p.name).map_or(Some(0.0), value))
                .collect()
        };
        let (panels, quoted) = match (measure(|m| m.angular_area_deg2_s), measure(|m| m.exposure_s)) {
            (Some(area), Some(exposure)) => (
                vec![
                    BarPanel { label: "angular area (deg²·s)".into(), values: area },
                    BarPanel { label: "exposure (s)".into(), values: exposure },
                    total,
                ],
                true,
            ),
            _ => (
                vec![
                    total,
                    BarPanel {
                        label: format!("paper's count, average ({unit})"),
                        values: parts.iter().map(|p| p.average).collect(),
                    },
                    BarPanel {
                        label: format!("paper's count, peak ({unit})"),
                        values: parts.iter().map(|p| f64::from(p.peak)).collect(),
                    },
                ],
                false,
            ),
        };
        let names = parts.iter().map(|p| readable_part_name(&p.name)).collect();
        PartBars { names, marked, panels, quoted }
    }

    fn row_height(size: FigureSize) -> i32 {
        mm(if size == FigureSize::OneColumn { 3.4 } else { 3.8 })
    }

    fn draw<B: DrawingBackend>(
        &self,
        root: &DrawingArea<B, Shift>,
        size: FigureSize,
        text: PlotText,
    ) -> DrawResult
    where
        B::ErrorType: 'static,
    {
        root.fill(&WHITE)?;
        let first = &self.panels[0].values;
        let mut order: Vec<usize> = (0..self.names.len()).collect();
        // Bottom up: the part with the largest first value ends up on top.
        order.sort_by(|&a, &b| first[a].total_cmp(&first[b]).then(b.cmp(&a)));
        let names: Vec<String> = order
            .iter()
            .map(|&i| if self.marked[i] { format!("* {}", self.names[i]) } else { self.names[i].clone() })
            .collect();
        let root = if text == PlotText::Drawn {
            let (top, rest) = root.split_vertically(mm(6.0));
            let key = "orange, *: the paper's top-5 union (by count)";
            top.draw(&Text::new(key, (mm(2.0), mm(1.5)), ("sans-serif", pt(LABEL_PT))))?;
            rest
        } else {
            root.clone()
        };
        // Room for the longest name (a name is never cut).
        let names_width = names.iter().map(|n| text_width(n, pt(LABEL_PT))).max().unwrap_or(0) + mm(2.5);
        let width = root.dim_in_pixel().0 as i32;
        // One column has room for the first two panels (the quoted measures, or
        // the paper's total and average); two columns show all three.
        let shown = if size == FigureSize::OneColumn { 2 } else { 3 };
        let count = self.panels.len().min(shown) as i32;
        let panel_width = (width - names_width) / count.max(1);
        let breaks: Vec<i32> = (1..count).map(|k| names_width + k * panel_width).collect();
        let areas = root.split_by_breakpoints(breaks, Vec::<i32>::new());
        for (panel_index, (area, panel)) in areas.iter().zip(&self.panels).enumerate() {
            let first = panel_index == 0;
            let layout = PanelLayout { first, text, names_width };
            draw_panel(area, panel, &order, &names, &self.marked, layout)?;
        }
        root.present()?;
        Ok(())
    }
}

/// Where a bar panel sits: the first carries the part names (`names_width` wide).
#[derive(Clone, Copy)]
struct PanelLayout {
    first: bool,
    text: PlotText,
    names_width: i32,
}

/// One panel of the bar chart, rows in `order` (bottom up).
fn draw_panel<B: DrawingBackend>(
    area: &DrawingArea<B, Shift>,
    panel: &BarPanel,
    order: &[usize],
    names: &[String],
    marked: &[bool],
    layout: PanelLayout,
) -> DrawResult
where
    B::ErrorType: 'static,
{
    let max = order.iter().map(|&i| panel.values[i]).fold(0.0, f64::max).max(1e-9) * 1.05;
    let mut builder = ChartBuilder::on(area);
    builder.margin_top(mm(1.0)).margin_right(mm(3.0)).margin_bottom(mm(1.0)).margin_left(mm(0.5));
    if layout.text == PlotText::Drawn {
        builder.x_label_area_size(mm(9.0)).y_label_area_size(if layout.first {
            layout.names_width
        } else {
            mm(0.5)
        });
    }
    let mut chart = builder.build_cartesian_2d(0.0..max, (0..order.len()).into_segmented())?;
    let label = |v: &SegmentValue<usize>| match v {
        SegmentValue::CenterOf(i) | SegmentValue::Exact(i) => names.get(*i).cloned().unwrap_or_default(),
        SegmentValue::Last => String::new(),
    };
    let no_label = |_: &SegmentValue<usize>| String::new();
    let x_tick = move |v: &f64| tick(*v, max);
    let mut mesh = chart.configure_mesh();
    style_mesh(&mut mesh);
    mesh.disable_y_mesh()
        .x_labels(3)
        .x_label_formatter(&x_tick)
        .axis_desc_style(("sans-serif", pt(LABEL_PT)));
    // plotters overflows on zero labels of a segmented axis: empty ones instead.
    mesh.y_labels(order.len());
    if layout.text == PlotText::Drawn && layout.first {
        mesh.y_label_formatter(&label);
    } else {
        mesh.y_label_formatter(&no_label);
    }
    if layout.text == PlotText::Drawn {
        mesh.x_desc(panel.label.as_str());
    } else {
        mesh.x_labels(0);
    }
    mesh.draw()?;
    chart.draw_series(order.iter().enumerate().map(|(row, &part)| {
        // Okabe–Ito orange and blue: apart in hue and in lightness (greyscale).
        let color = if marked[part] { series_color(4) } else { series_color(0) };
        let mut bar = Rectangle::new(
            [(0.0, SegmentValue::Exact(row)), (panel.values[part], SegmentValue::Exact(row + 1))],
            color.filled(),
        );
        bar.set_margin(2, 2, 0, 0);
        bar
    }))?;
    Ok(())
}

drawing!(PartBars, |bars: &PartBars, size: FigureSize| {
    (size.width_px(), (mm(18.0) + PartBars::row_height(size) * bars.names.len().max(1) as i32) as u32)
});

#[cfg(test)]
mod tests {
    use super::*;
    use crate::archive::capture_facts::EyeFrame;
    use crate::count::part_lookup::FrameRecord;

    fn record(eye: &str, pixels: u64, solid_angle_sr: Option<f64>) -> FrameRecord {
        let frame = EyeFrame { frame: 0, eye: eye.into(), time_s: Some(0.0), distance_m: Some(5.0) };
        FrameRecord {
            label: FrameLabel::EyeFrame(frame),
            pixels: vec![pixels],
            texels: vec![1],
            solid_angle_sr: solid_angle_sr.map(|sr| vec![sr]),
        }
    }

    #[test]
    fn visibility_is_in_square_degrees_per_eye_when_every_eye_frame_has_solid_angles() {
        let parts = vec!["door".to_string()];
        // One steradian over two eyes: half a steradian per eye.
        let table = FrameTable {
            parts: parts.clone(),
            records: vec![record("left", 10, Some(0.25)), record("right", 30, Some(0.75))],
        };
        let series = VisibilitySeries::new(&table).unwrap();
        assert!(series.angular);
        assert!((series.parts[0].1[0] - 0.5 * SQUARE_DEGREES_PER_SR).abs() < 1e-9);
        // Without the projection of one eye-frame: pixels per eye.
        let table =
            FrameTable { parts, records: vec![record("left", 10, Some(0.25)), record("right", 30, None)] };
        let series = VisibilitySeries::new(&table).unwrap();
        assert!(!series.angular);
        assert_eq!(series.parts[0].1, [20.0]);
    }

    #[test]
    fn at_one_column_the_legend_sits_below_the_data_which_takes_the_whole_width() {
        let names: Vec<String> = [
            "windshield_rail_left",
            "door_front_right",
            "b_pillar_left",
            "front_license_plate",
            "hood",
            "grill",
            "rear_fender_right",
            "side_mirror_left",
        ]
        .iter()
        .map(|n| readable_part_name(n))
        .collect();
        let one = VisibilityLayout::new(FigureSize::OneColumn, &names);
        let width = FigureSize::OneColumn.width_px() as i32;
        assert_eq!(one.size.0 as i32, width);
        assert_eq!(one.data[2] - one.data[0], width, "the data panel spans the figure");
        assert!(one.legend[1] >= one.data[3], "the legend overlaps the data: {one:?}");
        let two = VisibilityLayout::new(FigureSize::TwoColumns, &names);
        assert!(two.legend[0] >= two.data[2], "the legend overlaps the data: {two:?}");
        assert!(f64::from(two.data[2]) >= 0.6 * f64::from(two.size.0), "{two:?}");
        for layout in [one, two] {
            let entries = (0..names.len()).map(|i| (layout.entry_at(i), &names[i]));
            for ((x, y), name) in entries {
                // Inside the legend panel (the name never cut).
                let right = layout.legend[0] + x + mm(10.0) + text_width(name, pt(LABEL_PT));
                let bottom = layout.legend[1] + y + legend_row() / 2;
                assert!(
                    right <= layout.legend[2] && bottom <= layout.legend[3],
                    "{name} at {x},{y}: {layout:?}"
                );
            }
        }
    }

    #[test]
    fn a_default_plot_is_a_two_column_png_and_pdf_and_variants_add_svg_and_one_column() {
        if !font_available() {
            eprintln!("skipped: no font (set UFCSR_FONT)");
            return;
        }
        let table = FrameTable {
            parts: vec!["windshield_rail_left".to_string()],
            records: vec![record("left", 10, Some(0.25)), record("right", 30, Some(0.75))],
        };
        let dir = tempfile::tempdir().unwrap();
        let plots = write_plots(dir.path(), &[], Some(&table), None, "px", PlotFiles::Default).unwrap();
        assert_eq!(plots[0].files, ["plots/visibility-time.png", "plots/visibility-time.pdf"]);
        assert_eq!(plots[0].vector, "plots/visibility-time.pdf");
        let plots = write_plots(dir.path(), &[], Some(&table), None, "px", PlotFiles::WithVariants).unwrap();
        assert_eq!(plots[0].files.len(), 6, "{:?}", plots[0].files);
        let svg = std::fs::read_to_string(dir.path().join("plots/visibility-time-1col.svg")).unwrap();
        assert!(svg.contains("windshield rail, left") && !svg.contains("windshield_rail_left"));
        assert!(svg.contains("width=\"88.9mm\""), "{}", &svg[..200]);
    }
}
