//! The study's plot: error against run time, one point per setting.
//!
//! Log time axis, share L1 error (percentage points) against the exact
//! measure of every frame with its 95 % interval over frame offsets as a bar (or, without it, against the
//! finest setting), the precision against the finest setting as hollow grey
//! points, the Pareto front as a line, the recommended setting circled, the
//! tolerance dashed, each point labelled `ppd/step`, and a legend. The time axis has
//! tick labels in seconds at 1, 2, 5 × 10^k (plotters' own log axis left a range
//! inside one decade without any, issue 44 §2), and each interval is a bar with
//! end caps in Okabe–Ito blue. Sized like the analysis plots: two journal
//! columns (181.9 mm) at 300 dpi (`pHYs`), text ≥ 7 pt there, Okabe–Ito
//! colours. Labels need a TrueType font, looked up at run
//! time (`UFCSR_FONT`, else DejaVu Sans where Debian and most distributions
//! put it) so that building needs no fontconfig; without one the SVG is drawn
//! without text and no PNG is written.

use std::path::Path;

use plotters::coord::Shift;
use plotters::coord::combinators::{BindKeyPoints, WithKeyPoints};
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;

use crate::error::{CaptureError, Result};
use crate::study::Study;

/// The font lookup the analyzer's plots use (`UFCSR_FONT`, else DejaVu Sans).
fn font_available() -> bool {
    ufcsr::output::plot_font_available()
}

/// The plot's size, pixels: two journal columns (181.9 mm) at 300 dpi, 2:3 high.
fn size() -> (u32, u32) {
    let width = ufcsr::output::FigureSize::TwoColumns.width_px();
    (width, width * 2 / 3)
}

/// Lengths were laid out on a 900-pixel-wide plot: `v` of those, in figure pixels.
fn px(v: f64) -> i32 {
    (v * f64::from(size().0) / 900.0).round() as i32
}

/// Writes the plot as SVG (its width in millimetres): drawn into a string,
/// written by the file layer (plotters' file backend would write through a
/// link planted at `path`: issue 41).
pub(crate) fn plot_svg(study: &Study, path: &Path) -> Result<()> {
    let text = ufcsr::output::PlotText::available();
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, size()).into_drawing_area();
        draw(study, &root, text)
            .map_err(|e| CaptureError::bad_file(path, format!("drawing the study plot: {e}")))?;
    }
    let svg = ufcsr::output::svg_in_millimetres(&svg, ufcsr::output::FigureSize::TwoColumns, size().1);
    Ok(ufcsr::files::write_bytes_atomically(path, svg.as_bytes())?)
}

/// Writes the plot as PNG (drawn into pixels, encoded and written by the
/// file layer); returns false (and writes nothing) without a font.
pub(crate) fn plot_png(study: &Study, path: &Path) -> Result<bool> {
    if !font_available() {
        return Ok(false);
    }
    let (width, height) = size();
    let mut rgb = vec![0u8; width as usize * height as usize * 3];
    {
        let root = ufcsr::output::KernedBitmap(BitMapBackend::with_buffer(&mut rgb, (width, height)))
            .into_drawing_area();
        draw(study, &root, ufcsr::output::PlotText::Drawn)
            .and_then(|()| root.present().map_err(Into::into))
            .map_err(|e| CaptureError::bad_file(path, format!("drawing the study plot: {e}")))?;
    }
    ufcsr::files::write_figure_png(path, [width, height], &rgb, ufcsr::output::FIGURE_DPI)?;
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
    builder.margin(px(20.0));
    if text == ufcsr::output::PlotText::Drawn {
        let against = if exact { "the exact measure of every frame" } else { "the finest setting" };
        builder
            .caption(
                format!(
                    "Scenario {}, {}: share error against {against} vs run time",
                    study.scenario, study.measure
                ),
                ("sans-serif", ufcsr::output::figure_pt(9.0)),
            )
            .x_label_area_size(px(50.0))
            .y_label_area_size(px(70.0));
    }
    let (x0, x1) = (t_min * 0.8, t_max * 1.25);
    let ticks = time_ticks(x0, x1);
    let mut chart =
        builder.build_cartesian_2d((x0..x1).log_scale().with_key_points(ticks.clone()), 0.0..e_max)?;
    let mut mesh = chart.configure_mesh();
    if text == ufcsr::output::PlotText::Drawn {
        let y = if exact {
            "share L1 error vs exact (pp; bars: 95 % interval)"
        } else {
            "share L1 vs finest setting (pp)"
        };
        mesh.x_desc("capture + count time (s, log scale)")
            .y_desc(y)
            .x_labels(ticks.len())
            .x_label_formatter(&|v: &f64| format!("{} s", seconds_label(*v)))
            .label_style(("sans-serif", ufcsr::output::figure_pt(7.5)))
            .axis_desc_style(("sans-serif", ufcsr::output::figure_pt(8.5)))
            .set_all_tick_mark_size(ufcsr::output::figure_mm(1.0));
    } else {
        mesh.disable_x_mesh().disable_y_mesh().x_labels(0).y_labels(0);
    }
    mesh.draw()?;
    let grey = RGBColor(150, 150, 150);
    chart
        .draw_series(DashedLineSeries::new(
            [(x0, study.tolerance_pp), (x1, study.tolerance_pp)],
            px(6.0),
            px(4.0),
            grey.stroke_width(ufcsr::output::figure_stroke(0.7)),
        ))?
        .label(format!("tolerance {} pp", study.tolerance_pp))
        .legend(move |(x, y)| {
            PathElement::new([(x, y), (x + px(18.0), y)], grey.stroke_width(px(1.0) as u32))
        });
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
            .label_font(("sans-serif", ufcsr::output::figure_pt(7.5)))
            .legend_area_size(px(26.0))
            .margin(px(10.0))
            .draw()?;
    }
    root.present()?;
    Ok(())
}

type Chart<'a, B> = ChartContext<'a, B, Cartesian2d<WithKeyPoints<LogCoord<f64>>, RangedCoordf64>>;

/// The colour of the 95 % intervals (Okabe–Ito blue).
const INTERVAL: RGBColor = RGBColor(0, 114, 178);
/// The Pareto front's colour (Okabe–Ito vermillion) and the recommended setting's (bluish green).
const FRONT: RGBColor = RGBColor(213, 94, 0);
const RECOMMENDED: RGBColor = RGBColor(0, 158, 115);
/// The settings off the front (Okabe–Ito sky blue).
const SETTING: RGBColor = RGBColor(86, 180, 233);

/// The intervals' line width, pixels.
fn whisker() -> u32 {
    ufcsr::output::figure_stroke(1.0)
}

/// Tick values of a log time axis from `low` to `high` seconds: 1, 2 and 5
/// × 10^k inside the range; every 1, 1.5, 2–9 × 10^k when that gives fewer than
/// three; and the ends themselves (to two digits) when even that gives fewer than two.
fn time_ticks(low: f64, high: f64) -> Vec<f64> {
    let inside = |mantissas: &[f64]| -> Vec<f64> {
        let (first, last) = (low.log10().floor() as i32 - 1, high.log10().ceil() as i32 + 1);
        let mut ticks: Vec<f64> = (first..=last)
            .flat_map(|k| mantissas.iter().map(move |m| m * 10f64.powi(k)))
            .filter(|t| *t >= low && *t <= high)
            .collect();
        ticks.sort_by(f64::total_cmp);
        ticks
    };
    let ticks = inside(&[1.0, 2.0, 5.0]);
    if ticks.len() >= 3 {
        return ticks;
    }
    let ticks = inside(&[1.0, 1.5, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0]);
    if ticks.len() >= 2 {
        return ticks;
    }
    let round = |v: f64| {
        let scale = 10f64.powi(1 - v.log10().floor() as i32);
        (v * scale).round() / scale
    };
    let (first, last) = (round(low * 1.05), round(high / 1.05));
    let mut ends = vec![first];
    ends.extend(ticks.iter().filter(|t| **t > first && **t < last));
    ends.push(last);
    ends
}

/// Seconds as a tick label: at most three significant digits, no trailing zeros.
fn seconds_label(seconds: f64) -> String {
    let decimals = (2 - seconds.abs().max(1e-9).log10().floor() as i32).clamp(0, 6) as usize;
    let text = format!("{seconds:.decimals$}");
    if text.contains('.') { text.trim_end_matches('0').trim_end_matches('.').to_string() } else { text }
}

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
        study.rows.iter().zip(times).map(|(r, &t)| {
            Circle::new((t, r.precision.share_l1_pp), px(3.0), grey.stroke_width(px(1.0) as u32))
        });
    chart
        .draw_series(points)?
        .label("precision: vs finest setting")
        .legend(move |(x, y)| Circle::new((x + px(9.0), y), px(3.0), grey.stroke_width(px(1.0) as u32)));
    let bars: Vec<[(f64, f64); 2]> = study
        .rows
        .iter()
        .zip(times)
        .filter_map(|(row, &t)| row.error_vs_exact.as_ref().map(|e| [(t, e.ci95_pp[0]), (t, e.ci95_pp[1])]))
        .collect();
    chart
        .draw_series(bars.iter().map(|bar| PathElement::new(*bar, INTERVAL.stroke_width(whisker()))))?
        .label("95 % interval over frame offsets")
        .legend(|(x, y)| {
            PathElement::new(
                [(x + px(9.0), y - px(6.0)), (x + px(9.0), y + px(6.0))],
                INTERVAL.stroke_width(whisker()),
            )
        });
    // End caps each side of each end (in the plotting area's pixels).
    let area = chart.plotting_area().strip_coord_spec();
    let base = chart.plotting_area().get_base_pixel();
    for bar in &bars {
        for end in bar {
            let (x, y) = chart.backend_coord(end);
            let (x, y) = (x - base.0, y - base.1);
            area.draw(&PathElement::new(
                [(x - px(4.0), y), (x + px(4.0), y)],
                INTERVAL.stroke_width(whisker()),
            ))?;
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
        .draw_series(LineSeries::new(front, FRONT.stroke_width(ufcsr::output::figure_stroke(1.2))))?
        .label("Pareto front")
        .legend(|(x, y)| {
            PathElement::new(
                [(x, y), (x + px(18.0), y)],
                FRONT.stroke_width(ufcsr::output::figure_stroke(1.2)),
            )
        });
    let against = if study.exact.is_some() { "vs exact" } else { "vs finest" };
    chart
        .draw_series(study.rows.iter().zip(times).map(|(r, &t)| {
            let color = if r.pareto { FRONT.filled() } else { SETTING.filled() };
            Circle::new((t, r.ranking_error()), px(4.0), color)
        }))?
        .label(format!("setting, {against} (label ppd/step)"))
        .legend(|(x, y)| Circle::new((x + px(9.0), y), px(4.0), SETTING.filled()));
    if let Some(pick) = &study.recommended {
        let time = pick.seconds.max(1e-3);
        chart
            .draw_series(std::iter::once(Circle::new(
                (time, pick.share_l1_pp),
                px(7.0),
                RECOMMENDED.stroke_width(px(3.0) as u32),
            )))?
            .label(format!("recommended: {}", pick.setting))
            .legend(|(x, y)| {
                Circle::new((x + px(9.0), y), px(6.0), RECOMMENDED.stroke_width(px(3.0) as u32))
            });
    }
    if text == ufcsr::output::PlotText::Drawn {
        for (row, &time) in study.rows.iter().zip(times) {
            chart.draw_series(std::iter::once(Text::new(
                format!("{}/{}", row.ppd, row.frame_step),
                (time, row.ranking_error()),
                ("sans-serif", ufcsr::output::figure_pt(7.0)),
            )))?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::study::tests::{row, study};

    /// The study's SVG as drawn (with labels when a font is found).
    fn svg_of(study: &Study) -> String {
        let mut svg = String::new();
        {
            let root = SVGBackend::with_string(&mut svg, size()).into_drawing_area();
            draw(study, &root, ufcsr::output::PlotText::available()).unwrap();
        }
        svg
    }

    use ufcsr::synthetic::{svg_attribute as attribute, svg_polylines};

    #[test]
    fn each_settings_interval_is_drawn_from_its_low_to_its_high_end() {
        let s = study(
            vec![row(40.0, 4.0, 0.0, Some((2.0, [1.0, 3.0]))), row(20.0, 0.5, 1.0, Some((4.0, [3.5, 6.0])))],
            true,
        );
        let svg = svg_of(&s);
        if let Some(keep) = std::env::var_os("UFCSR_KEEP_FIGURES") {
            plot_png(&s, &std::path::Path::new(&keep).join("study.png")).unwrap();
        }
        // The settings' points (drawn in row order before the legend's) give the y axis's scale.
        let radius = px(4.0).to_string();
        let points: Vec<(f64, f64)> = svg
            .split("<circle")
            .skip(1)
            .filter(|tag| attribute(tag, "r").as_deref() == Some(radius.as_str()))
            .map(|tag| {
                (
                    attribute(tag, "cx").unwrap().parse().unwrap(),
                    attribute(tag, "cy").unwrap().parse().unwrap(),
                )
            })
            .take(2)
            .collect();
        let ys: Vec<f64> = points.iter().map(|p| p.1).collect();
        let value = |y: f64| 2.0 + (y - ys[0]) * (4.0 - 2.0) / (ys[1] - ys[0]);
        // The vertical interval bars, in Okabe–Ito blue.
        let setting_xs: Vec<f64> = points.iter().map(|p| p.0).collect();
        let mut spans: Vec<[f64; 2]> = svg_polylines(&svg, "#0072B2")
            .into_iter()
            .filter_map(|points| {
                // At a setting's time (the legend's sample is elsewhere).
                let at_setting = |x: f64| setting_xs.contains(&x);
                let vertical = points.len() == 2 && points[0].0 == points[1].0 && at_setting(points[0].0);
                vertical.then(|| [value(points[0].1.max(points[1].1)), value(points[0].1.min(points[1].1))])
            })
            .collect();
        spans.sort_by(|a, b| a[0].total_cmp(&b[0]));
        assert_eq!(spans.len(), 2, "{spans:?}");
        for (span, known) in spans.iter().zip([[1.0, 3.0], [3.5, 6.0]]) {
            assert!(
                (span[0] - known[0]).abs() < 0.05 && (span[1] - known[1]).abs() < 0.05,
                "{span:?} vs {known:?}"
            );
        }
    }

    #[test]
    fn the_time_axis_has_tick_labels_in_seconds_even_inside_one_decade() {
        assert_eq!(time_ticks(0.4, 25.0), [0.5, 1.0, 2.0, 5.0, 10.0, 20.0]);
        assert_eq!(time_ticks(0.95, 3.5), [1.0, 1.5, 2.0, 3.0]);
        assert_eq!(time_ticks(1.1, 1.9), [1.2, 1.5, 1.8]);
        assert_eq!(time_ticks(1.6, 1.9), [1.7, 1.8]);
        assert_eq!(time_ticks(0.72, 1.875), [0.8, 0.9, 1.0, 1.5]);
        assert_eq!(["0.5", "1", "20", "1.25"], [0.5, 1.0, 20.0, 1.25].map(seconds_label));
        if !font_available() {
            eprintln!("skipped the drawn labels: no font (set UFCSR_FONT)");
            return;
        }
        // Settings 0.9 s and 1.5 s apart: the axis runs 0.72–1.9 s, inside one decade.
        let s = study(vec![row(40.0, 1.5, 0.0, Some((2.0, [1.0, 3.0]))), row(20.0, 0.9, 1.0, None)], true);
        let svg = svg_of(&s);
        let texts: Vec<&str> = svg
            .split("<text")
            .skip(1)
            .map(|t| t[t.find('>').unwrap() + 1..].split('<').next().unwrap().trim())
            .collect();
        let ticks: Vec<&&str> = texts.iter().filter(|t| t.ends_with(" s") && t.len() < 8).collect();
        assert!(ticks.len() >= 3 && ticks.contains(&&"1 s"), "no time tick labels in {texts:?}");
        assert!(texts.contains(&"capture + count time (s, log scale)"), "{texts:?}");
    }
}
