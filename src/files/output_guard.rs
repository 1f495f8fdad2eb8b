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
