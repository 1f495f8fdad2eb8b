//! A capture never writes over one of its inputs (issue 19, item 2), nor
//! through a link (item 1's rule, which the analyzer follows).
//!
//! `ufcsr capture scene` into the folder that holds the scene's own
//! `vehicle.glb` used to replace the user's mesh with the unwrapped copy.
//! Every command that writes (the captures, `study`, `inspect`, `views`)
//! now lists the files it writes and the folders it owns in its output
//! folder, and checks them against every file it read before writing
//! anything: by resolved path (`./x`, `a/../x` and a link to `x` are all
//! `x`), with the analyzer's [`ufcsr::files::refuse_overwriting_inputs`], so the
//! rule and its message are the same in both programs. A link where a
//! folder the capture owns goes (`tiles/` → another folder) is replaced by
//! a real folder with the analyzer's [`ufcsr::files::real_dir`]: writing tiles and
//! removing old ones through it would change a folder outside `--out`.

use std::path::{Path, PathBuf};

use crate::error::{CaptureError, Result};

/// Errors, naming both, when writing one of `files` in `out`, or anything in
/// one of its `folders` (a capture writes and removes tiles there), would
/// replace one of `inputs`. Inputs that do not exist are left out.
pub(crate) fn refuse_overwriting_inputs(
    out: &Path,
    files: &[&str],
    folders: &[&str],
    inputs: &[PathBuf],
) -> Result<()> {
    let outputs: Vec<PathBuf> = files.iter().map(|name| out.join(name)).collect();
    ufcsr::files::refuse_overwriting_inputs(&outputs, inputs)?;
    for folder in folders.iter().map(|name| out.join(name)) {
        for input in inputs {
            let Ok(real) = input.canonicalize() else { continue };
            if real.ancestors().skip(1).any(|above| ufcsr::files::same_path(above, &folder)) {
                return Err(CaptureError::BadOptions(format!(
                    "writing into {} would overwrite the input {}: choose another output",
                    folder.display(),
                    input.display()
                )));
            }
        }
    }
    Ok(())
}

/// Replaces a symbolic link at any of `folders` in `out` by a real folder
/// (the link itself is removed, never what it points to); real folders and
/// absent ones are left as they are.
pub(crate) fn unlink_owned_folders(out: &Path, folders: &[&str]) -> Result<()> {
    for folder in folders.iter().map(|name| out.join(name)) {
        if std::fs::symlink_metadata(&folder).is_ok_and(|m| m.file_type().is_symlink()) {
            ufcsr::files::real_dir(&folder)?;
        }
    }
    Ok(())
}
