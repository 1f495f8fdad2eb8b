//! The tile decoder: 8-bit, non-interlaced grey, grey-alpha, RGB and RGBA
//! PNGs (every tile a renderer writes), inflated once.
//!
//! Through the png crate a tile was inflated twice: once for its rows and
//! once more by [`crate::png::zlib::verify_image_data`], because the
//! png crate may stop before the zlib trailer and never check the Adler-32.
//! Here the same inflater that produces the rows runs on to the end of the
//! stream and checks its Adler-32, so a tile costs one inflate, and rows are
//! unfiltered straight out of the inflater's buffer
//! ([`crate::png::unfilter`]).
//!
//! It takes only files whose chunks are plain — [`plain_layout`] walks them
//! first and checks every CRC: IHDR, then ancillary chunks, an optional
//! PLTE (RGB/RGBA), consecutive IDATs, and IEND last. Anything else (other
//! formats, interlacing, tRNS, which turns RGB into RGBA, APNG, unknown
//! critical chunks, a bad CRC, a missing IEND) goes to the png crate, which
//! decodes it or names what is wrong exactly as before.

use std::path::Path;

use crate::error::{Error, Result};
use crate::png::format::{HEADER_BYTES, PixelLayout, PngHeader, chunks};
use crate::png::unfilter::{Filter, GROUP, RowGroup, unfilter_rows};
use crate::png::zlib::{MISSING_TRAILER, inflate_message};

/// Deflate looks back at most 32 KiB.
const WINDOW: usize = 32 << 10;
/// The inflater's output buffer, at least (rows are read out of it).
const BUFFER: usize = 256 << 10;
/// Rows longer than this go to the png crate (whose limits then apply): the
/// decoder holds about 13 rows (inflate buffer and row group), allocated
/// before any data is read, so a header may not make them large. Tiles
/// are 1284 pixels wide, a 16k-wide RGBA texture has 64 KiB rows.
const MAX_ROW_BYTES: usize = 1 << 20;

/// What [`plain_layout`] found: the pixel layout and the IDAT payloads.
pub(crate) struct PlainPng<'a> {
    pub layout: PixelLayout,
    pub idat: Vec<&'a [u8]>,
}

/// The layout and image data of a plain 8-bit PNG (see the module doc), or
/// `None` for anything the png crate should handle.
pub(crate) fn plain_layout<'a>(header: &PngHeader, bytes: &'a [u8]) -> Option<PlainPng<'a>> {
    let layout = match (header.bit_depth, header.color_type) {
        (8, 0) => PixelLayout::Gray,
        (8, 2) => PixelLayout::Rgb,
        (8, 4) => PixelLayout::GrayAlpha,
        (8, 6) => PixelLayout::Rgba,
        _ => return None,
    };
    // Compression and filter method 0 (IHDR bytes 26 and 27), no interlacing.
    if header.interlaced || bytes[26] != 0 || bytes[27] != 0 {
        return None;
    }
    let row_bytes = (header.width as usize).checked_mul(layout.bytes_per_pixel())?;
    if row_bytes > MAX_ROW_BYTES {
        return None;
    }
    let idat = plain_chunks(bytes, layout)?;
    Some(PlainPng { layout, idat })
}

/// The IDAT payloads when every chunk after the signature is whole, has a
/// matching CRC and comes in the plain order; `None` otherwise.
fn plain_chunks(bytes: &[u8], layout: PixelLayout) -> Option<Vec<&[u8]>> {
    let mut idat = Vec::new();
    let mut idat_ended = false;
    for (index, chunk) in chunks(bytes).enumerate() {
        if !chunk.crc_matches() {
            return None;
        }
        let kind = chunk.kind;
        match &kind {
            b"IHDR" if index == 0 && chunk.body.len() == 13 => {}
            b"IDAT" if !idat_ended => idat.push(chunk.body),
            b"IEND" if chunk.body.is_empty() && !idat.is_empty() => return Some(idat),
            b"PLTE" if idat.is_empty() && matches!(layout, PixelLayout::Rgb | PixelLayout::Rgba) => {}
            // tRNS would add an alpha channel; APNG is refused by the png crate.
            b"tRNS" | b"acTL" | b"fcTL" | b"fdAT" => return None,
            // Other ancillary chunks (lower-case first letter) are ignored.
            _ if kind[0].is_ascii_lowercase() && kind.iter().all(u8::is_ascii_alphabetic) => {}
            _ => return None,
        }
        idat_ended |= !idat.is_empty() && &kind != b"IDAT";
    }
    None // no IEND
}

/// Rows of a plain PNG, unfiltered as they are inflated, [`GROUP`] at a time.
pub(crate) struct PlainDecoder<'a> {
    path: &'a Path,
    idat: Vec<&'a [u8]>,
    /// The IDAT payload being inflated (what is left of it) and the next one.
    input: &'a [u8],
    next_payload: usize,
    /// Boxed: its tables are large, and the reader is moved around.
    inflater: Box<fdeflate::Decompressor>,
    /// Inflated bytes; `filled` of them valid, those before `taken` used.
    buffer: Vec<u8>,
    filled: usize,
    taken: usize,
    bytes_per_pixel: usize,
    row_bytes: usize,
    height: u32,
    /// Rows unfiltered so far.
    decoded: u32,
    /// `GROUP + 1` rows `pitch` bytes apart: row 0 the last row of the
    /// previous group (zeros above the image), then the group's rows.
    rows: Vec<u8>,
    pitch: usize,
    group_rows: usize,
    /// The group's next row to hand out (1-based).
    group_next: usize,
}

impl<'a> PlainDecoder<'a> {
    pub(crate) fn new(path: &'a Path, header: &PngHeader, plain: PlainPng<'a>) -> PlainDecoder<'a> {
        let bytes_per_pixel = plain.layout.bytes_per_pixel();
        let row_bytes = header.width as usize * bytes_per_pixel;
        // 4 spare bytes per row: the side-by-side unfilter writes 4-byte pixels.
        let pitch = row_bytes + 4;
        PlainDecoder {
            path,
            input: plain.idat[0],
            next_payload: 1,
            idat: plain.idat,
            // Left checking the Adler-32 (the default): the stream is
            // inflated to its end in `finish`.
            inflater: Box::new(fdeflate::Decompressor::new()),
            buffer: spare_buffer(BUFFER.max(WINDOW + 2 * GROUP * (row_bytes + 1) + 8)),
            filled: 0,
            taken: 0,
            bytes_per_pixel,
            row_bytes,
            height: header.height,
            decoded: 0,
            rows: {
                // Row 0 is the zeros above the image; the rest is written
                // before it is read.
                let mut rows = spare_buffer((GROUP + 1) * pitch);
                rows[..pitch].fill(0);
                rows
            },
            pitch,
            group_rows: 0,
            group_next: 1,
        }
    }

    fn error(&self, message: String) -> Error {
        Error::Png { path: self.path.to_path_buf(), message }
    }

    /// The next row, unfiltered; `None` after the last.
    #[inline]
    pub(crate) fn next_row(&mut self) -> Result<Option<&[u8]>> {
        if self.group_next > self.group_rows {
            if self.decoded == self.height {
                return Ok(None);
            }
            self.decode_group()?;
        }
        let start = self.group_next * self.pitch;
        self.group_next += 1;
        Ok(Some(&self.rows[start..start + self.row_bytes]))
    }

    /// Inflates and unfilters the next group of rows.
    fn decode_group(&mut self) -> Result<()> {
        if self.group_rows > 0 {
            let last = self.group_rows * self.pitch;
            self.rows.copy_within(last..last + self.row_bytes, 0);
        }
        let stride = self.row_bytes + 1;
        let want = GROUP.min((self.height - self.decoded) as usize);
        while self.filled - self.taken < want * stride {
            if !self.inflate_more(want * stride + 4)? {
                let available = ((self.filled - self.taken) / stride) as u32;
                return Err(self.error(format!(
                    "the image data ends after {} of its {} rows (truncated or damaged)",
                    self.decoded + available,
                    self.height
                )));
            }
        }
        let mut filters = [Filter::None; GROUP];
        for (k, filter) in filters.iter_mut().enumerate().take(want) {
            let byte = self.buffer[self.taken + k * stride];
            *filter = Filter::from_byte(byte).ok_or_else(|| {
                self.error(format!(
                    "row {} has filter type {byte}, but PNG has only 0 to 4 (corrupt data)",
                    self.decoded as usize + k
                ))
            })?;
        }
        let out = &mut self.rows[..(want + 1) * self.pitch];
        unfilter_rows(RowGroup {
            filters: &filters[..want],
            bpp: self.bytes_per_pixel,
            row_bytes: self.row_bytes,
            filtered: &self.buffer[self.taken..],
            out,
            pitch: self.pitch,
        });
        self.taken += want * stride;
        self.decoded += want as u32;
        (self.group_rows, self.group_next) = (want, 1);
        Ok(())
    }

    /// Inflates more data into the buffer, first making room for `room`
    /// bytes after the unread ones; false when the stream has ended
    /// (checked) and nothing more can come.
    fn inflate_more(&mut self, room: usize) -> Result<bool> {
        if self.inflater.is_done() {
            return Ok(false);
        }
        // Keep the unread bytes and deflate's window; drop the rest.
        if self.buffer.len() - self.taken < room || self.buffer.len() - self.filled < WINDOW / 4 {
            let keep_from = self.taken.min(self.filled.saturating_sub(WINDOW));
            self.buffer.copy_within(keep_from..self.filled, 0);
            self.filled -= keep_from;
            self.taken -= keep_from;
        }
        loop {
            let last = self.next_payload == self.idat.len();
            let (consumed, produced) = self
                .inflater
                .read(self.input, &mut self.buffer, self.filled, last)
                .map_err(|e| self.error(inflate_message(&e)))?;
            self.input = &self.input[consumed..];
            self.filled += produced;
            if produced > 0 || self.inflater.is_done() {
                return Ok(true);
            }
            // With room in the buffer, `read` stops only when the input is
            // used up; anything else would loop for ever.
            if !self.input.is_empty() || last {
                return Err(self.error(MISSING_TRAILER.to_string()));
            }
            self.input = self.idat[self.next_payload];
            self.next_payload += 1;
        }
    }

    /// After the last row: inflates the rest of the stream (data beyond the
    /// rows is ignored, as by every PNG decoder) and fails unless it ends
    /// with its Adler-32.
    pub(crate) fn finish(&mut self) -> Result<()> {
        while !self.inflater.is_done() {
            self.taken = self.filled; // nothing more is read out
            self.inflate_more(0)?;
        }
        Ok(())
    }
}

impl Drop for PlainDecoder<'_> {
    fn drop(&mut self) {
        keep_spare(std::mem::take(&mut self.buffer));
        keep_spare(std::mem::take(&mut self.rows));
    }
}

/// Buffers up to this size are kept for the thread's next tile.
const SPARE_LIMIT: usize = 8 << 20;

thread_local! {
    /// A decoder's buffers, kept for the next tile on this thread: a fresh
    /// 256 KiB buffer per tile cost a zeroing and its page faults each time.
    static SPARES: std::cell::RefCell<Vec<Vec<u8>>> = const { std::cell::RefCell::new(Vec::new()) };
}

/// A buffer of `length` bytes (their contents are whatever a previous tile
/// left, or zeros).
fn spare_buffer(length: usize) -> Vec<u8> {
    let mut buffer = SPARES.with_borrow_mut(|spares| {
        let fits = spares.iter().position(|b| b.capacity() >= length);
        fits.map(|at| spares.swap_remove(at)).unwrap_or_default()
    });
    buffer.resize(length, 0);
    buffer
}

fn keep_spare(buffer: Vec<u8>) {
    if buffer.capacity() > 0 && buffer.capacity() <= SPARE_LIMIT {
        SPARES.with_borrow_mut(|spares| {
            if spares.len() < 4 {
                spares.push(buffer);
            }
        });
    }
}

// [`plain_layout`] reads the compression and filter method from IHDR.
const _: () = assert!(HEADER_BYTES >= 28);
