//! The one PNG encoder. Every PNG the two programs write — tiles, the PIdT,
//! palettes, heatmaps, views, pictures, the palette inside `vehicle.glb` —
//! is encoded by [`encode_rgb_png`], so the colour type, bit depth and the
//! order the settings are applied in (a filter chosen after the deflate
//! level, which picks one of its own) are decided once.
//!
//! The settings stay parameters ([`PngEncoding`]): the capture's tiles are
//! its hot path and keep their own deflate level and row filter
//! (`--compression`, `--tile-filter`); every other image takes a level and
//! the filter that level picks.

use std::io::Write;
use std::path::Path;

use crate::error::Result;
use crate::files::write_atomically;

/// How an image is encoded: the deflate level and, when not the one the
/// level picks, the row filter.
#[derive(Debug, Clone, Copy)]
pub struct PngEncoding {
    pub compression: png::Compression,
    /// `None`: the filter `compression` picks.
    pub filter: Option<png::Filter>,
}

impl From<png::Compression> for PngEncoding {
    fn from(compression: png::Compression) -> Self {
        PngEncoding { compression, filter: None }
    }
}

/// Encodes an 8-bit RGB image (`rgb` holds `width * height * 3` bytes) into `writer`.
pub fn encode_rgb_png(
    writer: impl Write,
    size: [u32; 2],
    rgb: &[u8],
    encoding: PngEncoding,
) -> std::result::Result<(), png::EncodingError> {
    encode_png(writer, size, rgb, encoding, None)
}

/// Writes an 8-bit RGBA PNG atomically (`rgba` holds `width * height * 4`
/// bytes): the tiles of a capture of 32-bit texel ids, whose alpha carries
/// the id's high byte ([`crate::rgba32_id`]).
pub fn write_rgba_png(
    path: &Path,
    size: [u32; 2],
    rgba: &[u8],
    encoding: impl Into<PngEncoding>,
) -> Result<()> {
    let encoding = encoding.into();
    write_atomically(path, |writer| {
        encode_with_color(writer, size, (rgba, png::ColorType::Rgba), encoding, None)
            .map_err(std::io::Error::other)
    })
}

/// [`encode_rgb_png`], with the resolution (`pHYs`, pixels per metre) when
/// given: figures say how large they print.
fn encode_png(
    writer: impl Write,
    size: [u32; 2],
    rgb: &[u8],
    encoding: PngEncoding,
    pixels_per_metre: Option<u32>,
) -> std::result::Result<(), png::EncodingError> {
    encode_with_color(writer, size, (rgb, png::ColorType::Rgb), encoding, pixels_per_metre)
}

/// [`encode_png`] of `pixels` in the given colour type (RGB or RGBA).
fn encode_with_color(
    writer: impl Write,
    [width, height]: [u32; 2],
    (pixels, color): (&[u8], png::ColorType),
    encoding: PngEncoding,
    pixels_per_metre: Option<u32>,
) -> std::result::Result<(), png::EncodingError> {
    let rgb = pixels;
    let mut encoder = png::Encoder::new(writer, width, height);
    if let Some(ppm) = pixels_per_metre {
        encoder.set_pixel_dims(Some(png::PixelDimensions { xppu: ppm, yppu: ppm, unit: png::Unit::Meter }));
    }
    encoder.set_color(color);
    encoder.set_depth(png::BitDepth::Eight);
    // set_compression also picks a filter: a chosen one goes after it.
    encoder.set_compression(encoding.compression);
    if let Some(filter) = encoding.filter {
        encoder.set_filter(filter);
    }
    let mut png_writer = encoder.write_header()?;
    png_writer.write_image_data(rgb)?;
    png_writer.finish()
}

/// Writes an 8-bit RGB PNG atomically (`rgb` holds `width * height * 3` bytes).
pub fn write_rgb_png(
    path: &Path,
    size: [u32; 2],
    rgb: &[u8],
    encoding: impl Into<PngEncoding>,
) -> Result<()> {
    let encoding = encoding.into();
    write_atomically(path, |writer| {
        encode_rgb_png(writer, size, rgb, encoding).map_err(std::io::Error::other)
    })
}

/// Writes a figure (a plot, the views, a picture for a paper) as an 8-bit RGB
/// PNG atomically, with its resolution in a `pHYs` chunk: `dpi` pixels per
/// inch, so that an application places it at its printed size (without one,
/// a 96-dpi fallback places a 1051-pixel plot 278 mm wide).
pub fn write_figure_png(path: &Path, size: [u32; 2], rgb: &[u8], dpi: f64) -> Result<()> {
    let ppm = (dpi / 0.0254).round().clamp(1.0, f64::from(u32::MAX)) as u32;
    write_atomically(path, |writer| {
        encode_png(writer, size, rgb, png::Compression::Fast.into(), Some(ppm)).map_err(std::io::Error::other)
    })
}

#[cfg(test)]
mod tests {
    #[test]
    fn a_figure_png_says_300_dpi_in_its_phys_chunk() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("figure.png");
        super::write_figure_png(&path, [3, 2], &[200; 18], 300.0).unwrap();
        let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(&path).unwrap()));
        let reader = decoder.read_info().unwrap();
        let dims = reader.info().pixel_dims.expect("a pHYs chunk");
        // 300 dpi = 11811 pixels per metre (300 / 0.0254).
        assert_eq!((dims.xppu, dims.yppu, dims.unit), (11811, 11811, png::Unit::Meter));
    }
}
