//! Reading OBJ files (and the MTL files they name) safely.
//!
//! `tobj::load_obj` opens the OBJ and its `mtllib` itself: a FIFO hangs it and
//! a link to `/dev/zero` reads until memory runs out. Here both go through the
//! analyzer's [`ufcsr::read_limited`] (regular files only, never blocking,
//! at most [`ufcsr::MODEL_LIMIT`] bytes), and the `mtllib` follows the same
//! containment rule as glTF buffers ([`ufcsr::resolve_inside`]: a file inside
//! the OBJ's own folder). glTF goes through [`ufcsr::read_gltf`].

use std::cell::RefCell;
use std::path::{Path, PathBuf};

use crate::error::{CaptureError, Result};

/// An OBJ as loaded: its models, materials, and every file read (the OBJ
/// and the MTL files it names).
pub struct LoadedObj {
    pub models: Vec<tobj::Model>,
    pub materials: Vec<tobj::Material>,
    pub files: Vec<PathBuf>,
}

/// Loads an OBJ with its materials; a missing MTL leaves the materials out
/// (as tobj does), an MTL that cannot be read safely is an error naming it.
pub fn load_obj(path: &Path, options: &tobj::LoadOptions) -> Result<LoadedObj> {
    let bytes = ufcsr::read_limited(path, ufcsr::MODEL_LIMIT)?;
    let files = RefCell::new(vec![path.to_path_buf()]);
    let read_material = |reference: &Path| {
        let file = ufcsr::resolve_inside(path, &reference.to_string_lossy())?;
        let mtl = ufcsr::read_limited(&file, ufcsr::MODEL_LIMIT)?;
        files.borrow_mut().push(file);
        Ok(mtl)
    };
    let (models, materials) = obj_from_bytes(path, &bytes, options, read_material)?;
    Ok(LoadedObj { models, materials, files: files.into_inner() })
}

/// Parses OBJ `bytes` (`path` names it in messages), reading each `mtllib`
/// with `read_material`: a missing MTL (not found) leaves the materials
/// out, as tobj does; any other error stops the load.
pub fn obj_from_bytes(
    path: &Path,
    bytes: &[u8],
    options: &tobj::LoadOptions,
    read_material: impl Fn(&Path) -> ufcsr::Result<Vec<u8>>,
) -> Result<(Vec<tobj::Model>, Vec<tobj::Material>)> {
    let refused: RefCell<Option<ufcsr::Error>> = RefCell::new(None);
    let load_material =
        |reference: &Path| match read_material(reference).and_then(|mtl| check_mtl(reference, mtl)) {
            Ok(mtl) => tobj::load_mtl_buf(&mut mtl.as_slice()),
            Err(ufcsr::Error::Io { cause, .. }) if cause.kind() == std::io::ErrorKind::NotFound => {
                Err(tobj::LoadError::OpenFileFailed)
            }
            Err(error) => {
                refused.borrow_mut().get_or_insert(error);
                Err(tobj::LoadError::OpenFileFailed)
            }
        };
    let loaded = tobj::load_obj_buf(&mut &bytes[..], options, load_material);
    if let Some(error) = refused.into_inner() {
        return Err(error.into());
    }
    let (models, materials) = loaded.map_err(|e| CaptureError::bad_input(path, format!("OBJ: {e}")))?;
    Ok((models, materials.unwrap_or_default()))
}

/// The MTL bytes if tobj can read them without panicking: tobj 4 unwraps
/// the colour of a `Ka`/`Kd`/`Ks`/`Ke` line with fewer than three numbers
/// (found by fuzzing), so such a line is an error naming the file and line.
fn check_mtl(reference: &Path, mtl: Vec<u8>) -> ufcsr::Result<Vec<u8>> {
    let text = String::from_utf8_lossy(&mtl);
    for (number, line) in text.lines().enumerate() {
        let mut words = line.split_whitespace();
        if let Some(key @ ("Ka" | "Kd" | "Ks" | "Ke")) = words.next()
            && words.count() < 3
        {
            return Err(ufcsr::Error::bad_file(
                reference,
                format!("line {}: {key} needs three numbers (r g b)", number + 1),
            ));
        }
    }
    Ok(mtl)
}
