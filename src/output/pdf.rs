//! The figures' PDFs, written with `pdf-writer` (a maintained PDF crate)
//! and the font subsetted by `subsetter` (issue 44 §1): a plotters backend
//! that writes PDF drawing operators (lines, rectangles, polygons, circles
//! as Bézier curves) and real text in the TrueType font the layout measures
//! with (`UFCSR_FONT`, else DejaVu Sans; [`crate::output::figure`]),
//! embedded as a subset (`FontFile2`, a Type 0 font with `Identity-H` and a
//! `ToUnicode` map, so the text stays searchable and copyable). Publishers
//! refuse PDFs whose fonts are not embedded (IEEE PDF eXpress: every font
//! embedded and subset; Elsevier's artwork rules), and a font drawn other
//! than the one measured leaves right-aligned labels ragged: here each
//! glyph advances by the font's own width and the pair kerning the PNG
//! uses, so the text sits where the PNG's does.
//!
//! Figure pixels (300 dpi, y down) become points (y up) on a page of the
//! figure's printed size; a colour with alpha is mixed with the white paper,
//! as on screen.
//!
//! Raster figures (the views, the placement overview) become PDFs too
//! ([`pdf_image_document`]): the picture as one image XObject, compressed
//! with Flate over PNG row predictors, on a page of the journal width.

use std::collections::BTreeMap;

use ab_glyph::{Font as _, FontRef, GlyphId};
use pdf_writer::types::{CidFontType, FontFlags, LineCapStyle, LineJoinStyle, SystemInfo};
use pdf_writer::{Content, Filter, Finish as _, Name, Pdf, Rect, Ref, Str, TextStr};
use plotters::prelude::DrawingBackend;
use plotters_backend::{
    BackendColor, BackendCoord, BackendStyle, BackendTextStyle, DrawingErrorKind, FontTransform,
};

use crate::output::figure::{BASELINE, DPI, anchor_offset, figure_font, kerned_text_size};

/// The page being drawn: its size in figure pixels, its content stream and
/// the glyphs its text uses.
pub(crate) struct PdfPage {
    size: (u32, u32),
    content: Content,
    glyphs: Glyphs,
}

/// The glyphs of the embedded font a page uses: their number in the subset
/// (the subset's glyph id is the text's character id), width and text.
struct Glyphs {
    remapper: subsetter::GlyphRemapper,
    /// Subset glyph id → (advance in 1/1000 em, the character it shows).
    used: BTreeMap<u16, (f32, char)>,
}

/// The backend drawing onto a [`PdfPage`].
pub(crate) struct PdfBackend<'a> {
    page: &'a mut PdfPage,
}

/// Drawing into memory cannot fail.
#[derive(Debug)]
pub(crate) struct NoError;

impl std::fmt::Display for NoError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("no error")
    }
}

impl std::error::Error for NoError {}

/// Points per figure pixel.
const K: f32 = (72.0 / DPI) as f32;

/// The font's resource name on the page.
const FONT: Name<'static> = Name(b"F1");

impl PdfPage {
    /// An empty page of `size` figure pixels.
    pub(crate) fn new(size: (u32, u32)) -> PdfPage {
        PdfPage {
            size,
            content: Content::new(),
            glyphs: Glyphs { remapper: subsetter::GlyphRemapper::new(), used: BTreeMap::new() },
        }
    }

    /// The backend that draws onto this page.
    pub(crate) fn backend(&mut self) -> PdfBackend<'_> {
        PdfBackend { page: self }
    }

    fn x(&self, x: i32) -> f32 {
        x as f32 * K
    }

    fn y(&self, y: i32) -> f32 {
        (self.size.1 as i32 - y) as f32 * K
    }

    /// Sets the fill or stroke colour, mixed with white paper.
    fn color(&mut self, color: BackendColor, fill: bool) {
        let mix = |c: u8| (f64::from(c) / 255.0 * color.alpha + (1.0 - color.alpha)).clamp(0.0, 1.0) as f32;
        let (r, g, b) = color.rgb;
        if fill {
            self.content.set_fill_rgb(mix(r), mix(g), mix(b));
        } else {
            self.content.set_stroke_rgb(mix(r), mix(g), mix(b));
        }
    }

    fn path(&mut self, points: &[BackendCoord]) {
        for (index, &(x, y)) in points.iter().enumerate() {
            let (x, y) = (self.x(x), self.y(y));
            if index == 0 {
                self.content.move_to(x, y);
            } else {
                self.content.line_to(x, y);
            }
        }
    }

    /// Shows `text` at the current text position: each character as its
    /// glyph of the subset (two bytes), kerned as the PNG is.
    fn show_glyphs(&mut self, font: &FontRef<'_>, text: &str) {
        let per_em = font.units_per_em().unwrap_or(2048.0);
        let mut shown = self.content.show_positioned();
        let mut items = shown.items();
        let mut run: Vec<u8> = Vec::new();
        let mut previous: Option<GlyphId> = None;
        for c in text.chars() {
            let id = font.glyph_id(c);
            if let Some(before) = previous {
                let kern = font.kern_unscaled(before, id);
                if kern != 0.0 {
                    items.show(Str(&run));
                    run.clear();
                    items.adjust(-kern / per_em * 1000.0);
                }
            }
            previous = Some(id);
            let new = self.glyphs.remapper.remap(id.0);
            self.glyphs.used.entry(new).or_insert((font.h_advance_unscaled(id) / per_em * 1000.0, c));
            run.extend_from_slice(&new.to_be_bytes());
        }
        items.show(Str(&run));
    }

    /// The whole file: the page, its font (subsetted and embedded when the
    /// page has text) and `title` in the document information.
    pub(crate) fn finish(self, title: &str) -> Vec<u8> {
        let (w, h) = (self.size.0 as f32 * K, self.size.1 as f32 * K);
        let mut pdf = Pdf::new();
        let [catalog, pages, page, content, info, font] = [1, 2, 3, 4, 5, 6].map(Ref::new);
        pdf.catalog(catalog).pages(pages);
        pdf.pages(pages).kids([page]).count(1);
        let mut page_dict = pdf.page(page);
        page_dict.parent(pages).media_box(Rect::new(0.0, 0.0, w, h)).contents(content);
        let has_text = !self.glyphs.used.is_empty();
        if has_text {
            page_dict.resources().fonts().pair(FONT, font);
        }
        page_dict.finish();
        pdf.stream(content, &self.content.finish());
        document_info(&mut pdf, info, title);
        if has_text && let Some(font_ref) = figure_font() {
            embed_font(&mut pdf, font, &font_ref, &self.glyphs);
        }
        pdf.finish()
    }
}

fn document_info(pdf: &mut Pdf, id: Ref, title: &str) {
    let producer = format!("ufcsr {}", env!("CARGO_PKG_VERSION"));
    pdf.document_info(id).title(TextStr(title)).producer(TextStr(&producer));
}

/// Writes the Type 0 font `id` (objects `id` to `id + 4`): the CID font,
/// its descriptor, the subset as `FontFile2` and the `ToUnicode` map.
fn embed_font(pdf: &mut Pdf, id: Ref, font: &FontRef<'_>, glyphs: &Glyphs) {
    let [cid_id, descriptor_id, file_id, unicode_id] = [1, 2, 3, 4].map(|k| Ref::new(id.get() + k));
    let subset = subsetter::subset(font.font_data(), 0, &glyphs.remapper).unwrap_or_default();
    let base = format!("{}+{}", subset_tag(glyphs), postscript_name(font.font_data()));
    let base = Name(base.as_bytes());
    let system = || SystemInfo { registry: Str(b"Adobe"), ordering: Str(b"Identity"), supplement: 0 };
    pdf.type0_font(id)
        .base_font(base)
        .encoding_predefined(Name(b"Identity-H"))
        .descendant_font(cid_id)
        .to_unicode(unicode_id);
    let mut cid = pdf.cid_font(cid_id);
    cid.subtype(CidFontType::Type2)
        .base_font(base)
        .system_info(system())
        .font_descriptor(descriptor_id)
        .default_width(0.0)
        .cid_to_gid_map_predefined(Name(b"Identity"));
    let mut widths = cid.widths();
    for (&glyph, &(width, _)) in &glyphs.used {
        widths.consecutive(glyph, [width]);
    }
    widths.finish();
    cid.finish();
    let per_em = font.units_per_em().unwrap_or(2048.0);
    let scale = |v: f32| v / per_em * 1000.0;
    let bounds = font.outline(font.glyph_id('H')).map(|o| o.bounds);
    let cap_height = bounds.map_or(scale(font.ascent_unscaled()) * 0.7, |b| scale(b.max.y));
    pdf.font_descriptor(descriptor_id)
        .name(base)
        .flags(FontFlags::NON_SYMBOLIC)
        .bbox(font_box(font))
        .italic_angle(0.0)
        .ascent(scale(font.ascent_unscaled()))
        .descent(scale(font.descent_unscaled()))
        .cap_height(cap_height)
        .stem_v(80.0)
        .font_file2(file_id);
    let compressed = fdeflate::compress_to_vec(&subset);
    pdf.stream(file_id, &compressed).filter(Filter::FlateDecode).pair(Name(b"Length1"), subset.len() as i32);
    let mut cmap = pdf_writer::types::UnicodeCmap::new(Name(b"Custom"), system());
    for (&glyph, &(_, c)) in &glyphs.used {
        cmap.pair(glyph, c);
    }
    pdf.cmap(unicode_id, &cmap.finish());
}

/// The box every glyph of the font fits in (1/1000 em), from the font's
/// ascent and descent and the widest advance of the Latin letters.
fn font_box(font: &FontRef<'_>) -> Rect {
    let per_em = font.units_per_em().unwrap_or(2048.0);
    let scale = |v: f32| v / per_em * 1000.0;
    let widest =
        ('A'..='Z').chain('a'..='z').map(|c| font.h_advance_unscaled(font.glyph_id(c))).fold(0.0, f32::max);
    Rect::new(
        -scale(widest) * 0.2,
        scale(font.descent_unscaled()),
        scale(widest) * 1.2,
        scale(font.ascent_unscaled()),
    )
}

/// Six capitals naming the subset (the same glyphs give the same tag).
fn subset_tag(glyphs: &Glyphs) -> String {
    let mut hash: u32 = 2_166_136_261;
    for &glyph in glyphs.used.keys() {
        for byte in glyph.to_be_bytes() {
            hash = (hash ^ u32::from(byte)).wrapping_mul(16_777_619);
        }
    }
    (0..6).map(|k| char::from(b'A' + ((hash >> (k * 5)) % 26) as u8)).collect()
}

/// The font's PostScript name (name ID 6), letters and digits only;
/// "Font" when the font has none.
fn postscript_name(data: &[u8]) -> String {
    let name = ttf_parser::Face::parse(data, 0).ok().and_then(|face| {
        face.names()
            .into_iter()
            .filter(|n| n.name_id == ttf_parser::name_id::POST_SCRIPT_NAME)
            .find_map(|n| n.to_string())
    });
    let name: String =
        name.unwrap_or_default().chars().filter(|c| c.is_ascii_alphanumeric() || *c == '-').collect();
    if name.is_empty() { "Font".into() } else { name }
}

type Drawn = Result<(), DrawingErrorKind<NoError>>;

impl DrawingBackend for PdfBackend<'_> {
    type ErrorType = NoError;

    fn get_size(&self) -> (u32, u32) {
        self.page.size
    }
    fn ensure_prepared(&mut self) -> Drawn {
        Ok(())
    }
    fn present(&mut self) -> Drawn {
        Ok(())
    }
    fn draw_pixel(&mut self, at: BackendCoord, color: BackendColor) -> Drawn {
        self.draw_rect(at, (at.0 + 1, at.1 + 1), &color, true)
    }
    fn draw_line<S: BackendStyle>(&mut self, from: BackendCoord, to: BackendCoord, style: &S) -> Drawn {
        self.draw_path([from, to], style)
    }
    fn draw_rect<S: BackendStyle>(
        &mut self,
        a: BackendCoord,
        b: BackendCoord,
        style: &S,
        fill: bool,
    ) -> Drawn {
        if style.color().alpha == 0.0 {
            return Ok(());
        }
        let page = &mut *self.page;
        let (x, y) = (page.x(a.0.min(b.0)), page.y(a.1.max(b.1)));
        let (w, h) = ((b.0 - a.0).abs() as f32 * K, (b.1 - a.1).abs() as f32 * K);
        page.color(style.color(), fill);
        if fill {
            page.content.rect(x, y, w, h).fill_nonzero();
        } else {
            page.content.set_line_width(style.stroke_width() as f32 * K).rect(x, y, w, h).stroke();
        }
        Ok(())
    }
    fn draw_path<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        path: I,
        style: &S,
    ) -> Drawn {
        if style.color().alpha == 0.0 {
            return Ok(());
        }
        let points: Vec<BackendCoord> = path.into_iter().collect();
        if points.len() < 2 {
            return Ok(());
        }
        let page = &mut *self.page;
        page.color(style.color(), false);
        page.content
            .set_line_width(style.stroke_width() as f32 * K)
            .set_line_cap(LineCapStyle::RoundCap)
            .set_line_join(LineJoinStyle::RoundJoin);
        page.path(&points);
        page.content.stroke();
        Ok(())
    }
    fn draw_circle<S: BackendStyle>(&mut self, c: BackendCoord, radius: u32, style: &S, fill: bool) -> Drawn {
        if style.color().alpha == 0.0 {
            return Ok(());
        }
        let page = &mut *self.page;
        // Four Bézier quarters (κ = 0.5523).
        let (x, y, r) = (page.x(c.0), page.y(c.1), radius as f32 * K);
        let k = 0.5523 * r;
        page.color(style.color(), fill);
        page.content
            .set_line_width(style.stroke_width() as f32 * K)
            .move_to(x + r, y)
            .cubic_to(x + r, y + k, x + k, y + r, x, y + r)
            .cubic_to(x - k, y + r, x - r, y + k, x - r, y)
            .cubic_to(x - r, y - k, x - k, y - r, x, y - r)
            .cubic_to(x + k, y - r, x + r, y - k, x + r, y);
        if fill {
            page.content.fill_nonzero();
        } else {
            page.content.stroke();
        }
        Ok(())
    }
    fn fill_polygon<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        vert: I,
        style: &S,
    ) -> Drawn {
        if style.color().alpha == 0.0 {
            return Ok(());
        }
        let points: Vec<BackendCoord> = vert.into_iter().collect();
        if points.len() < 3 {
            return Ok(());
        }
        let page = &mut *self.page;
        page.color(style.color(), true);
        page.path(&points);
        page.content.close_path().fill_nonzero();
        Ok(())
    }
    fn estimate_text_size<T: BackendTextStyle>(
        &self,
        text: &str,
        style: &T,
    ) -> Result<(u32, u32), DrawingErrorKind<NoError>> {
        kerned_text_size(text, style)
    }
    fn draw_text<T: BackendTextStyle>(&mut self, text: &str, style: &T, at: BackendCoord) -> Drawn {
        let Some(font) = figure_font() else { return Ok(()) };
        if style.color().alpha == 0.0 || text.is_empty() {
            return Ok(());
        }
        let (width, height) = self.estimate_text_size(text, style)?;
        let (dx, dy) = anchor_offset(style, width, height);
        let baseline = (BASELINE * style.size()) as i32;
        let transform = style.transform();
        let (ox, oy) = transform.transform(dx, dy + baseline);
        let page = &mut *self.page;
        let (x, y) = (page.x(at.0 + ox), page.y(at.1 + oy));
        // Figure-pixel rotations are clockwise on screen: counter-clockwise in PDF's y-up.
        let (cos, sin) = match transform {
            FontTransform::Rotate90 => (0.0, -1.0),
            FontTransform::Rotate180 => (-1.0, 0.0),
            FontTransform::Rotate270 => (0.0, 1.0),
            _ => (1.0, 0.0),
        };
        // The em the PNG draws with: ab_glyph scales the font's height
        // (ascent − descent) to the plotters size.
        let em = em_px(&font, style.size()) * K;
        page.color(style.color(), true);
        page.content.begin_text().set_font(FONT, em).set_text_matrix([cos, sin, -sin, cos, x, y]);
        page.show_glyphs(&font, text);
        page.content.end_text();
        Ok(())
    }
}

/// The em, in figure pixels, of text drawn at plotters size `size` by the
/// PNG's rasterizer (ab_glyph's `PxScale` is the font's ascent − descent).
pub(crate) fn em_px(font: &FontRef<'_>, size: f64) -> f32 {
    let height = font.ascent_unscaled() - font.descent_unscaled();
    size as f32 * font.units_per_em().unwrap_or(height) / height
}

/// A one-page PDF of an RGB picture (`size` pixels, rows top to bottom)
/// printed `width_mm` wide (its height in proportion), with `title` in its
/// document information. The pixels are kept exactly: PNG row predictors
/// (Sub or Up, whichever leaves more zeros) and Flate, which every PDF
/// reader decodes.
pub(crate) fn pdf_image_document(
    rgb: &[u8],
    [width, height]: [u32; 2],
    width_mm: f64,
    title: &str,
) -> Vec<u8> {
    let w_pt = (width_mm / 25.4 * 72.0) as f32;
    let h_pt = w_pt * height as f32 / width.max(1) as f32;
    let stream = fdeflate::compress_to_vec(&predicted_rows(rgb, width as usize));
    let mut pdf = Pdf::new();
    let [catalog, pages, page, content_id, info, image] = [1, 2, 3, 4, 5, 6].map(Ref::new);
    pdf.catalog(catalog).pages(pages);
    pdf.pages(pages).kids([page]).count(1);
    let mut page_dict = pdf.page(page);
    page_dict.parent(pages).media_box(Rect::new(0.0, 0.0, w_pt, h_pt)).contents(content_id);
    page_dict.resources().x_objects().pair(Name(b"Im1"), image);
    page_dict.finish();
    let mut xobject = pdf.image_xobject(image, &stream);
    xobject.filter(Filter::FlateDecode);
    xobject.width(width as i32).height(height as i32).bits_per_component(8);
    xobject.color_space().device_rgb();
    xobject
        .decode_parms()
        .predictor(pdf_writer::types::Predictor::PngOptimum)
        .colors(3)
        .bits_per_component(8)
        .columns(width as i32);
    xobject.finish();
    let mut content = Content::new();
    content.save_state().transform([w_pt, 0.0, 0.0, h_pt, 0.0, 0.0]).x_object(Name(b"Im1")).restore_state();
    pdf.stream(content_id, &content.finish());
    document_info(&mut pdf, info, title);
    pdf.finish()
}

/// The rows of `rgb` (`width` pixels each) as PNG-predicted rows: a filter
/// byte (1 Sub, 2 Up) and the differences, so that flat areas are zeros.
fn predicted_rows(rgb: &[u8], width: usize) -> Vec<u8> {
    let stride = width * 3;
    let mut out = Vec::with_capacity(rgb.len() + rgb.len() / stride.max(1) + 1);
    let mut sub = vec![0u8; stride];
    let mut up = vec![0u8; stride];
    for (y, row) in rgb.chunks_exact(stride.max(1)).enumerate() {
        for x in 0..stride {
            sub[x] = row[x].wrapping_sub(if x >= 3 { row[x - 3] } else { 0 });
            up[x] = row[x].wrapping_sub(if y > 0 { rgb[(y - 1) * stride + x] } else { 0 });
        }
        let zeros = |bytes: &[u8]| bytes.iter().filter(|&&b| b == 0).count();
        let (filter, bytes) = if zeros(&up) > zeros(&sub) { (2u8, &up) } else { (1u8, &sub) };
        out.push(filter);
        out.extend_from_slice(bytes);
    }
    out
}

/// Writes the picture `rgb` as `path` (a PDF `width_mm` wide), atomically.
pub(crate) fn write_image_pdf(
    path: &std::path::Path,
    rgb: &[u8],
    size: [u32; 2],
    width_mm: f64,
    title: &str,
) -> crate::error::Result<()> {
    crate::files::write_bytes_atomically(path, &pdf_image_document(rgb, size, width_mm, title))
}

#[cfg(test)]
mod tests {
    use super::*;
    use plotters::prelude::*;
    use plotters::style::text_anchor::{HPos, Pos, VPos};

    /// Where `needle` first occurs in `haystack` at or after `from`.
    fn find(haystack: &[u8], needle: &[u8], from: usize) -> Option<usize> {
        haystack.get(from..)?.windows(needle.len()).position(|w| w == needle).map(|i| i + from)
    }

    /// The objects of a PDF: number → (dictionary text, stream bytes).
    fn objects(pdf: &[u8]) -> BTreeMap<u32, (String, Vec<u8>)> {
        let mut found = BTreeMap::new();
        let mut at = 0;
        while let Some(start) = find(pdf, b" 0 obj", at) {
            let digits = pdf[..start].iter().rev().take_while(|b| b.is_ascii_digit()).count();
            let number: u32 = std::str::from_utf8(&pdf[start - digits..start]).unwrap().parse().unwrap();
            let body_from = start + 6;
            let stream_at = find(pdf, b"stream", body_from);
            let end_at = find(pdf, b"endobj", body_from).unwrap();
            let (dict, stream, next) = match stream_at.filter(|&s| s < end_at) {
                Some(s) => {
                    let dict = String::from_utf8_lossy(&pdf[body_from..s]).into_owned();
                    let length: usize = dict
                        .split("/Length ")
                        .nth(1)
                        .unwrap()
                        .split_whitespace()
                        .next()
                        .unwrap()
                        .parse()
                        .unwrap();
                    let data_from = s + 6 + if pdf[s + 6] == b'\r' { 2 } else { 1 };
                    let data = pdf[data_from..data_from + length].to_vec();
                    (dict, data, find(pdf, b"endobj", data_from + length).unwrap())
                }
                None => (String::from_utf8_lossy(&pdf[body_from..end_at]).into_owned(), Vec::new(), end_at),
            };
            found.insert(number, (dict, stream));
            at = next;
        }
        found
    }

    /// The object a key of `dict` refers to (`/Key N 0 R`).
    fn reference(dict: &str, key: &str) -> Option<u32> {
        let rest = dict.split(&format!("/{key} ")).nth(1)?;
        rest.split_whitespace().next()?.parse().ok()
    }

    fn inflate(data: &[u8]) -> Vec<u8> {
        use std::io::Read as _;
        let mut out = Vec::new();
        flate2::read::ZlibDecoder::new(data).read_to_end(&mut out).unwrap();
        out
    }

    /// A page with a right-aligned label ending at x = 1500 figure pixels.
    fn labelled_page(label: &str) -> PdfPage {
        let mut page = PdfPage::new((2000, 400));
        {
            let root = page.backend().into_drawing_area();
            let style = TextStyle::from(("sans-serif", crate::output::figure::pt(7.0)).into_font())
                .pos(Pos::new(HPos::Right, VPos::Center));
            root.draw_text(label, &style, (1500, 200)).unwrap();
        }
        page
    }

    #[test]
    fn every_font_of_a_plot_pdf_is_an_embedded_subset_of_the_measured_font() {
        let Some(font) = figure_font() else {
            eprintln!("skipped: no TrueType font (UFCSR_FONT or DejaVu Sans)");
            return;
        };
        let pdf = labelled_page("windshield rail (left) – 12.4 deg²").finish("t");
        assert!(pdf.starts_with(b"%PDF-"));
        let objects = objects(&pdf);
        let fonts: Vec<&String> = objects
            .values()
            .map(|(dict, _)| dict)
            .filter(|d| d.contains("/Type /Font") && !d.contains("/Type /FontDescriptor"))
            .collect();
        assert!(!fonts.is_empty(), "no font in the PDF");
        let mut embedded = 0;
        for dict in fonts {
            assert!(!dict.contains("Helvetica") && !dict.contains("/Type1"), "{dict}");
            let base = dict.split("/BaseFont /").nth(1).unwrap().split_whitespace().next().unwrap();
            let (tag, name) = base.split_once('+').expect("a subset tag");
            assert!(tag.len() == 6 && tag.chars().all(|c| c.is_ascii_uppercase()), "{base}");
            assert!(name.starts_with("DejaVuSans") || std::env::var_os("UFCSR_FONT").is_some(), "{base}");
            if dict.contains("/Subtype /Type0") {
                continue;
            }
            let descriptor = &objects[&reference(dict, "FontDescriptor").expect("a FontDescriptor")].0;
            let (file_dict, file) = &objects[&reference(descriptor, "FontFile2").expect("a FontFile2")];
            let subset = inflate(file);
            let length1: usize = file_dict
                .split("/Length1 ")
                .nth(1)
                .unwrap()
                .split_whitespace()
                .next()
                .unwrap()
                .parse()
                .unwrap();
            assert_eq!(subset.len(), length1);
            let face = ttf_parser::Face::parse(&subset, 0).expect("the embedded font parses");
            // A subset: far fewer glyphs than DejaVu Sans's 6000-odd.
            assert!(face.number_of_glyphs() < 40, "{} glyphs", face.number_of_glyphs());
            assert!(font.glyph_count() > 1000);
            embedded += 1;
        }
        assert_eq!(embedded, 1);
    }

    /// Content-stream tokens: numbers, names, strings (bytes), `[`/`]`, operators.
    #[derive(Debug, Clone, PartialEq)]
    enum Token {
        Number(f32),
        Bytes(Vec<u8>),
        Word(String),
    }

    fn tokens(ops: &[u8]) -> Vec<Token> {
        let mut out = Vec::new();
        let mut i = 0;
        while i < ops.len() {
            let c = ops[i];
            if c.is_ascii_whitespace() {
                i += 1;
            } else if c == b'(' {
                let mut bytes = Vec::new();
                let mut depth = 1;
                i += 1;
                while depth > 0 {
                    let b = ops[i];
                    i += 1;
                    match b {
                        b'\\' => {
                            let e = ops[i];
                            i += 1;
                            match e {
                                b'n' => bytes.push(b'\n'),
                                b'r' => bytes.push(b'\r'),
                                b't' => bytes.push(b'\t'),
                                b'b' => bytes.push(8),
                                b'f' => bytes.push(12),
                                b'0'..=b'7' => {
                                    let mut v = u32::from(e - b'0');
                                    for _ in 0..2 {
                                        if (b'0'..=b'7').contains(&ops[i]) {
                                            v = v * 8 + u32::from(ops[i] - b'0');
                                            i += 1;
                                        }
                                    }
                                    bytes.push(v as u8);
                                }
                                other => bytes.push(other),
                            }
                        }
                        b'(' => {
                            depth += 1;
                            bytes.push(b);
                        }
                        b')' => {
                            depth -= 1;
                            if depth > 0 {
                                bytes.push(b);
                            }
                        }
                        _ => bytes.push(b),
                    }
                }
                out.push(Token::Bytes(bytes));
            } else if c == b'<' {
                let end = i + ops[i..].iter().position(|&b| b == b'>').unwrap();
                let hex = std::str::from_utf8(&ops[i + 1..end]).unwrap();
                out.push(Token::Bytes(
                    (0..hex.len())
                        .step_by(2)
                        .map(|k| u8::from_str_radix(&hex[k..k + 2], 16).unwrap())
                        .collect(),
                ));
                i = end + 1;
            } else if c == b'[' || c == b']' {
                out.push(Token::Word((c as char).to_string()));
                i += 1;
            } else {
                let end = i + ops[i..]
                    .iter()
                    .position(|b| b.is_ascii_whitespace() || b"[]()<".contains(b))
                    .unwrap_or(ops.len() - i);
                let word = std::str::from_utf8(&ops[i..end]).unwrap();
                out.push(word.parse().map(Token::Number).unwrap_or_else(|_| Token::Word(word.into())));
                i = end;
            }
        }
        out
    }

    #[test]
    fn a_right_aligned_label_ends_at_its_anchor_within_half_a_point() {
        if figure_font().is_none() {
            eprintln!("skipped: no TrueType font (UFCSR_FONT or DejaVu Sans)");
            return;
        }
        // Wide and narrow glyphs, and kerned pairs (AV, To).
        let mut page = labelled_page("AVATAR windshield_rail_left Tow WWW iii");
        let used = page.glyphs.used.clone();
        let ops = std::mem::replace(&mut page.content, Content::new()).finish();
        let tokens = tokens(&ops);
        let number = |t: &Token| if let Token::Number(v) = t { *v } else { panic!("{t:?}") };
        let at = |word: &str| tokens.iter().position(|t| *t == Token::Word(word.into())).unwrap();
        let tf = at("Tf");
        let em = number(&tokens[tf - 1]);
        let tm = at("Tm");
        let start_x = number(&tokens[tm - 2]);
        // TJ: glyph runs advance by their widths; numbers move back by n/1000 em.
        let (open, close) = (at("["), at("TJ") - 1);
        let mut advance = 0.0f32;
        for token in &tokens[open + 1..close] {
            match token {
                Token::Number(n) => advance -= n,
                Token::Bytes(bytes) => {
                    for pair in bytes.chunks_exact(2) {
                        advance += used[&u16::from_be_bytes([pair[0], pair[1]])].0;
                    }
                }
                Token::Word(w) => panic!("{w}"),
            }
        }
        let end_x = start_x + advance / 1000.0 * em;
        let anchor = 1500.0 * K;
        assert!((end_x - anchor).abs() <= 0.5, "ends at {end_x:.2} pt, anchor {anchor:.2} pt");
        assert!(advance > 10_000.0, "the label's glyphs were all read: {advance}");
    }

    #[test]
    fn an_image_pdf_keeps_every_pixel_at_the_journal_width() {
        let (width, height) = (37u32, 5u32);
        let rgb: Vec<u8> =
            (0..width * height * 3).map(|i| if i % 7 == 0 { 255 } else { (i / 40) as u8 }).collect();
        let pdf = pdf_image_document(&rgb, [width, height], 183.0, "views");
        let objects = objects(&pdf);
        let page = objects
            .values()
            .find(|(d, _)| d.contains("/Type /Page\n") || d.contains("/Type /Page "))
            .unwrap();
        // 183 mm = 518.74 pt; the height in proportion.
        let media = page.0.split("/MediaBox [").nth(1).unwrap().split(']').next().unwrap();
        let numbers: Vec<f64> = media.split_whitespace().map(|v| v.parse().unwrap()).collect();
        assert!((numbers[2] - 518.74).abs() < 0.01 && (numbers[3] - 70.10).abs() < 0.01, "{media}");
        let (_, stream) = objects.values().find(|(d, _)| d.contains("/Subtype /Image")).unwrap();
        let rows = inflate(stream);
        let stride = (width * 3) as usize;
        let mut pixels: Vec<u8> = Vec::new();
        for (y, row) in rows.chunks_exact(stride + 1).enumerate() {
            for x in 0..stride {
                let left = if x >= 3 { pixels[y * stride + x - 3] } else { 0 };
                let above = if y > 0 { pixels[(y - 1) * stride + x] } else { 0 };
                let base = if row[0] == 1 { left } else { above };
                assert!(row[0] == 1 || row[0] == 2);
                pixels.push(row[1 + x].wrapping_add(base));
            }
        }
        assert_eq!(pixels, rgb);
    }
}
