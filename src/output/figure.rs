//! Figures for a paper (issue 35 item 2): the plots are drawn once, in
//! figure pixels at 300 dpi, for a journal column width ([`FigureSize`]:
//! one column 88.9 mm, two columns 181.9 mm — IEEE's column and text
//! widths, which also fit Elsevier's 90 and 190 mm) with every text size given in
//! points, so that text is ≥ 7 pt at the size the figure is printed; and
//! written three ways — PNG (300 dpi, kerned text: plotters' own ab_glyph
//! drawing drops each glyph's side bearing, "fen der_righ t"), SVG (real
//! text, its width in millimetres) and PDF (vector, real text in the same
//! font, embedded as a subset, through [`crate::output::pdf`]).
//!
//! Series are told apart by the Okabe–Ito palette (colour-blind safe) AND
//! by a marker shape and a dash pattern each, so they survive greyscale.

use std::sync::OnceLock;

use ab_glyph::{Font as _, FontRef, PxScale, ScaleFont as _, point};
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters_backend::{
    BackendColor, BackendCoord, BackendStyle, BackendTextStyle, DrawingErrorKind, text_anchor::HPos,
    text_anchor::VPos,
};

/// Figure pixels per inch (the PNG's resolution at the printed size).
pub const DPI: f64 = 300.0;
/// Millimetres per point (1/72 inch).
pub const MM_PER_PT: f64 = 25.4 / 72.0;
/// The smallest text a figure may have at its printed size, in points.
pub const MIN_TEXT_PT: f64 = 7.0;

/// A printed figure width: one or two journal columns, each the narrower of
/// IEEE's and Elsevier's (IEEE 88.9 / 181.9 mm, Elsevier 90 / 190 mm), so
/// one file fits both publishers unscaled (issue 44 §2).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FigureSize {
    /// 88.9 mm: IEEE's column (3.5 in), inside Elsevier's 90 mm.
    OneColumn,
    /// 181.9 mm: IEEE's text width (7.16 in), inside Elsevier's 190 mm.
    TwoColumns,
}

impl FigureSize {
    /// Both sizes, the default (two columns) first.
    pub const ALL: [FigureSize; 2] = [FigureSize::TwoColumns, FigureSize::OneColumn];

    /// The printed width.
    pub fn width_mm(self) -> f64 {
        match self {
            FigureSize::OneColumn => ONE_COLUMN_MM,
            FigureSize::TwoColumns => TWO_COLUMNS_MM,
        }
    }

    /// The file name's suffix (`parts.svg`, `parts-1col.svg`).
    pub fn suffix(self) -> &'static str {
        match self {
            FigureSize::OneColumn => "-1col",
            FigureSize::TwoColumns => "",
        }
    }

    /// The width in figure pixels: rounded down, so the printed figure is
    /// never wider than the column.
    pub fn width_px(self) -> u32 {
        (self.width_mm() / 25.4 * DPI).floor() as u32
    }
}

/// IEEE's column width (3.5 in); Elsevier's is 90 mm.
pub(crate) const ONE_COLUMN_MM: f64 = 88.9;
/// IEEE's text width (7.16 in); Elsevier's is 190 mm.
pub(crate) const TWO_COLUMNS_MM: f64 = 181.9;

/// Figure pixels in `mm` millimetres.
pub fn mm(mm: f64) -> i32 {
    (mm / 25.4 * DPI).round() as i32
}

/// The plotters font size that prints at `points` (plotters draws a size
/// `s` at an em of `s / 1.24` pixels, as its SVG's `font-size` says).
pub fn pt(points: f64) -> f64 {
    points / 72.0 * DPI * 1.24
}

/// A line `points` wide, in figure pixels.
pub fn stroke(points: f64) -> u32 {
    (points / 72.0 * DPI).round().max(1.0) as u32
}

/// The Okabe–Ito palette (Okabe & Ito 2008), ordered for lines on white:
/// blue, vermillion, bluish green, reddish purple, orange, sky blue, black,
/// yellow.
pub const OKABE_ITO: [[u8; 3]; 8] = [
    [0, 114, 178],
    [213, 94, 0],
    [0, 158, 115],
    [204, 121, 167],
    [230, 159, 0],
    [86, 180, 233],
    [0, 0, 0],
    [240, 228, 66],
];

/// The colour of series `index`.
pub(crate) fn series_color(index: usize) -> RGBColor {
    let [r, g, b] = OKABE_ITO[index % OKABE_ITO.len()];
    RGBColor(r, g, b)
}

/// The dash pattern of series `index`: (dash, gap) in points, `None` solid.
pub(crate) fn series_dash(index: usize) -> Option<(f64, f64)> {
    [None, Some((5.0, 2.5)), Some((1.5, 1.5)), Some((8.0, 2.0))][index % 4]
}

/// The marker outline of series `index` around the origin, `radius` pixels:
/// circle, triangle, square, diamond; filled for the first four series,
/// hollow for the next four.
pub(crate) fn marker_shape(index: usize, radius: i32) -> (Vec<(i32, i32)>, bool) {
    let r = f64::from(radius);
    let polygon = |corners: usize, start_deg: f64| -> Vec<(i32, i32)> {
        (0..corners)
            .map(|k| {
                let angle = (start_deg + 360.0 * k as f64 / corners as f64).to_radians();
                ((r * angle.cos()).round() as i32, (r * angle.sin()).round() as i32)
            })
            .collect()
    };
    let shape = match index % 4 {
        0 => polygon(16, 0.0),
        1 => polygon(3, -90.0),
        2 => polygon(4, 45.0),
        _ => polygon(4, 0.0),
    };
    (shape, (index / 4).is_multiple_of(2))
}

/// Draws series `index`'s marker at `at` (backend pixels) on `area`.
pub(crate) fn draw_marker<B: DrawingBackend>(
    area: &DrawingArea<B, Shift>,
    index: usize,
    at: (i32, i32),
    radius: i32,
) -> DrawResult
where
    B::ErrorType: 'static,
{
    let (shape, filled) = marker_shape(index, radius);
    let color = series_color(index);
    let points: Vec<(i32, i32)> = shape.iter().map(|&(x, y)| (at.0 + x, at.1 + y)).collect();
    if filled {
        area.draw(&Polygon::new(points, color.filled()))?;
    } else {
        area.draw(&Polygon::new(points.clone(), WHITE.filled()))?;
        let mut closed = points;
        closed.push(closed[0]);
        area.draw(&PathElement::new(closed, Color::stroke_width(&color, stroke(0.8))))?;
    }
    Ok(())
}

/// The dashed pieces of the polyline `points` (backend pixels) for a
/// (dash, gap) pattern in pixels; the whole line when `dash` is `None`.
pub(crate) fn dashed(points: &[(i32, i32)], dash: Option<(f64, f64)>) -> Vec<Vec<(i32, i32)>> {
    let Some((on, off)) = dash else { return vec![points.to_vec()] };
    let mut pieces = Vec::new();
    let mut current: Vec<(i32, i32)> = Vec::new();
    // Position inside the pattern, and whether the pen is down.
    let (mut left, mut down) = (on, true);
    for pair in points.windows(2) {
        let (a, b) =
            ((f64::from(pair[0].0), f64::from(pair[0].1)), (f64::from(pair[1].0), f64::from(pair[1].1)));
        let length = ((b.0 - a.0).powi(2) + (b.1 - a.1).powi(2)).sqrt();
        let at = |t: f64| ((a.0 + (b.0 - a.0) * t).round() as i32, (a.1 + (b.1 - a.1) * t).round() as i32);
        let mut travelled = 0.0;
        if down && current.is_empty() {
            current.push(at(0.0));
        }
        while length - travelled > left {
            travelled += left;
            let t = travelled / length.max(1e-9);
            if down {
                current.push(at(t));
                pieces.push(std::mem::take(&mut current));
            } else {
                current.push(at(t));
            }
            down = !down;
            left = if down { on } else { off };
        }
        left -= length - travelled;
        if down {
            current.push(at(1.0));
        }
    }
    if current.len() > 1 {
        pieces.push(current);
    }
    pieces
}

/// Draws series `index`'s line through `points` (backend pixels).
pub(crate) fn draw_series_line<B: DrawingBackend>(
    area: &DrawingArea<B, Shift>,
    index: usize,
    points: &[(i32, i32)],
) -> DrawResult
where
    B::ErrorType: 'static,
{
    let px = DPI / 72.0;
    let dash = series_dash(index).map(|(on, off)| (on * px, off * px));
    let style = Color::stroke_width(&series_color(index), stroke(1.2));
    for piece in dashed(points, dash) {
        area.draw(&PathElement::new(piece, style))?;
    }
    Ok(())
}

/// What drawing a figure returns.
pub(crate) type DrawResult = std::result::Result<(), Box<dyn std::error::Error>>;

/// The TrueType font the figures' text is drawn and measured with, once
/// found ([`font_bytes`]).
static FONT_BYTES: OnceLock<Option<&'static [u8]>> = OnceLock::new();

const FONT_CANDIDATES: [&str; 3] = [
    "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf",
    "/usr/share/fonts/TTF/DejaVuSans.ttf",
    "/usr/share/fonts/dejavu/DejaVuSans.ttf",
];

/// The figures' font (`UFCSR_FONT`, else DejaVu Sans), found and registered
/// with plotters on first use. Measuring text looks it up too, so a layout
/// computed before anything is drawn has real widths (a placement picture
/// laid out first measured every text as 0 px wide: its key ran off the
/// edge and its legend labels overlapped).
pub(crate) fn font_bytes() -> Option<&'static [u8]> {
    *FONT_BYTES.get_or_init(|| {
        let mut candidates: Vec<std::path::PathBuf> =
            std::env::var_os("UFCSR_FONT").map(std::path::PathBuf::from).into_iter().collect();
        candidates.extend(FONT_CANDIDATES.iter().map(std::path::PathBuf::from));
        for path in candidates {
            if let Ok(bytes) = crate::files::read_limited(&path, crate::files::SMALL_INPUT_LIMIT) {
                // plotters keeps fonts for the life of the process.
                let bytes: &'static [u8] = Box::leak(bytes.into_boxed_slice());
                if plotters::style::register_font("sans-serif", FontStyle::Normal, bytes).is_ok() {
                    return Some(bytes);
                }
            }
        }
        None
    })
}

/// The figures' font, parsed (`None` without one): the PNG's rasterizer,
/// the measuring and the PDF's embedded subset all use it.
pub(crate) fn figure_font() -> Option<FontRef<'static>> {
    font_bytes().and_then(|bytes| FontRef::try_from_slice(bytes).ok())
}

/// The box of `text` for anchoring it: the kerned advance width the glyphs
/// are drawn with ([`text_width`]; plotters' own box leaves side bearings
/// out, so right-aligned labels would not end at their anchor) and
/// plotters' height.
pub(crate) fn kerned_text_size<T: BackendTextStyle, E: std::error::Error + Send + Sync>(
    text: &str,
    style: &T,
) -> Result<(u32, u32), DrawingErrorKind<E>> {
    let ((_, top), (_, bottom)) =
        style.layout_box(text).map_err(|e| DrawingErrorKind::FontError(Box::new(e)))?;
    Ok((text_width(text, style.size()).max(0) as u32, (bottom - top).max(0) as u32))
}

/// The glyph coverage of `text` at plotters size `size`, kerned and with each
/// glyph's side bearing, calling `plot(x, y, coverage)` with pixels relative to
/// the left end of the baseline.
pub(crate) fn rasterize_text(text: &str, size: f64, mut plot: impl FnMut(i32, i32, f32)) {
    let Some(font) = figure_font() else { return };
    let scale = PxScale::from(size as f32);
    let scaled = font.as_scaled(scale);
    let mut caret = 0.0f32;
    let mut previous = None;
    for c in text.chars() {
        let id = font.glyph_id(c);
        if let Some(before) = previous {
            caret += scaled.kern(before, id);
        }
        previous = Some(id);
        let glyph = id.with_scale_and_position(scale, point(caret, 0.0));
        if let Some(outline) = font.outline_glyph(glyph) {
            let bounds = outline.px_bounds();
            outline.draw(|x, y, coverage| {
                plot(bounds.min.x as i32 + x as i32, bounds.min.y as i32 + y as i32, coverage);
            });
        }
        caret += scaled.h_advance(id);
    }
}

/// The advance width of `text` at plotters size `size`, kerned, in figure
/// pixels (0 without a font).
pub(crate) fn text_width(text: &str, size: f64) -> i32 {
    let Some(font) = figure_font() else { return 0 };
    let scaled = font.as_scaled(PxScale::from(size as f32));
    let mut width = 0.0f32;
    let mut previous = None;
    for c in text.chars() {
        let id = font.glyph_id(c);
        if let Some(before) = previous {
            width += scaled.kern(before, id);
        }
        previous = Some(id);
        width += scaled.h_advance(id);
    }
    width.ceil() as i32
}

/// The kerned width, in figure pixels, of each prefix of `text` followed by
/// `end` at plotters size `size`: element k is the width of the first k
/// characters and `end` (as [`text_width`] measures it, rounded up). One
/// pass over the text, so cutting a label to its room is linear in its
/// length (measuring each prefix again took 41–73 s for a 10,000-character
/// part name). Empty without a font.
pub(crate) fn widths_with_end(text: &str, end: char, size: f64) -> Vec<i32> {
    let Some(font) = figure_font() else { return Vec::new() };
    let scaled = font.as_scaled(PxScale::from(size as f32));
    let end_id = font.glyph_id(end);
    let end_advance = scaled.h_advance(end_id);
    let mut widths = Vec::with_capacity(text.len() + 1);
    widths.push(end_advance.ceil() as i32);
    let (mut caret, mut previous) = (0.0f32, None);
    for c in text.chars() {
        let id = font.glyph_id(c);
        if let Some(before) = previous {
            caret += scaled.kern(before, id);
        }
        previous = Some(id);
        caret += scaled.h_advance(id);
        #[cfg(test)]
        GLYPHS_MEASURED.with(|count| count.set(count.get() + 1));
        widths.push((caret + scaled.kern(id, end_id) + end_advance).ceil() as i32);
    }
    widths
}

#[cfg(test)]
thread_local! {
    /// Glyphs [`widths_with_end`] measured on this thread (tests bound the work).
    pub static GLYPHS_MEASURED: std::cell::Cell<usize> = const { std::cell::Cell::new(0) };
}

/// Where the baseline lies below the top of plotters' text box, as a share
/// of the plotters size (the box is `size / 1.24` high; this keeps
/// descenders inside it and capitals at its top).
pub(crate) const BASELINE: f64 = 0.6;

/// A bitmap backend whose text is kerned and keeps side bearings (plotters'
/// own ab_glyph drawing drops them); everything else is the bitmap's.
pub struct KernedBitmap<'a>(pub BitMapBackend<'a>);

impl DrawingBackend for KernedBitmap<'_> {
    type ErrorType = <BitMapBackend<'static> as DrawingBackend>::ErrorType;

    fn get_size(&self) -> (u32, u32) {
        self.0.get_size()
    }
    fn ensure_prepared(&mut self) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.ensure_prepared()
    }
    fn present(&mut self) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.present()
    }
    fn draw_pixel(
        &mut self,
        at: BackendCoord,
        color: BackendColor,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.draw_pixel(at, color)
    }
    fn draw_line<S: BackendStyle>(
        &mut self,
        from: BackendCoord,
        to: BackendCoord,
        style: &S,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.draw_line(from, to, style)
    }
    fn draw_rect<S: BackendStyle>(
        &mut self,
        upper_left: BackendCoord,
        bottom_right: BackendCoord,
        style: &S,
        fill: bool,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.draw_rect(upper_left, bottom_right, style, fill)
    }
    fn fill_polygon<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        vertices: I,
        style: &S,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.fill_polygon(vertices, style)
    }
    fn estimate_text_size<T: BackendTextStyle>(
        &self,
        text: &str,
        style: &T,
    ) -> Result<(u32, u32), DrawingErrorKind<Self::ErrorType>> {
        kerned_text_size(text, style)
    }
    fn draw_text<T: BackendTextStyle>(
        &mut self,
        text: &str,
        style: &T,
        at: BackendCoord,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        let color = style.color();
        let (width, height) = self.estimate_text_size(text, style)?;
        let (dx, dy) = anchor_offset(style, width, height);
        let baseline = (BASELINE * style.size()) as i32;
        let transform = style.transform();
        let mut pixels = Vec::new();
        rasterize_text(text, style.size(), |x, y, coverage| pixels.push((x, y, coverage)));
        let (w, h) = self.get_size();
        for (x, y, coverage) in pixels {
            let (x, y) = transform.transform(x + dx, y + dy + baseline);
            let (x, y) = (at.0 + x, at.1 + y);
            if x >= 0 && y >= 0 && (x as u32) < w && (y as u32) < h && coverage > 0.0 {
                self.0.draw_pixel((x, y), color.mix(f64::from(coverage.min(1.0))))?;
            }
        }
        Ok(())
    }
}

/// The offset of a text box's top left from its anchor point.
pub(crate) fn anchor_offset<T: BackendTextStyle>(style: &T, width: u32, height: u32) -> (i32, i32) {
    let (width, height) = (width as i32, height as i32);
    let dx = match style.anchor().h_pos {
        HPos::Left => 0,
        HPos::Right => -width,
        HPos::Center => -width / 2,
    };
    let dy = match style.anchor().v_pos {
        VPos::Top => 0,
        VPos::Center => -height / 2,
        VPos::Bottom => -height,
    };
    (dx, dy)
}

/// Gives an SVG of `size` its printed size: the root's `width` and `height`
/// in millimetres (its viewBox stays in figure pixels), and a font list
/// that names the drawing font first.
pub fn svg_in_millimetres(svg: &str, size: FigureSize, height_px: u32) -> String {
    let width_mm = size.width_mm();
    let height_mm = f64::from(height_px) * width_mm / f64::from(size.width_px());
    let header = format!("width=\"{}\" height=\"{}\"", size.width_px(), height_px);
    svg.replacen(&header, &format!("width=\"{width_mm}mm\" height=\"{height_mm:.1}mm\""), 1)
        .replace("font-family=\"sans-serif\"", "font-family=\"DejaVu Sans, Helvetica, Arial, sans-serif\"")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dashes_alternate_along_a_straight_line() {
        let pieces = dashed(&[(0, 0), (100, 0)], Some((10.0, 5.0)));
        // 0–10, 15–25, … 90–100: seven dashes.
        assert_eq!(pieces.len(), 7);
        assert_eq!(pieces[0], [(0, 0), (10, 0)]);
        assert_eq!(pieces[1], [(15, 0), (25, 0)]);
        assert_eq!(dashed(&[(0, 0), (5, 5)], None), [[(0, 0), (5, 5)]]);
    }

    #[test]
    fn every_series_of_the_eight_has_its_own_color_and_marker_or_dash() {
        let styles: Vec<_> = (0..8)
            .map(|i| (series_color(i), marker_shape(i, 10), series_dash(i).map(|d| d.0 as i32)))
            .collect();
        for (i, a) in styles.iter().enumerate() {
            for b in &styles[i + 1..] {
                assert_ne!(a.0, b.0, "colours repeat");
                assert!(a.1 != b.1 || a.2 != b.2, "two series differ by colour alone");
            }
        }
    }

    #[test]
    fn both_widths_fit_ieee_and_elsevier_at_300_dpi() {
        // IEEE: 88.9 / 181.9 mm; Elsevier: 90 / 190 mm.
        for (size, ieee, elsevier) in
            [(FigureSize::OneColumn, 88.9, 90.0), (FigureSize::TwoColumns, 181.9, 190.0)]
        {
            let printed_mm = f64::from(size.width_px()) / DPI * 25.4;
            assert!(printed_mm <= ieee + 1e-9 && printed_mm <= elsevier, "{size:?}: {printed_mm} mm");
            assert!(printed_mm > ieee - 0.1, "{size:?}: {printed_mm} mm wastes the column");
        }
        assert_eq!(FigureSize::TwoColumns.width_px(), 2148);
        assert_eq!(FigureSize::OneColumn.width_px(), 1050);
        assert!((pt(7.0) / 1.24 * 181.9 / 2148.0 / MM_PER_PT - 7.0).abs() < 0.02);
    }
}
