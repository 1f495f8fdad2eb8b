//! Atomic output files: write to a temporary file beside the target, then rename.
//!
//! An interrupted run therefore leaves either the previous file or the complete
//! new one, never half a result that a later script would read as truth.

use std::fs::{self, File};
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use crate::error::{Error, Result};

/// Writes `path` atomically: `fill` writes into a buffered temporary file in the
/// same directory, which is flushed, synced and renamed over `path` only if
/// `fill` succeeds. On failure the temporary file is removed.
pub fn write_atomically<F>(path: &Path, fill: F) -> Result<()>
where
    F: FnOnce(&mut BufWriter<File>) -> std::io::Result<()>,
{
    let temporary = temporary_path(path);
    let outcome = (|| {
        let file = File::create(&temporary)?;
        let mut writer = BufWriter::with_capacity(1 << 20, file);
        fill(&mut writer)?;
        writer.flush()?;
        let file = writer.into_inner().map_err(|e| e.into_error())?;
        file.sync_all()?;
        drop(file);
        fs::rename(&temporary, path)
    })();
    outcome.map_err(|source| {
        let _ = fs::remove_file(&temporary);
        Error::io(path, source)
    })
}

/// Writes bytes to `path` atomically.
pub fn write_bytes_atomically(path: &Path, bytes: &[u8]) -> Result<()> {
    write_atomically(path, |writer| writer.write_all(bytes))
}

/// Writes an 8-bit RGB PNG atomically (`rgb` holds `width * height * 3` bytes).
pub fn write_rgb_png(
    path: &Path,
    width: u32,
    height: u32,
    rgb: &[u8],
    compression: png::Compression,
) -> Result<()> {
    write_atomically(path, |writer| {
        let mut encoder = png::Encoder::new(writer, width, height);
        encoder.set_color(png::ColorType::Rgb);
        encoder.set_depth(png::BitDepth::Eight);
        encoder.set_compression(compression);
        let mut png_writer = encoder.write_header().map_err(std::io::Error::other)?;
        png_writer.write_image_data(rgb).map_err(std::io::Error::other)?;
        png_writer.finish().map_err(std::io::Error::other)
    })
}

/// `dir/.name.tmp-<pid>`: same directory, so the rename never crosses devices.
fn temporary_path(path: &Path) -> PathBuf {
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    path.with_file_name(format!(".{name}.tmp-{}", std::process::id()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn failed_write_leaves_old_file_and_no_temporary() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("result.json");
        write_bytes_atomically(&path, b"old").unwrap();
        let failed = write_atomically(&path, |w| {
            w.write_all(b"half")?;
            Err(std::io::Error::other("interrupted"))
        });
        assert!(failed.is_err());
        assert_eq!(fs::read(&path).unwrap(), b"old");
        assert_eq!(fs::read_dir(dir.path()).unwrap().count(), 1);
    }
}
