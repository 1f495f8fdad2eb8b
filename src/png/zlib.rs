//! The zlib stream of a PNG's image data, checked end to end.
//!
//! The png crate verifies the Adler-32 only when its inflater happens to
//! reach the trailer while producing rows, and accepts a stream whose
//! trailer is missing ("libpng generally doesn't treat them as fatal"): a
//! tile with one damaged byte and no trailer would be counted as a
//! neighbouring texel. [`verify_image_data`] inflates the IDAT chunks once
//! more, discarding the output, and fails the file unless the stream ends
//! with a matching Adler-32. Every PNG the analyzer reads (tiles, palette,
//! PIdT) and the capture's `--resume` and `verify` go through it.

use std::path::Path;

use crate::error::{Error, Result};
use crate::png::format::chunks;

/// Output window: deflate looks back at most 32 KiB.
const WINDOW: usize = 32 << 10;
const BUFFER: usize = 256 << 10;

/// The payloads of the IDAT chunks, in order (CRCs are the png crate's to
/// check; a chunk running past the end stops the list).
fn idat_payloads(bytes: &[u8]) -> Vec<&[u8]> {
    let mut payloads = Vec::new();
    for chunk in chunks(bytes) {
        match &chunk.kind {
            b"IDAT" => payloads.push(chunk.body),
            b"IEND" => break,
            _ if !payloads.is_empty() => break, // IDAT chunks are consecutive
            _ => {}
        }
    }
    payloads
}

/// Fails `path` unless the zlib stream of its image data is complete and
/// ends with a matching Adler-32 checksum.
pub fn verify_image_data(path: &Path, bytes: &[u8]) -> Result<()> {
    let failed = |message: String| Error::Png { path: path.to_path_buf(), message };
    let mut inflater = fdeflate::Decompressor::new();
    let mut output = vec![0u8; BUFFER];
    let mut position = 0usize;
    for mut input in idat_payloads(bytes) {
        loop {
            let (consumed, produced) = inflater
                .read(input, &mut output, position, false)
                .map_err(|e| failed(inflate_message(&e)))?;
            input = &input[consumed..];
            position += produced;
            if inflater.is_done() {
                return Ok(());
            }
            if position == output.len() {
                output.copy_within(position - WINDOW..position, 0);
                position = WINDOW;
            } else if input.is_empty() {
                break;
            }
        }
    }
    Err(failed(MISSING_TRAILER.to_string()))
}

/// Why a zlib stream that stops before its checksum is refused.
pub(crate) const MISSING_TRAILER: &str = "the image data's zlib stream ends without its Adler-32 checksum \
     (truncated or damaged data cannot be trusted)";

/// What an inflate error means, for the file's error message.
pub(crate) fn inflate_message(error: &fdeflate::DecompressionError) -> String {
    match error {
        fdeflate::DecompressionError::WrongChecksum => {
            "the image data's zlib checksum (Adler-32) does not match: the data is damaged".to_string()
        }
        fdeflate::DecompressionError::InsufficientInput => MISSING_TRAILER.to_string(),
        other => format!("the image data's zlib stream is corrupt ({other:?})"),
    }
}
