//! The study's plot: error against run time, one point per setting.
//!
//! Log time axis, share L1 error (percentage points) against the exact
//! measure of every frame with its 95 % interval over frame offsets as a bar (or, without it, against the
//! finest setting), the precision against the finest setting as hollow grey
//! points, the Pareto front as a line, the recommended setting circled, the
//! tolerance dashed, each point labelled `ppd/step`, and a legend. Labels need a TrueType font, looked up at run
//! time (`UFCSR_FONT`, else DejaVu Sans where Debian and most distributions
//! put it) so that building needs no fontconfig; without one the SVG is drawn
//! without text and no PNG is written.

use std::path::Path;

use plotters::coord::Shift;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;

use crate::error::{CaptureError, Result};
use crate::study::Study;

/// The font lookup the analyzer's plots use (`UFCSR_FONT`, else DejaVu Sans).
fn font_available() -> bool {
    ufcsr::output::plot_font_available()
}

/// The plot's size, pixels.
const SIZE: (u32, u32) = (900, 600);

/// Writes the plot as SVG: drawn into a string, written by the file layer
/// (plotters' file backend would write through a link planted at `path`:
/// issue 41).
pub fn plot_svg(study: &Study, path: &Path) -> Result<()> {
    let text = ufcsr::output::PlotText::available();
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, SIZE).into_drawing_area();
        draw(study, &root, text)
            .map_err(|e| CaptureError::bad_file(path, format!("drawing the study plot: {e}")))?;
    }
    Ok(ufcsr::files::write_bytes_atomically(path, svg.as_bytes())?)
}

/// Writes the plot as PNG (drawn into pixels, encoded and written by the
/// file layer); returns false (and writes nothing) without a font.
pub fn plot_png(study: &Study, path: &Path) -> Result<bool> {
    if !font_available() {
        return Ok(false);
    }
    let mut rgb = vec![0u8; SIZE.0 as usize * SIZE.1 as usize * 3];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, SIZE).into_drawing_area();
        draw(study, &root, ufcsr::output::PlotText::Drawn)
            .and_then(|()| root.present().map_err(Into::into))
            .map_err(|e| CaptureError::bad_file(path, format!("drawing the study plot: {e}")))?;
    }
    ufcsr::files::write_rgb_png(path, [SIZE.0, SIZE.1], &rgb, png::Compression::Fast)?;
    Ok(true)
}

fn draw<B: DrawingBackend>(
    study: &Study,
    root: &DrawingArea<B, Shift>,
    text: ufcsr::output::PlotText,
) -> std::result::Result<(), Box<dyn std::error::Error>>
where
    B::ErrorType: 'static,
{
    root.fill(&WHITE)?;
    let times: Vec<f64> = study.rows.iter().map(|r| r.seconds.max(1e-3)).collect();
    let errors: Vec<f64> = study.rows.iter().map(|r| r.ranking_error()).collect();
    let highs = study.rows.iter().map(|r| r.error_vs_exact.as_ref().map_or(0.0, |e| e.ci95_pp[1]));
    let precisions = study.rows.iter().map(|r| r.precision.share_l1_pp);
    let (t_min, t_max) = times.iter().fold((f64::MAX, f64::MIN), |(lo, hi), &t| (lo.min(t), hi.max(t)));
    let e_max =
        errors.iter().copied().chain(highs).chain(precisions).fold(study.tolerance_pp, f64::max) * 1.1 + 0.1;
    let exact = study.exact.is_some();
    let mut builder = ChartBuilder::on(root);
    builder.margin(20);
    if text == ufcsr::output::PlotText::Drawn {
        let against = if exact { "the exact measure of every frame" } else { "the finest setting" };
        builder
            .caption(
                format!(
                    "Scenario {}, {}: share error against {against} vs run time",
                    study.scenario, study.measure
                ),
                ("sans-serif", 20),
            )
            .x_label_area_size(50)
            .y_label_area_size(70);
    }
    let (x0, x1) = (t_min * 0.8, t_max * 1.25);
    let mut chart = builder.build_cartesian_2d((x0..x1).log_scale(), 0.0..e_max)?;
    let mut mesh = chart.configure_mesh();
    if text == ufcsr::output::PlotText::Drawn {
        let y =
            if exact { "share L1 error vs exact, pp (bars: 95 %)" } else { "share L1 vs finest setting, pp" };
        mesh.x_desc("capture + count, seconds (log scale)")
            .y_desc(y)
            .label_style(("sans-serif", 14))
            .axis_desc_style(("sans-serif", 16));
    } else {
        mesh.disable_x_mesh().disable_y_mesh().x_labels(0).y_labels(0);
    }
    mesh.draw()?;
    let grey = RGBColor(150, 150, 150);
    chart
        .draw_series(DashedLineSeries::new(
            [(x0, study.tolerance_pp), (x1, study.tolerance_pp)],
            6,
            4,
            grey.stroke_width(1),
        ))?
        .label(format!("tolerance {} pp", study.tolerance_pp))
        .legend(move |(x, y)| PathElement::new([(x, y), (x + 18, y)], grey));
    if exact {
        draw_precision_and_intervals(study, &mut chart, &times)?;
    }
    draw_front_and_points(study, &mut chart, &times, text)?;
    if text == ufcsr::output::PlotText::Drawn {
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperRight)
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .label_font(("sans-serif", 14))
            .draw()?;
    }
    root.present()?;
    Ok(())
}

type Chart<'a, B> = ChartContext<'a, B, Cartesian2d<LogCoord<f64>, RangedCoordf64>>;

/// The precision (against the finest setting) as hollow grey points, and
/// each setting's 95 % interval against the exact measure as a bar.
fn draw_precision_and_intervals<B: DrawingBackend>(
    study: &Study,
    chart: &mut Chart<'_, B>,
    times: &[f64],
) -> std::result::Result<(), Box<dyn std::error::Error>>
where
    B::ErrorType: 'static,
{
    let grey = RGBColor(150, 150, 150);
    let points =
        study.rows.iter().zip(times).map(|(r, &t)| Circle::new((t, r.precision.share_l1_pp), 3, grey));
    chart
        .draw_series(points)?
        .label("precision: vs finest setting")
        .legend(move |(x, y)| Circle::new((x + 9, y), 3, grey));
    for (row, &t) in study.rows.iter().zip(times) {
        if let Some(e) = &row.error_vs_exact {
            let bar = [(t, e.ci95_pp[0]), (t, e.ci95_pp[1])];
            chart.draw_series(std::iter::once(PathElement::new(bar, BLUE.mix(0.5).stroke_width(1))))?;
        }
    }
    Ok(())
}

/// The Pareto front, every setting (labelled `ppd/step`) and the recommended one.
fn draw_front_and_points<B: DrawingBackend>(
    study: &Study,
    chart: &mut Chart<'_, B>,
    times: &[f64],
    text: ufcsr::output::PlotText,
) -> std::result::Result<(), Box<dyn std::error::Error>>
where
    B::ErrorType: 'static,
{
    let mut front: Vec<(f64, f64)> = study
        .rows
        .iter()
        .zip(times)
        .filter(|(r, _)| r.pareto)
        .map(|(r, &t)| (t, r.ranking_error()))
        .collect();
    front.sort_by(|a, b| a.0.total_cmp(&b.0));
    chart
        .draw_series(LineSeries::new(front, RED.stroke_width(2)))?
        .label("Pareto front")
        .legend(|(x, y)| PathElement::new([(x, y), (x + 18, y)], RED.stroke_width(2)));
    let against = if study.exact.is_some() { "vs exact" } else { "vs finest" };
    chart
        .draw_series(study.rows.iter().zip(times).map(|(r, &t)| {
            let color = if r.pareto { RED.filled() } else { BLUE.mix(0.7).filled() };
            Circle::new((t, r.ranking_error()), 4, color)
        }))?
        .label(format!("setting, {against} (label ppd/step)"))
        .legend(|(x, y)| Circle::new((x + 9, y), 4, BLUE.mix(0.7).filled()));
    if let Some(pick) = &study.recommended {
        let time = pick.seconds.max(1e-3);
        chart
            .draw_series(std::iter::once(Circle::new((time, pick.share_l1_pp), 7, GREEN.stroke_width(3))))?
            .label(format!("recommended: {}", pick.setting))
            .legend(|(x, y)| Circle::new((x + 9, y), 6, GREEN.stroke_width(3)));
    }
    if text == ufcsr::output::PlotText::Drawn {
        for (row, &time) in study.rows.iter().zip(times) {
            chart.draw_series(std::iter::once(Text::new(
                format!("{}/{}", row.ppd, row.frame_step),
                (time, row.ranking_error()),
                ("sans-serif", 12),
            )))?;
        }
    }
    Ok(())
}
