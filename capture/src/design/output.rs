//! The merged result's three files written as one set (issue 41 §2).
//!
//! Written one after another, a `design.html` that could not be replaced (a
//! folder, a FIFO, a link planted there) was refused after `design.json` and
//! `design.csv` were already new: half a result, and `--json` said
//! `written: []`. Here every target is checked first (nothing is replaced
//! that is not a regular file), then the three are written into a staging
//! folder and moved into place together ([`ufcsr::files::Staging`]): the folder
//! holds the old set or the new, never a mix.

use std::path::{Path, PathBuf};

use ufcsr::format::DesignResult;

use super::report::{csv, page};
use crate::error::{CaptureError, Result};

/// The result set's files, in the order they are listed.
pub const RESULT_FILES: [&str; 3] = ["design.json", "design.csv", "design.html"];

/// Writes `design.json`, `design.csv` and `design.html` into `dir` as one set, never over one of
/// `inputs` nor over anything but a regular file; returns their paths.
pub fn write_result_set(result: &DesignResult, dir: &Path, inputs: &[PathBuf]) -> Result<Vec<PathBuf>> {
    ufcsr::files::create_output_dir(dir)?;
    let files = RESULT_FILES.map(|f| dir.join(f));
    ufcsr::files::refuse_overwriting_inputs(&files, inputs)?;
    for file in &files {
        ufcsr::files::refuse_replacing_non_file(file)?;
    }
    let json =
        serde_json::to_vec_pretty(result).map_err(|e| CaptureError::bad_file(&files[0], e.to_string()))?;
    let staging = ufcsr::files::Staging::new(dir)?;
    let contents = [json, csv(result).into_bytes(), page(result).into_bytes()];
    for (name, bytes) in RESULT_FILES.iter().zip(&contents) {
        ufcsr::files::write_bytes_atomically(&staging.path().join(name), bytes)?;
    }
    staging.commit(dir, &RESULT_FILES)?;
    Ok(files.to_vec())
}
