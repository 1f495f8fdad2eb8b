//! Reading OBJ files (and the MTL files they name) safely.
//!
//! `tobj::load_obj` opens the OBJ and its `mtllib` itself: a FIFO hangs it and
//! a link to `/dev/zero` reads until memory runs out. Here both go through the
//! analyzer's [`ufcsr::read_limited`] (regular files only, never blocking,
//! at most [`ufcsr::MODEL_LIMIT`] bytes), and the `mtllib` follows the same
//! containment rule as glTF buffers ([`ufcsr::resolve_inside`]: a file inside
//! the OBJ's own folder). glTF goes through [`ufcsr::read_gltf`].

use std::cell::RefCell;
use std::path::Path;

use crate::error::{CaptureError, Result};

/// Loads an OBJ with its materials; a missing MTL leaves the materials out
/// (as tobj does), an MTL that cannot be read safely is an error naming it.
pub fn load_obj(path: &Path, options: &tobj::LoadOptions) -> Result<(Vec<tobj::Model>, Vec<tobj::Material>)> {
    let bytes = ufcsr::read_limited(path, ufcsr::MODEL_LIMIT)?;
    let refused: RefCell<Option<ufcsr::Error>> = RefCell::new(None);
    let load_material = |reference: &Path| {
        let mtl = ufcsr::resolve_inside(path, &reference.to_string_lossy())
            .and_then(|file| ufcsr::read_limited(&file, ufcsr::MODEL_LIMIT));
        match mtl {
            Ok(mtl) => tobj::load_mtl_buf(&mut mtl.as_slice()),
            Err(ufcsr::Error::Io { cause, .. }) if cause.kind() == std::io::ErrorKind::NotFound => {
                Err(tobj::LoadError::OpenFileFailed)
            }
            Err(error) => {
                refused.borrow_mut().get_or_insert(error);
                Err(tobj::LoadError::OpenFileFailed)
            }
        }
    };
    let loaded = tobj::load_obj_buf(&mut bytes.as_slice(), options, load_material);
    if let Some(error) = refused.into_inner() {
        return Err(error.into());
    }
    let (models, materials) = loaded.map_err(|e| CaptureError::bad_input(path, format!("OBJ: {e}")))?;
    Ok((models, materials.unwrap_or_default()))
}
