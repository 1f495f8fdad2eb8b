//! The capture's occluders in glTF: `scene.glb`.
//!
//! An archive describes its scene so that Blender, Unity or a third party
//! can rebuild it: `vehicle.glb` is the vehicle in its own frame, the
//! manifest places it and every eye per frame, and `scene.glb` holds what
//! hid the vehicle — boxes, environment meshes, parked vehicles, the ground
//! — in world coordinates, one node per occluder named after it. A moving
//! occluder is a node at the world origin holding its triangles in its own
//! frame: the manifest's frames give its pose (position and yaw) in each
//! frame, as they give the vehicle's for `vehicle.glb`. Axes follow [`crate::archive::glb`]: world `(x, y, z)` (x east,
//! y north, z up) is glTF `(y, z, x)`.

use std::path::Path;

use gltf_json as json;

use crate::archive::glb::{Bounds, GlbBuilder, to_gltf_axes};
use crate::error::{Error, Result};

/// One occluder: a triangle list around its origin.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct SceneObject {
    /// The node name (unique in the scene).
    pub name: String,
    /// Where the node stands, world metres (z up).
    pub origin: [f64; 3],
    /// Triangle corners relative to `origin`, world axes (z up), metres.
    pub triangles: Vec<[f32; 3]>,
}

/// Writes `scene.glb`: each object a node at its origin (glTF axes) with
/// one unlit primitive in `color` (linear RGBA; the capture's background, in
/// which occluders are drawn). An empty scene is a file with no nodes.
pub fn write_scene_glb(path: &Path, objects: &[SceneObject], color: [f32; 4]) -> Result<()> {
    let bytes = scene_glb(objects, color).map_err(|message| Error::bad_file(path, message))?;
    crate::files::write_bytes_atomically(path, &bytes)
}

fn scene_glb(objects: &[SceneObject], color: [f32; 4]) -> std::result::Result<Vec<u8>, String> {
    let mut glb = GlbBuilder::new();
    let material = glb.unlit_material("occluder", None, color);
    let mut nodes = Vec::with_capacity(objects.len());
    for object in objects {
        if object.triangles.is_empty() || !object.triangles.len().is_multiple_of(3) {
            return Err(format!(
                "occluder {:?} has {} corners: not a triangle list",
                object.name,
                object.triangles.len()
            ));
        }
        let positions: Vec<[f32; 3]> = object.triangles.iter().map(|&p| to_gltf_axes(p)).collect();
        let position = glb.attribute(&positions, Bounds::Written);
        let origin = to_gltf_axes(object.origin.map(|v| v as f32));
        let attributes = vec![(json::mesh::Semantic::Positions, position)];
        nodes.push(glb.mesh_node(&object.name, attributes, material, Some(origin)));
    }
    glb.finish(nodes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_occluder_stands_at_its_world_place_in_gltf_axes_under_its_name() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("scene.glb");
        // A 2 m tall wall 10 m east of the origin, 4 m long northwards.
        let wall = SceneObject {
            name: "wall".into(),
            origin: [10.0, 0.0, 0.0],
            triangles: vec![[0.0, -2.0, 0.0], [0.0, 2.0, 0.0], [0.0, 2.0, 2.0]],
        };
        write_scene_glb(&path, &[wall], [0.0, 0.0, 1.0, 1.0]).unwrap();
        let gltf = gltf::Gltf::open(&path).unwrap();
        let node = gltf.document.nodes().next().unwrap();
        assert_eq!(node.name(), Some("wall"));
        // East (world +x) is glTF +z, north (+y) glTF +x, up glTF +y.
        assert_eq!(node.transform().decomposed().0, [0.0, 0.0, 10.0]);
        let bounds = node.mesh().unwrap().primitives().next().unwrap().bounding_box();
        assert_eq!((bounds.min, bounds.max), ([-2.0, 0.0, 0.0], [2.0, 2.0, 0.0]));
        let material = node.mesh().unwrap().primitives().next().unwrap().material();
        assert_eq!(material.pbr_metallic_roughness().base_color_factor(), [0.0, 0.0, 1.0, 1.0]);
    }
}
