//! Where a model's own UVs overlap, in words, for `--keep-uvs` and
//! `inspect` (the overlapping texels are found by
//! [`crate::texture::uv_islands::uv_overlaps`]): the count alone ("1418 texels are covered by more than one triangle") left a
//! user with nowhere to look. Overlaps are grouped by the pair of parts
//! whose triangles share texels, with example triangle numbers, and the
//! pairs that are coincident duplicate faces (the same surface twice in the
//! mesh, [`crate::scene::coincident`]) are told apart from real overlaps
//! (a licence plate mapped over body faces, mirrored halves).

use std::collections::{BTreeMap, HashMap};

use crate::scene::coincident::covered_triangles;
use crate::scene::mesh::Mesh;

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

/// The overlaps found on `palette` (`texels` covered more than once; per
/// pair of triangles, earlier first, the texels they share), grouped by
/// pair of parts with example triangles, duplicate faces told apart.
pub(crate) fn summarize_overlaps(
    mesh: &Mesh,
    palette: [u32; 2],
    texels: u64,
    pairs: HashMap<(u32, u32), u64>,
) -> UvOverlaps {
    if texels == 0 {
        return UvOverlaps { palette, ..UvOverlaps::default() };
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
    UvOverlaps { palette, texels, by_parts }
}
