//! What a PNG says about itself before any pixel is decoded: the IHDR
//! header ([`parse_header`]), its chunks ([`chunks`]) and the layout of
//! decoded samples ([`PixelLayout`]). Both decoders ([`crate::png::rows`] over the png
//! crate, [`crate::png::decode`] for plain tiles) start from here.

use std::path::Path;

use crate::error::{Error, Result};

/// What the IHDR chunk says, read without decoding anything.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct PngHeader {
    pub width: u32,
    pub height: u32,
    pub bit_depth: u8,
    pub color_type: u8,
    pub interlaced: bool,
}

const SIGNATURE: [u8; 8] = [0x89, b'P', b'N', b'G', 0x0D, 0x0A, 0x1A, 0x0A];

/// Bytes needed by [`parse_header`]: signature, IHDR length, type and body.
pub(crate) const HEADER_BYTES: usize = 8 + 8 + 13;

/// Reads width, height and format from the first [`HEADER_BYTES`] bytes.
pub(crate) fn parse_header(path: &Path, bytes: &[u8]) -> Result<PngHeader> {
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

/// One chunk of a PNG: its type and data, and the CRC stored after them.
pub(crate) struct Chunk<'a> {
    pub kind: [u8; 4],
    pub body: &'a [u8],
    /// Type and data: what the CRC covers.
    covered: &'a [u8],
    stored_crc: u32,
}

impl Chunk<'_> {
    /// Whether the stored CRC is that of the chunk's type and data.
    pub(crate) fn crc_matches(&self) -> bool {
        crc32fast::hash(self.covered) == self.stored_crc
    }
}

/// The chunks after the signature, in order, up to the first that does not
/// fit in `bytes` with its CRC or claims more than 2³¹ − 1 bytes.
pub(crate) fn chunks(bytes: &[u8]) -> impl Iterator<Item = Chunk<'_>> {
    let be32 = |b: &[u8]| u32::from_be_bytes([b[0], b[1], b[2], b[3]]);
    let mut at = 8usize;
    std::iter::from_fn(move || {
        let header = bytes.get(at..at.checked_add(8)?)?;
        let length = be32(header);
        if length > i32::MAX as u32 {
            return None;
        }
        let body_end = (at + 8).checked_add(length as usize)?;
        let crc = bytes.get(body_end..body_end.checked_add(4)?)?;
        let chunk = Chunk {
            kind: [header[4], header[5], header[6], header[7]],
            body: &bytes[at + 8..body_end],
            covered: &bytes[at + 4..body_end],
            stored_crc: be32(crc),
        };
        at = body_end + 4;
        Some(chunk)
    })
}

/// A PNG file's bytes: the signature, then each `(type, body)` chunk with
/// its length and CRC. For tests that need damaged or unusual PNGs (the
/// decoder's unit tests, and the integration tests through
/// `ufcsr::synthetic`).
#[cfg(any(test, feature = "synthetic"))]
pub fn png_from_chunks(chunks: &[(&[u8; 4], &[u8])]) -> Vec<u8> {
    let mut png = vec![0x89, b'P', b'N', b'G', 0x0D, 0x0A, 0x1A, 0x0A];
    for (kind, body) in chunks {
        png.extend((body.len() as u32).to_be_bytes());
        let start = png.len();
        png.extend(*kind);
        png.extend(*body);
        let crc = crc32fast::hash(&png[start..]);
        png.extend(crc.to_be_bytes());
    }
    png
}
