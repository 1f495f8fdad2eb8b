//! Reading OBJ files (and the MTL files they name) safely.
//!
//! `tobj::load_obj` opens the OBJ and its `mtllib` itself: a FIFO hangs it and
//! a link to `/dev/zero` reads until memory runs out. Here both go through the
//! analyzer's [`ufcsr::files::read_limited`] (regular files only, never blocking,
//! at most [`ufcsr::files::MODEL_LIMIT`] bytes), and the `mtllib` follows the same
//! containment rule as glTF buffers ([`ufcsr::files::resolve_inside`]: a file inside
//! the OBJ's own folder). glTF goes through [`ufcsr::files::read_gltf`].

use std::cell::RefCell;
use std::path::{Path, PathBuf};

use crate::error::{CaptureError, Result};

/// An OBJ as loaded: its models, materials, and every file read (the OBJ
/// and the MTL files it names).
pub(crate) struct LoadedObj {
    pub models: Vec<tobj::Model>,
    pub materials: Vec<tobj::Material>,
    pub files: Vec<PathBuf>,
}

/// Loads an OBJ with its materials; a missing MTL leaves the materials out
/// (as tobj does), an MTL that cannot be read safely is an error naming it.
pub(crate) fn load_obj(path: &Path, options: &tobj::LoadOptions) -> Result<LoadedObj> {
    let bytes = ufcsr::files::read_limited(path, ufcsr::files::MODEL_LIMIT)?;
    let files = RefCell::new(vec![path.to_path_buf()]);
    let read_material = |reference: &Path| {
        let file = ufcsr::files::resolve_inside(path, &reference.to_string_lossy())?;
        let mtl = ufcsr::files::read_limited(&file, ufcsr::files::MODEL_LIMIT)?;
        files.borrow_mut().push(file);
        Ok(mtl)
    };
    let (models, materials) = obj_from_bytes(path, &bytes, options, read_material)?;
    Ok(LoadedObj { models, materials, files: files.into_inner() })
}

/// Parses OBJ `bytes` (`path` names it in messages), reading each `mtllib`
/// with `read_material`: a missing MTL (not found) leaves the materials
/// out, as tobj does; any other error stops the load.
pub(crate) fn obj_from_bytes(
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
    check_obj_indices(path, bytes)?;
    let loaded = tobj::load_obj_buf(&mut &bytes[..], options, load_material);
    if let Some(error) = refused.into_inner() {
        return Err(error.into());
    }
    let (models, materials) = loaded.map_err(|e| CaptureError::bad_file(path, format!("OBJ: {e}")))?;
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

/// Largest face index (in magnitude) an OBJ may use: more vertices than a
/// model within [`ufcsr::files::MODEL_LIMIT`] can hold.
const MAX_OBJ_INDEX: i64 = 1 << 31;

/// An error unless every index of every `f`, `l` and `p` line is a whole
/// number from 1 to [`MAX_OBJ_INDEX`], or a relative one (-1 the last) that
/// stays within the vertices, UVs or normals given so far: tobj 4 offsets
/// them without checking, and an index before the first (`f 1/-129`) or
/// near 2^63 overflows inside it (a panic in a debug build, an
/// out-of-bounds index in release; found by fuzzing).
fn check_obj_indices(path: &Path, bytes: &[u8]) -> Result<()> {
    let text = String::from_utf8_lossy(bytes);
    // Positions, UVs and normals so far.
    let mut counts = [0i64; 3];
    for (number, line) in text.lines().enumerate() {
        let mut words = line.split_whitespace();
        match words.next() {
            Some("v") => counts[0] += 1,
            Some("vt") => counts[1] += 1,
            Some("vn") => counts[2] += 1,
            Some("f" | "l" | "p") => {
                for word in words {
                    for (kind, index) in word.split('/').enumerate().filter(|(_, i)| !i.is_empty()) {
                        let known = counts.get(kind).copied().unwrap_or(0);
                        let fits = index
                            .parse::<i64>()
                            .is_ok_and(|i| (1..=MAX_OBJ_INDEX).contains(&i) || (-known..0).contains(&i));
                        if !fits {
                            return Err(CaptureError::bad_file(
                                path,
                                format!(
                                    "line {}: index {index:?} is neither from 1 to {MAX_OBJ_INDEX} nor a relative \
                                     index within the {known} given before it",
                                    number + 1
                                ),
                            ));
                        }
                    }
                }
            }
            _ => {}
        }
    }
    Ok(())
}
