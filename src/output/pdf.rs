//! A vector PDF of a figure: a plotters backend that writes PDF drawing
//! operators (lines, rectangles, polygons, circles as Bézier curves) and
//! real text in Helvetica, one of PDF's standard fonts, so no font is
//! embedded and the text stays text (searchable, editable in a journal's
//! workflow). Small by design — one page, no compression, no transparency
//! (a colour with alpha is mixed with the white paper, as on screen) —
//! so the figures need no PDF crate.
//!
//! Figure pixels (300 dpi, y down) become points (y up) on a page of the
//! figure's printed size.
//!
//! Raster figures (the views, the placement overview) become PDFs too
//! ([`pdf_image_document`]): the picture as one image XObject, compressed
//! with Flate over PNG row predictors (fdeflate, as the PNGs), on a page of
//! the journal width.

use std::fmt::Write as _;

use plotters::prelude::DrawingBackend;
use plotters_backend::{
    BackendColor, BackendCoord, BackendStyle, BackendTextStyle, DrawingErrorKind, FontTransform,
};

use crate::output::figure::{BASELINE, DPI, anchor_offset};

/// The page being drawn: its size in figure pixels and its content stream.
pub struct PdfBackend<'a> {
    size: (u32, u32),
    content: &'a mut String,
}

/// Drawing into a string cannot fail.
#[derive(Debug)]
pub struct NoError;

impl std::fmt::Display for NoError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("no error")
    }
}

impl std::error::Error for NoError {}

/// Points per figure pixel.
const K: f64 = 72.0 / DPI;

impl<'a> PdfBackend<'a> {
    /// A page of `size` figure pixels drawing into `content`.
    pub fn new(content: &'a mut String, size: (u32, u32)) -> PdfBackend<'a> {
        PdfBackend { size, content }
    }

    fn x(&self, x: i32) -> f64 {
        f64::from(x) * K
    }

    fn y(&self, y: i32) -> f64 {
        f64::from(self.size.1 as i32 - y) * K
    }

    /// Sets the fill (`rg`) or stroke (`RG`) colour, mixed with white paper.
    fn color(&mut self, color: BackendColor, operator: &str) {
        let mix = |c: u8| (f64::from(c) / 255.0 * color.alpha + (1.0 - color.alpha)).clamp(0.0, 1.0);
        let (r, g, b) = color.rgb;
        let _ = writeln!(self.content, "{:.3} {:.3} {:.3} {operator}", mix(r), mix(g), mix(b));
    }

    fn path(&mut self, points: &[BackendCoord], end: PathEnd) {
        for (index, &(x, y)) in points.iter().enumerate() {
            let op = if index == 0 { "m" } else { "l" };
            let _ = writeln!(self.content, "{:.2} {:.2} {op}", self.x(x), self.y(y));
        }
        if end == PathEnd::Closed {
            self.content.push_str("h\n");
        }
    }
}

type Drawn = Result<(), DrawingErrorKind<NoError>>;

/// Whether a path ends where it started (a polygon) or stays open (a line).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum PathEnd {
    Open,
    Closed,
}

impl DrawingBackend for PdfBackend<'_> {
    type ErrorType = NoError;

    fn get_size(&self) -> (u32, u32) {
        self.size
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
        let (x, y) = (self.x(a.0.min(b.0)), self.y(a.1.max(b.1)));
        let (w, h) = (f64::from((b.0 - a.0).abs()) * K, f64::from((b.1 - a.1).abs()) * K);
        if fill {
            self.color(style.color(), "rg");
            let _ = writeln!(self.content, "{x:.2} {y:.2} {w:.2} {h:.2} re f");
        } else {
            self.color(style.color(), "RG");
            let width = f64::from(style.stroke_width()) * K;
            let _ = writeln!(self.content, "{width:.2} w {x:.2} {y:.2} {w:.2} {h:.2} re S");
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
        self.color(style.color(), "RG");
        let _ = writeln!(self.content, "{:.2} w 1 J 1 j", f64::from(style.stroke_width()) * K);
        self.path(&points, PathEnd::Open);
        self.content.push_str("S\n");
        Ok(())
    }
    fn draw_circle<S: BackendStyle>(&mut self, c: BackendCoord, radius: u32, style: &S, fill: bool) -> Drawn {
        if style.color().alpha == 0.0 {
            return Ok(());
        }
        // Four Bézier quarters (κ = 0.5523).
        let (x, y, r) = (self.x(c.0), self.y(c.1), f64::from(radius) * K);
        let k = 0.5523 * r;
        self.color(style.color(), if fill { "rg" } else { "RG" });
        let _ = writeln!(
            self.content,
            "{:.2} w {a:.2} {y:.2} m {a:.2} {b:.2} {c1:.2} {t:.2} {x:.2} {t:.2} c {c2:.2} {t:.2} {l:.2} {b:.2} {l:.2} {y:.2} c \
             {l:.2} {d:.2} {c2:.2} {u:.2} {x:.2} {u:.2} c {c1:.2} {u:.2} {a:.2} {d:.2} {a:.2} {y:.2} c {}",
            f64::from(style.stroke_width()) * K,
            if fill { "f" } else { "S" },
            a = x + r,
            b = y + k,
            c1 = x + k,
            t = y + r,
            c2 = x - k,
            l = x - r,
            d = y - k,
            u = y - r,
        );
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
        self.color(style.color(), "rg");
        self.path(&points, PathEnd::Closed);
        self.content.push_str("f\n");
        Ok(())
    }
    fn draw_text<T: BackendTextStyle>(&mut self, text: &str, style: &T, at: BackendCoord) -> Drawn {
        if style.color().alpha == 0.0 || text.is_empty() {
            return Ok(());
        }
        let (width, height) = self.estimate_text_size(text, style)?;
        let (dx, dy) = anchor_offset(style, width, height);
        let baseline = (BASELINE * style.size()) as i32;
        let transform = style.transform();
        let (ox, oy) = transform.transform(dx, dy + baseline);
        let (x, y) = (self.x(at.0 + ox), self.y(at.1 + oy));
        // Figure-pixel rotations are clockwise on screen: counter-clockwise in PDF's y-up.
        let (cos, sin) = match transform {
            FontTransform::Rotate90 => (0.0, -1.0),
            FontTransform::Rotate180 => (-1.0, 0.0),
            FontTransform::Rotate270 => (0.0, 1.0),
            _ => (1.0, 0.0),
        };
        // The em is `size / 1.24` figure pixels, as in the SVG.
        let em = style.size() / 1.24 * K;
        self.color(style.color(), "rg");
        let _ = writeln!(
            self.content,
            "BT /F1 {em:.2} Tf {cos} {sin} {} {cos} {x:.2} {y:.2} Tm ({}) Tj ET",
            -sin,
            win_ansi(text)
        );
        Ok(())
    }
}

/// `text` as a PDF string in WinAnsiEncoding (Latin-1 and a few more;
/// other characters become `?`), with `(`, `)` and `\` escaped.
fn win_ansi(text: &str) -> String {
    let mut out = String::new();
    for c in text.chars() {
        let code: u32 = match c {
            '(' | ')' | '\\' => {
                out.push('\\');
                c as u32
            }
            '\u{20}'..='\u{7e}' | '\u{a0}'..='\u{ff}' => c as u32,
            '–' => 0x96,
            '—' => 0x97,
            '’' => 0x92,
            '‘' => 0x91,
            '•' => 0x95,
            '…' => 0x85,
            _ => u32::from(b'?'),
        };
        if (0x20..0x7f).contains(&code) {
            out.push(char::from_u32(code).unwrap_or('?'));
        } else {
            let _ = write!(out, "\\{code:03o}");
        }
    }
    out
}

/// A one-page PDF of `content` (drawn by [`PdfBackend`]) on a page of
/// `size` figure pixels, with `title` in its document information.
pub fn pdf_document(content: &str, size: (u32, u32), title: &str) -> Vec<u8> {
    let (w, h) = (f64::from(size.0) * K, f64::from(size.1) * K);
    let objects = [
        "<< /Type /Catalog /Pages 2 0 R >>".as_bytes().to_vec(),
        "<< /Type /Pages /Kids [3 0 R] /Count 1 >>".as_bytes().to_vec(),
        format!(
            "<< /Type /Page /Parent 2 0 R /MediaBox [0 0 {w:.2} {h:.2}] /Resources << /Font << /F1 4 0 R >> >> /Contents 5 0 R >>"
        )
        .into_bytes(),
        "<< /Type /Font /Subtype /Type1 /BaseFont /Helvetica /Encoding /WinAnsiEncoding >>".as_bytes().to_vec(),
        format!("<< /Length {} >>\nstream\n{content}endstream", content.len()).into_bytes(),
        info(title),
    ];
    assemble(&objects)
}

/// The document information object.
fn info(title: &str) -> Vec<u8> {
    format!("<< /Title ({}) /Producer (ufcsr {}) >>", win_ansi(title), env!("CARGO_PKG_VERSION")).into_bytes()
}

/// The file: header, `objects` numbered from 1 (the last is the document
/// information), the cross-reference table and the trailer.
fn assemble(objects: &[Vec<u8>]) -> Vec<u8> {
    let mut pdf = "%PDF-1.4\n%\u{e2}\u{e3}\u{cf}\u{d3}\n".as_bytes().to_vec();
    let mut offsets = Vec::new();
    for (index, object) in objects.iter().enumerate() {
        offsets.push(pdf.len());
        pdf.extend_from_slice(format!("{} 0 obj\n", index + 1).as_bytes());
        pdf.extend_from_slice(object);
        pdf.extend_from_slice(b"\nendobj\n");
    }
    let xref = pdf.len();
    let mut table = format!("xref\n0 {}\n0000000000 65535 f \n", objects.len() + 1);
    for offset in offsets {
        let _ = writeln!(table, "{offset:010} 00000 n ");
    }
    let _ = write!(
        table,
        "trailer\n<< /Size {} /Root 1 0 R /Info {} 0 R >>\nstartxref\n{xref}\n%%EOF\n",
        objects.len() + 1,
        objects.len()
    );
    pdf.extend_from_slice(table.as_bytes());
    pdf
}

/// A one-page PDF of an RGB picture (`size` pixels, rows top to bottom)
/// printed `width_mm` wide (its height in proportion), with `title` in its
/// document information. The pixels are kept exactly: PNG row predictors
/// (Sub or Up, whichever leaves more zeros) and Flate, which every PDF
/// reader decodes.
pub fn pdf_image_document(rgb: &[u8], [width, height]: [u32; 2], width_mm: f64, title: &str) -> Vec<u8> {
    let w_pt = width_mm / 25.4 * 72.0;
    let h_pt = w_pt * f64::from(height) / f64::from(width.max(1));
    let stream = fdeflate::compress_to_vec(&predicted_rows(rgb, width as usize));
    let mut image = format!(
        "<< /Type /XObject /Subtype /Image /Width {width} /Height {height} /ColorSpace /DeviceRGB \
         /BitsPerComponent 8 /Filter /FlateDecode /DecodeParms << /Predictor 15 /Colors 3 \
         /BitsPerComponent 8 /Columns {width} >> /Length {} >>\nstream\n",
        stream.len()
    )
    .into_bytes();
    image.extend_from_slice(&stream);
    image.extend_from_slice(b"\nendstream");
    let content = format!("q {w_pt:.3} 0 0 {h_pt:.3} 0 0 cm /Im1 Do Q\n");
    let objects = [
        "<< /Type /Catalog /Pages 2 0 R >>".as_bytes().to_vec(),
        "<< /Type /Pages /Kids [3 0 R] /Count 1 >>".as_bytes().to_vec(),
        format!(
            "<< /Type /Page /Parent 2 0 R /MediaBox [0 0 {w_pt:.2} {h_pt:.2}] /Resources << /XObject << /Im1 4 0 R >> >> /Contents 5 0 R >>"
        )
        .into_bytes(),
        image,
        format!("<< /Length {} >>\nstream\n{content}endstream", content.len()).into_bytes(),
        info(title),
    ];
    assemble(&objects)
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
pub fn write_image_pdf(
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

    #[test]
    fn text_is_win_ansi_with_escapes() {
        assert_eq!(win_ansi("a (b) \\"), "a \\(b\\) \\\\");
        assert_eq!(win_ansi("deg²·s"), "deg\\262\\267s");
        assert_eq!(win_ansi("→"), "?");
    }

    #[test]
    fn an_image_pdf_keeps_every_pixel_at_the_journal_width() {
        use std::io::Read as _;
        let (width, height) = (37u32, 5u32);
        let rgb: Vec<u8> =
            (0..width * height * 3).map(|i| if i % 7 == 0 { 255 } else { (i / 40) as u8 }).collect();
        let pdf = pdf_image_document(&rgb, [width, height], 183.0, "views");
        let text = String::from_utf8_lossy(&pdf).into_owned();
        // 183 mm = 518.74 pt; the height in proportion.
        assert!(text.contains("/MediaBox [0 0 518.74 70.10]"), "{}", &text[..400]);
        // The table and trailer are ASCII; the image stream before them is not.
        let tail_at = pdf.windows(4).rposition(|w| w == b"xref").unwrap() - 5;
        let tail = std::str::from_utf8(&pdf[tail_at..]).unwrap();
        let xref_at: usize =
            tail.rsplit("startxref\n").next().unwrap().lines().next().unwrap().parse().unwrap();
        let table = std::str::from_utf8(&pdf[xref_at..]).unwrap();
        for (index, line) in table.lines().skip(3).take(6).enumerate() {
            let offset: usize = line[..10].parse().unwrap();
            assert!(
                pdf[offset..].starts_with(format!("{} 0 obj", index + 1).as_bytes()),
                "object {}",
                index + 1
            );
        }
        // The stream inflates to predicted rows that give the pixels back.
        let start = pdf.windows(7).position(|w| w == b"stream\n").unwrap() + 7;
        let length: usize =
            text.split("/Length ").nth(1).unwrap().split(' ').next().unwrap().parse().unwrap();
        let mut rows = Vec::new();
        flate2::read::ZlibDecoder::new(&pdf[start..start + length]).read_to_end(&mut rows).unwrap();
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

    #[test]
    fn the_cross_reference_table_points_at_each_object() {
        let pdf = pdf_document("0 0 m 1 1 l S\n", (300, 300), "t");
        let text = String::from_utf8_lossy(&pdf).into_owned();
        let xref_at: usize =
            text.rsplit("startxref\n").next().unwrap().lines().next().unwrap().parse().unwrap();
        assert!(text[xref_at..].starts_with("xref"));
        for (index, line) in text[xref_at..].lines().skip(3).take(6).enumerate() {
            let offset: usize = line[..10].parse().unwrap();
            assert!(text[offset..].starts_with(&format!("{} 0 obj", index + 1)), "object {}", index + 1);
        }
        // 300 figure pixels at 300 dpi: one inch, 72 points.
        assert!(text.contains("/MediaBox [0 0 72.00 72.00]"));
    }
}
