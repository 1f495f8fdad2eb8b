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
    [width, height]: [u32; 2],
    rgb: &[u8],
    encoding: PngEncoding,
) -> std::result::Result<(), png::EncodingError> {
    let mut encoder = png::Encoder::new(writer, width, height);
    encoder.set_color(png::ColorType::Rgb);
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
