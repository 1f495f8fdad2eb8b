//! What turns the eight rendered views into figures: flat Lambert shading
//! and outlines so that regions of one colour (the grey of never-seen
//! texels above all) still show their shape, a compass in each view that
//! marks where the pedestrian stood, and the contact sheet with each view's
//! name, a colour bar with ticks and units, and a caption in words.
//!
//! [`write_views`] writes them (`views/NAME.png` and `views.png`); the
//! shading comes from the model's geometry, rasterised here with the
//! CPU z-buffer whichever renderer filled the heatmap's colours, so the CPU
//! views and `ufcsr views` stay alike.

use std::path::{Path, PathBuf};

use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use crate::archive::options::Scale;
use crate::archive::vehicle_model::VehicleModel;
use crate::error::Result;
use crate::optics::vector::{dot, normalize};
use crate::output::figure::{FigureSize, MIN_TEXT_PT};
use crate::output::heatmap::{plasma, position};
use crate::output::heatmap_views::{
    DIRECTIONS, NEVER_SEEN, ViewCamera, ViewTexture, render_view, view_cameras,
};
use crate::output::legend::TextLayout;
use crate::output::numbers::grouped;
use crate::output::raster::ZBuffer;

const PAPER: [u8; 3] = [255, 255, 255];
/// Share of a colour kept where the light does not reach (the rest is Lambert).
const AMBIENT: f64 = 0.62;
/// Share of a colour kept on outlines (silhouette, part boundaries, creases).
const OUTLINE: f64 = 0.4;
/// Faces meeting at more than this many degrees draw a crease line.
const CREASE_DEG: f64 = 35.0;
/// The pedestrian's marks in the compass.
const PEDESTRIAN: [u8; 3] = [0, 150, 60];

/// The nearest face at every pixel: its part and its normal (towards the
/// viewer); `None` off the vehicle.
fn surface(model: &VehicleModel, camera: &ViewCamera) -> Vec<Option<(usize, [f64; 3])>> {
    let [width, height] = camera.size;
    let mut buffer = ZBuffer::new(width, height);
    let mut nearest = vec![None; (width * height) as usize];
    for (index, part) in model.parts.iter().enumerate() {
        for corners in part.positions.chunks_exact(3) {
            let p = corners.iter().map(|c| c.map(f64::from)).collect::<Vec<_>>();
            let (a, b) = ([0, 1, 2].map(|k| p[1][k] - p[0][k]), [0, 1, 2].map(|k| p[2][k] - p[0][k]));
            let mut normal =
                normalize([a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]);
            if dot(normal, camera.back) < 0.0 {
                normal = normal.map(|c| -c);
            }
            let projected = [0, 1, 2].map(|k| camera.to_picture(corners[k]));
            buffer.triangle(projected, |pixel, _| nearest[pixel] = Some((index, normal)));
        }
    }
    nearest
}

/// Whether the pixel at `here` draws an outline against `there`.
fn is_edge(here: (usize, [f64; 3]), there: Option<(usize, [f64; 3])>) -> bool {
    match there {
        None => true,
        Some((part, normal)) => part != here.0 || dot(normal, here.1) < CREASE_DEG.to_radians().cos(),
    }
}

/// Shades the heatmap's colours with a light from the viewer's upper left
/// and darkens outlines.
fn shade(rgb: &mut [u8], model: &VehicleModel, camera: &ViewCamera) {
    let [width, height] = camera.size.map(|s| s as usize);
    let light =
        normalize([0, 1, 2].map(|k| 0.6 * camera.back[k] + 0.6 * camera.up[k] - 0.4 * camera.right[k]));
    let nearest = surface(model, camera);
    for y in 0..height {
        for x in 0..width {
            let pixel = y * width + x;
            let Some(here) = nearest[pixel] else { continue };
            let neighbours = [(x > 0, pixel.wrapping_sub(1)), (x + 1 < width, pixel + 1)]
                .into_iter()
                .chain([(y > 0, pixel.wrapping_sub(width)), (y + 1 < height, pixel + width)]);
            let edge = neighbours.into_iter().any(|(inside, other)| !inside || is_edge(here, nearest[other]));
            let factor = if edge { OUTLINE } else { AMBIENT + (1.0 - AMBIENT) * dot(here.1, light).max(0.0) };
            for channel in &mut rgb[pixel * 3..pixel * 3 + 3] {
                *channel = (f64::from(*channel) * factor).round() as u8;
            }
        }
    }
}

/// A point on the compass: `azimuth_deg` counter-clockwise from the
/// vehicle's front, which points up; `reach` in radii.
fn compass_point(centre: (i32, i32), radius: f64, azimuth_deg: f64, reach: f64) -> (i32, i32) {
    let (sin, cos) = azimuth_deg.to_radians().sin_cos();
    (centre.0 - (sin * radius * reach).round() as i32, centre.1 - (cos * radius * reach).round() as i32)
}

/// The compass in a view's top-right corner, seen from above with the
/// vehicle's front up: the vehicle, this view's line of sight (black) and,
/// in green, a dot on the rim for every frame's direction of the pedestrian.
fn draw_compass(rgb: &mut [u8], camera: &ViewCamera, azimuths: &[f64], scale: u32) {
    let [width, height] = camera.size;
    let radius = f64::from(26 * scale);
    let centre = ((width - 34 * scale) as i32, (34 * scale) as i32);
    let root = BitMapBackend::with_buffer(rgb, (width, height)).into_drawing_area();
    let grey = RGBColor(150, 150, 150);
    let stroke = scale.max(1);
    let (half_length, half_width) = ((radius * 0.45) as i32, (radius * 0.2) as i32);
    let pedestrian = RGBColor(PEDESTRIAN[0], PEDESTRIAN[1], PEDESTRIAN[2]);
    let mut drawn = root
        .draw(&Circle::new(centre, radius as i32, grey.stroke_width(stroke)))
        .and(root.draw(&Rectangle::new(
            [
                (centre.0 - half_width, centre.1 - half_length),
                (centre.0 + half_width, centre.1 + half_length),
            ],
            grey.filled(),
        )))
        .and(root.draw(&PathElement::new(
            vec![centre, compass_point(centre, radius, camera.azimuth_deg, 1.0)],
            BLACK.stroke_width(stroke),
        )));
    for &azimuth in azimuths {
        let at = compass_point(centre, radius, azimuth, 1.0);
        drawn = drawn.and(root.draw(&Circle::new(at, (2 * scale) as i32, pedestrian.filled())));
    }
    // Marks are a courtesy: a drawing error leaves the picture as it is.
    let _ = drawn.and(root.present());
}

/// Shades a rendered view and adds its compass (when the pedestrian's
/// directions are known): what `views/NAME.png` shows.
pub(crate) fn finish_view(rgb: &mut [u8], model: &VehicleModel, camera: &ViewCamera, texture: &ViewTexture) {
    shade(rgb, model, camera);
    if !texture.pedestrian_azimuths_deg.is_empty() {
        draw_compass(rgb, camera, &texture.pedestrian_azimuths_deg, texture.views_scale.max(1));
    }
}

/// Counts worth a tick on the colour bar, from 0 to `max`: round numbers
/// (1, 2 or 5 times a power of ten apart) on a linear scale, 0 and powers
/// of ten on a log scale; `max` itself always.
pub fn bar_ticks(max: u32, scale: Scale) -> Vec<u32> {
    let mut ticks = vec![0];
    if max == 0 {
        return ticks;
    }
    match scale {
        Scale::Linear => {
            let rough = f64::from(max) / 5.0;
            let power = 10f64.powf(rough.log10().floor());
            let step =
                [1.0, 2.0, 5.0, 10.0].into_iter().map(|m| m * power).find(|s| *s >= rough).unwrap_or(rough);
            let step = (step.round() as u32).max(1);
            ticks.extend((1..).map(|k| k * step).take_while(|&t| t * 10 < max * 9));
        }
        Scale::Log => ticks.extend((0..10).map(|k| 10u32.pow(k)).take_while(|&t| t * 10 < max * 7)),
    }
    ticks.push(max);
    ticks
}

/// The contact sheet: the views four by two, each named, and the colour
/// bar with ticks, units and the caption underneath. Returns RGB and size.
/// Its text is sized to print at least 7 pt when the sheet is printed two
/// journal columns (183 mm) wide, as `views.pdf` is ([`sheet_text_px`]).
pub(crate) fn contact_sheet(
    pictures: &[Vec<u8>],
    cameras: &[ViewCamera],
    texture: &ViewTexture,
) -> (Vec<u8>, [u32; 2]) {
    let [width, height] = cameras.first().map_or([1, 1], |camera| camera.size);
    let scale = texture.views_scale.max(1);
    let sheet_width = width * 4;
    let bar = ColorBar::new(sheet_width, height * 2, scale);
    let band = band_text(sheet_width, texture, &bar);
    let sheet_height = band.bottom;
    let mut sheet = PAPER.repeat((sheet_width * sheet_height) as usize);
    for (index, rgb) in pictures.iter().enumerate() {
        let (column, row) = (index as u32 % 4, index as u32 / 4);
        for y in 0..height {
            let from = (y * width * 3) as usize;
            let to = (((row * height + y) * sheet_width + column * width) * 3) as usize;
            sheet[to..to + (width * 3) as usize].copy_from_slice(&rgb[from..from + (width * 3) as usize]);
        }
    }
    bar.paint(&mut sheet, sheet_width);
    if crate::output::plots::font_available() {
        label_sheet(&mut sheet, [sheet_width, sheet_height], [width, height], texture, &bar, &band);
    }
    (sheet, [sheet_width, sheet_height])
}

/// The plotters text size of a contact sheet `sheet_width` pixels wide:
/// 7 pt when printed 183 mm wide (27 at the default 1600 × scale pixels).
pub fn sheet_text_px(sheet_width: u32) -> f64 {
    crate::output::legend::text_px_for(MIN_TEXT_PT, sheet_width, FigureSize::TwoColumns.width_mm()).ceil()
}

/// The paragraphs under the colour bar's numbers (caption with the bar's
/// unit, the compass key), wrapped to the sheet's width, and where the
/// sheet ends.
struct BandText {
    numbers_y: u32,
    text: TextLayout,
    bottom: u32,
}

fn band_text(sheet_width: u32, texture: &ViewTexture, bar: &ColorBar) -> BandText {
    let scale = bar.scale;
    let mut text = TextLayout::new(sheet_text_px(sheet_width));
    let numbers_y = bar.strip().end + 6 * scale;
    let margin = 12 * scale;
    let room = f64::from(sheet_width - 2 * margin);
    let scale_name = match texture.options.scale {
        Scale::Linear => "linear",
        Scale::Log => "log",
    };
    let caption = format!("{}. Colour bar: {} ({scale_name} scale).", texture.caption, texture.unit);
    let mut y = text.paragraph(&caption, margin, numbers_y + text.line() + 4 * scale, room);
    if !texture.pedestrian_azimuths_deg.is_empty() {
        let key = "Compass (top right of each view): the vehicle from above, front up; black = this view's line \
                   of sight, green = where the pedestrian was, one dot per frame.";
        y = text.paragraph(key, margin, y, room);
    }
    BandText { numbers_y, text, bottom: y + 8 * scale }
}

/// Where the colour bar lies on the sheet.
struct ColorBar {
    scale: u32,
    top: u32,
    /// The never-seen swatch: from the margin to here.
    grey_end: u32,
    /// The plasma scale's first and last pixel columns.
    start: u32,
    end: u32,
}

impl ColorBar {
    fn new(sheet_width: u32, top: u32, scale: u32) -> ColorBar {
        let margin = 12 * scale;
        // Wide enough for "never seen" under it at the sheet's text size.
        let grey_end = margin + sheet_width / 9;
        ColorBar {
            scale,
            top: top + 8 * scale,
            grey_end,
            start: grey_end + 10 * scale,
            end: sheet_width - margin - 1,
        }
    }

    fn strip(&self) -> std::ops::Range<u32> {
        self.top..self.top + 16 * self.scale
    }

    fn x_of(&self, at: f64) -> u32 {
        self.start + (at * f64::from(self.end - self.start)).round() as u32
    }

    fn paint(&self, sheet: &mut [u8], sheet_width: u32) {
        for y in self.strip() {
            for x in 12 * self.scale..=self.end {
                let color = if x < self.grey_end {
                    NEVER_SEEN
                } else if x < self.start {
                    PAPER
                } else {
                    plasma(f64::from(x - self.start) / f64::from(self.end - self.start))
                };
                let i = ((y * sheet_width + x) * 3) as usize;
                sheet[i..i + 3].copy_from_slice(&color);
            }
        }
    }
}

/// A colour-bar number of a measured quantity: four significant digits at
/// most, trailing zeros dropped (the ticks are round values, the maximum
/// is not).
pub(crate) fn tick_value(value: f64) -> String {
    if value == 0.0 {
        return "0".to_string();
    }
    let decimals = (3 - value.abs().log10().floor() as i32).clamp(0, 12) as usize;
    let text = format!("{value:.decimals$}");
    if text.contains('.') { text.trim_end_matches('0').trim_end_matches('.').to_string() } else { text }
}

/// Each view's name, the bar's ticks and numbers, and the band's
/// paragraphs (kerned text, [`crate::output::figure::KernedBitmap`]).
fn label_sheet(
    sheet: &mut [u8],
    size: [u32; 2],
    view: [u32; 2],
    texture: &ViewTexture,
    bar: &ColorBar,
    band: &BandText,
) {
    let scale = bar.scale;
    {
        let backend =
            crate::output::figure::KernedBitmap(BitMapBackend::with_buffer(sheet, (size[0], size[1])));
        let root = backend.into_drawing_area();
        let style = ("sans-serif", band.text.size).into_font().color(&BLACK);
        let mut drawn: std::result::Result<(), _> = Ok(());
        for (index, (name, _)) in DIRECTIONS.iter().enumerate() {
            let (column, row) = (index as u32 % 4, index as u32 / 4);
            let at = ((column * view[0] + 6 * scale) as i32, (row * view[1] + 4 * scale) as i32);
            drawn = drawn.and(root.draw(&Text::new((*name).to_string(), at, style.clone())));
        }
        let max = texture.max();
        let strip_end = bar.strip().end;
        let numbers_y = band.numbers_y as i32;
        let centred = style.clone().pos(Pos::new(HPos::Center, VPos::Top));
        for count in bar_ticks(max, texture.options.scale) {
            let x = bar.x_of(position(count, max, texture.options.scale)) as i32;
            let tick = PathElement::new(
                vec![(x, strip_end as i32), (x, (strip_end + 4 * scale) as i32)],
                BLACK.stroke_width(scale),
            );
            let number = match texture.quantum {
                Some(quantum) => tick_value(f64::from(count) * quantum),
                None => grouped(u64::from(count)),
            };
            // The top's number ends at the bar's end, inside the sheet.
            let anchor = if count == max && count > 0 {
                style.clone().pos(Pos::new(HPos::Right, VPos::Top))
            } else {
                centred.clone()
            };
            drawn = drawn.and(root.draw(&tick)).and(root.draw(&Text::new(number, (x, numbers_y), anchor)));
        }
        drawn = drawn
            .and(root.draw(&Text::new("never seen", ((12 * scale) as i32, numbers_y), style.clone())))
            .and(root.present());
        // Labels are a courtesy: a drawing error leaves the colours as they are.
        let _ = drawn;
    }
    band.text.draw(sheet, size);
}

/// The files [`write_views`] wrote.
#[derive(Debug, Clone)]
pub struct WrittenViews {
    pub contact_sheet: PathBuf,
    pub views: Vec<PathBuf>,
    /// `views.pdf`: the contact sheet for a paper, 183 mm wide.
    pub pdf: PathBuf,
}

/// The contact sheet as a PDF, printed two journal columns (183 mm) wide,
/// its text ≥ 7 pt there.
pub const VIEWS_PDF_FILE: &str = "views.pdf";

/// Writes `dir/views/NAME.png` for the eight directions and `dir/views.png`,
/// drawn with the CPU renderer ([`render_view`]).
pub fn write_views(model: &VehicleModel, texture: &ViewTexture, dir: &Path) -> Result<WrittenViews> {
    write_sheet_and_views(model, texture, dir, SingleViews::Written)
}

/// Whether each view is also written alone (`views/NAME.png`) beside the
/// sheet: an analysis writes them only with `--figures all` (issue 45 §5),
/// `ufcsr views` always.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum SingleViews {
    Written,
    Omitted,
}

/// [`write_views`], each view written alone or not.
pub(crate) fn write_sheet_and_views(
    model: &VehicleModel,
    texture: &ViewTexture,
    dir: &Path,
    singles: SingleViews,
) -> Result<WrittenViews> {
    // The views are independent: drawn on all cores, then handed over in order.
    use rayon::prelude::*;
    let cameras = view_cameras(model, texture.views_scale);
    let mut drawn: Vec<Vec<u8>> =
        cameras.par_iter().map(|camera| render_view(model, texture, camera)).collect();
    drawn.reverse();
    let render = |_: &ViewCamera| Ok(drawn.pop().unwrap_or_default());
    finish_views(model, texture, (dir, singles), &cameras, render)
}

/// The views of [`write_views`] for `cameras` ([`view_cameras`], computed
/// once by the caller): `render` draws one camera's picture (RGB,
/// `camera.size`, rows top to bottom), the heatmap's colours unlit; shading,
/// outlines, the pedestrian marker, the sheet and its colour bar are drawn
/// here, on all cores.
fn finish_views(
    model: &VehicleModel,
    texture: &ViewTexture,
    (dir, singles): (&Path, SingleViews),
    cameras: &[ViewCamera],
    mut render: impl FnMut(&ViewCamera) -> Result<Vec<u8>>,
) -> Result<WrittenViews> {
    use rayon::prelude::*;
    let views_dir = dir.join("views");
    if singles == SingleViews::Written {
        crate::files::real_dir(&views_dir)?;
    }
    let mut drawn = Vec::with_capacity(cameras.len());
    for camera in cameras {
        let [width, height] = camera.size;
        let rgb = render(camera)?;
        if rgb.len() != (width * height * 3) as usize {
            return Err(crate::error::Error::bad_file(
                &views_dir,
                format!("the {} view has {} bytes, not {width}×{height} RGB", camera.name, rgb.len()),
            ));
        }
        drawn.push(rgb);
    }
    let finished: Vec<(PathBuf, Vec<u8>)> = cameras
        .par_iter()
        .zip(drawn)
        .map(|(camera, mut rgb)| {
            finish_view(&mut rgb, model, camera, texture);
            let path = views_dir.join(format!("{}.png", camera.name));
            if singles == SingleViews::Written {
                let [width, height] = camera.size;
                crate::files::write_figure_png(&path, [width, height], &rgb, crate::output::figure::DPI)?;
            }
            Ok((path, rgb))
        })
        .collect::<Result<_>>()?;
    let (mut views, pictures): (Vec<PathBuf>, Vec<Vec<u8>>) = finished.into_iter().unzip();
    if singles == SingleViews::Omitted {
        views.clear();
    }
    let (sheet, [sheet_width, sheet_height]) = contact_sheet(&pictures, cameras, texture);
    let contact_sheet = dir.join("views.png");
    let width_mm = FigureSize::TwoColumns.width_mm();
    // The sheet says the resolution that prints it as views.pdf does (183 mm).
    let dpi = f64::from(sheet_width) / (width_mm / 25.4);
    crate::files::write_figure_png(&contact_sheet, [sheet_width, sheet_height], &sheet, dpi)?;
    let pdf = dir.join(VIEWS_PDF_FILE);
    let title = "The heatmap on the vehicle from eight directions";
    crate::output::pdf::write_image_pdf(&pdf, &sheet, [sheet_width, sheet_height], width_mm, title)?;
    Ok(WrittenViews { contact_sheet, views, pdf })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tick_values_of_a_measure_have_four_significant_digits_at_most() {
        assert_eq!(tick_value(0.0), "0");
        assert_eq!(tick_value(0.002), "0.002");
        assert_eq!(tick_value(0.0137049), "0.0137");
        assert_eq!(tick_value(12.5), "12.5");
        assert_eq!(tick_value(24_000.0), "24000");
    }

    #[test]
    fn bar_ticks_are_round_counts_ending_at_the_maximum() {
        assert_eq!(bar_ticks(0, Scale::Linear), [0]);
        assert_eq!(bar_ticks(24, Scale::Linear), [0, 5, 10, 15, 20, 24]);
        assert_eq!(bar_ticks(1000, Scale::Linear), [0, 200, 400, 600, 800, 1000]);
        assert_eq!(bar_ticks(3, Scale::Linear), [0, 1, 2, 3]);
        assert_eq!(bar_ticks(5000, Scale::Log), [0, 1, 10, 100, 1000, 5000]);
    }
}
