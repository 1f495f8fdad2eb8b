//! Plots for people, under `--out/plots/` (PNG and SVG each): the
//! visibility of the most visible parts against time and against the
//! vehicle's distance (from `frames.csv`), and the paper's per-part bar
//! chart — total, average and peak count, the paper's top-5 union marked.
//! Each title names the archive (the scenario); ticks of counts are whole
//! numbers with thousands separators, lines carry no per-frame markers, and
//! the legend sits beside the plot, never over a curve.
//!
//! Labels need a TrueType font, looked up at run time (`UFCSR_FONT`, else
//! DejaVu Sans where Debian and most distributions put it) so that building
//! needs no fontconfig; without one the SVGs are drawn without text and no
//! PNG is written (the report then shows the SVGs).

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use plotters::coord::Shift;
use plotters::coord::ranged1d::SegmentValue;
use plotters::prelude::*;

use crate::error::{Error, Result};
use crate::output::numbers::tick;
use crate::result::part_stats::PartStats;
use crate::{count::part_lookup::FrameLabel, result::frames::FrameTable};

/// Folder of the plots inside the output folder.
pub const PLOTS_DIR: &str = "plots";

/// Every plot a result set can have (`plots/NAME.svg`, `.png`).
pub const PLOT_NAMES: [&str; 3] = ["visibility-time", "visibility-distance", "parts"];

/// Parts drawn in the time and distance plots.
pub const TOP_PARTS: usize = 8;

const FONT_CANDIDATES: [&str; 3] = [
    "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf",
    "/usr/share/fonts/TTF/DejaVuSans.ttf",
    "/usr/share/fonts/dejavu/DejaVuSans.ttf",
];

/// Registers a sans-serif font with plotters once; false when none is found
/// (`ufcsr-capture`'s study plot uses it too).
pub fn font_available() -> bool {
    static FOUND: OnceLock<bool> = OnceLock::new();
    *FOUND.get_or_init(|| {
        let mut candidates: Vec<PathBuf> =
            std::env::var_os("UFCSR_FONT").map(PathBuf::from).into_iter().collect();
        candidates.extend(FONT_CANDIDATES.iter().map(PathBuf::from));
        for path in candidates {
            if let Ok(bytes) = crate::files::read_limited(&path, crate::files::SMALL_INPUT_LIMIT) {
                // plotters keeps fonts for the life of the process.
                let bytes: &'static [u8] = Box::leak(bytes.into_boxed_slice());
                if plotters::style::register_font("sans-serif", FontStyle::Normal, bytes).is_ok() {
                    return true;
                }
            }
        }
        false
    })
}

/// One plot as written: its name and the image to show (PNG when a font
/// was found, else SVG).
#[derive(Debug, Clone, PartialEq)]
pub struct Plot {
    /// What it shows, for the report's alt text.
    pub title: String,
    /// The image to show, relative to the output folder (`plots/NAME.png`).
    pub shown: String,
    /// The SVG, relative to the output folder.
    pub svg: String,
}

type DrawResult = std::result::Result<(), Box<dyn std::error::Error>>;

/// A plot drawn on any backend (`text`: whether labels can be drawn).
trait Drawing {
    fn size(&self) -> (u32, u32);
    fn draw_svg(&self, root: &DrawingArea<SVGBackend, Shift>, text: bool) -> DrawResult;
    fn draw_png(&self, root: &DrawingArea<BitMapBackend, Shift>) -> DrawResult;
}

/// Writes `drawing` as `plots/NAME.svg` and, with a font, `plots/NAME.png`.
fn write_plot(out_dir: &Path, name: &str, title: &str, drawing: &dyn Drawing) -> Result<Plot> {
    let dir = out_dir.join(PLOTS_DIR);
    crate::files::real_dir(&dir)?;
    let text = font_available();
    let svg = dir.join(format!("{name}.svg"));
    {
        let root = SVGBackend::new(&svg, drawing.size()).into_drawing_area();
        drawing.draw_svg(&root, text).map_err(|e| Error::bad_file(&svg, format!("drawing the plot: {e}")))?;
    }
    let mut shown = format!("{PLOTS_DIR}/{name}.svg");
    if text {
        let png = dir.join(format!("{name}.png"));
        let root = BitMapBackend::new(&png, drawing.size()).into_drawing_area();
        drawing.draw_png(&root).map_err(|e| Error::bad_file(&png, format!("drawing the plot: {e}")))?;
        shown = format!("{PLOTS_DIR}/{name}.png");
    }
    Ok(Plot { title: title.to_string(), shown, svg: format!("{PLOTS_DIR}/{name}.svg") })
}

/// Writes every plot the data allows into `out_dir/plots/`: the time and
/// distance plots need `frames` with eye-frames (a manifest), the bar chart
/// needs parts.
/// `scenario` (the archive's name) goes into every title.
pub fn write_plots(
    out_dir: &Path,
    parts: &[PartStats],
    frames: Option<&FrameTable>,
    scenario: &str,
) -> Result<Vec<Plot>> {
    let mut plots = Vec::new();
    if let Some(series) = frames.and_then(VisibilitySeries::new) {
        let by_time = Visibility { series: &series, against_distance: false, scenario };
        let what = series.quantity();
        plots.push(write_plot(
            out_dir,
            "visibility-time",
            &format!("{what} per eye of the top parts against time"),
            &by_time,
        )?);
        if series.has_distance {
            let by_distance = Visibility { series: &series, against_distance: true, scenario };
            plots.push(write_plot(
                out_dir,
                "visibility-distance",
                &format!("{what} per eye of the top parts against the vehicle's distance"),
                &by_distance,
            )?);
        }
    }
    if !parts.is_empty() {
        let bars = PartBars { parts, scenario };
        plots.push(write_plot(
            out_dir,
            "parts",
            "total, average and peak count per part, the paper's top-5 union marked",
            &bars,
        )?);
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

    /// What the series measure, in words.
    fn quantity(&self) -> &'static str {
        if self.angular { "angular area (deg²)" } else { "pixels" }
    }
}

/// Line colours of the top parts.
fn series_color(index: usize) -> RGBColor {
    const COLORS: [RGBColor; TOP_PARTS] = [
        RGBColor(31, 119, 180),
        RGBColor(255, 127, 14),
        RGBColor(44, 160, 44),
        RGBColor(214, 39, 40),
        RGBColor(148, 103, 189),
        RGBColor(140, 86, 75),
        RGBColor(227, 119, 194),
        RGBColor(127, 127, 127),
    ];
    COLORS[index % TOP_PARTS]
}

struct Visibility<'a> {
    series: &'a VisibilitySeries,
    against_distance: bool,
    /// The archive's name, for the title.
    scenario: &'a str,
}

/// Width of the legend panel right of the time and distance plots.
const LEGEND_WIDTH: u32 = 230;

/// The legend of the top parts in its own panel (beside the data, so it
/// never hides a curve): a coloured line and the part's name per row.
fn draw_legend<B: DrawingBackend>(panel: &DrawingArea<B, Shift>, names: &[&str]) -> DrawResult
where
    B::ErrorType: 'static,
{
    for (index, name) in names.iter().enumerate() {
        let y = 60 + 22 * index as i32;
        let color = series_color(index);
        panel.draw(&PathElement::new(vec![(8, y), (32, y)], color.stroke_width(3)))?;
        panel.draw(&Text::new(name.to_string(), (40, y - 7), ("sans-serif", 13)))?;
    }
    Ok(())
}

impl Visibility<'_> {
    fn draw<B: DrawingBackend>(&self, root: &DrawingArea<B, Shift>, text: bool) -> DrawResult
    where
        B::ErrorType: 'static,
    {
        root.fill(&WHITE)?;
        let (plot_area, legend_area) = if text {
            let width = root.dim_in_pixel().0;
            root.split_horizontally(width.saturating_sub(LEGEND_WIDTH))
        } else {
            (root.clone(), root.clone())
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
        builder.margin(20);
        if text {
            let caption = if self.against_distance {
                format!("{}: visibility of the top parts against distance", self.scenario)
            } else {
                format!("{}: visibility of the top parts over time", self.scenario)
            };
            builder.caption(caption, ("sans-serif", 20)).x_label_area_size(45).y_label_area_size(80);
        }
        let mut chart = builder.build_cartesian_2d(x_min..x_max, 0.0..y_max)?;
        let mut mesh = chart.configure_mesh();
        let x_span = x_max - x_min;
        let x_tick = move |v: &f64| tick(*v, x_span);
        let y_tick = move |v: &f64| tick(*v, y_max);
        if text {
            mesh.x_desc(if self.against_distance { "vehicle distance, m" } else { "time, s" })
                .y_desc(if self.series.angular {
                    "angular area of the part, deg² (per eye)"
                } else {
                    "pixels showing the part (per eye)"
                })
                .x_label_formatter(&x_tick)
                .y_label_formatter(&y_tick);
        } else {
            mesh.x_labels(0).y_labels(0);
        }
        mesh.draw()?;
        for (index, (_, ys)) in self.series.parts.iter().enumerate() {
            let color = series_color(index);
            let mut points: Vec<(f64, f64)> = xs.iter().copied().zip(ys.iter().copied()).collect();
            if self.against_distance {
                // Distance need not change monotonically: points, joined in distance order.
                points.sort_by(|a, b| a.0.total_cmp(&b.0));
            }
            // A plain line: per-frame markers thicken it into a band at 181 frames.
            chart.draw_series(LineSeries::new(points, color.stroke_width(2)))?;
        }
        if text {
            let names: Vec<&str> = self.series.parts.iter().map(|(name, _)| name.as_str()).collect();
            draw_legend(&legend_area, &names)?;
        }
        root.present()?;
        Ok(())
    }
}

impl Drawing for Visibility<'_> {
    fn size(&self) -> (u32, u32) {
        (900 + LEGEND_WIDTH, 520)
    }
    fn draw_svg(&self, root: &DrawingArea<SVGBackend, Shift>, text: bool) -> DrawResult {
        self.draw(root, text)
    }
    fn draw_png(&self, root: &DrawingArea<BitMapBackend, Shift>) -> DrawResult {
        self.draw(root, true)
    }
}

/// One measure of a part, as a bar length.
type PartValue = fn(&PartStats) -> f64;

/// Horizontal bars per part (sorted by total): total, average, peak.
struct PartBars<'a> {
    parts: &'a [PartStats],
    /// The archive's name, for the title.
    scenario: &'a str,
}

impl PartBars<'_> {
    fn draw<B: DrawingBackend>(&self, root: &DrawingArea<B, Shift>, text: bool) -> DrawResult
    where
        B::ErrorType: 'static,
    {
        root.fill(&WHITE)?;
        let parts = self.parts;
        let marked = crate::result::part_stats::top_five_union(parts);
        let mut order: Vec<usize> = (0..parts.len()).collect();
        // Bottom up: the part with the highest total ends up on top.
        order.sort_by(|&a, &b| parts[a].total.cmp(&parts[b].total).then(b.cmp(&a)));
        let names: Vec<String> = order
            .iter()
            .map(|&i| if marked[i] { format!("* {}", parts[i].name) } else { parts[i].name.clone() })
            .collect();
        let root = if text {
            let (top, rest) = root.split_vertically(40);
            top.titled(
                &format!(
                    "{}: total, average and peak count per part (orange, *: the paper's top-5 union)",
                    self.scenario
                ),
                ("sans-serif", 18),
            )?;
            rest
        } else {
            root.clone()
        };
        let panels = root.split_evenly((1, 3));
        let measures: [(&str, PartValue); 3] =
            [("total", |p| p.total as f64), ("average", |p| p.average), ("peak", |p| f64::from(p.peak))];
        for (panel_index, (panel, (label, value))) in panels.iter().zip(measures.iter()).enumerate() {
            let max = order.iter().map(|&i| value(&parts[i])).fold(0.0, f64::max).max(1e-9) * 1.05;
            let mut builder = ChartBuilder::on(panel);
            builder.margin(8);
            if text {
                builder
                    .caption(*label, ("sans-serif", 15))
                    .x_label_area_size(30)
                    .y_label_area_size(if panel_index == 0 { 170 } else { 8 });
            }
            let mut chart = builder.build_cartesian_2d(0.0..max, (0..order.len()).into_segmented())?;
            let label = |v: &SegmentValue<usize>| match v {
                SegmentValue::CenterOf(i) | SegmentValue::Exact(i) => {
                    names.get(*i).cloned().unwrap_or_default()
                }
                SegmentValue::Last => String::new(),
            };
            let mut mesh = chart.configure_mesh();
            let x_tick = move |v: &f64| tick(*v, max);
            mesh.disable_y_mesh().x_labels(4).x_label_formatter(&x_tick);
            let no_label = |_: &SegmentValue<usize>| String::new();
            // plotters overflows on zero labels of a segmented axis: empty ones instead.
            mesh.y_labels(order.len());
            if text && panel_index == 0 {
                mesh.y_label_style(("sans-serif", 11)).y_label_formatter(&label);
            } else {
                mesh.y_label_formatter(&no_label);
            }
            if !text {
                mesh.x_labels(0);
            }
            mesh.draw()?;
            chart.draw_series(order.iter().enumerate().map(|(row, &part)| {
                let color = if marked[part] { RGBColor(245, 140, 20) } else { RGBColor(70, 110, 180) };
                let mut bar = Rectangle::new(
                    [(0.0, SegmentValue::Exact(row)), (value(&parts[part]), SegmentValue::Exact(row + 1))],
                    color.filled(),
                );
                bar.set_margin(2, 2, 0, 0);
                bar
            }))?;
        }
        root.present()?;
        Ok(())
    }
}

impl Drawing for PartBars<'_> {
    fn size(&self) -> (u32, u32) {
        (1100, 120 + 16 * self.parts.len().max(1) as u32)
    }
    fn draw_svg(&self, root: &DrawingArea<SVGBackend, Shift>, text: bool) -> DrawResult {
        self.draw(root, text)
    }
    fn draw_png(&self, root: &DrawingArea<BitMapBackend, Shift>) -> DrawResult {
        self.draw(root, true)
    }
}

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
}
