//! The vehicle as unwrapped, in glTF: `vehicle.glb` and `heatmap.glb`.
//!
//! A capture keeps the vehicle mesh exactly as it was unwrapped onto the
//! palette (positions and the UVs that address palette texels, one glTF
//! node and mesh per part, named after it), so that per-texel results go back
//! onto the vehicle: `vehicle.glb` carries the palette and `heatmap.glb` the
//! heatmap as the base-colour texture, nearest filtering, unlit — they open
//! upright in Blender, three.js and any glTF viewer, because positions are
//! stored in glTF's axes and read back into the vehicle frame by the rule of
//! [`crate::archive::glb`] (old z-up files included). Written with
//! `gltf-json`, read back with `gltf`.

use std::path::Path;

use gltf_json as json;

use crate::archive::glb::{Bounds, FileAxes, GlbBuilder, IDENTITY, multiply, to_gltf_axes, transform_point};
use crate::error::{Error, Result};

/// One part: a triangle list (three vertices per triangle).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ModelPart {
    pub name: String,
    /// Vehicle frame (x forward, y left, z up), metres; files hold them in
    /// glTF's axes.
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
    /// Writes the model as binary glTF; with `texture` (its name and PNG
    /// bytes) every part gets it as an unlit, nearest-filtered base-colour
    /// texture.
    pub fn write_glb(&self, path: &Path, texture: Option<(&str, &[u8])>) -> Result<()> {
        let bytes = self.to_glb(texture).map_err(|message| Error::bad_file(path, message))?;
        crate::files::write_bytes_atomically(path, &bytes)
    }

    /// The GLB: one node and mesh per part in glTF's axes (see
    /// [`crate::archive::glb`]), every primitive with the one unlit material
    /// (textured when `texture` is given).
    fn to_glb(&self, texture: Option<(&str, &[u8])>) -> std::result::Result<Vec<u8>, String> {
        let mut glb = GlbBuilder::new();
        let material = match texture {
            Some((name, png)) => {
                let texture = glb.png_texture(png, name);
                glb.unlit_material(name, Some(texture), [1.0; 4])
            }
            None => glb.unlit_material("vehicle", None, [1.0; 4]),
        };
        let mut nodes = Vec::with_capacity(self.parts.len());
        for part in &self.parts {
            check_triangle_list(part)?;
            let positions: Vec<[f32; 3]> = part.positions.iter().map(|&p| to_gltf_axes(p)).collect();
            let position = glb.attribute(&positions, Bounds::Written);
            let uv = glb.attribute(&part.uvs, Bounds::Omitted);
            let attributes =
                vec![(json::mesh::Semantic::Positions, position), (json::mesh::Semantic::TexCoords(0), uv)];
            nodes.push(glb.mesh_node(&part.name, attributes, material, None));
        }
        glb.finish(nodes)
    }

    /// Reads a glTF/GLB model: every node of the scene with a mesh is a part
    /// (named after the node, else its mesh), its triangles in world space of
    /// the file (node transforms applied) taken into the vehicle frame by
    /// [`FileAxes::of`] (glTF's axes, or an old ufcsr file's z-up frame), with
    /// the UVs of set 0. Buffers may be the GLB's chunk, `data:` URIs or files
    /// beside the model (see [`crate::files::read_gltf`]). A primitive without UVs or
    /// triangles, or with a vertex that is not finite or beyond
    /// [`crate::files::MAX_COORDINATE_M`], is an error naming it and the file.
    pub fn read(path: &Path) -> Result<VehicleModel> {
        VehicleModel::read_with(path, Uvs::Required)
    }

    /// The shapes of a glTF file, UVs or not (missing UVs read as 0, 0):
    /// the occluders of `scene.glb` for the scenario map.
    pub fn read_shapes(path: &Path) -> Result<VehicleModel> {
        VehicleModel::read_with(path, Uvs::Optional)
    }

    fn read_with(path: &Path, uvs: Uvs) -> Result<VehicleModel> {
        let model = crate::files::read_gltf(path, crate::files::MODEL_LIMIT)?;
        let axes = FileAxes::of(&model.document);
        let mut parts = Vec::new();
        for (node, transform) in scene_nodes(path, &model.document)? {
            let Some(mesh) = node.mesh() else { continue };
            let name =
                node.name().or(mesh.name()).map_or_else(|| format!("node{}", node.index()), str::to_string);
            let mut part = ModelPart { name, ..ModelPart::default() };
            for primitive in mesh.primitives() {
                read_primitive(path, (&model, uvs), &mesh, &primitive, &mut part)?;
            }
            for p in &mut part.positions {
                *p = axes.to_frame(transform_point(&transform, *p));
            }
            for &position in &part.positions {
                crate::files::check_coordinates(path, &format!("part {:?}", part.name), position)?;
            }
            parts.push(part);
        }
        if parts.is_empty() {
            return Err(Error::bad_file(path, "has no mesh"));
        }
        Ok(VehicleModel { parts })
    }
}

/// Whether a model's primitives must have UVs (a vehicle's do).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Uvs {
    Required,
    Optional,
}

/// Checks that a part is a list of whole triangles with a UV per vertex.
fn check_triangle_list(part: &ModelPart) -> std::result::Result<(), String> {
    let count = part.positions.len();
    if count == 0 || count != part.uvs.len() || !count.is_multiple_of(3) {
        return Err(format!(
            "part {:?} has {} positions and {} UVs: not a triangle list",
            part.name,
            count,
            part.uvs.len()
        ));
    }
    Ok(())
}

/// The nodes of the document's scene (the default, else the first; every
/// node when it has none), each with its world transform. A node met twice
/// (a cycle or a shared child) is an error: glTF's nodes form a forest.
fn scene_nodes<'a>(
    path: &Path,
    document: &'a gltf::Document,
) -> Result<Vec<(gltf::Node<'a>, [[f32; 4]; 4])>> {
    let roots: Vec<gltf::Node> = match document.default_scene().or_else(|| document.scenes().next()) {
        Some(scene) => scene.nodes().collect(),
        None => {
            let children: Vec<usize> =
                document.nodes().flat_map(|n| n.children()).map(|c| c.index()).collect();
            document.nodes().filter(|n| !children.contains(&n.index())).collect()
        }
    };
    let mut stack: Vec<(gltf::Node, [[f32; 4]; 4])> = roots.into_iter().map(|n| (n, IDENTITY)).collect();
    let mut visited = vec![false; document.nodes().len()];
    let mut out = Vec::new();
    while let Some((node, parent)) = stack.pop() {
        if std::mem::replace(&mut visited[node.index()], true) {
            return Err(Error::bad_file(
                path,
                format!(
                    "glTF node {} appears twice in the node tree (a cycle or a shared child)",
                    node.index()
                ),
            ));
        }
        let transform = multiply(&parent, &node.transform().matrix());
        stack.extend(node.children().map(|child| (child, transform)));
        out.push((node, transform));
    }
    out.sort_by_key(|(node, _)| node.index());
    Ok(out)
}

/// Appends one primitive's triangles (a triangle list, vertex by vertex) to `part`.
fn read_primitive(
    path: &Path,
    (model, need): (&crate::files::GltfModel, Uvs),
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
    crate::files::check_accessors(path, &describe(), model, primitive)?;
    let reader = primitive.reader(|buffer| model.buffer(buffer));
    let positions: Vec<[f32; 3]> = reader
        .read_positions()
        .ok_or_else(|| Error::bad_file(path, format!("{} has no positions", describe())))?
        .collect();
    for &position in &positions {
        crate::files::check_coordinates(path, &describe(), position)?;
    }
    let uvs: Vec<[f32; 2]> = match (reader.read_tex_coords(0), need) {
        (Some(uvs), _) => uvs.into_f32().collect(),
        (None, Uvs::Optional) => vec![[0.0, 0.0]; positions.len()],
        (None, Uvs::Required) => {
            return Err(Error::bad_file(path, format!("{} has no UVs (TEXCOORD_0)", describe())));
        }
    };
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
        model.write_glb(&path, Some(("heatmap", &png))).unwrap();
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

    /// Bounds of every POSITION accessor's min/max as the file stores them.
    fn accessor_bounds(path: &Path) -> ([f64; 3], [f64; 3]) {
        let gltf = gltf::Gltf::open(path).unwrap();
        let (mut lo, mut hi) = ([f64::MAX; 3], [f64::MIN; 3]);
        for node in gltf.document.nodes() {
            assert!(node.transform().matrix() == IDENTITY, "ufcsr writes no node transforms");
            for primitive in node.mesh().unwrap().primitives() {
                let bounds = primitive.bounding_box();
                for k in 0..3 {
                    lo[k] = lo[k].min(f64::from(bounds.min[k]));
                    hi[k] = hi[k].max(f64::from(bounds.max[k]));
                }
            }
        }
        (lo, hi)
    }

    #[test]
    fn a_written_model_stands_upright_in_gltf_axes_and_reads_back_in_the_vehicle_frame() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("vehicle.glb");
        let model = triangle_model();
        model.write_glb(&path, None).unwrap();
        // Vehicle x (forward) 0..3 is glTF z, y (left) 0..1 is glTF x, z (up) 0..0.5 is glTF y.
        assert_eq!(accessor_bounds(&path), ([0.0, 0.0, 0.0], [1.0, 0.5, 3.0]));
        assert_eq!(VehicleModel::read(&path).unwrap(), model);
        let gltf = gltf::Gltf::open(&path).unwrap();
        assert_eq!(FileAxes::of(&gltf.document), FileAxes::Gltf);
        // Every primitive has a material, even without a texture.
        assert!(gltf.document.meshes().flat_map(|m| m.primitives()).all(|p| p.material().index() == Some(0)));
    }

    #[test]
    fn an_old_z_up_vehicle_glb_still_reads_in_the_vehicle_frame() {
        // The bundled example archive's vehicle.glb as it was before it was
        // regenerated upright: it predates the axis rule (generator "ufcsr
        // 0.1.0", no mark, positions in the vehicle frame).
        let old =
            Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/reference/vehicle-z-up-ufcsr-0.1.0.glb"));
        let gltf = gltf::Gltf::open(old).unwrap();
        assert_eq!(FileAxes::of(&gltf.document), FileAxes::OldUfcsrFrame);
        let model = VehicleModel::read(old).unwrap();
        let (lo, hi) = accessor_bounds(old);
        let all: Vec<[f32; 3]> = model.parts.iter().flat_map(|p| p.positions.iter().copied()).collect();
        for k in 0..3 {
            assert_eq!(all.iter().map(|p| f64::from(p[k])).fold(f64::MAX, f64::min), lo[k]);
            assert_eq!(all.iter().map(|p| f64::from(p[k])).fold(f64::MIN, f64::max), hi[k]);
        }
        // Upright in the vehicle frame: z (up) from the ground to the roof.
        assert_eq!((lo[2], hi[2] > 1.0), (0.0, true));
        // Rewritten, it is in glTF axes and reads back the same.
        let dir = tempfile::tempdir().unwrap();
        let new = dir.path().join("vehicle.glb");
        model.write_glb(&new, None).unwrap();
        assert_eq!(VehicleModel::read(&new).unwrap(), model);
        let (new_lo, new_hi) = accessor_bounds(&new);
        assert_eq!((new_lo, new_hi), ([lo[1], lo[2], lo[0]], [hi[1], hi[2], hi[0]]));
    }
}
