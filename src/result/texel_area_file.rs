//! `texel-area.f32`: the per-texel angular area (deg²·s,
//! [`crate::Analysis::texel_angular_area`]) kept beside `result.json`, so
//! that what draws a result later (the comparison page on one colour scale,
//! the capture's `views`) paints the measure to quote from the values
//! themselves, not from `heatmap.png`'s colours and not from a
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
pub(crate) const TEXEL_AREA_MAGIC: &[u8; 20] = b"ufcsr-texel-area/1\n\0";

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

/// `texel-area.f32` in the result folder `dir`, when there is one: `None`
/// only when nothing is at that name (a result without per-texel area).
/// Anything else there goes through [`read_texel_area`]'s checks, so a
/// folder, a FIFO, a device or a link to one is refused naming the file,
/// never silently taken for "no area" (the count painted instead).
pub fn read_texel_area_in(dir: &Path, width: u32, height: u32) -> Result<Option<Vec<f32>>> {
    let path = dir.join(TEXEL_AREA_FILE);
    match path.symlink_metadata() {
        Err(error) if error.kind() == std::io::ErrorKind::NotFound => Ok(None),
        Err(error) => Err(Error::io(&path, error)),
        Ok(_) => read_texel_area(&path, width, height).map(Some),
    }
}

/// The file a shard's result keeps beside `texel-area.f32`: the integer
/// sums the values were made from, which `merge` adds exactly (the `f32`
/// values of shards would not add up to the whole's bits).
pub const TEXEL_AREA_UNITS_FILE: &str = "texel-area.units";

/// Its first bytes: format name and version.
const UNITS_MAGIC: &[u8; 20] = b"ufcsr-texel-units/1\n";

/// Bytes before its values: magic, width, height, the factor.
const UNITS_HEADER: usize = UNITS_MAGIC.len() + 16;

/// Per-texel solid angles summed over the eye-frames, in units of
/// [`crate::count::texel_area::TEXEL_SOLID_ANGLE_UNITS_PER_SR`] (row-major
/// over the palette), and the factor to deg²·s per sr
/// ([`crate::result::measures::Measures::texel_area_factor`]).
#[derive(Debug, Clone, PartialEq)]
pub struct TexelAreaUnits {
    pub units: Vec<u64>,
    pub deg2_s_per_sr: f64,
}

impl TexelAreaUnits {
    /// The per-texel angular area, deg²·s: the same operations for an
    /// analysis and a merge, so equal sums give equal bits.
    pub fn areas(&self) -> Vec<f32> {
        let per_sr = crate::count::texel_area::TEXEL_SOLID_ANGLE_UNITS_PER_SR;
        self.units.iter().map(|&u| (u as f64 / per_sr * self.deg2_s_per_sr) as f32).collect()
    }

    /// Writes `texel-area.units` for a palette of `width × height`.
    pub fn write(&self, path: &Path, width: u32, height: u32) -> Result<()> {
        let mut bytes = Vec::with_capacity(UNITS_HEADER + self.units.len() * 8);
        bytes.extend_from_slice(UNITS_MAGIC);
        bytes.extend_from_slice(&width.to_le_bytes());
        bytes.extend_from_slice(&height.to_le_bytes());
        bytes.extend_from_slice(&self.deg2_s_per_sr.to_le_bytes());
        for unit in &self.units {
            bytes.extend_from_slice(&unit.to_le_bytes());
        }
        crate::files::write_bytes_atomically(path, &bytes)
    }

    /// `texel-area.units` in the result folder `dir`, `None` when nothing
    /// is at that name; anything else must be the file of a `width × height`
    /// palette (a folder, FIFO, device, truncated or foreign file is refused
    /// naming it).
    pub fn read_in(dir: &Path, width: u32, height: u32) -> Result<Option<TexelAreaUnits>> {
        let path = dir.join(TEXEL_AREA_UNITS_FILE);
        match path.symlink_metadata() {
            Err(error) if error.kind() == std::io::ErrorKind::NotFound => return Ok(None),
            Err(error) => return Err(Error::io(&path, error)),
            Ok(_) => {}
        }
        let texels = width as usize * height as usize;
        let bytes = crate::files::read_limited(&path, (UNITS_HEADER + texels * 8) as u64)?;
        let bad = |what: String| Error::bad_file(&path, what);
        if bytes.len() != UNITS_HEADER + texels * 8 || &bytes[..UNITS_MAGIC.len()] != UNITS_MAGIC {
            return Err(bad(format!(
                "not a ufcsr-texel-units/1 file of a {width}×{height} palette ({} bytes)",
                bytes.len()
            )));
        }
        let at = UNITS_MAGIC.len();
        let size =
            [&bytes[at..at + 4], &bytes[at + 4..at + 8]].map(|b| u32::from_le_bytes(b.try_into().unwrap()));
        let deg2_s_per_sr = f64::from_le_bytes(bytes[at + 8..at + 16].try_into().unwrap());
        if size != [width, height] || !(deg2_s_per_sr.is_finite() && deg2_s_per_sr > 0.0) {
            return Err(bad(format!(
                "holds a {}×{} raster at {deg2_s_per_sr} deg²·s per sr; the result's palette is {width}×{height}",
                size[0], size[1]
            )));
        }
        let units = bytes[UNITS_HEADER..]
            .chunks_exact(8)
            .map(|b| u64::from_le_bytes(b.try_into().unwrap()))
            .collect();
        Ok(Some(TexelAreaUnits { units, deg2_s_per_sr }))
    }
}

/// [`read_texel_area`] of the file's bytes (`path` names it in messages).
pub(crate) fn parse_texel_area(path: &Path, bytes: &[u8], width: u32, height: u32) -> Result<Vec<f32>> {
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

    #[test]
    fn a_texel_area_that_is_no_regular_file_is_refused_by_name_not_taken_for_none() {
        let dir = tempfile::tempdir().unwrap();
        assert_eq!(read_texel_area_in(dir.path(), 3, 2).unwrap(), None, "no file: no area");
        let path = dir.path().join(TEXEL_AREA_FILE);
        let refused = |what: &str| {
            let error = read_texel_area_in(dir.path(), 3, 2).unwrap_err().to_string();
            assert!(error.contains(TEXEL_AREA_FILE), "{what}: {error}");
        };
        std::fs::create_dir(&path).unwrap();
        refused("a folder");
        std::fs::remove_dir(&path).unwrap();
        #[cfg(unix)]
        {
            std::os::unix::fs::symlink("/dev/zero", &path).unwrap();
            refused("a link to /dev/zero");
            std::fs::remove_file(&path).unwrap();
            std::os::unix::fs::symlink(dir.path().join("nowhere"), &path).unwrap();
            refused("a dangling link");
            std::fs::remove_file(&path).unwrap();
            let made = std::process::Command::new("mkfifo").arg(&path).status();
            if made.is_ok_and(|status| status.success()) {
                refused("a FIFO");
                std::fs::remove_file(&path).unwrap();
            }
        }
        write_texel_area(&path, 3, 2, &[0.0, 1.0, 2.0, 3.0, 4.0, 5.0]).unwrap();
        assert_eq!(read_texel_area_in(dir.path(), 3, 2).unwrap().unwrap()[5], 5.0);
    }
}
