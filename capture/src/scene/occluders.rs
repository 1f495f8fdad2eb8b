//! Occluders: what hides the vehicle but is never counted. The still ones
//! are world-space triangles grouped into objects with bounds (for per-tile
//! culling) and names (for `scene.glb`); the moving ones
//! ([`crate::scene::moving`]) keep their own frame and get a pose per frame.

use glam::DVec3;

use crate::scene::mesh::Mesh;
use crate::scene::moving::MovingOccluder;

/// Occluders: world-space geometry drawn in the background colour, kept as
/// objects with bounds so that objects outside a tile's view are skipped.
/// Positions are f64: a scene 10 km from the origin would lose a millimetre
/// in f32 (the renderer converts them relative to the pedestrian instead).
/// `positions` and `objects` are the static occluders; those that move
/// (traffic, other pedestrians) are in `moving`, each in its own frame with
/// a pose per frame. `names` groups static objects into the occluders a
/// scene named (an environment mesh is many culling objects but one
/// occluder), for `scene.glb`.
#[derive(Debug, Clone, Default)]
pub struct Occluders {
    pub positions: Vec<DVec3>,
    pub objects: Vec<OccluderObject>,
    /// `(first object, name)`: the objects from there to the next entry
    /// form one named occluder; objects before the first entry are
    /// unnamed (one occluder each).
    pub names: Vec<(usize, String)>,
    /// The occluders that move.
    pub moving: Vec<MovingOccluder>,
}

/// One occluder object: a run of triangle vertices in [`Occluders::positions`]
/// and its world-space bounding box (for per-tile culling).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OccluderObject {
    pub first_vertex: u32,
    pub vertex_count: u32,
    pub min: DVec3,
    pub max: DVec3,
}

impl Occluders {
    /// Adds a mesh already in world coordinates as one object.
    pub fn add_mesh(&mut self, mesh: &Mesh, to_world: glam::DMat4) {
        if mesh.triangles.is_empty() {
            return;
        }
        let first = self.positions.len() as u32;
        let mut min = DVec3::splat(f64::INFINITY);
        let mut max = DVec3::splat(f64::NEG_INFINITY);
        for tri in &mesh.triangles {
            for &i in tri {
                let p = to_world.transform_point3(mesh.positions[i as usize].as_dvec3());
                min = min.min(p);
                max = max.max(p);
                self.positions.push(p);
            }
        }
        self.objects.push(OccluderObject {
            first_vertex: first,
            vertex_count: self.positions.len() as u32 - first,
            min,
            max,
        });
    }

    /// Adds a large mesh (an environment) as one object per `cell` × `cell`
    /// metre square of the ground plan, by triangle centroid, so that a tile
    /// draws only the pieces its frustum can see.
    pub fn add_mesh_chunked(&mut self, mesh: &Mesh, to_world: glam::DMat4, cell: f64) {
        let mut chunks: std::collections::BTreeMap<(i64, i64), Vec<[DVec3; 3]>> = Default::default();
        for tri in &mesh.triangles {
            let corners = tri.map(|i| to_world.transform_point3(mesh.positions[i as usize].as_dvec3()));
            let centroid = (corners[0] + corners[1] + corners[2]) / 3.0;
            let key = ((centroid.x / cell).floor() as i64, (centroid.y / cell).floor() as i64);
            chunks.entry(key).or_default().push(corners);
        }
        for triangles in chunks.values() {
            let first = self.positions.len() as u32;
            let mut min = DVec3::splat(f64::INFINITY);
            let mut max = DVec3::splat(f64::NEG_INFINITY);
            for p in triangles.iter().flatten() {
                min = min.min(*p);
                max = max.max(*p);
                self.positions.push(*p);
            }
            self.objects.push(OccluderObject {
                first_vertex: first,
                vertex_count: self.positions.len() as u32 - first,
                min,
                max,
            });
        }
    }

    /// Names the objects added from now on (until the next name) as one occluder.
    pub fn begin_named(&mut self, name: impl Into<String>) {
        self.names.push((self.objects.len(), name.into()));
    }

    /// The occluders by name, each with its objects; an unnamed object is
    /// an occluder of its own, `occluder N` after its object number.
    pub fn named_groups(&self) -> Vec<(String, std::ops::Range<usize>)> {
        let mut groups = Vec::new();
        let first_named = self.names.first().map_or(self.objects.len(), |(first, _)| *first);
        for object in 0..first_named.min(self.objects.len()) {
            groups.push((format!("occluder {object}"), object..object + 1));
        }
        for (k, (first, name)) in self.names.iter().enumerate() {
            let end = self.names.get(k + 1).map_or(self.objects.len(), |(next, _)| *next);
            if *first < end {
                groups.push((name.clone(), *first..end));
            }
        }
        groups
    }

    /// The occluders for `scene.glb`: one object per named still occluder,
    /// its origin on the ground under the middle of its bounds and its
    /// triangles relative to it (f32 stays exact to a millimetre then); then
    /// one per moving occluder, at the world origin with its triangles in its
    /// own frame (the manifest poses it per frame).
    pub fn scene_objects(&self) -> Vec<ufcsr::output::SceneObject> {
        let mut used = std::collections::BTreeSet::new();
        let moving = self.moving.iter().map(|occluder| {
            let mesh = &occluder.mesh;
            let triangles = mesh.triangles.iter().flatten().map(|&i| mesh.positions[i as usize].to_array());
            (occluder.name.clone(), [0.0; 3], triangles.collect::<Vec<_>>())
        });
        self.named_groups()
            .into_iter()
            .map(|(name, objects)| {
                let objects = &self.objects[objects];
                let min = objects.iter().fold(DVec3::INFINITY, |m, o| m.min(o.min));
                let max = objects.iter().fold(DVec3::NEG_INFINITY, |m, o| m.max(o.max));
                let origin = DVec3::new((min.x + max.x) / 2.0, (min.y + max.y) / 2.0, min.z);
                let triangles = objects
                    .iter()
                    .flat_map(|o| {
                        &self.positions[o.first_vertex as usize..(o.first_vertex + o.vertex_count) as usize]
                    })
                    .map(|p| (*p - origin).as_vec3().to_array())
                    .collect();
                (name, origin.to_array(), triangles)
            })
            .chain(moving)
            .map(|(name, origin, triangles)| {
                // Node names are unique, as Blender and Unity want them.
                let mut unique = name.clone();
                let mut copy = 1;
                while !used.insert(unique.clone()) {
                    copy += 1;
                    unique = format!("{name} ({copy})");
                }
                ufcsr::output::SceneObject { name: unique, origin, triangles }
            })
            .collect()
    }

    /// Appends another set of occluders, object by object, names and all.
    pub fn append(&mut self, other: &Occluders) {
        let first_object = self.objects.len();
        // The other's groups, its unnamed objects named so that they do not
        // join a named occluder of ours.
        self.names.extend(
            other.named_groups().into_iter().map(|(name, objects)| (objects.start + first_object, name)),
        );
        self.moving.extend(other.moving.iter().cloned());
        let base = self.positions.len() as u32;
        self.positions.extend(&other.positions);
        self.objects.extend(
            other
                .objects
                .iter()
                .map(|&object| OccluderObject { first_vertex: object.first_vertex + base, ..object }),
        );
    }

    /// Adds an axis-aligned box (all six faces).
    pub fn add_box(&mut self, min: DVec3, max: DVec3) {
        let mut mesh = Mesh::default();
        mesh.add_box(min.as_vec3(), max.as_vec3(), [Some("box"); 6]);
        self.add_mesh(&mesh, glam::DMat4::IDENTITY);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::vec3;

    #[test]
    fn environment_meshes_split_into_chunks_with_tight_bounds() {
        let mut ground = Mesh::default();
        for i in 0..10 {
            let x = i as f32 * 10.0;
            ground.add_quad(
                "g",
                vec3(x, 0.0, 0.0),
                vec3(x + 10.0, 0.0, 0.0),
                vec3(x + 10.0, 5.0, 0.0),
                vec3(x, 5.0, 0.0),
            );
        }
        let mut occluders = Occluders::default();
        occluders.add_mesh_chunked(&ground, glam::DMat4::IDENTITY, 25.0);
        assert_eq!(occluders.objects.len(), 4);
        assert_eq!(occluders.positions.len(), 60);
        let OccluderObject { min, max, .. } = occluders.objects[0];
        assert_eq!((min.x, max.x), (0.0, 30.0));
    }

    #[test]
    fn occluders_are_grouped_by_the_name_they_were_added_under_and_keep_it_when_appended() {
        let mut wall = Mesh::default();
        wall.add_quad(
            "w",
            vec3(0.0, 0.0, 0.0),
            vec3(30.0, 0.0, 0.0),
            vec3(30.0, 0.0, 3.0),
            vec3(0.0, 0.0, 3.0),
        );
        let mut occluders = Occluders::default();
        occluders.add_box(DVec3::ZERO, DVec3::ONE); // unnamed
        occluders.begin_named("city");
        occluders.add_mesh_chunked(&wall, glam::DMat4::IDENTITY, 10.0); // two culling objects
        let mut other = Occluders::default();
        other.begin_named("city");
        other.add_box(DVec3::ZERO, DVec3::ONE);
        occluders.append(&other);
        let groups: Vec<(String, std::ops::Range<usize>)> = occluders.named_groups();
        assert_eq!(groups, [("occluder 0".into(), 0..1), ("city".into(), 1..3), ("city".into(), 3..4)]);
        let objects = occluders.scene_objects();
        let names: Vec<&str> = objects.iter().map(|o| o.name.as_str()).collect();
        assert_eq!(names, ["occluder 0", "city", "city (2)"]);
        // The wall's origin: the ground under the middle of its bounds; corners relative to it.
        assert_eq!(objects[1].origin, [15.0, 0.0, 0.0]);
        assert_eq!(objects[1].triangles.len(), 6);
        assert!(objects[1].triangles.iter().all(|p| p[0].abs() <= 15.0 && p[2] >= 0.0));
    }
}
