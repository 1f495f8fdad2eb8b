//! PNG reading: cheap headers, streaming rows for tiles, whole images for textures.
//!
//! Tiles are read whole (compressed) and decoded row by row, so a worker
//! holds the compressed bytes and one row. (They used to be memory-mapped; a
//! tile truncated by another process while mapped kills the process with
//! SIGBUS, while a read just sees a short, reported file.) The zlib stream
//! of the image data must be whole and end with a matching Adler-32
//! ([`crate::png::zlib`]): a corrupted IDAT with valid chunk CRCs, or
//! one without its trailer, must fail, not count wrong texels. Every accepted PNG is turned into 8-bit
//! samples (palette and low-bit grey expanded); 16-bit images are rejected,
//! because their colours cannot name 8-bit palette texels exactly.

use std::io::Cursor;
use std::ops::Deref;
use std::path::Path;

use crate::error::{Error, Result};
use crate::png::decode::{PlainDecoder, plain_layout};
pub use crate::png::format::PixelLayout;
pub(crate) use crate::png::format::{HEADER_BYTES, PngHeader, parse_header};
use crate::png::zlib::verify_image_data;

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

/// A streaming decoder over a PNG held in memory: tiles as renderers write
/// them through the one-inflate decoder of [`crate::png::decode`],
/// everything else through the png crate.
pub struct RowReader<'a> {
    decoder: Decoder<'a>,
    layout: PixelLayout,
    path: &'a Path,
    bytes: &'a [u8],
    header: PngHeader,
}

enum Decoder<'a> {
    Plain(PlainDecoder<'a>),
    // Boxed: the png crate's reader is large and the plain path is the common one.
    Crate(Box<png::Reader<Cursor<&'a [u8]>>>),
}

impl<'a> RowReader<'a> {
    /// Reads the PNG's header chunks and prepares row decoding.
    pub fn new(path: &'a Path, bytes: &'a [u8]) -> Result<RowReader<'a>> {
        // Cheap structural checks first give clearer messages than the decoder's.
        let header = parse_header(path, bytes)?;
        if let Some(plain) = plain_layout(&header, bytes) {
            let layout = plain.layout;
            let decoder = Decoder::Plain(PlainDecoder::new(path, &header, plain));
            return Ok(RowReader { decoder, layout, path, bytes, header });
        }
        RowReader::with_png_crate(path, bytes, header)
    }

    /// The png crate's decoder, for every PNG that is not plain.
    pub(crate) fn with_png_crate(
        path: &'a Path,
        bytes: &'a [u8],
        header: PngHeader,
    ) -> Result<RowReader<'a>> {
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
        Ok(RowReader { decoder: Decoder::Crate(Box::new(reader)), layout, path, bytes, header })
    }

    /// Sample layout of the rows this reader returns.
    pub fn layout(&self) -> PixelLayout {
        self.layout
    }

    /// Image width in pixels.
    pub fn width(&self) -> u32 {
        self.header.width
    }

    /// Image height in pixels.
    pub fn height(&self) -> u32 {
        self.header.height
    }

    /// Whether rows come in Adam7 passes ([`RowReader::next_row`]) rather
    /// than in raster order.
    pub fn interlaced(&self) -> bool {
        self.header.interlaced
    }

    /// The next decoded row. For interlaced images these are the rows of the
    /// seven passes in turn: every pixel is returned exactly once, but not in
    /// raster order (which counting does not need).
    #[inline]
    pub fn next_row(&mut self) -> Result<Option<&[u8]>> {
        match &mut self.decoder {
            Decoder::Plain(plain) => plain.next_row(),
            Decoder::Crate(reader) => match reader.next_row() {
                Ok(Some(row)) => Ok(Some(row.data())),
                Ok(None) => Ok(None),
                Err(error) => Err(png_error(self.path, error)),
            },
        }
    }

    /// Reads to the end of the file after the last row and verifies that
    /// the image data's zlib stream is whole and ends with a matching
    /// Adler-32 (call once `next_row` is done; a file that fails here must
    /// not be counted).
    pub fn finish(&mut self) -> Result<()> {
        match &mut self.decoder {
            // Its one inflate has run to the checksum.
            Decoder::Plain(plain) => plain.finish(),
            Decoder::Crate(reader) => {
                reader.finish().map_err(|e| png_error(self.path, e))?;
                verify_image_data(self.path, self.bytes)
            }
        }
    }

    /// Decodes the whole image in raster order into packed `0xRRGGBB` colours.
    pub fn into_colors(mut self) -> Result<Vec<u32>> {
        let (layout, step) = (self.layout, self.layout.bytes_per_pixel());
        let pack_all = |colors: &mut Vec<u32>, buffer: &[u8]| {
            colors.extend(buffer.chunks_exact(step).map(|pixel| layout.pack(pixel)));
        };
        let mut colors = Vec::new();
        match &mut self.decoder {
            // No reservation from the header: a forged height would ask for
            // it before any row is shown to exist.
            Decoder::Plain(_) => {
                while let Some(row) = self.next_row()? {
                    pack_all(&mut colors, row);
                }
            }
            Decoder::Crate(reader) => {
                let size = reader.output_buffer_size().ok_or_else(|| Error::Png {
                    path: self.path.to_path_buf(),
                    message: "image too large to decode".to_string(),
                })?;
                let mut buffer = vec![0u8; size];
                reader.next_frame(&mut buffer).map_err(|e| png_error(self.path, e))?;
                pack_all(&mut colors, &buffer);
            }
        }
        self.finish()?;
        Ok(colors)
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
    let mut rows = decoded_rows([width, height], info.interlaced);
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
fn decoded_rows([width, height]: [u32; 2], interlaced: bool) -> Box<dyn Iterator<Item = (u32, u32, u32)>> {
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
/// `[width, height]` from the header first, so a wrong or absurd size is
/// rejected before anything is allocated.
pub fn read_color_image(path: &Path, check_size: impl FnOnce([u32; 2]) -> Result<()>) -> Result<ColorImage> {
    let bytes = read_file(path)?;
    let header = parse_header(path, &bytes)?;
    check_size([header.width, header.height])?;
    let reader = RowReader::new(path, &bytes)?;
    let (width, height) = (reader.width(), reader.height());
    let colors = reader.into_colors()?;
    Ok(ColorImage { width, height, colors })
}

#[cfg(test)]
mod tests {
    //! The plain decoder ([`crate::png::decode`]) against the png
    //! crate's rows, and what it refuses.
    use super::*;
    use crate::png::decode::plain_layout;
    use crate::png::format::png_from_chunks;

    const PATH: &str = "tile.png";

    fn png_with(
        size: [u32; 2],
        color_type: u8,
        zlib: &[u8],
        split: usize,
        extra: &[(&[u8; 4], &[u8])],
    ) -> Vec<u8> {
        let mut ihdr = Vec::new();
        ihdr.extend(size[0].to_be_bytes());
        ihdr.extend(size[1].to_be_bytes());
        ihdr.extend([8, color_type, 0, 0, 0]);
        let mut chunks: Vec<(&[u8; 4], &[u8])> = vec![(b"IHDR", &ihdr)];
        chunks.extend(extra.iter().copied());
        chunks.extend(zlib.chunks(split.max(1)).map(|part| (b"IDAT", part)));
        chunks.push((b"IEND", &[]));
        png_from_chunks(&chunks)
    }

    /// Deterministic pseudo-random bytes.
    fn noise(seed: u64, length: usize) -> Vec<u8> {
        let mut state = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
        (0..length)
            .map(|_| {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                (state >> 24) as u8
            })
            .collect()
    }

    /// Filtered scanlines: each row a filter byte (cycling through 0–4, or
    /// `filter`) and random bytes, so every filter meets every neighbour.
    fn scanlines(seed: u64, row_bytes: usize, height: usize, filter: Option<u8>) -> Vec<u8> {
        let data = noise(seed, row_bytes * height);
        let mut out = Vec::new();
        for (y, row) in data.chunks(row_bytes.max(1)).enumerate().take(height) {
            out.push(filter.unwrap_or((y % 5) as u8));
            out.extend(row);
        }
        out
    }

    type Rows = Result<Vec<Vec<u8>>>;

    fn rows(reader: &mut RowReader) -> Rows {
        let mut rows = Vec::new();
        while let Some(row) = reader.next_row()? {
            rows.push(row.to_vec());
        }
        reader.finish()?;
        Ok(rows)
    }

    /// Rows through the plain decoder and through the png crate.
    fn both(bytes: &[u8]) -> (Rows, Rows) {
        let path = Path::new(PATH);
        let header = parse_header(path, bytes).unwrap();
        assert!(plain_layout(&header, bytes).is_some(), "a plain PNG");
        let plain = RowReader::new(path, bytes).and_then(|mut r| rows(&mut r));
        let reference = RowReader::with_png_crate(path, bytes, header).and_then(|mut r| rows(&mut r));
        (plain, reference)
    }

    #[test]
    fn plain_pngs_decode_to_the_png_crates_rows_for_every_filter_and_layout() {
        for (color_type, bpp) in [(0u8, 1usize), (4, 2), (2, 3), (6, 4)] {
            for width in [1u32, 2, 5, 16, 33] {
                for filter in [None, Some(0), Some(1), Some(2), Some(3), Some(4)] {
                    let seed = u64::from(width) * 31 + u64::from(color_type);
                    // Two whole groups of rows for the side-by-side
                    // unfilter, and a partial one.
                    let data = scanlines(seed, width as usize * bpp, 19, filter);
                    let zlib = fdeflate::compress_to_vec(&data);
                    let bytes = png_with([width, 19], color_type, &zlib, 13, &[(b"tEXt", b"k\0v")]);
                    let (plain, reference) = both(&bytes);
                    assert_eq!(
                        plain.unwrap(),
                        reference.unwrap(),
                        "type {color_type} width {width} {filter:?}"
                    );
                }
            }
        }
    }

    #[test]
    fn random_filter_mixes_and_sizes_decode_to_the_png_crates_rows() {
        // Each row's filter drawn at random, so groups of rows meet every
        // mix the side-by-side unfilter may take or refuse.
        let dice = noise(99, 4 * 300);
        for case in 0..300usize {
            let roll = |k: usize| usize::from(dice[4 * case + k]);
            let (color_type, bpp) = [(2u8, 3usize), (6, 4), (0, 1), (4, 2)][roll(0) % 4];
            let (width, height) = (1 + roll(1) % 90, 1 + roll(2) % 40);
            let row_bytes = width * bpp;
            let mut data = scanlines(case as u64, row_bytes, height, None);
            let filters = noise(case as u64 + 1000, height);
            for (y, filter) in filters.iter().enumerate() {
                data[y * (row_bytes + 1)] = filter % 5;
            }
            let zlib = fdeflate::compress_to_vec(&data);
            let bytes = png_with([width as u32, height as u32], color_type, &zlib, 1 + roll(3) * 50, &[]);
            let (plain, reference) = both(&bytes);
            assert_eq!(plain.unwrap(), reference.unwrap(), "case {case}: type {color_type} {width}×{height}");
        }
    }

    #[test]
    fn rows_longer_than_the_inflate_buffer_and_many_of_them_decode_exactly() {
        // 1.7 MB of RGBA in 40 KB rows: the buffer is compacted many times.
        let (width, height) = (10_000u32, 43u32);
        let data = scanlines(7, width as usize * 4, height as usize, None);
        let bytes = png_with([width, height], 6, &fdeflate::compress_to_vec(&data), 1 << 16, &[]);
        let (plain, reference) = both(&bytes);
        let plain = plain.unwrap();
        assert_eq!(plain.len(), height as usize);
        assert_eq!(plain, reference.unwrap());
    }

    #[test]
    fn a_damaged_stream_a_missing_checksum_or_missing_rows_are_refused() {
        let data = scanlines(3, 3 * 20, 10, None);
        let zlib = fdeflate::compress_to_vec(&data);
        let decode = |zlib: &[u8]| {
            let bytes = png_with([20, 10], 2, zlib, 1 << 20, &[]);
            let path = Path::new(PATH);
            RowReader::new(path, &bytes).and_then(|mut r| rows(&mut r)).map_err(|e| e.to_string())
        };
        assert!(decode(&zlib).is_ok());
        let mut checksum = zlib.clone();
        *checksum.last_mut().unwrap() ^= 1;
        assert!(decode(&checksum).unwrap_err().contains("Adler-32"), "{:?}", decode(&checksum));
        let trailer_cut = &zlib[..zlib.len() - 4];
        assert!(decode(trailer_cut).unwrap_err().contains("Adler-32"), "{:?}", decode(trailer_cut));
        let short = fdeflate::compress_to_vec(&data[..data.len() - 61]);
        let message = decode(&short).unwrap_err();
        assert!(message.contains("ends after 9 of its 10 rows"), "{message}");
        let mut filter = data.clone();
        filter[61 * 4] = 7;
        let message = decode(&fdeflate::compress_to_vec(&filter)).unwrap_err();
        assert!(message.contains("row 4 has filter type 7"), "{message}");
        assert!(message.contains(PATH), "{message}");
    }

    #[test]
    fn only_plain_chunk_layouts_take_the_fast_path() {
        let data = scanlines(1, 12, 2, Some(0));
        let zlib = fdeflate::compress_to_vec(&data);
        let plain =
            |bytes: &[u8]| plain_layout(&parse_header(Path::new(PATH), bytes).unwrap(), bytes).is_some();
        assert!(plain(&png_with([4, 2], 2, &zlib, 5, &[(b"PLTE", &[0; 3]), (b"gAMA", &[0; 4])])));
        assert!(!plain(&png_with([4, 2], 2, &zlib, 5, &[(b"tRNS", &[0; 6])])), "tRNS adds alpha");
        assert!(!plain(&png_with([4, 2], 2, &zlib, 5, &[(b"acTL", &[0; 8])])), "APNG");
        assert!(!plain(&png_with([4, 2], 2, &zlib, 5, &[(b"XYZW", &[])])), "unknown critical chunk");
        let mut bad_crc = png_with([4, 2], 2, &zlib, 5, &[]);
        let at = bad_crc.len() - 13; // the last IDAT's CRC
        bad_crc[at] ^= 1;
        assert!(!plain(&bad_crc), "a bad CRC is the png crate's to report");
        let no_end = png_with([4, 2], 2, &zlib, 5, &[]);
        assert!(!plain(&no_end[..no_end.len() - 12]), "no IEND");
        let mut interlaced = png_with([4, 2], 2, &zlib, 5, &[]);
        interlaced[28] = 1;
        assert!(!plain(&interlaced));
        assert!(!plain(&png_with([4, 2], 3, &zlib, 5, &[(b"PLTE", &[0; 3])])), "palette images");
        // A header may not make the decoder's buffers large (1.2 MB rows).
        assert!(!plain(&png_with([300_000, 2], 6, &zlib, 5, &[])), "rows over 1 MiB");
        assert!(plain(&png_with([200_000, 2], 6, &zlib, 5, &[])), "rows under 1 MiB");
    }
}
