//! The vehicle as unwrapped, in glTF: `vehicle.glb` and `heatmap.glb`.
//!
//! A capture keeps the vehicle mesh exactly as it was unwrapped onto the
//! palette (positions and the UVs that address palette texels, one glTF
//! node and mesh per part, named after it), so that per-texel results go back
//! onto the vehicle: `heatmap.glb` is that mesh with the heatmap as its
//! base-colour texture, nearest filtering, unlit — it opens in Blender,
//! three.js and any glTF viewer. Written with `gltf-json`, read back with
//! `gltf`.

use std::borrow::Cow;
use std::path::Path;

use gltf_json as json;
use json::validation::Checked::Valid;
use json::validation::USize64;

use crate::error::{Error, Result};

/// One part: a triangle list (three vertices per triangle).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ModelPart {
    pub name: String,
    /// Vehicle frame, metres (glTF's axes are the caller's business).
    pub positions: Vec<[f32; 3]>,
    /// Palette UVs, 0..1 with v = 0 at the top row (as glTF).
    pub uvs: Vec<[f32; 2]>,
}

/// A vehicle model: its parts in order.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct VehicleModel {
    pub parts: Vec<ModelPart>,
}

impl VehicleModel {
    /// Writes the model as binary glTF; with `texture` (PNG bytes) every part
    /// gets it as an unlit, nearest-filtered base-colour texture.
    pub fn write_glb(&self, path: &Path, texture: Option<&[u8]>) -> Result<()> {
        let bytes = self.to_glb(texture).map_err(|message| Error::bad_file(path, message))?;
        crate::files::write_bytes_atomically(path, &bytes)
    }

    #[allow(clippy::too_many_lines)] // issue 16: still to split below 80 lines
    fn to_glb(&self, texture: Option<&[u8]>) -> std::result::Result<Vec<u8>, String> {
        let mut root = json::Root::default();
        let mut bin: Vec<u8> = Vec::new();
        let buffer = root.push(json::Buffer {
            byte_length: USize64(0), // set below, once the data is all in
            extensions: None,
            extras: Default::default(),
            name: None,
            uri: None,
        });
        let material = texture.map(|png| {
            let view = push_view(&mut root, &mut bin, buffer, png, None);
            let image = root.push(json::Image {
                buffer_view: Some(view),
                mime_type: Some(json::image::MimeType("image/png".into())),
                name: Some("heatmap".into()),
                uri: None,
                extensions: None,
                extras: Default::default(),
            });
            let sampler = root.push(json::texture::Sampler {
                // Nearest: a texel is one point of the vehicle, never a blend.
                mag_filter: Some(Valid(json::texture::MagFilter::Nearest)),
                min_filter: Some(Valid(json::texture::MinFilter::Nearest)),
                name: None,
                wrap_s: Valid(json::texture::WrappingMode::ClampToEdge),
                wrap_t: Valid(json::texture::WrappingMode::ClampToEdge),
                extensions: None,
                extras: Default::default(),
            });
            let texture = root.push(json::Texture {
                name: None,
                sampler: Some(sampler),
                source: image,
                extensions: None,
                extras: Default::default(),
            });
            root.extensions_used.push("KHR_materials_unlit".into());
            root.push(json::Material {
                name: Some("heatmap".into()),
                double_sided: true,
                pbr_metallic_roughness: json::material::PbrMetallicRoughness {
                    base_color_texture: Some(json::texture::Info {
                        index: texture,
                        tex_coord: 0,
                        extensions: None,
                        extras: Default::default(),
                    }),
                    metallic_factor: json::material::StrengthFactor(0.0),
                    roughness_factor: json::material::StrengthFactor(1.0),
                    ..Default::default()
                },
                // Other material extensions exist when other crates enable
                // their gltf-json features, hence the struct update.
                #[allow(clippy::needless_update)]
                extensions: Some(json::extensions::material::Material {
                    unlit: Some(json::extensions::material::Unlit {}),
                    ..Default::default()
                }),
                ..Default::default()
            })
        });
        let mut nodes = Vec::with_capacity(self.parts.len());
        for part in &self.parts {
            if part.positions.is_empty()
                || part.positions.len() != part.uvs.len()
                || part.positions.len() % 3 != 0
            {
                return Err(format!(
                    "part {:?} has {} positions and {} UVs: not a triangle list",
                    part.name,
                    part.positions.len(),
                    part.uvs.len()
                ));
            }
            let positions: Vec<u8> = part.positions.iter().flatten().flat_map(|v| v.to_le_bytes()).collect();
            let uvs: Vec<u8> = part.uvs.iter().flatten().flat_map(|v| v.to_le_bytes()).collect();
            let (min, max) = bounds(&part.positions);
            let count = part.positions.len();
            let position_view = push_view(&mut root, &mut bin, buffer, &positions, Some(12));
            let uv_view = push_view(&mut root, &mut bin, buffer, &uvs, Some(8));
            let position =
                root.push(accessor(position_view, count, json::accessor::Type::Vec3, Some((min, max))));
            let uv = root.push(accessor(uv_view, count, json::accessor::Type::Vec2, None));
            let primitive = json::mesh::Primitive {
                attributes: [
                    (Valid(json::mesh::Semantic::Positions), position),
                    (Valid(json::mesh::Semantic::TexCoords(0)), uv),
                ]
                .into_iter()
                .collect(),
                extensions: None,
                extras: Default::default(),
                indices: None,
                material,
                mode: Valid(json::mesh::Mode::Triangles),
                targets: None,
            };
            let mesh = root.push(json::Mesh {
                extensions: None,
                extras: Default::default(),
                name: Some(part.name.clone()),
                primitives: vec![primitive],
                weights: None,
            });
            nodes.push(root.push(json::Node {
                mesh: Some(mesh),
                name: Some(part.name.clone()),
                ..Default::default()
            }));
        }
        root.buffers[0].byte_length = USize64::from(bin.len());
        let scene =
            root.push(json::Scene { extensions: None, extras: Default::default(), name: None, nodes });
        root.scene = Some(scene);
        root.asset.generator = Some(concat!("ufcsr ", env!("CARGO_PKG_VERSION")).into());
        let json = json::serialize::to_vec(&root).map_err(|e| format!("glTF JSON: {e}"))?;
        let glb = gltf::binary::Glb {
            header: gltf::binary::Header { magic: *b"glTF", version: 2, length: 0 },
            json: Cow::Owned(json),
            bin: Some(Cow::Owned(bin)),
        };
        glb.to_vec().map_err(|e| format!("GLB: {e}"))
    }

    /// Reads a glTF/GLB model: every node with a mesh is a part (named after
    /// the node, else its mesh), its triangles in world space of the file
    /// with the UVs of set 0. Buffers may be the GLB's chunk, `data:` URIs or
    /// files beside the model (see [`crate::read_gltf`]). A primitive without
    /// UVs or triangles, or with a vertex that is not finite or beyond
    /// [`crate::MAX_COORDINATE_M`], is an error naming it and the file.
    pub fn read(path: &Path) -> Result<VehicleModel> {
        let model = crate::files::read_gltf(path, crate::files::MODEL_LIMIT)?;
        let mut parts = Vec::new();
        for node in model.document.nodes() {
            let Some(mesh) = node.mesh() else { continue };
            let name =
                node.name().or(mesh.name()).map_or_else(|| format!("node{}", node.index()), str::to_string);
            let mut part = ModelPart { name, ..ModelPart::default() };
            for primitive in mesh.primitives() {
                read_primitive(path, &model, &mesh, &primitive, &mut part)?;
            }
            parts.push(part);
        }
        if parts.is_empty() {
            return Err(Error::bad_file(path, "has no mesh"));
        }
        Ok(VehicleModel { parts })
    }
}

/// Appends one primitive's triangles (a triangle list, vertex by vertex) to `part`.
fn read_primitive(
    path: &Path,
    model: &crate::files::GltfModel,
    mesh: &gltf::Mesh,
    primitive: &gltf::Primitive,
    part: &mut ModelPart,
) -> Result<()> {
    let describe = || format!("primitive {} of mesh {:?}", primitive.index(), mesh.name().unwrap_or(""));
    if primitive.mode() != gltf::mesh::Mode::Triangles {
        return Err(Error::bad_file(
            path,
            format!(
                "{} is {:?}, not triangles: a vehicle model is a triangle list",
                describe(),
                primitive.mode()
            ),
        ));
    }
    let reader = primitive.reader(|buffer| model.buffer(buffer));
    let positions: Vec<[f32; 3]> = reader
        .read_positions()
        .ok_or_else(|| Error::bad_file(path, format!("{} has no positions", describe())))?
        .collect();
    for &position in &positions {
        crate::files::check_coordinates(path, &describe(), position)?;
    }
    let uvs: Vec<[f32; 2]> = reader
        .read_tex_coords(0)
        .ok_or_else(|| Error::bad_file(path, format!("{} has no UVs (TEXCOORD_0)", describe())))?
        .into_f32()
        .collect();
    let order: Vec<usize> = match reader.read_indices() {
        Some(indices) => indices.into_u32().map(|i| i as usize).collect(),
        None => (0..positions.len()).collect(),
    };
    if order.is_empty() || !order.len().is_multiple_of(3) {
        return Err(Error::bad_file(
            path,
            format!("{} has {} vertices: not a list of whole triangles", describe(), order.len()),
        ));
    }
    for index in order {
        let (Some(&p), Some(&uv)) = (positions.get(index), uvs.get(index)) else {
            return Err(Error::bad_file(path, format!("{} has an index out of range", describe())));
        };
        if !uv.iter().all(|v| v.is_finite()) {
            return Err(Error::bad_file(path, format!("{} has a UV of {uv:?}: not finite", describe())));
        }
        part.positions.push(p);
        part.uvs.push(uv);
    }
    Ok(())
}

fn bounds(positions: &[[f32; 3]]) -> (Vec<f32>, Vec<f32>) {
    let mut min = [f32::MAX; 3];
    let mut max = [f32::MIN; 3];
    for p in positions {
        for axis in 0..3 {
            min[axis] = min[axis].min(p[axis]);
            max[axis] = max[axis].max(p[axis]);
        }
    }
    (min.to_vec(), max.to_vec())
}

fn push_view(
    root: &mut json::Root,
    bin: &mut Vec<u8>,
    buffer: json::Index<json::Buffer>,
    bytes: &[u8],
    stride: Option<usize>,
) -> json::Index<json::buffer::View> {
    while !bin.len().is_multiple_of(4) {
        bin.push(0);
    }
    let offset = bin.len();
    bin.extend_from_slice(bytes);
    root.push(json::buffer::View {
        buffer,
        byte_length: USize64::from(bytes.len()),
        byte_offset: Some(USize64::from(offset)),
        byte_stride: stride.map(json::buffer::Stride),
        name: None,
        target: stride.map(|_| Valid(json::buffer::Target::ArrayBuffer)),
        extensions: None,
        extras: Default::default(),
    })
}

fn accessor(
    view: json::Index<json::buffer::View>,
    count: usize,
    kind: json::accessor::Type,
    bounds: Option<(Vec<f32>, Vec<f32>)>,
) -> json::Accessor {
    json::Accessor {
        buffer_view: Some(view),
        byte_offset: Some(USize64(0)),
        count: USize64::from(count),
        component_type: Valid(json::accessor::GenericComponentType(json::accessor::ComponentType::F32)),
        extensions: None,
        extras: Default::default(),
        type_: Valid(kind),
        min: bounds.as_ref().map(|(min, _)| json::Value::from(min.clone())),
        max: bounds.map(|(_, max)| json::Value::from(max)),
        name: None,
        normalized: false,
        sparse: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn triangle_model() -> VehicleModel {
        VehicleModel {
            parts: vec![
                ModelPart {
                    name: "hood".into(),
                    positions: vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.5]],
                    uvs: vec![[0.0, 0.0], [0.25, 0.0], [0.0, 0.25]],
                },
                ModelPart {
                    name: "door front left".into(),
                    positions: vec![[2.0, 0.0, 0.0], [3.0, 0.0, 0.0], [2.0, 1.0, 0.0]],
                    uvs: vec![[0.5, 0.5], [0.75, 0.5], [0.5, 0.75]],
                },
            ],
        }
    }

    #[test]
    fn a_model_round_trips_with_part_names_uvs_and_a_nearest_unlit_texture() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("heatmap.glb");
        let png = std::fs::read(concat!(env!("CARGO_MANIFEST_DIR"), "/fixtures/example/pidt.png")).unwrap();
        let model = triangle_model();
        model.write_glb(&path, Some(&png)).unwrap();
        assert_eq!(VehicleModel::read(&path).unwrap(), model);
        let gltf = gltf::Gltf::open(&path).unwrap();
        let material = gltf.document.materials().next().unwrap();
        assert!(gltf.document.extensions_used().any(|e| e == "KHR_materials_unlit"));
        let texture = material.pbr_metallic_roughness().base_color_texture().unwrap().texture();
        assert_eq!(texture.sampler().mag_filter(), Some(gltf::texture::MagFilter::Nearest));
        assert_eq!(texture.sampler().min_filter(), Some(gltf::texture::MinFilter::Nearest));
        let gltf::image::Source::View { view, mime_type } = texture.source().source() else {
            panic!("embedded")
        };
        assert_eq!(mime_type, "image/png");
        let blob = gltf.blob.as_ref().unwrap();
        assert_eq!(&blob[view.offset()..view.offset() + view.length()], &png[..]);
    }
}
