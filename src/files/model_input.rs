//! Reading 3-D model files safely, for both crates: `--mesh` here, every
//! vehicle and environment mesh in `ufcsr capture`.
//!
//! A model names other files (glTF buffers, an OBJ's `mtllib`), and a loader
//! that opens them itself can hang on a FIFO or read `/dev/zero` until memory
//! runs out. So the model and every file it names are read through
//! [`crate::files::read_limited`] (regular files only, never blocking, bounded), and
//! one rule says which files a model may name:
//!
//! **Containment rule.** A file a model names is either a `data:` URI (its
//! bytes are inside the model, which was read with a cap) or a relative path
//! of plain names (no `..`, no root, no drive, no `file:` or other scheme)
//! that, with symbolic links resolved, lies inside the model's own folder.
//! Anything else is refused with a message naming the model and the reference.
//!
//! Coordinates are bounded too ([`MAX_COORDINATE_M`]): a vertex at 1e30 m or
//! a node scale of 1e38 is a unit or export mistake, and would otherwise make
//! pictures and bounds that never finish or overflow to infinity.

use std::path::{Component, Path, PathBuf};

use crate::error::{Error, Result};
use crate::files::read_limited;

/// Cap for a model file and everything it names, together.
pub const MODEL_LIMIT: u64 = 1 << 30;

/// Largest coordinate (metres, after node transforms and unit scale) a model
/// may have: 100 km, where f32 still resolves 8 mm. A vehicle is metres in
/// its own frame; an environment beyond this belongs around an `origin`.
pub const MAX_COORDINATE_M: f64 = 1.0e5;

/// A glTF document with the data of every buffer.
pub struct GltfModel {
    pub document: gltf::Document,
    pub buffers: Vec<Vec<u8>>,
}

impl GltfModel {
    /// The bytes of a buffer, for `primitive.reader`.
    pub fn buffer(&self, buffer: gltf::Buffer) -> Option<&[u8]> {
        self.buffers.get(buffer.index()).map(Vec::as_slice)
    }
}

/// Reads a `.gltf` or `.glb` with its buffers (images are never read), at
/// most `limit` bytes in all, under the containment rule.
pub fn read_gltf(path: &Path, limit: u64) -> Result<GltfModel> {
    let bytes = read_limited(path, limit)?;
    parse_gltf(path, &bytes, limit)
}

/// [`read_gltf`] of a model's bytes already read (`path` names it and is
/// where the files its buffers name are looked for): at most `limit`
/// bytes with those files. The fuzz targets call this.
pub fn parse_gltf(path: &Path, bytes: &[u8], limit: u64) -> Result<GltfModel> {
    // gltf 1.4 subtracts the header's size from the length a GLB header
    // gives without checking it (an overflow; found by fuzzing).
    if let Some(length) = bytes.strip_prefix(b"glTF").and_then(|rest| rest.get(4..8))
        && u32::from_le_bytes([length[0], length[1], length[2], length[3]]) < 12
    {
        return Err(Error::bad_file(path, "not a glTF model: its GLB header gives a length under 12 bytes"));
    }
    let not_gltf = |e: gltf::Error| Error::bad_file(path, format!("not a glTF model: {e}"));
    let mut gltf = gltf::Gltf::from_slice_without_validation(bytes).map_err(not_gltf)?;
    check_position_indices(path, gltf.document.as_json())?;
    // Validated only now: the gltf-json 1.4 validator indexes a primitive's
    // POSITION accessor without checking it exists (a panic; found by fuzzing).
    gltf.document = gltf::Document::from_json(gltf.document.into_json()).map_err(not_gltf)?;
    let mut budget = limit.saturating_sub(bytes.len() as u64);
    let mut blob = gltf.blob;
    let mut buffers = Vec::new();
    for buffer in gltf.document.buffers() {
        let index = buffer.index();
        let (mut data, origin) = match buffer.source() {
            gltf::buffer::Source::Bin => {
                let data = blob.take().ok_or_else(|| {
                    Error::bad_file(path, format!("buffer {index} is the GLB's binary chunk, which it lacks"))
                })?;
                (data, "the binary chunk".to_string())
            }
            gltf::buffer::Source::Uri(uri) if uri.starts_with("data:") => {
                let data = data_uri_bytes(uri)
                    .map_err(|e| Error::bad_file(path, format!("buffer {index}: data URI: {e}")))?;
                (data, "its data URI".to_string())
            }
            gltf::buffer::Source::Uri(uri) => {
                let file = resolve_inside(path, uri)?;
                let data = read_limited(&file, budget)
                    .map_err(|e| Error::bad_file(path, format!("buffer {index} ({uri:?}): {e}")))?;
                budget -= data.len() as u64;
                (data, format!("{uri:?}"))
            }
        };
        if data.len() < buffer.length() {
            return Err(Error::bad_file(
                path,
                format!(
                    "buffer {index} ({origin}) has {} bytes, the model says {}",
                    data.len(),
                    buffer.length()
                ),
            ));
        }
        // As gltf's own importer: accessors may read up to a 4-byte boundary.
        data.resize(data.len().next_multiple_of(4), 0);
        buffers.push(data);
    }
    Ok(GltfModel { document: gltf.document, buffers })
}

/// The bytes of a `data:[MIME];base64,DATA` URI (what gltf's importer
/// decodes; its `import` feature is off, with its image decoders).
fn data_uri_bytes(uri: &str) -> std::result::Result<Vec<u8>, String> {
    use base64::Engine;
    let (_, encoded) = uri.split_once(";base64,").ok_or("not a base64 data URI (no \";base64,\")")?;
    base64::engine::general_purpose::STANDARD.decode(encoded).map_err(|e| e.to_string())
}

/// An error for a primitive whose POSITION names an accessor that does not exist.
fn check_position_indices(path: &Path, json: &gltf::json::Root) -> Result<()> {
    let positions = gltf::json::validation::Checked::Valid(gltf::Semantic::Positions);
    for (number, mesh) in json.meshes.iter().enumerate() {
        for (primitive, attributes) in mesh.primitives.iter().map(|p| &p.attributes).enumerate() {
            if let Some(index) = attributes.get(&positions)
                && index.value() >= json.accessors.len()
            {
                return Err(Error::bad_file(
                    path,
                    format!(
                        "not a glTF model: primitive {primitive} of mesh {number} has POSITION accessor {}, \
                         but there are {} accessors",
                        index.value(),
                        json.accessors.len()
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// Checks the accessors of `primitive` that the loaders of both crates read
/// (`POSITION`, `TEXCOORD_0`, the indices) before the gltf crate reads them:
/// it trusts their types, strides and counts (a `TEXCOORD_0` of VEC4 fails a
/// debug assertion, an index of type F32 is `unreachable!`, a count of 2^62
/// overflows) and found by fuzzing. Each must be of the type glTF prescribes,
/// not sparse, and lie within its buffer view and buffer. `what` names the
/// primitive in messages.
pub fn check_accessors(
    path: &Path,
    what: &str,
    model: &GltfModel,
    primitive: &gltf::Primitive,
) -> Result<()> {
    use gltf::Semantic;
    use gltf::accessor::{DataType, Dimensions};
    let wanted: [(Option<gltf::Accessor>, &str, Dimensions, &[DataType]); 3] = [
        (primitive.get(&Semantic::Positions), "POSITION", Dimensions::Vec3, &[DataType::F32]),
        (
            primitive.get(&Semantic::TexCoords(0)),
            "TEXCOORD_0",
            Dimensions::Vec2,
            &[DataType::F32, DataType::U8, DataType::U16],
        ),
        (primitive.indices(), "indices", Dimensions::Scalar, &[DataType::U8, DataType::U16, DataType::U32]),
    ];
    for (accessor, name, dimensions, types) in wanted {
        let Some(accessor) = accessor else { continue };
        check_accessor(model, &accessor, dimensions, types)
            .map_err(|why| Error::bad_file(path, format!("{what}: the {name} accessor {why}")))?;
    }
    Ok(())
}

/// One accessor: its type, no sparse storage, a view, and every element
/// within the view and the view within its buffer (checked arithmetic).
fn check_accessor(
    model: &GltfModel,
    accessor: &gltf::Accessor,
    dimensions: gltf::accessor::Dimensions,
    types: &[gltf::accessor::DataType],
) -> std::result::Result<(), String> {
    if accessor.dimensions() != dimensions || !types.contains(&accessor.data_type()) {
        return Err(format!(
            "is {:?} of {:?}; glTF wants {dimensions:?} of {}",
            accessor.dimensions(),
            accessor.data_type(),
            types.iter().map(|t| format!("{t:?}")).collect::<Vec<_>>().join(" or ")
        ));
    }
    if accessor.sparse().is_some() {
        return Err("is sparse, which vehicle models may not be".into());
    }
    let Some(view) = accessor.view() else { return Err("has no buffer view".into()) };
    let size = accessor.size();
    let stride = view.stride().unwrap_or(size);
    if accessor.count() == 0 || stride < size {
        return Err(format!("has {} elements of {size} bytes {stride} bytes apart", accessor.count()));
    }
    let end = stride
        .checked_mul(accessor.count() - 1)
        .and_then(|span| span.checked_add(accessor.offset()))
        .and_then(|span| span.checked_add(size));
    if end.is_none_or(|end| end > view.length()) {
        return Err(format!(
            "({} elements from byte {}) runs past its buffer view of {} bytes",
            accessor.count(),
            accessor.offset(),
            view.length()
        ));
    }
    let buffer = model.buffers.get(view.buffer().index()).map_or(0, Vec::len);
    if view.offset().checked_add(view.length()).is_none_or(|end| end > buffer) {
        return Err(format!("is in a buffer view that runs past its buffer of {buffer} bytes"));
    }
    Ok(())
}

/// The file `reference` (a glTF URI or an OBJ `mtllib`, percent-encoded or
/// not) names beside `model`, if the containment rule allows it.
pub fn resolve_inside(model: &Path, reference: &str) -> Result<PathBuf> {
    let refuse = |why: &str| {
        Error::bad_file(
            model,
            format!(
                "names {reference:?}, which {why}: a model may name only data: URIs and files inside its own folder"
            ),
        )
    };
    let decoded = percent_decode(reference).ok_or_else(|| refuse("is not a valid URI"))?;
    if decoded.contains(':') || decoded.contains('\\') {
        return Err(refuse("has a scheme, a drive or a backslash"));
    }
    let relative = Path::new(&decoded);
    let plain = relative.components().all(|c| matches!(c, Component::Normal(_) | Component::CurDir));
    if !plain || relative.as_os_str().is_empty() {
        return Err(refuse("leaves the model's folder"));
    }
    let folder = match model.parent() {
        Some(parent) if !parent.as_os_str().is_empty() => parent.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let file = folder.join(relative);
    let real_folder = folder.canonicalize().map_err(|e| Error::io(&folder, e))?;
    let real_file = file.canonicalize().map_err(|e| Error::io(&file, e))?;
    if !real_file.starts_with(&real_folder) {
        return Err(refuse(&format!("is a link to {}, outside the model's folder", real_file.display())));
    }
    Ok(file)
}

/// `%XX` decoded (URIs in glTF are percent-encoded); `None` when malformed.
fn percent_decode(text: &str) -> Option<String> {
    let bytes = text.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' {
            let hex = std::str::from_utf8(bytes.get(i + 1..i + 3)?).ok()?;
            out.push(u8::from_str_radix(hex, 16).ok()?);
            i += 3;
        } else {
            out.push(bytes[i]);
            i += 1;
        }
    }
    String::from_utf8(out).ok()
}

/// Checks one vertex: finite and within [`MAX_COORDINATE_M`]. `what` names
/// the primitive or object for the message.
pub fn check_coordinates(path: &Path, what: &str, position: [f32; 3]) -> Result<()> {
    if !position.iter().all(|v| v.is_finite()) {
        return Err(Error::bad_file(
            path,
            format!("{what}: a vertex at {position:?} is not finite (NaN or infinity)"),
        ));
    }
    if position.iter().any(|v| f64::from(v.abs()) > MAX_COORDINATE_M) {
        return Err(Error::bad_file(
            path,
            format!(
                "{what}: a vertex at {position:?} m is beyond ±{MAX_COORDINATE_M:e} m: check the units \
                 (axes.scale), node scales and axes.origin"
            ),
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn references_outside_the_model_folder_are_refused() {
        let dir = tempfile::tempdir().unwrap();
        let model = dir.path().join("car.gltf");
        std::fs::write(dir.path().join("car data.bin"), [0u8; 4]).unwrap();
        assert_eq!(resolve_inside(&model, "car%20data.bin").unwrap(), dir.path().join("car data.bin"));
        for reference in ["../../dev/zero", "/dev/zero", "file:///dev/zero", "a/../../b", "%2e%2e/x", "%zz"] {
            let error = resolve_inside(&model, reference).unwrap_err().to_string();
            assert!(error.contains("inside its own folder"), "{reference}: {error}");
        }
        #[cfg(unix)]
        {
            std::os::unix::fs::symlink("/dev/zero", dir.path().join("zero.bin")).unwrap();
            let error = resolve_inside(&model, "zero.bin").unwrap_err().to_string();
            assert!(error.contains("outside the model's folder"), "{error}");
        }
    }
}
