//! Triangle meshes: the vehicle (with named parts), and what occluders are made of.
//!
//! The vehicle lives in its own frame — x forward, y left, z up, metres, the
//! origin on the ground under its centre — so that a pose (position + yaw)
//! places it in the world. Loaders convert glTF 2.0 and OBJ files (Y up by
//! convention) into that frame with a configurable forward and up axis, and
//! name each triangle's part after its node, mesh or material.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use glam::{DVec3, Vec2, Vec3, vec3};
use serde::{Deserialize, Serialize};

use crate::error::{CaptureError, Result};

/// A triangle mesh with a part per triangle.
#[derive(Debug, Clone, Default)]
pub struct Mesh {
    pub positions: Vec<Vec3>,
    /// Per-vertex UVs (v = 0 at the top row), if the source had them.
    pub uvs: Option<Vec<Vec2>>,
    pub triangles: Vec<[u32; 3]>,
    /// Index into `parts` for each triangle.
    pub triangle_part: Vec<u32>,
    pub parts: Vec<String>,
    /// Primitives (glTF) or objects (OBJ) that came without UVs, named for
    /// the `--keep-uvs` error; `uvs` is `None` when this is not empty.
    pub missing_uvs: Vec<String>,
    /// Loaded models only: every vertex's own UV as the file has it, NaN
    /// where its primitive has none (a part map labels the triangles that
    /// have them, [`crate::scene::part_map`]). Empty for meshes built here.
    pub own_uvs: Vec<Vec2>,
}

/// Two meshes are equal when every field is, the own UVs compared bit for
/// bit: they hold NaN where a primitive has no UVs (a plain OBJ or glTF has
/// none at all), and NaN never equals itself, so a derived equality made
/// such a mesh unequal to its own copy (every `--count` capture of it was
/// refused as "a different vehicle", issue 42 §5).
impl PartialEq for Mesh {
    fn eq(&self, other: &Mesh) -> bool {
        self.positions == other.positions
            && self.uvs == other.uvs
            && self.triangles == other.triangles
            && self.triangle_part == other.triangle_part
            && self.parts == other.parts
            && self.missing_uvs == other.missing_uvs
            && self.own_uvs.len() == other.own_uvs.len()
            && self
                .own_uvs
                .iter()
                .zip(&other.own_uvs)
                .all(|(a, b)| a.to_array().map(f32::to_bits) == b.to_array().map(f32::to_bits))
    }
}

impl Mesh {
    /// The index of part `name`, added if new.
    pub fn part(&mut self, name: &str) -> u32 {
        match self.parts.iter().position(|p| p == name) {
            Some(index) => index as u32,
            None => {
                self.parts.push(name.to_string());
                (self.parts.len() - 1) as u32
            }
        }
    }

    /// Adds a triangle (counter-clockwise seen from outside).
    pub fn add_triangle(&mut self, part: &str, a: Vec3, b: Vec3, c: Vec3) {
        let part = self.part(part);
        let base = self.positions.len() as u32;
        self.positions.extend([a, b, c]);
        self.triangles.push([base, base + 1, base + 2]);
        self.triangle_part.push(part);
    }

    /// Adds a planar quad a-b-c-d (counter-clockwise seen from outside).
    pub fn add_quad(&mut self, part: &str, a: Vec3, b: Vec3, c: Vec3, d: Vec3) {
        self.add_triangle(part, a, b, c);
        self.add_triangle(part, a, c, d);
    }

    /// Adds an axis-aligned box; `faces` names the part of the +x, −x, +y, −y,
    /// +z, −z faces, `None` leaving a face out (hidden against other parts).
    pub fn add_box(&mut self, min: Vec3, max: Vec3, faces: [Option<&str>; 6]) {
        let p = |x: bool, y: bool, z: bool| {
            vec3(if x { max.x } else { min.x }, if y { max.y } else { min.y }, if z { max.z } else { min.z })
        };
        let quads = [
            [p(true, false, false), p(true, true, false), p(true, true, true), p(true, false, true)],
            [p(false, true, false), p(false, false, false), p(false, false, true), p(false, true, true)],
            [p(true, true, false), p(false, true, false), p(false, true, true), p(true, true, true)],
            [p(false, false, false), p(true, false, false), p(true, false, true), p(false, false, true)],
            [p(false, false, true), p(true, false, true), p(true, true, true), p(false, true, true)],
            [p(false, true, false), p(true, true, false), p(true, false, false), p(false, false, false)],
        ];
        for (quad, part) in quads.into_iter().zip(faces) {
            if let Some(part) = part {
                self.add_quad(part, quad[0], quad[1], quad[2], quad[3]);
            }
        }
    }

    /// Appends another mesh (parts merged by name).
    pub fn append(&mut self, other: &Mesh) {
        let base = self.positions.len() as u32;
        let map: Vec<u32> = other.parts.iter().map(|name| self.part(name)).collect();
        self.positions.extend(&other.positions);
        match (&mut self.uvs, &other.uvs) {
            (Some(uvs), Some(theirs)) => uvs.extend(theirs),
            _ => self.uvs = None,
        }
        self.missing_uvs.extend(other.missing_uvs.iter().cloned());
        if !(self.own_uvs.is_empty() && other.own_uvs.is_empty()) {
            self.own_uvs.resize(base as usize, Vec2::NAN);
            self.own_uvs.extend(&other.own_uvs);
            self.own_uvs.resize(self.positions.len(), Vec2::NAN);
        }
        self.triangles.extend(other.triangles.iter().map(|t| t.map(|i| i + base)));
        self.triangle_part.extend(other.triangle_part.iter().map(|&p| map[p as usize]));
    }

    /// Axis-aligned bounds `(min, max)`; zero for an empty mesh.
    pub fn bounds(&self) -> (DVec3, DVec3) {
        if self.positions.is_empty() {
            return (DVec3::ZERO, DVec3::ZERO);
        }
        let mut min = DVec3::splat(f64::INFINITY);
        let mut max = DVec3::splat(f64::NEG_INFINITY);
        for p in &self.positions {
            min = min.min(p.as_dvec3());
            max = max.max(p.as_dvec3());
        }
        (min, max)
    }

    /// Corners of one triangle.
    pub fn corners(&self, triangle: usize) -> [Vec3; 3] {
        self.triangles[triangle].map(|i| self.positions[i as usize])
    }

    /// Surface area in m².
    pub fn area(&self) -> f64 {
        (0..self.triangles.len()).map(|t| triangle_area(self.corners(t))).sum()
    }

    /// Renames parts (`from → to`); parts renamed to the same name merge.
    pub fn rename_parts(&mut self, rename: &BTreeMap<String, String>) {
        if rename.is_empty() {
            return;
        }
        let old = std::mem::take(&mut self.parts);
        let map: Vec<u32> = old
            .iter()
            .map(|name| self.part(rename.get(name).map_or(name.as_str(), String::as_str)))
            .collect();
        for part in &mut self.triangle_part {
            *part = map[*part as usize];
        }
    }

    /// Checks indices and finiteness.
    pub fn check(&self, what: &str) -> Result<()> {
        let n = self.positions.len() as u32;
        if self.triangles.is_empty() {
            return Err(CaptureError::BadOptions(format!("{what} has no triangles")));
        }
        if self.triangles.iter().flatten().any(|&i| i >= n) || !self.positions.iter().all(|p| p.is_finite()) {
            return Err(CaptureError::BadOptions(format!("{what} has bad indices or non-finite positions")));
        }
        Ok(())
    }
}

/// Area of a triangle in m².
pub fn triangle_area([a, b, c]: [Vec3; 3]) -> f64 {
    let (a, b, c) = (a.as_dvec3(), b.as_dvec3(), c.as_dvec3());
    (b - a).cross(c - a).length() / 2.0
}

/// What names a vehicle part when loading a file.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum PartSource {
    /// The glTF node name, or the OBJ object/group name.
    #[default]
    Node,
    /// The glTF mesh name (OBJ: the object/group name).
    Mesh,
    /// The material name.
    Material,
}

/// How a file's axes map to the vehicle frame.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Axes {
    /// The file axis that points forward: `"+x"`, `"-z"`, ...
    pub forward: String,
    /// The file axis that points up.
    pub up: String,
    /// Uniform scale to metres.
    pub scale: f64,
    /// The point of the file (file units, after glTF node transforms) that
    /// becomes the vehicle's origin — on the ground under its centre. It is
    /// subtracted before scaling and axis conversion.
    pub origin: [f64; 3],
}

impl Default for Axes {
    /// glTF's convention: +Y up, the front of the asset facing +Z.
    fn default() -> Axes {
        Axes { forward: "+z".into(), up: "+y".into(), scale: 1.0, origin: [0.0; 3] }
    }
}

fn parse_axis(text: &str) -> Result<Vec3> {
    let v = match text.trim().to_ascii_lowercase().as_str() {
        "+x" | "x" => Vec3::X,
        "-x" => -Vec3::X,
        "+y" | "y" => Vec3::Y,
        "-y" => -Vec3::Y,
        "+z" | "z" => Vec3::Z,
        "-z" => -Vec3::Z,
        other => {
            return Err(CaptureError::BadOptions(format!("axis must be one of ±x, ±y, ±z, not {other:?}")));
        }
    };
    Ok(v)
}

impl Axes {
    /// The file's forward, left and up unit axes.
    fn basis(&self) -> Result<[Vec3; 3]> {
        let forward = parse_axis(&self.forward)?;
        let up = parse_axis(&self.up)?;
        if forward.dot(up) != 0.0 {
            return Err(CaptureError::BadOptions(format!(
                "forward {} and up {} must be different axes",
                self.forward, self.up
            )));
        }
        if !(self.scale.is_finite() && self.scale > 0.0 && DVec3::from(self.origin).is_finite()) {
            return Err(CaptureError::BadOptions(format!(
                "axes: scale must be positive and origin finite (scale {}, origin {:?})",
                self.scale, self.origin
            )));
        }
        // Vehicle frame: x forward, y left, z up; right-handed, so left = up × forward.
        Ok([forward, up.cross(forward), up])
    }

    /// The map from file coordinates to the vehicle frame.
    pub fn converter(&self) -> Result<impl Fn([f32; 3]) -> Vec3 + use<>> {
        let [forward, left, up] = self.basis()?;
        let scale = self.scale as f32;
        let origin = DVec3::from(self.origin).as_vec3();
        Ok(move |p: [f32; 3]| {
            let p = (Vec3::from(p) - origin) * scale;
            vec3(p.dot(forward), p.dot(left), p.dot(up))
        })
    }

    /// The inverse of [`Axes::converter`]: where a vehicle-frame point lies
    /// in the file (to suggest an `origin`).
    pub fn to_file(&self, vehicle: DVec3) -> Result<DVec3> {
        let [forward, left, up] = self.basis()?.map(|v| v.as_dvec3());
        Ok((forward * vehicle.x + left * vehicle.y + up * vehicle.z) / self.scale + DVec3::from(self.origin))
    }
}

/// Loads a glTF 2.0 (`.gltf`/`.glb`) or OBJ vehicle.
pub fn load_vehicle(path: &Path, source: PartSource, axes: &Axes) -> Result<Mesh> {
    load_model(path, source, axes).map(|(mesh, _)| mesh)
}

/// [`load_vehicle`], with every file it read: the model and the buffers or
/// MTL files it names (a capture must never write over one of them).
pub(crate) fn load_model(path: &Path, source: PartSource, axes: &Axes) -> Result<(Mesh, Vec<PathBuf>)> {
    let ext = path.extension().map(|e| e.to_string_lossy().to_ascii_lowercase()).unwrap_or_default();
    let (mesh, files) = match ext.as_str() {
        "gltf" | "glb" => {
            // The model and its buffers through the analyzer's safe reader (see ufcsr::files::read_gltf).
            let gltf = ufcsr::files::read_gltf(path, ufcsr::files::MODEL_LIMIT)?;
            (gltf_mesh(path, &gltf, source, axes)?, gltf_files(path, &gltf)?)
        }
        "obj" => load_obj(path, source, axes)?,
        _ => return Err(CaptureError::bad_file(path, "vehicle mesh must be .glb, .gltf or .obj")),
    };
    check_model(path, &mesh)?;
    Ok((mesh, files))
}

/// The checks every loaded model passes: triangles, indices, and finite
/// coordinates within [`ufcsr::files::MAX_COORDINATE_M`].
pub(crate) fn check_model(path: &Path, mesh: &Mesh) -> Result<()> {
    mesh.check(&path.display().to_string())?;
    for position in &mesh.positions {
        ufcsr::files::check_coordinates(path, "the mesh", position.to_array())?;
    }
    Ok(())
}

/// The model and the files its buffers name (data: URIs and the GLB's own
/// chunk are inside it).
fn gltf_files(path: &Path, gltf: &ufcsr::files::GltfModel) -> Result<Vec<PathBuf>> {
    let mut files = vec![path.to_path_buf()];
    for buffer in gltf.document.buffers() {
        if let gltf::buffer::Source::Uri(uri) = buffer.source()
            && !uri.starts_with("data:")
        {
            files.push(ufcsr::files::resolve_inside(path, uri)?);
        }
    }
    Ok(files)
}

/// The mesh of a glTF model read by [`ufcsr::files::read_gltf`] (or from bytes);
/// `path` names it in messages.
pub(crate) fn gltf_mesh(
    path: &Path,
    gltf: &ufcsr::files::GltfModel,
    source: PartSource,
    axes: &Axes,
) -> Result<Mesh> {
    let convert = axes.converter()?;
    let scene = gltf.document.default_scene().or_else(|| gltf.document.scenes().next());
    let Some(scene) = scene else {
        return Err(CaptureError::bad_file(path, "glTF has no scene"));
    };
    let mut mesh = Mesh { uvs: Some(Vec::new()), ..Mesh::default() };
    let mut stack: Vec<(gltf::Node, glam::Mat4)> = scene.nodes().map(|n| (n, glam::Mat4::IDENTITY)).collect();
    // glTF nodes form a forest: a node met twice means a cycle (which would
    // grow this stack forever) or a shared child, both invalid.
    let mut visited = vec![false; gltf.document.nodes().len()];
    while let Some((node, parent)) = stack.pop() {
        if std::mem::replace(&mut visited[node.index()], true) {
            return Err(CaptureError::bad_file(
                path,
                format!(
                    "glTF node {} appears twice in the node tree (a cycle or a shared child)",
                    node.index()
                ),
            ));
        }
        let transform = parent * glam::Mat4::from_cols_array_2d(&node.transform().matrix());
        for child in node.children() {
            stack.push((child, transform));
        }
        let Some(node_mesh) = node.mesh() else { continue };
        for (number, primitive) in node_mesh.primitives().enumerate() {
            if primitive.mode() != gltf::mesh::Mode::Triangles {
                continue;
            }
            ufcsr::files::check_accessors(
                path,
                &describe_primitive(&node, &node_mesh, &primitive, number),
                gltf,
                &primitive,
            )?;
            let reader = primitive.reader(|b| gltf.buffer(b));
            let Some(positions) = reader.read_positions() else { continue };
            let positions: Vec<Vec3> =
                positions.map(|p| convert(transform.transform_point3(Vec3::from(p)).to_array())).collect();
            let uvs: Option<Vec<Vec2>> =
                reader.read_tex_coords(0).map(|t| t.into_f32().map(Vec2::from).collect());
            let indices: Vec<u32> = match reader.read_indices() {
                Some(indices) => indices.into_u32().collect(),
                None => (0..positions.len() as u32).collect(),
            };
            let name = match source {
                PartSource::Node => node.name().map(str::to_string),
                PartSource::Mesh => node_mesh.name().map(str::to_string),
                PartSource::Material => primitive.material().name().map(str::to_string),
            }
            .unwrap_or_else(|| format!("node{}_prim{number}", node.index()));
            let part = mesh.part(&name);
            let base = mesh.positions.len() as u32;
            let count = positions.len();
            mesh.positions.extend(positions);
            match &uvs {
                Some(uvs) if uvs.len() == count => mesh.own_uvs.extend(uvs),
                _ => mesh.own_uvs.extend(std::iter::repeat_n(Vec2::NAN, count)),
            }
            match (&mut mesh.uvs, uvs) {
                (Some(all), Some(uvs)) if uvs.len() == count => all.extend(uvs),
                (_, uvs) => {
                    mesh.uvs = None;
                    if uvs.is_none_or(|uvs| uvs.len() != count) {
                        mesh.missing_uvs.push(format!(
                            "{} (no TEXCOORD_0)",
                            describe_primitive(&node, &node_mesh, &primitive, number)
                        ));
                    }
                }
            }
            // A mirroring transform flips the winding; culling is off, so it does not matter.
            for tri in indices.chunks_exact(3) {
                mesh.triangles.push([tri[0], tri[1], tri[2]].map(|i| i.saturating_add(base)));
                mesh.triangle_part.push(part);
            }
        }
    }
    Ok(mesh)
}

/// Names a glTF primitive for messages: node, mesh, primitive number and material.
fn describe_primitive(
    node: &gltf::Node,
    mesh: &gltf::Mesh,
    primitive: &gltf::Primitive,
    number: usize,
) -> String {
    let quoted = |name: Option<&str>| name.map_or_else(|| "unnamed".to_string(), |n| format!("{n:?}"));
    format!(
        "primitive {number} of mesh {} ({}) in node {} ({}), material {}",
        mesh.index(),
        quoted(mesh.name()),
        node.index(),
        quoted(node.name()),
        quoted(primitive.material().name()),
    )
}

fn load_obj(path: &Path, source: PartSource, axes: &Axes) -> Result<(Mesh, Vec<PathBuf>)> {
    let loaded = crate::scene::model_files::load_obj(path, &obj_options())?;
    let mesh = obj_mesh(loaded.models, &loaded.materials, source, axes)?;
    Ok((mesh, loaded.files))
}

/// How OBJ files are read: triangulated, one index per vertex.
pub(crate) fn obj_options() -> tobj::LoadOptions {
    tobj::LoadOptions { triangulate: true, single_index: true, ..Default::default() }
}

/// The mesh of OBJ models and their materials.
pub(crate) fn obj_mesh(
    models: Vec<tobj::Model>,
    materials: &[tobj::Material],
    source: PartSource,
    axes: &Axes,
) -> Result<Mesh> {
    let convert = axes.converter()?;
    let mut mesh = Mesh { uvs: Some(Vec::new()), ..Mesh::default() };
    for model in models {
        let m = &model.mesh;
        let name = match source {
            PartSource::Material => {
                m.material_id.and_then(|i| materials.get(i)).map(|mat| mat.name.clone()).unwrap_or(model.name)
            }
            PartSource::Node | PartSource::Mesh => model.name,
        };
        let part = mesh.part(&name);
        let base = mesh.positions.len() as u32;
        let count = m.positions.len() / 3;
        mesh.positions.extend(m.positions.chunks_exact(3).map(|p| convert([p[0], p[1], p[2]])));
        if m.texcoords.len() == count * 2 {
            mesh.own_uvs.extend(m.texcoords.chunks_exact(2).map(|t| Vec2::new(t[0], 1.0 - t[1])));
        } else {
            mesh.own_uvs.extend(std::iter::repeat_n(Vec2::NAN, count));
        }
        match &mut mesh.uvs {
            // OBJ puts v = 0 at the bottom of the texture; the palette's row 0 is the top.
            Some(all) if m.texcoords.len() == count * 2 => {
                all.extend(m.texcoords.chunks_exact(2).map(|t| Vec2::new(t[0], 1.0 - t[1])))
            }
            _ => {
                mesh.uvs = None;
                if m.texcoords.len() != count * 2 {
                    mesh.missing_uvs.push(format!("object {:?} (no vt texture coordinates)", name));
                }
            }
        }
        for tri in m.indices.chunks_exact(3) {
            mesh.triangles.push([tri[0], tri[1], tri[2]].map(|i| i.saturating_add(base)));
            mesh.triangle_part.push(part);
        }
    }
    Ok(mesh)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn box_faces_point_outwards_and_axes_convert() {
        let mut mesh = Mesh::default();
        mesh.add_box(Vec3::ZERO, Vec3::ONE, [Some("a"), None, Some("b"), Some("b"), Some("c"), None]);
        assert_eq!(mesh.triangles.len(), 8);
        assert_eq!(mesh.parts, ["a", "b", "c"]);
        let centre = Vec3::splat(0.5);
        for t in 0..mesh.triangles.len() {
            let [a, b, c] = mesh.corners(t);
            let normal = (b - a).cross(c - a);
            assert!(normal.dot(a - centre) > 0.0, "triangle {t} faces inwards");
        }
        assert!((mesh.area() - 4.0).abs() < 1e-6);
        // glTF: +Z forward, +Y up, so +X is the vehicle's left.
        let convert = Axes::default().converter().unwrap();
        assert_eq!(convert([1.0, 2.0, 3.0]), vec3(3.0, 1.0, 2.0));
        let mut rename = BTreeMap::new();
        rename.insert("a".to_string(), "c".to_string());
        mesh.rename_parts(&rename);
        assert_eq!(mesh.parts, ["c", "b"]);
    }

    #[test]
    fn a_mesh_without_own_uvs_equals_its_own_copy() {
        let mut mesh = Mesh::default();
        mesh.add_box(Vec3::ZERO, Vec3::ONE, [Some("a"); 6]);
        // What the loaders hold for a primitive without UVs: NaN per vertex.
        mesh.own_uvs = vec![Vec2::NAN; mesh.positions.len()];
        assert_eq!(mesh, mesh.clone());
        let mut other = mesh.clone();
        other.own_uvs[0] = Vec2::ZERO;
        assert_ne!(mesh, other);
    }
}
