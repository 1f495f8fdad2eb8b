//! Where a model's own UVs overlap, for `--keep-uvs` and `inspect`: the
//! count alone ("1418 texels are covered by more than one triangle") left a
//! user with nowhere to look. Overlaps are grouped by the pair of parts
//! whose triangles share texels, with example triangle numbers, and the
//! pairs that are coincident duplicate faces (the same surface twice in the
//! mesh, [`crate::scene::coincident`]) are told apart from real overlaps
//! (a licence plate mapped over body faces, mirrored halves).

use std::collections::{BTreeMap, HashMap};

use glam::DVec2;

use crate::scene::coincident::covered_triangles;
use crate::scene::mesh::Mesh;
use crate::texture::uv_islands::for_texel_centres;

/// Example triangle pairs listed per pair of parts.
const EXAMPLES: usize = 3;

/// Overlapping texels between two parts.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PartOverlap {
    /// The two parts' names (the same name twice: within one part).
    pub parts: (String, String),
    /// Texels whose centre two or more of these triangles cover.
    pub texels: u64,
    /// Of those, the overlaps a coincident duplicate face makes (one of the
    /// two triangles covers an earlier face whole): removing the duplicate
    /// faces removes these.
    pub duplicate_texels: u64,
    /// A few triangle pairs (mesh triangle numbers).
    pub examples: Vec<(u32, u32)>,
}

/// The overlaps of a mesh's own UVs on a palette.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct UvOverlaps {
    pub palette: [u32; 2],
    /// Texels covered by more than one triangle.
    pub texels: u64,
    /// By pair of parts, most texels first.
    pub by_parts: Vec<PartOverlap>,
}

impl UvOverlaps {
    /// One line per pair of parts, for messages.
    pub fn lines(&self) -> Vec<String> {
        self.by_parts
            .iter()
            .map(|o| {
                let pairs: Vec<String> = o.examples.iter().map(|(a, b)| format!("{a} & {b}")).collect();
                let duplicates = match o.duplicate_texels {
                    0 => String::new(),
                    n if n == o.texels => ", all made by coincident duplicate faces".to_string(),
                    n => format!(", {n} of them made by coincident duplicate faces"),
                };
                format!(
                    "{} × {}: {} texels{duplicates} (triangles {})",
                    o.parts.0,
                    o.parts.1,
                    o.texels,
                    pairs.join(", ")
                )
            })
            .collect()
    }
}

/// The texels of `palette` that more than one triangle's own UVs cover
/// (texel centres strictly inside, as `--keep-uvs` checks), by pair of parts.
/// `None` when the mesh has no UVs.
pub fn uv_overlaps(mesh: &Mesh, palette: [u32; 2]) -> Option<UvOverlaps> {
    let uvs = mesh.uvs.as_ref()?;
    let size = DVec2::new(f64::from(palette[0]), f64::from(palette[1]));
    let width = palette[0] as usize;
    let mut owner = vec![u32::MAX; width * palette[1] as usize];
    // (earlier triangle, later triangle) → texels they share.
    let mut pairs: HashMap<(u32, u32), u64> = HashMap::new();
    let mut texels = 0u64;
    for (number, triangle) in mesh.triangles.iter().enumerate() {
        let uv = triangle.map(|i| uvs.get(i as usize).map_or(DVec2::ZERO, |uv| uv.as_dvec2() * size));
        for_texel_centres(&uv, palette, |x, y| {
            let slot = &mut owner[y as usize * width + x as usize];
            if *slot != u32::MAX && *slot != number as u32 {
                texels += 1;
                *pairs.entry((*slot, number as u32)).or_default() += 1;
            }
            *slot = number as u32;
        });
    }
    if texels == 0 {
        return Some(UvOverlaps { palette, ..UvOverlaps::default() });
    }
    let covered = covered_triangles(mesh);
    let name = |t: u32| mesh.parts[mesh.triangle_part[t as usize] as usize].clone();
    let mut by_parts: BTreeMap<(String, String), PartOverlap> = BTreeMap::new();
    let mut sorted: Vec<((u32, u32), u64)> = pairs.into_iter().collect();
    sorted.sort_unstable();
    for ((a, b), count) in sorted {
        let (mut first, mut second) = (name(a), name(b));
        if second < first {
            std::mem::swap(&mut first, &mut second);
        }
        let entry = by_parts
            .entry((first.clone(), second.clone()))
            .or_insert_with(|| PartOverlap { parts: (first, second), ..PartOverlap::default() });
        entry.texels += count;
        if covered[a as usize] || covered[b as usize] {
            entry.duplicate_texels += count;
        }
        if entry.examples.len() < EXAMPLES {
            entry.examples.push((a, b));
        }
    }
    let mut by_parts: Vec<PartOverlap> = by_parts.into_values().collect();
    by_parts.sort_by(|a, b| b.texels.cmp(&a.texels).then_with(|| a.parts.cmp(&b.parts)));
    Some(UvOverlaps { palette, texels, by_parts })
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{Vec2, vec3};

    #[test]
    fn overlaps_are_named_by_part_pair_and_duplicate_faces_are_told_apart() {
        let mut mesh = Mesh { uvs: Some(Vec::new()), ..Mesh::default() };
        let uv = |mesh: &mut Mesh, corners: [[f32; 2]; 3]| {
            mesh.uvs.as_mut().unwrap().extend(corners.map(|[u, v]| Vec2::new(u, v)));
        };
        // 0: body over the left half of the palette; 1: a plate elsewhere in
        // space mapped over the same texels; 2: an exact duplicate of 0.
        mesh.add_triangle("body", vec3(0.0, 0.0, 0.0), vec3(1.0, 0.0, 0.0), vec3(0.0, 0.0, 1.0));
        uv(&mut mesh, [[0.0, 0.0], [0.5, 0.0], [0.0, 0.5]]);
        mesh.add_triangle("plate", vec3(5.0, 0.0, 0.0), vec3(6.0, 0.0, 0.0), vec3(5.0, 0.0, 1.0));
        uv(&mut mesh, [[0.0, 0.0], [0.5, 0.0], [0.0, 0.5]]);
        mesh.add_triangle("body", vec3(0.0, 0.0, 0.0), vec3(1.0, 0.0, 0.0), vec3(0.0, 0.0, 1.0));
        uv(&mut mesh, [[0.0, 0.0], [0.5, 0.0], [0.0, 0.5]]);
        // 3: its own texels.
        mesh.add_triangle("roof", vec3(0.0, 2.0, 0.0), vec3(1.0, 2.0, 0.0), vec3(0.0, 2.0, 1.0));
        uv(&mut mesh, [[0.6, 0.6], [1.0, 0.6], [0.6, 1.0]]);
        let overlaps = uv_overlaps(&mesh, [16, 16]).unwrap();
        // Texel centres strictly inside an 8-texel right triangle: 28.
        let inside = 28;
        assert_eq!(overlaps.texels, 2 * inside, "plate over body, then the duplicate over the plate");
        let pairs: Vec<(&str, &str, u64, u64)> = overlaps
            .by_parts
            .iter()
            .map(|o| (o.parts.0.as_str(), o.parts.1.as_str(), o.texels, o.duplicate_texels))
            .collect();
        assert_eq!(pairs, [("body", "plate", 2 * inside, inside)]);
        let lines = overlaps.lines();
        assert!(
            lines[0].contains("body × plate: 56 texels, 28 of them made by coincident duplicate faces"),
            "{lines:?}"
        );
        assert!(lines[0].contains("0 & 1") && lines[0].contains("1 & 2"), "{lines:?}");
    }
}
