//! Atomic output files: write to a temporary file beside the target, then rename.
//!
//! An interrupted run therefore leaves either the previous file or the complete
//! new one, never half a result that a later script would read as truth. A
//! result set of several files is written into a [`Staging`] folder first and
//! moved into place only when every file was written (with the old files
//! restored if a move fails). Temporary files and staging folders are
//! registered while they exist, so that a signal handler in the binaries can
//! remove them ([`remove_temporaries`]) before exiting.

use std::fs::{self, File};
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::{Mutex, PoisonError};

use crate::error::{Error, Result};

/// Temporary files and folders that exist right now.
static TEMPORARIES: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

fn register(path: &Path) {
    TEMPORARIES.lock().unwrap_or_else(PoisonError::into_inner).push(path.to_path_buf());
}

fn unregister(path: &Path) {
    let mut registered = TEMPORARIES.lock().unwrap_or_else(PoisonError::into_inner);
    if let Some(at) = registered.iter().rposition(|p| p == path) {
        registered.swap_remove(at);
    }
}

/// Removes every temporary file and staging folder this process has open
/// (for a SIGINT/SIGTERM handler, which then exits): an interrupted run
/// leaves the previous outputs and nothing else. Returns how many were removed.
pub fn remove_temporaries() -> usize {
    let registered = std::mem::take(&mut *TEMPORARIES.lock().unwrap_or_else(PoisonError::into_inner));
    let mut removed = 0;
    for path in registered {
        let gone = if path.is_dir() { fs::remove_dir_all(&path) } else { fs::remove_file(&path) };
        removed += usize::from(gone.is_ok());
    }
    removed
}

/// For the binaries: on SIGINT/SIGTERM, remove this process's temporary files
/// and staging folders (previous outputs stay whole), say so, and exit 130.
#[cfg(feature = "cli")]
pub fn remove_temporaries_on_interrupt() {
    let installed = ctrlc::set_handler(|| {
        let removed = remove_temporaries();
        eprintln!("interrupted: {removed} temporary files removed; earlier outputs are untouched");
        std::process::exit(130);
    });
    if let Err(error) = installed {
        eprintln!("warning: no interrupt handler ({error}); an interrupted run may leave temporary files");
    }
}

/// A folder inside the output folder that a result set is written into, then
/// moved into place by [`Staging::commit`]; removed if dropped uncommitted.
pub struct Staging {
    dir: PathBuf,
}

impl Staging {
    /// A fresh staging folder inside `out_dir` (same file system: moves are renames).
    pub fn new(out_dir: &Path) -> Result<Staging> {
        let dir = tempfile::Builder::new()
            .prefix(".ufcsr-staging-")
            .tempdir_in(out_dir)
            .map_err(|e| Error::io(out_dir, e))?
            .keep();
        register(&dir);
        Ok(Staging { dir })
    }

    pub fn path(&self) -> &Path {
        &self.dir
    }

    /// Moves every file of the staging folder into `out_dir`, replacing
    /// same-named files (folders such as `views/` are merged file by file, so
    /// nothing else in them is lost). When `out_dir` held an earlier result
    /// set (its `result.json`), the top-level files of `set` (every name a
    /// set can have) that the new set lacks are taken away, so no stale
    /// `frames.csv` or `heatmap.glb` sits beside results it does not belong
    /// to. If a move fails, everything is put back: `out_dir` holds the old
    /// set or the new.
    pub fn commit(self, out_dir: &Path, set: &[&str]) -> Result<()> {
        let backups = self.dir.join(".replaced");
        let earlier_set = out_dir.join("result.json").is_file();
        // (target, its backup): a move to undo on failure.
        let mut done: Vec<(PathBuf, Option<PathBuf>)> = Vec::new();
        let outcome = (|| -> Result<()> {
            fs::create_dir_all(&backups).map_err(|e| Error::io(&backups, e))?;
            let mut counter = 0usize;
            move_tree(&self.dir, out_dir, &backups, &mut counter, &mut done, true)?;
            if earlier_set {
                for name in set {
                    let target = out_dir.join(name);
                    let staged = done.iter().any(|(t, _)| t.starts_with(&target));
                    if !staged && target.is_file() {
                        counter += 1;
                        let backup = backups.join(counter.to_string());
                        fs::rename(&target, &backup).map_err(|e| Error::io(&target, e))?;
                        done.push((target, Some(backup)));
                    }
                }
            }
            Ok(())
        })();
        if outcome.is_err() {
            for (target, backup) in done.iter().rev() {
                if let Some(backup) = backup {
                    let _ = fs::remove_file(target);
                    let _ = fs::rename(backup, target);
                } else {
                    let _ = fs::remove_file(target);
                }
            }
        }
        outcome
        // Drop removes the staging folder with the replaced files in it.
    }
}

/// Moves the files under `from` into `to` (folders created or merged),
/// backing up each replaced file into `backups` and recording every move in
/// `done`. `top` skips the staging folder's own backup folder.
fn move_tree(
    from: &Path,
    to: &Path,
    backups: &Path,
    counter: &mut usize,
    done: &mut Vec<(PathBuf, Option<PathBuf>)>,
    top: bool,
) -> Result<()> {
    let mut entries: Vec<PathBuf> = fs::read_dir(from)
        .map_err(|e| Error::io(from, e))?
        .map(|entry| entry.map(|e| e.path()).map_err(|e| Error::io(from, e)))
        .collect::<Result<_>>()?;
    entries.sort();
    for entry in entries {
        let Some(name) = entry.file_name() else { continue };
        if top && entry == backups {
            continue;
        }
        let target = to.join(name);
        if entry.is_dir() {
            if !target.is_dir() {
                fs::create_dir_all(&target).map_err(|e| Error::io(&target, e))?;
            }
            move_tree(&entry, &target, backups, counter, done, false)?;
            continue;
        }
        let backup = match fs::symlink_metadata(&target) {
            Ok(_) => {
                *counter += 1;
                let backup = backups.join(counter.to_string());
                fs::rename(&target, &backup).map_err(|e| Error::io(&target, e))?;
                Some(backup)
            }
            Err(_) => None,
        };
        let renamed = fs::rename(&entry, &target).map_err(|e| Error::io(&target, e));
        done.push((target, backup));
        renamed?;
    }
    Ok(())
}

impl Drop for Staging {
    fn drop(&mut self) {
        let _ = fs::remove_dir_all(&self.dir);
        unregister(&self.dir);
    }
}

/// Writes `path` atomically: `fill` writes into a buffered temporary file in the
/// same directory, which is flushed, synced and renamed over `path` only if
/// `fill` succeeds. On failure the temporary file is removed.
pub fn write_atomically<F>(path: &Path, fill: F) -> Result<()>
where
    F: FnOnce(&mut BufWriter<File>) -> std::io::Result<()>,
{
    let temporary = temporary_path(path);
    register(&temporary);
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
    unregister(&temporary);
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
