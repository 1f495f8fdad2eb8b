//! Dot-and-whisker figures (issue 44 §2: "where a number has an interval,
//! the figure shows it"): one row per value, a dot at the value and a
//! whisker with end caps over its 95 % interval, for the numbers the
//! capture's studies give with intervals and had no figure for — the
//! observers' per-part angular area over the population and the design's
//! main effects. Drawn like the analysis plots ([`crate::output::figure`]:
//! two journal columns, 181.9 mm, 300 dpi PNG and vector PDF, text ≥ 7 pt,
//! Okabe–Ito, "quantity (unit)" on the axis, names in words).

use std::path::{Path, PathBuf};

use plotters::coord::Shift;
use plotters::coord::ranged1d::SegmentValue;
use plotters::prelude::*;

use crate::error::{Error, Result};
use crate::output::figure::{
    DrawResult, FigureSize, KernedBitmap, draw_marker, mm, pt, series_color, stroke, svg_in_millimetres,
    text_width,
};
use crate::output::numbers::tick;
use crate::output::pdf::PdfPage;
use crate::output::plots::PlotText;

/// One row: what it is, its value and its 95 % interval (none: only the dot).
#[derive(Debug, Clone, PartialEq)]
pub struct IntervalRow {
    pub label: String,
    pub value: f64,
    pub interval: Option<[f64; 2]>,
}

/// A dot-and-whisker figure: its rows top to bottom and its axis title.
#[derive(Debug, Clone, PartialEq)]
pub struct IntervalFigure {
    /// The PDF's title.
    pub title: String,
    /// "quantity (unit)".
    pub axis: String,
    pub rows: Vec<IntervalRow>,
}

/// Text of the row labels and ticks, points.
const LABEL_PT: f64 = 7.5;
/// Height of one row, millimetres.
const ROW_MM: f64 = 4.0;

impl IntervalFigure {
    /// The figure's size at two journal columns, pixels.
    pub fn size(&self) -> (u32, u32) {
        let rows = self.rows.len().max(1) as f64;
        (FigureSize::TwoColumns.width_px(), mm(14.0 + ROW_MM * rows) as u32)
    }

    /// The horizontal axis's range: every value and interval end, and 0.
    fn range(&self) -> (f64, f64) {
        let ends =
            self.rows.iter().flat_map(|r| [r.value].into_iter().chain(r.interval.into_iter().flatten()));
        let (low, high) =
            ends.filter(|v| v.is_finite()).fold((0.0f64, 0.0f64), |(l, h), v| (l.min(v), h.max(v)));
        let pad = (high - low).max(1e-9) * 0.05;
        (if low < 0.0 { low - pad } else { 0.0 }, high + pad)
    }

    fn draw<B: DrawingBackend>(&self, root: &DrawingArea<B, Shift>, text: PlotText) -> DrawResult
    where
        B::ErrorType: 'static,
    {
        root.fill(&WHITE)?;
        let names_width =
            self.rows.iter().map(|r| text_width(&r.label, pt(LABEL_PT))).max().unwrap_or(0) + mm(2.5);
        let (low, high) = self.range();
        let rows = self.rows.len();
        let mut builder = ChartBuilder::on(root);
        builder.margin_top(mm(2.0)).margin_right(mm(4.0)).margin_bottom(mm(1.0)).margin_left(mm(1.0));
        if text == PlotText::Drawn {
            builder.x_label_area_size(mm(10.0)).y_label_area_size(names_width);
        }
        // Row 0 is drawn on top: segments count bottom up.
        let mut chart = builder.build_cartesian_2d(low..high, (0..rows.max(1)).into_segmented())?;
        let label = |v: &SegmentValue<usize>| match v {
            SegmentValue::CenterOf(i) | SegmentValue::Exact(i) if *i < rows => {
                self.rows[rows - 1 - i].label.clone()
            }
            _ => String::new(),
        };
        let span = high - low;
        let x_tick = move |v: &f64| tick(*v, span);
        let mut mesh = chart.configure_mesh();
        mesh.label_style(("sans-serif", pt(LABEL_PT)))
            .axis_desc_style(("sans-serif", pt(8.5)))
            .light_line_style(RGBColor(238, 238, 238).stroke_width(stroke(0.3)))
            .bold_line_style(RGBColor(210, 210, 210).stroke_width(stroke(0.4)))
            .axis_style(BLACK.stroke_width(stroke(0.6)))
            .set_all_tick_mark_size(mm(1.0))
            .disable_y_mesh()
            .y_labels(rows.max(1))
            .y_label_formatter(&label)
            .x_labels(6)
            .x_label_formatter(&x_tick);
        if text == PlotText::Drawn {
            mesh.x_desc(self.axis.as_str());
        } else {
            mesh.x_labels(0);
        }
        mesh.draw()?;
        if low < 0.0 {
            let zero = [(0.0, SegmentValue::Exact(0)), (0.0, SegmentValue::Last)];
            chart.draw_series(std::iter::once(PathElement::new(zero, BLACK.stroke_width(stroke(0.5)))))?;
        }
        let color = series_color(0);
        let cap = mm(0.8);
        for (index, row) in self.rows.iter().enumerate() {
            let at = SegmentValue::CenterOf(rows - 1 - index);
            if let Some([from, to]) = row.interval {
                let (a, b) =
                    (chart.backend_coord(&(from, at.clone())), chart.backend_coord(&(to, at.clone())));
                let whisker = Color::stroke_width(&color, stroke(0.9));
                root.draw(&PathElement::new([a, b], whisker))?;
                for end in [a, b] {
                    root.draw(&PathElement::new([(end.0, end.1 - cap), (end.0, end.1 + cap)], whisker))?;
                }
            }
            draw_marker(root, 0, chart.backend_coord(&(row.value, at)), mm(0.9))?;
        }
        Ok(())
    }

    /// The figure as SVG (its width in millimetres; no text without a font).
    pub fn svg(&self) -> Result<String> {
        let (w, h) = self.size();
        let mut svg = String::new();
        {
            let root = SVGBackend::with_string(&mut svg, (w, h)).into_drawing_area();
            self.draw(&root, PlotText::available()).map_err(|e| drawing_error(&self.title, e))?;
            root.present().map_err(|e| drawing_error(&self.title, e))?;
        }
        Ok(svg_in_millimetres(&svg, FigureSize::TwoColumns, h))
    }

    /// Writes `STEM.png` (300 dpi) and `STEM.pdf` (vector, the font embedded);
    /// returns their paths, none without a font (the labels could not be drawn).
    pub fn write(&self, stem: &Path) -> Result<Vec<PathBuf>> {
        if PlotText::available() == PlotText::Omitted {
            return Ok(Vec::new());
        }
        let (w, h) = self.size();
        let png = stem.with_extension("png");
        let mut rgb = vec![255u8; w as usize * h as usize * 3];
        {
            let root = KernedBitmap(BitMapBackend::with_buffer(&mut rgb, (w, h))).into_drawing_area();
            self.draw(&root, PlotText::Drawn).map_err(|e| drawing_error(&self.title, e))?;
            root.present().map_err(|e| drawing_error(&self.title, e))?;
        }
        crate::files::write_figure_png(&png, [w, h], &rgb, crate::output::figure::DPI)?;
        let pdf = stem.with_extension("pdf");
        let mut page = PdfPage::new((w, h));
        {
            let root = page.backend().into_drawing_area();
            self.draw(&root, PlotText::Drawn).map_err(|e| drawing_error(&self.title, e))?;
        }
        crate::files::write_bytes_atomically(&pdf, &page.finish(&self.title))?;
        Ok(vec![png, pdf])
    }
}

fn drawing_error(title: &str, error: impl std::fmt::Display) -> Error {
    Error::bad_file(Path::new(title), format!("drawing the figure: {error}"))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::synthetic::{svg_attribute as attribute, svg_polylines};

    #[test]
    fn each_whisker_spans_its_rows_interval_on_the_axis() {
        let figure = IntervalFigure {
            title: "t".into(),
            axis: "effect on legible time (s)".into(),
            rows: vec![
                IntervalRow { label: "a".into(), value: 1.0, interval: Some([0.5, 1.5]) },
                IntervalRow { label: "b".into(), value: -1.0, interval: Some([-2.0, 0.25]) },
                IntervalRow { label: "c".into(), value: 3.0, interval: None },
            ],
        };
        let svg = figure.svg().unwrap();
        if let Some(keep) = std::env::var_os("UFCSR_KEEP_FIGURES") {
            figure.write(&Path::new(&keep).join("interval-figure")).unwrap();
        }
        // Horizontal whiskers in Okabe–Ito blue, in pixels; the caps are vertical.
        let lines: Vec<[(f64, f64); 2]> = svg_polylines(&svg, "#0072B2")
            .into_iter()
            .filter_map(|points| (points.len() == 2).then(|| [points[0], points[1]]))
            .collect();
        let whiskers: Vec<&[(f64, f64); 2]> = lines.iter().filter(|l| l[0].1 == l[1].1).collect();
        assert_eq!(whiskers.len(), 2, "{lines:?}");
        // The axis: the dots' x (value 1.0 and 3.0) give pixels per unit.
        let dots: Vec<f64> = svg
            .split("<polygon")
            .skip(1)
            .filter_map(|tag| {
                let points = attribute(tag, "points")?;
                let xs: Vec<f64> =
                    points.split_whitespace().filter_map(|p| p.split_once(',')?.0.parse().ok()).collect();
                Some(xs.iter().sum::<f64>() / xs.len() as f64)
            })
            .collect();
        assert_eq!(dots.len(), 3, "a dot per row");
        let value = |x: f64| 1.0 + (x - dots[0]) * (3.0 - 1.0) / (dots[2] - dots[0]);
        for (whisker, known) in whiskers.iter().zip([[0.5, 1.5], [-2.0, 0.25]]) {
            let (from, to) = (value(whisker[0].0), value(whisker[1].0));
            assert!(
                (from - known[0]).abs() < 0.02 && (to - known[1]).abs() < 0.02,
                "{from}..{to} vs {known:?}"
            );
        }
        assert!(svg.contains("width=\"181.9mm\""));
    }
}
