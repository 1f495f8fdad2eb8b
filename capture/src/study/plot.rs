//! The study's plot: error against run time, one point per setting.
//!
//! Log time axis, share L1 error (percentage points) against the reference,
//! the Pareto front as a line, the tolerance as a dashed line, each point
//! labelled with its setting. Labels need a TrueType font, looked up at run
//! time (`UFCSR_FONT`, else DejaVu Sans where Debian and most distributions
//! put it) so that building needs no fontconfig; without one the SVG is drawn
//! without text and no PNG is written.

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use crate::error::{CaptureError, Result};
use crate::study::Study;

/// The font lookup the analyzer's plots use (`UFCSR_FONT`, else DejaVu Sans).
fn font_available() -> bool {
    ufcsr::plot_font_available()
}

/// Writes the plot as SVG.
pub fn plot_svg(study: &Study, path: &Path) -> Result<()> {
    let text = font_available();
    let root = SVGBackend::new(path, (900, 600)).into_drawing_area();
    draw(study, &root, text)
        .map_err(|e| CaptureError::bad_input(path, format!("drawing the study plot: {e}")))
}

/// Writes the plot as PNG; returns false (and writes nothing) without a font.
pub fn plot_png(study: &Study, path: &Path) -> Result<bool> {
    if !font_available() {
        return Ok(false);
    }
    let root = BitMapBackend::new(path, (900, 600)).into_drawing_area();
    draw(study, &root, true)
        .map_err(|e| CaptureError::bad_input(path, format!("drawing the study plot: {e}")))?;
    Ok(true)
}

fn draw<B: DrawingBackend>(
    study: &Study,
    root: &DrawingArea<B, Shift>,
    text: bool,
) -> std::result::Result<(), Box<dyn std::error::Error>>
where
    B::ErrorType: 'static,
{
    root.fill(&WHITE)?;
    let times: Vec<f64> = study.rows.iter().map(|r| r.seconds.max(1e-3)).collect();
    let errors: Vec<f64> = study.rows.iter().map(|r| r.error.share_l1_pp).collect();
    let (t_min, t_max) = times.iter().fold((f64::MAX, f64::MIN), |(lo, hi), &t| (lo.min(t), hi.max(t)));
    let e_max = errors.iter().copied().fold(study.tolerance_pp, f64::max) * 1.1 + 0.1;
    let mut builder = ChartBuilder::on(root);
    builder.margin(20);
    if text {
        builder
            .caption(
                format!(
                    "Scenario {}: share error against run time (reference {})",
                    study.scenario, study.reference
                ),
                ("sans-serif", 20),
            )
            .x_label_area_size(45)
            .y_label_area_size(60);
    }
    let mut chart = builder.build_cartesian_2d((t_min * 0.8..t_max * 1.25).log_scale(), 0.0..e_max)?;
    let mut mesh = chart.configure_mesh();
    if text {
        mesh.x_desc("capture + count, seconds (log)").y_desc("share L1 error vs reference, pp");
    } else {
        mesh.disable_x_mesh().disable_y_mesh().x_labels(0).y_labels(0);
    }
    mesh.draw()?;
    // Tolerance.
    chart.draw_series(DashedLineSeries::new(
        [(t_min * 0.8, study.tolerance_pp), (t_max * 1.25, study.tolerance_pp)],
        6,
        4,
        RGBColor(150, 150, 150).stroke_width(1),
    ))?;
    // Pareto front, in time order.
    let mut front: Vec<(f64, f64)> = study
        .rows
        .iter()
        .zip(&times)
        .filter(|(r, _)| r.pareto)
        .map(|(r, &t)| (t, r.error.share_l1_pp))
        .collect();
    front.sort_by(|a, b| a.0.total_cmp(&b.0));
    chart.draw_series(LineSeries::new(front, RED.stroke_width(2)))?;
    for (index, (row, &time)) in study.rows.iter().zip(&times).enumerate() {
        let colour = if Some(index) == study.cheapest_within_tolerance {
            GREEN.filled()
        } else if row.pareto {
            RED.filled()
        } else {
            BLUE.mix(0.6).filled()
        };
        chart.draw_series(std::iter::once(Circle::new((time, row.error.share_l1_pp), 4, colour)))?;
        if text {
            chart.draw_series(std::iter::once(Text::new(
                format!("{}/{}", row.ppd, row.frame_step),
                (time, row.error.share_l1_pp),
                ("sans-serif", 11),
            )))?;
        }
    }
    root.present()?;
    Ok(())
}
