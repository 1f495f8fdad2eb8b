//! `texel-area.f32`: the per-texel angular area (deg²·s,
//! [`crate::Analysis::texel_angular_area`]) kept beside `result.json`, so
//! that what draws a result later (the comparison page on one colour scale,
//! the capture's `views`) paints the measure to quote from the values
//! themselves, not from `heatmap-area.png`'s colours and not from a
//! re-analysis.
//!
//! Why a raster and not a `result.json` field: the values are floats for
//! every texel (up to 2^24), which JSON would spell out at ~10 bytes each and
//! parse slowly; this file is exactly the analysis' `f32`s. Layout (all
//! little-endian): the 20-byte magic [`TEXEL_AREA_MAGIC`], the palette's
//! width and height (`u32` each), then `width × height` `f32` values, row-major
//! like `result.json`'s texel counts. The reader checks the magic, the size
//! against the result's palette, and every value (finite, ≥ 0): a truncated,
//! foreign or edited file is an error naming it, never a wrong picture.

use std::path::Path;

use crate::error::{Error, Result};

/// The file's name in a result set.
pub const TEXEL_AREA_FILE: &str = "texel-area.f32";

/// The first bytes of the file: format name and version.
pub const TEXEL_AREA_MAGIC: &[u8; 20] = b"ufcsr-texel-area/1\n\0";

/// Bytes before the values: magic, width, height.
const HEADER: usize = TEXEL_AREA_MAGIC.len() + 8;

/// Writes `values` (deg²·s per texel, `width × height`, row-major) to
/// `path` atomically.
pub fn write_texel_area(path: &Path, width: u32, height: u32, values: &[f32]) -> Result<()> {
    let mut bytes = Vec::with_capacity(HEADER + values.len() * 4);
    bytes.extend_from_slice(TEXEL_AREA_MAGIC);
    bytes.extend_from_slice(&width.to_le_bytes());
    bytes.extend_from_slice(&height.to_le_bytes());
    for value in values {
        bytes.extend_from_slice(&value.to_le_bytes());
    }
    crate::files::write_bytes_atomically(path, &bytes)
}

/// Reads `path`, which must hold `width × height` values (the palette of
/// the result it sits beside). The read is capped at exactly that size.
pub fn read_texel_area(path: &Path, width: u32, height: u32) -> Result<Vec<f32>> {
    let texels = width as usize * height as usize;
    let expected = HEADER + texels * 4;
    let bytes = crate::files::read_limited(path, expected as u64)?;
    parse_texel_area(path, &bytes, width, height)
}

/// [`read_texel_area`] of the file's bytes (`path` names it in messages).
pub fn parse_texel_area(path: &Path, bytes: &[u8], width: u32, height: u32) -> Result<Vec<f32>> {
    let bad = |what: String| Error::bad_file(path, what);
    if bytes.len() < HEADER || &bytes[..TEXEL_AREA_MAGIC.len()] != TEXEL_AREA_MAGIC {
        return Err(bad("not a ufcsr texel-area.f32 (ufcsr-texel-area/1) file".into()));
    }
    let word = |at: usize| u32::from_le_bytes([bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]]);
    let (w, h) = (word(TEXEL_AREA_MAGIC.len()), word(TEXEL_AREA_MAGIC.len() + 4));
    if (w, h) != (width, height) {
        return Err(bad(format!("holds a {w}×{h} raster but the result's palette is {width}×{height}")));
    }
    let texels = width as usize * height as usize;
    if bytes.len() != HEADER + texels * 4 {
        return Err(bad(format!(
            "{} bytes where a {width}×{height} raster takes {} (truncated or edited?)",
            bytes.len(),
            HEADER + texels * 4
        )));
    }
    let values: Vec<f32> =
        bytes[HEADER..].chunks_exact(4).map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]])).collect();
    if let Some(at) = values.iter().position(|v| !v.is_finite() || *v < 0.0) {
        return Err(bad(format!("texel {at} holds {}: not an angular area (finite, ≥ 0)", values[at])));
    }
    Ok(values)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_written_raster_reads_back_exactly_and_a_wrong_one_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join(TEXEL_AREA_FILE);
        let values = [0.0, 1.5e-7, 0.0137, 3.0e4, 0.0, 2.0];
        write_texel_area(&path, 3, 2, &values).unwrap();
        assert_eq!(read_texel_area(&path, 3, 2).unwrap(), values);
        // Another palette size, a truncated file, a foreign file, a bad value.
        assert!(read_texel_area(&path, 2, 3).unwrap_err().to_string().contains("palette is 2×3"));
        assert!(read_texel_area(&path, 4, 2).is_err());
        let bytes = std::fs::read(&path).unwrap();
        assert!(
            parse_texel_area(&path, &bytes[..bytes.len() - 1], 3, 2)
                .unwrap_err()
                .to_string()
                .contains("bytes")
        );
        assert!(parse_texel_area(&path, b"PNG....", 3, 2).unwrap_err().to_string().contains("not a ufcsr"));
        let mut nan = bytes.clone();
        nan[HEADER + 4..HEADER + 8].copy_from_slice(&f32::NAN.to_le_bytes());
        assert!(parse_texel_area(&path, &nan, 3, 2).unwrap_err().to_string().contains("texel 1"));
    }
}
