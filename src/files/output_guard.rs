//! Where outputs may go: never over an input, never through a link.
//!
//! Both binaries write into folders the user names, and those folders can
//! hold the inputs themselves (`heatmap R/result.json --out R/result.json`,
//! `report A B --out A`) or links planted by someone else (`views/` a link
//! to another folder). Every command checks its planned outputs against its
//! inputs here ([`refuse_overwriting_inputs`], by resolved path, so `./x`,
//! `a/../x` and a link to `x` are all `x`), and every folder of a result set
//! is made with [`real_dir`], which replaces a link by a real folder instead
//! of writing into the folder it points to.

use std::path::{Path, PathBuf};

use crate::error::{Error, Result};

/// `path` resolved: links and `.`/`..` taken out. A path that does not exist
/// yet is its (resolved) parent joined with its name; `None` if even the
/// parent cannot be resolved.
pub fn resolved(path: &Path) -> Option<PathBuf> {
    if let Ok(real) = path.canonicalize() {
        return Some(real);
    }
    let name = path.file_name()?;
    let parent = match path.parent() {
        Some(parent) if !parent.as_os_str().is_empty() => parent,
        _ => Path::new("."),
    };
    Some(resolved(parent)?.join(name))
}

/// True when `a` and `b` name the same file (or would, once written).
pub fn same_path(a: &Path, b: &Path) -> bool {
    match (resolved(a), resolved(b)) {
        (Some(a), Some(b)) => a == b,
        _ => false,
    }
}

/// Errors, naming both, when writing any of `outputs` would replace one of
/// `inputs`. Every command of both binaries calls this before it writes.
pub fn refuse_overwriting_inputs(outputs: &[PathBuf], inputs: &[PathBuf]) -> Result<()> {
    let inputs: Vec<(&PathBuf, PathBuf)> =
        inputs.iter().filter_map(|input| Some((input, resolved(input)?))).collect();
    for output in outputs {
        let Some(output_real) = resolved(output) else { continue };
        if let Some((input, _)) = inputs.iter().find(|(_, real)| *real == output_real) {
            return Err(Error::BadOptions(format!(
                "writing {} would overwrite the input {}: choose another output",
                output.display(),
                input.display()
            )));
        }
    }
    Ok(())
}

/// Makes sure `dir` is a real folder, not a link: a symbolic link there
/// (to a folder or anything else) is removed, the link itself and never
/// what it points to, and a folder is made in its place. Returns whether a
/// link was replaced.
#[allow(clippy::disallowed_methods)] // the layer: removes only a link, never what it points to
pub fn real_dir(dir: &Path) -> Result<bool> {
    let replaced = match std::fs::symlink_metadata(dir) {
        Ok(metadata) if metadata.file_type().is_symlink() => {
            std::fs::remove_file(dir).map_err(|e| Error::io(dir, e))?;
            true
        }
        Ok(metadata) if metadata.is_dir() => return Ok(false),
        Ok(_) => return Err(Error::bad_file(dir, "is a file where a folder of outputs must go")),
        Err(_) => false,
    };
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    Ok(replaced)
}

/// Makes the output folder `dir` (and its parents) that the user named. A
/// link there is the user's own choice and is followed; anything that is
/// not a folder (a file, a device, a FIFO, a link to one) is refused by name.
#[allow(clippy::disallowed_methods)] // the layer: making a folder replaces nothing
pub fn create_output_dir(dir: &Path) -> Result<()> {
    match std::fs::metadata(dir) {
        Ok(metadata) if metadata.is_dir() => return Ok(()),
        Ok(metadata) => {
            return Err(Error::bad_file(
                dir,
                format!(
                    "is {} where a folder of outputs must go",
                    crate::files::limited_read::kind(&metadata)
                ),
            ));
        }
        Err(_) => {}
    }
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))
}

/// Makes the folder `dir` new, readable by this user only (0700 on Unix):
/// anything already there, a link planted there included, is an error and
/// never followed (the capture's private runtime folder in the shared
/// temporary folder).
#[allow(clippy::disallowed_methods, clippy::disallowed_types)] // the layer: mkdir never follows a link at its name; one there fails
pub fn create_private_dir(dir: &Path) -> Result<()> {
    let mut builder = std::fs::DirBuilder::new();
    #[cfg(unix)]
    std::os::unix::fs::DirBuilderExt::mode(&mut builder, 0o700);
    builder.create(dir).map_err(|e| Error::io(dir, e))
}

/// Makes the sub-folder `relative` of the output folder `out` (e.g.
/// `placement-views`, `observer-000`) as a real folder: a link at it or at
/// a folder on the way is removed (the link itself, never what it points
/// to) and a real folder made, so nothing is written through a link.
/// Returns the folder's path.
pub fn output_sub_dir(out: &Path, relative: &Path) -> Result<PathBuf> {
    let mut at = out.to_path_buf();
    for component in relative.components() {
        match component {
            std::path::Component::Normal(name) => at.push(name),
            _ => {
                return Err(Error::bad_file(
                    &out.join(relative),
                    "is not a plain folder inside the output folder",
                ));
            }
        }
        real_dir(&at)?;
    }
    Ok(at)
}

/// Removes `path` (a file, a link, or a folder tree the run owns) when it
/// lies inside the output folder `out` and no folder on the way is a link;
/// a link is removed itself, never what it points to. Anything else is
/// refused by name. Returns whether something was removed.
#[allow(clippy::disallowed_methods)] // the layer: checked to be inside `out`, links not followed
pub fn remove_inside(out: &Path, path: &Path) -> Result<bool> {
    let relative = path.strip_prefix(out).unwrap_or(path);
    let plain = relative.components().all(|c| matches!(c, std::path::Component::Normal(_)));
    if relative.as_os_str().is_empty() || !plain || (path.is_absolute() && !path.starts_with(out)) {
        return Err(Error::bad_file(path, format!("is not inside the output folder {}", out.display())));
    }
    if crosses_link(out, relative) {
        return Err(Error::bad_file(path, "lies behind a link inside the output folder: not removed"));
    }
    let target = out.join(relative);
    let outcome = match std::fs::symlink_metadata(&target) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(false),
        Err(e) => Err(e),
        // `remove_dir_all` does not follow links inside the tree.
        Ok(metadata) if metadata.is_dir() => std::fs::remove_dir_all(&target),
        Ok(_) => std::fs::remove_file(&target),
    };
    outcome.map(|()| true).map_err(|e| Error::io(&target, e))
}

/// True when some folder between `base` and `base/relative` is a link:
/// writing or removing there would reach outside `base`.
pub fn crosses_link(base: &Path, relative: &Path) -> bool {
    let mut at = base.to_path_buf();
    let mut components = relative.components().peekable();
    while let Some(component) = components.next() {
        at.push(component);
        if components.peek().is_none() {
            break;
        }
        if std::fs::symlink_metadata(&at).is_ok_and(|m| m.file_type().is_symlink()) {
            return true;
        }
    }
    false
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn aliases_of_one_file_are_the_same_path() {
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("result.json");
        std::fs::write(&file, b"{}").unwrap();
        std::fs::create_dir(dir.path().join("sub")).unwrap();
        assert!(same_path(&file, &dir.path().join("sub/../result.json")));
        assert!(same_path(&file, &dir.path().join("./result.json")));
        assert!(same_path(&dir.path().join("new.png"), &dir.path().join(".").join("new.png")));
        assert!(!same_path(&file, &dir.path().join("other.json")));
        let error = refuse_overwriting_inputs(std::slice::from_ref(&file), std::slice::from_ref(&file));
        assert!(error.unwrap_err().to_string().contains("would overwrite the input"));
    }
}
