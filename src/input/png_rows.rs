//! PNG reading: cheap headers, streaming rows for tiles, whole images for textures.
//!
//! Tiles are read whole (compressed) and decoded row by row, so a worker
//! holds the compressed bytes and one row. (They used to be memory-mapped; a
//! tile truncated by another process while mapped kills the process with
//! SIGBUS, while a read just sees a short, reported file.) The zlib stream
//! of the image data must be whole and end with a matching Adler-32
//! ([`crate::input::png_zlib`]): a corrupted IDAT with valid chunk CRCs, or
//! one without its trailer, must fail, not count wrong texels. Every accepted PNG is turned into 8-bit
//! samples (palette and low-bit grey expanded); 16-bit images are rejected,
//! because their colours cannot name 8-bit palette texels exactly.

use std::io::Cursor;
use std::ops::Deref;
use std::path::Path;

use crate::error::{Error, Result};
use crate::input::png_zlib::verify_image_data;

/// The bytes of an input file, read whole.
pub struct FileBytes(Vec<u8>);

impl Deref for FileBytes {
    type Target = [u8];
    fn deref(&self) -> &[u8] {
        &self.0
    }
}

/// Reads `path` (a regular file; see [`crate::files`]).
pub fn read_file(path: &Path) -> Result<FileBytes> {
    crate::files::read_limited(path, crate::files::IMAGE_LIMIT).map(FileBytes)
}

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

/// A streaming decoder over a PNG held in memory.
pub struct RowReader<'a> {
    reader: png::Reader<Cursor<&'a [u8]>>,
    layout: PixelLayout,
    path: &'a Path,
    bytes: &'a [u8],
}

impl<'a> RowReader<'a> {
    /// Reads the PNG's header chunks and prepares row decoding.
    pub fn new(path: &'a Path, bytes: &'a [u8]) -> Result<RowReader<'a>> {
        // Cheap structural checks first give clearer messages than the decoder's.
        let header = parse_header(path, bytes)?;
        if header.color_type == INDEXED {
            check_palette_indices(path, bytes)?;
        }
        // The png crate skips the zlib checksum by default, and checks it only
        // when its inflater reaches the trailer: [`RowReader::finish`]
        // verifies the whole stream instead ([`verify_image_data`]).
        let mut decoder = png::Decoder::new(Cursor::new(bytes));
        decoder.set_transformations(png::Transformations::EXPAND);
        let reader = decoder.read_info().map_err(|e| png_error(path, e))?;
        let info = reader.info();
        if info.bit_depth == png::BitDepth::Sixteen {
            return Err(Error::UnsupportedPng {
                path: path.to_path_buf(),
                message: "16-bit PNG: its colours cannot be mapped to 8-bit palette texels exactly; \
                          render or save the tiles as 8-bit RGB"
                    .to_string(),
            });
        }
        if info.animation_control.is_some() {
            return Err(Error::UnsupportedPng {
                path: path.to_path_buf(),
                message: "animated PNG (APNG): save each frame as its own PNG".to_string(),
            });
        }
        let layout = match reader.output_color_type() {
            (png::ColorType::Grayscale, png::BitDepth::Eight) => PixelLayout::Gray,
            (png::ColorType::GrayscaleAlpha, png::BitDepth::Eight) => PixelLayout::GrayAlpha,
            (png::ColorType::Rgb, png::BitDepth::Eight) => PixelLayout::Rgb,
            (png::ColorType::Rgba, png::BitDepth::Eight) => PixelLayout::Rgba,
            (color, depth) => {
                return Err(Error::UnsupportedPng {
                    path: path.to_path_buf(),
                    message: format!("unsupported sample format {color:?} at {depth:?} after expansion"),
                });
            }
        };
        Ok(RowReader { reader, layout, path, bytes })
    }

    /// Sample layout of the rows this reader returns.
    pub fn layout(&self) -> PixelLayout {
        self.layout
    }

    /// Image width in pixels.
    pub fn width(&self) -> u32 {
        self.reader.info().width
    }

    /// Image height in pixels.
    pub fn height(&self) -> u32 {
        self.reader.info().height
    }

    /// Whether rows come in Adam7 passes ([`RowReader::next_row`]) rather
    /// than in raster order.
    pub fn interlaced(&self) -> bool {
        self.reader.info().interlaced
    }

    /// The next decoded row. For interlaced images these are the rows of the
    /// seven passes in turn: every pixel is returned exactly once, but not in
    /// raster order (which counting does not need).
    #[inline]
    pub fn next_row(&mut self) -> Result<Option<&[u8]>> {
        match self.reader.next_row() {
            Ok(Some(row)) => Ok(Some(row.data())),
            Ok(None) => Ok(None),
            Err(error) => Err(png_error(self.path, error)),
        }
    }

    /// Reads to the end of the file after the last row and verifies that
    /// the image data's zlib stream is whole and ends with a matching
    /// Adler-32 (call once `next_row` is done; a file that fails here must
    /// not be counted).
    pub fn finish(&mut self) -> Result<()> {
        self.reader.finish().map_err(|e| png_error(self.path, e))?;
        verify_image_data(self.path, self.bytes)
    }

    /// Decodes the whole image in raster order into packed `0xRRGGBB` colours.
    pub fn into_colors(mut self) -> Result<Vec<u32>> {
        let size = self.reader.output_buffer_size().ok_or_else(|| Error::Png {
            path: self.path.to_path_buf(),
            message: "image too large to decode".to_string(),
        })?;
        let mut buffer = vec![0u8; size];
        self.reader.next_frame(&mut buffer).map_err(|e| png_error(self.path, e))?;
        self.finish()?;
        let step = self.layout.bytes_per_pixel();
        let layout = self.layout;
        Ok(buffer.chunks_exact(step).map(|pixel| layout.pack(pixel)).collect())
    }
}

/// PNG colour type 3: palette indices.
const INDEXED: u8 = 3;

/// An index beyond the PLTE's entries is corrupt data, but the png crate
/// expands it to black, which names texel 0 (or another texel): refuse the
/// file instead. Only images whose PLTE is shorter than their bit depth
/// allows can hold such an index; those are decoded once more, unexpanded,
/// to check every index (indexed tiles are rare: renderers write RGB).
fn check_palette_indices(path: &Path, bytes: &[u8]) -> Result<()> {
    let mut decoder = png::Decoder::new(Cursor::new(bytes));
    decoder.set_transformations(png::Transformations::IDENTITY);
    let mut reader = decoder.read_info().map_err(|e| png_error(path, e))?;
    let info = reader.info();
    let depth = info.bit_depth as u8;
    let entries = info.palette.as_ref().map_or(0, |p| p.len() / 3);
    if entries >= 1usize << depth {
        return Ok(());
    }
    // Row by row: a header may claim billions of rows that the data does not hold.
    let (width, height) = (info.width, info.height);
    let mut rows = decoded_rows(width, height, info.interlaced);
    let per_byte = 8 / usize::from(depth);
    let mask = ((1u16 << depth) - 1) as u8;
    while let Some(row) = reader.next_row().map_err(|e| png_error(path, e))? {
        let (y, x0, dx) = rows.next().unwrap_or((0, 0, 1));
        // Interlaced passes have shorter rows; bits past the last pixel are
        // zero padding, index 0, which a PLTE of at least one entry has.
        let data = row.data();
        let pixels = (u64::from(width).saturating_sub(u64::from(x0))).div_ceil(u64::from(dx)) as usize;
        for i in 0..(data.len() * per_byte).min(pixels) {
            let shift = 8 - usize::from(depth) * (i % per_byte + 1);
            let index = usize::from((data[i / per_byte] >> shift) & mask);
            if index >= entries {
                let x = u64::from(x0) + i as u64 * u64::from(dx);
                return Err(Error::Png {
                    path: path.to_path_buf(),
                    message: format!(
                        "pixel ({x}, {y}) has palette index {index}, but the PLTE has {entries} entries \
                         (corrupt data; it would decode as black)"
                    ),
                });
            }
        }
    }
    Ok(())
}

/// The image row, first column and column step of each row the decoder
/// returns, in order: raster order, or the rows of the seven Adam7 passes
/// in turn (passes without pixels have no rows).
fn decoded_rows(width: u32, height: u32, interlaced: bool) -> Box<dyn Iterator<Item = (u32, u32, u32)>> {
    if !interlaced {
        return Box::new((0..height).map(|y| (y, 0, 1)));
    }
    const PASSES: [(u32, u32, u32, u32); 7] =
        [(0, 0, 8, 8), (4, 0, 8, 8), (0, 4, 4, 8), (2, 0, 4, 4), (0, 2, 2, 4), (1, 0, 2, 2), (0, 1, 1, 2)];
    Box::new(
        PASSES
            .into_iter()
            .filter(move |&(x0, y0, _, _)| x0 < width && y0 < height)
            .flat_map(move |(x0, y0, dx, dy)| (y0..height).step_by(dy as usize).map(move |y| (y, x0, dx))),
    )
}

fn png_error(path: &Path, error: png::DecodingError) -> Error {
    let message = match error {
        png::DecodingError::IoError(io) if io.kind() == std::io::ErrorKind::UnexpectedEof => {
            "truncated (file ends before the image data does)".to_string()
        }
        other => other.to_string(),
    };
    Error::Png { path: path.to_path_buf(), message }
}

/// A whole decoded image as packed colours, row 0 first.
pub struct ColorImage {
    pub width: u32,
    pub height: u32,
    pub colors: Vec<u32>,
}

/// Decodes a texture (palette or PIdT) completely. `check_size` sees the
/// width and height from the header first, so a wrong or absurd size is
/// rejected before anything is allocated.
pub fn read_color_image(path: &Path, check_size: impl FnOnce(u32, u32) -> Result<()>) -> Result<ColorImage> {
    let bytes = read_file(path)?;
    let header = parse_header(path, &bytes)?;
    check_size(header.width, header.height)?;
    let reader = RowReader::new(path, &bytes)?;
    let (width, height) = (reader.width(), reader.height());
    let colors = reader.into_colors()?;
    Ok(ColorImage { width, height, colors })
}
