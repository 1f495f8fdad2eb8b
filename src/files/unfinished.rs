//! A capture rewrites its archive folder in place (issue 41, §4): its first
//! step removes the earlier `manifest.json` (so a mix of old and new tiles is
//! never counted under it) and it writes the new one last, so a capture
//! interrupted, failed or (sharded) not yet assembled leaves a folder that
//! holds part of a capture and no manifest — which the analyzer used to
//! count (exit 0) as if it were whole, while the interrupt message said the
//! earlier outputs were untouched.
//!
//! Keeping the earlier archive until the new one is whole (staging tiles,
//! then swapping folders) would double the disk a capture needs and fight
//! `--resume` and shards, which finish a capture in place. Instead the
//! folder is *marked*: [`mark_unfinished`] writes [`UNFINISHED_FILE`] before
//! anything of the earlier archive goes, [`mark_finished`] removes it once
//! the whole manifest is written, the analyzer refuses a marked folder
//! ([`refuse_unfinished`]), and the interrupt handler asks
//! [`unfinished_outputs`] which folders this run leaves unfinished, to say
//! so instead of "untouched".

use std::path::{Path, PathBuf};
use std::sync::Mutex;

use crate::error::{Error, Result};

/// The marker in an archive folder whose capture has not finished.
pub const UNFINISHED_FILE: &str = "capture-unfinished";

/// Folders this process marked and has not finished.
static UNFINISHED: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

fn unfinished() -> std::sync::MutexGuard<'static, Vec<PathBuf>> {
    UNFINISHED.lock().unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// What the marker says to someone who opens it.
const MARKER_TEXT: &str = "A capture into this folder began and has not finished (interrupted, failed, or its \
shards not yet assembled): the folder holds part of it and no manifest.json of an earlier capture, so \
`ufcsr analyze` refuses it. Capture again (or add --resume), or run `ufcsr assemble` for shards; the \
capture removes this file when its manifest.json is written.\n";

/// Marks `dir` (an existing folder) as holding a capture that has not
/// finished, before anything of an earlier capture there is removed.
pub fn mark_unfinished(dir: &Path) -> Result<()> {
    crate::files::write_bytes_atomically(&dir.join(UNFINISHED_FILE), MARKER_TEXT.as_bytes())?;
    let mut marked = unfinished();
    if !marked.iter().any(|d| d == dir) {
        marked.push(dir.to_path_buf());
    }
    Ok(())
}

/// Removes `dir`'s marker: its capture's `manifest.json` is written.
pub fn mark_finished(dir: &Path) -> Result<()> {
    crate::files::remove_inside(dir, &dir.join(UNFINISHED_FILE))?;
    unfinished().retain(|d| d != dir);
    Ok(())
}

/// The folders this process marked unfinished and has not finished.
pub fn unfinished_outputs() -> Vec<PathBuf> {
    unfinished().clone()
}

/// Errors, naming the folder and the marker, when `dir` holds a capture that
/// has not finished.
pub fn refuse_unfinished(dir: &Path) -> Result<()> {
    let marker = dir.join(UNFINISHED_FILE);
    if std::fs::symlink_metadata(&marker).is_err() {
        return Ok(());
    }
    Err(Error::bad_file(
        dir,
        format!(
            "a capture into this folder has not finished (interrupted, failed, or its shards not yet \
             assembled; {UNFINISHED_FILE} marks it): it holds part of a capture and no earlier one's \
             manifest.json; capture again (or add --resume), or assemble the shards"
        ),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_marked_folder_is_refused_until_it_is_finished() {
        let dir = tempfile::tempdir().unwrap();
        refuse_unfinished(dir.path()).unwrap();
        mark_unfinished(dir.path()).unwrap();
        assert!(unfinished_outputs().contains(&dir.path().to_path_buf()));
        let error = refuse_unfinished(dir.path()).unwrap_err().to_string();
        assert!(
            error.contains(&dir.path().display().to_string()) && error.contains(UNFINISHED_FILE),
            "{error}"
        );
        mark_finished(dir.path()).unwrap();
        assert!(!dir.path().join(UNFINISHED_FILE).exists());
        assert!(!unfinished_outputs().contains(&dir.path().to_path_buf()));
        refuse_unfinished(dir.path()).unwrap();
    }
}
