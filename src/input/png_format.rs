//! What a PNG says about itself before any pixel is decoded: the IHDR
//! header ([`parse_header`]) and the layout of decoded samples
//! ([`PixelLayout`]). Both decoders ([`crate::input::png_rows`] over the png
//! crate, [`crate::input::png_decode`] for plain tiles) start from here.

use std::path::Path;

use crate::error::{Error, Result};

/// What the IHDR chunk says, read without decoding anything.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PngHeader {
    pub width: u32,
    pub height: u32,
    pub bit_depth: u8,
    pub color_type: u8,
    pub interlaced: bool,
}

const SIGNATURE: [u8; 8] = [0x89, b'P', b'N', b'G', 0x0D, 0x0A, 0x1A, 0x0A];

/// Bytes needed by [`parse_header`]: signature, IHDR length, type and body.
pub const HEADER_BYTES: usize = 8 + 8 + 13;

/// Reads width, height and format from the first [`HEADER_BYTES`] bytes.
pub fn parse_header(path: &Path, bytes: &[u8]) -> Result<PngHeader> {
    let png_error = |message: &str| Error::Png { path: path.to_path_buf(), message: message.to_string() };
    if bytes.is_empty() {
        return Err(png_error("empty file (0 bytes)"));
    }
    if bytes.len() < 8 || bytes[..8] != SIGNATURE {
        return Err(png_error("no PNG signature (not a PNG file)"));
    }
    if bytes.len() < HEADER_BYTES {
        return Err(png_error("truncated before the end of the IHDR header"));
    }
    if &bytes[12..16] != b"IHDR" {
        return Err(png_error("first chunk is not IHDR"));
    }
    let be32 = |at: usize| u32::from_be_bytes([bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]]);
    let header = PngHeader {
        width: be32(16),
        height: be32(20),
        bit_depth: bytes[24],
        color_type: bytes[25],
        interlaced: bytes[28] != 0,
    };
    if header.width == 0 || header.height == 0 {
        return Err(png_error("image has zero width or height"));
    }
    Ok(header)
}

/// How the decoded samples of one pixel are laid out (always 8 bits each).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PixelLayout {
    Gray,
    GrayAlpha,
    Rgb,
    Rgba,
}

impl PixelLayout {
    /// Bytes per pixel.
    pub const fn bytes_per_pixel(self) -> usize {
        match self {
            PixelLayout::Gray => 1,
            PixelLayout::GrayAlpha => 2,
            PixelLayout::Rgb => 3,
            PixelLayout::Rgba => 4,
        }
    }

    /// The packed `0xRRGGBB` colour of one pixel's samples (alpha ignored).
    #[inline(always)]
    pub fn pack(self, pixel: &[u8]) -> u32 {
        match self {
            PixelLayout::Gray | PixelLayout::GrayAlpha => u32::from(pixel[0]) * 0x01_0101,
            PixelLayout::Rgb | PixelLayout::Rgba => {
                (u32::from(pixel[0]) << 16) | (u32::from(pixel[1]) << 8) | u32::from(pixel[2])
            }
        }
    }
}
