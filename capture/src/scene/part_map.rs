//! Parts from a part map: an image painted over the model's OWN UVs
//! (TEXCOORD_0 in glTF, `vt` in OBJ), each colour a part of a legend — the
//! paper's way of labelling a vehicle (painted in Blender over the artist's
//! UVs). The capture still measures on its own unwrap: the map only names
//! each triangle's part, so artist UVs that overlap (mirrored doors, a
//! licence plate over body faces, duplicated faces) label parts without
//! breaking the exactness of the unwrap the counts are made on.
//!
//! The rule, per triangle: the part-map texels whose centres lie inside the
//! triangle's UV triangle (nearest sampling: the texel containing the UV,
//! `floor(u·W)`, `floor(v·H)`, v = 0 at the image's top row; UVs outside
//! 0..1 repeat, as glTF's default sampler does) vote, and the legend part
//! with most votes names the triangle (ties: the legend's first). A UV
//! triangle too small to hold a texel centre takes the texel under its
//! centroid. A large UV triangle is sampled on every k-th texel along u and
//! every l-th along v (its box's proportions) so that no triangle takes more
//! than [`MAX_SAMPLES`] (about; at most twice), however thin or long. Colours the legend does
//! not list do not vote; a triangle with no listed colour gets the part
//! [`UNMAPPED_PART`]. Both are counted and reported, as are the triangles
//! whose votes were split between parts (they straddle a boundary of the
//! map, which the triangle-level labelling cannot follow). Triangles of
//! primitives without UVs (glass often has none) keep the part their name
//! gives (`names`: node by default), reported with the primitives.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use glam::DVec2;
use serde::{Deserialize, Serialize};
use ufcsr::{Color, Legend};

use crate::error::{CaptureError, Result};
use crate::scene::mesh::{Mesh, PartSource, triangle_area};

/// The part of triangles on which the map shows no legend colour.
pub const UNMAPPED_PART: &str = "unmapped";
/// About how many part-map texels one triangle samples at most.
pub(crate) const MAX_SAMPLES: f64 = 4096.0;
/// Largest part map read, texels per side.
pub(crate) const MAX_SIDE: u32 = 16384;

/// `"parts_from": {"part_map": "partmap.png", "legend": "parts.csv"}` in a
/// scene file's vehicle (paths relative to the scene file).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PartMapSpec {
    /// A PNG painted over the model's own UVs.
    pub part_map: String,
    /// Its legend: CSV `name,color` or JSON `[{"name", "color"}]`, as the analyzer reads.
    pub legend: String,
    /// What names the triangles of primitives without UVs: `node` (default), `mesh` or `material`.
    #[serde(default)]
    pub names: PartSource,
}

/// What labelling through the map found.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PartMapReport {
    pub part_map: PathBuf,
    pub legend: PathBuf,
    /// Part-map texels sampled in all.
    pub samples: u64,
    /// Samples in colours the legend does not list, by colour.
    pub unknown_colors: BTreeMap<Color, u64>,
    /// Triangles whose samples name more than one part, and their share of the surface.
    pub split_triangles: usize,
    pub split_area_share: f64,
    /// Triangles on which the map shows no legend colour ([`UNMAPPED_PART`]).
    pub unmapped_triangles: usize,
    /// Triangles without own UVs (they keep their name's part), and the primitives they belong to.
    pub without_uvs: usize,
    pub primitives_without_uvs: Vec<String>,
}

impl PartMapReport {
    /// One line per thing the reader should know.
    pub fn warnings(&self) -> Vec<String> {
        let mut warnings = Vec::new();
        let map = self.part_map.display();
        if !self.unknown_colors.is_empty() {
            let texels: u64 = self.unknown_colors.values().sum();
            let mut by_count: Vec<(&Color, &u64)> = self.unknown_colors.iter().collect();
            by_count.sort_by(|a, b| b.1.cmp(a.1));
            let examples: Vec<String> = by_count.iter().take(5).map(|(c, n)| format!("{c} ×{n}")).collect();
            warnings.push(format!(
                "{map}: {texels} of {} samples are in {} colours the legend {} does not list (e.g. {}); they do \
                 not vote (antialiased brush edges? paint with a hard brush)",
                self.samples,
                self.unknown_colors.len(),
                self.legend.display(),
                examples.join(", ")
            ));
        }
        if self.unmapped_triangles > 0 {
            warnings.push(format!(
                "{map}: {} triangles show no legend colour under their UVs: they form the part {UNMAPPED_PART:?}",
                self.unmapped_triangles
            ));
        }
        if self.without_uvs > 0 {
            warnings.push(format!(
                "{map}: {} triangles have no UVs of their own and keep the part their name gives ({})",
                self.without_uvs,
                self.primitives_without_uvs.join("; ")
            ));
        }
        if self.split_triangles > 0 {
            warnings.push(format!(
                "{map}: {} triangles ({:.2} % of the surface) straddle a part boundary of the map and take their \
                 majority part (parts follow triangles, not texels)",
                self.split_triangles,
                self.split_area_share * 100.0
            ));
        }
        warnings
    }
}

/// The part map and legend, loaded and checked.
struct PartMap {
    width: u32,
    height: u32,
    colors: Vec<u32>,
    /// Packed colour → legend index.
    parts: BTreeMap<u32, usize>,
    names: Vec<String>,
}

impl PartMap {
    fn load(spec: &PartMapSpec, base: &Path, scene: &Path) -> Result<(PartMap, PathBuf, PathBuf)> {
        let (map_path, legend_path) = (base.join(&spec.part_map), base.join(&spec.legend));
        let legend = Legend::load(&legend_path)?;
        if legend.parts.is_empty() {
            return Err(CaptureError::bad_file(&legend_path, "the part map's legend lists no part"));
        }
        let image = ufcsr::read_color_image(&map_path, |[width, height]| {
            if width <= MAX_SIDE && height <= MAX_SIDE {
                Ok(())
            } else {
                Err(ufcsr::Error::bad_file(
                    &map_path,
                    format!("a part map of {width}×{height} texels is larger than {MAX_SIDE} per side"),
                ))
            }
        })?;
        let mut parts = BTreeMap::new();
        for (index, part) in legend.parts.iter().enumerate() {
            if part.name == UNMAPPED_PART {
                return Err(CaptureError::bad_file(
                    scene,
                    format!(
                        "vehicle.parts_from: the legend may not name a part {UNMAPPED_PART:?} (it is ufcsr's)"
                    ),
                ));
            }
            parts.insert(part.color.packed(), index);
        }
        let names = legend.parts.iter().map(|p| p.name.clone()).collect();
        let map = PartMap { width: image.width, height: image.height, colors: image.colors, parts, names };
        Ok((map, map_path, legend_path))
    }

    /// The colour under UV `uv` (nearest, repeating).
    fn at(&self, x: i64, y: i64) -> u32 {
        let x = x.rem_euclid(i64::from(self.width)) as usize;
        let y = y.rem_euclid(i64::from(self.height)) as usize;
        self.colors[y * self.width as usize + x]
    }
}

/// Names every triangle of `mesh` by the part map of `spec` (paths
/// relative to `base`; `scene` names the scene file in messages).
pub(crate) fn apply(mesh: &mut Mesh, spec: &PartMapSpec, base: &Path, scene: &Path) -> Result<PartMapReport> {
    let uvs = own_uvs(mesh);
    let has_uvs =
        |triangle: &[u32; 3]| triangle.iter().all(|&i| uvs.get(i as usize).is_some_and(|uv| uv.is_finite()));
    if !mesh.triangles.iter().any(has_uvs) {
        return Err(CaptureError::bad_file(
            scene,
            "vehicle.parts_from.part_map is painted over the model's own UVs, but the model has none (TEXCOORD_0 / vt)",
        ));
    }
    let (map, part_map, legend) = PartMap::load(spec, base, scene)?;
    let mut report = PartMapReport {
        part_map,
        legend,
        primitives_without_uvs: mesh.missing_uvs.clone(),
        ..PartMapReport::default()
    };
    let size = DVec2::new(f64::from(map.width), f64::from(map.height));
    let mut assigned = Vec::with_capacity(mesh.triangles.len());
    let mut split_area = 0.0;
    for (t, triangle) in mesh.triangles.iter().enumerate() {
        if !has_uvs(triangle) {
            report.without_uvs += 1;
            assigned.push(mesh.parts[mesh.triangle_part[t] as usize].clone());
            continue;
        }
        let uv = triangle.map(|i| uvs[i as usize].as_dvec2() * size);
        let mut votes = vec![0u64; map.names.len()];
        sample(&uv, |x, y| {
            report.samples += 1;
            let color = map.at(x, y);
            match map.parts.get(&color) {
                Some(&part) => votes[part] += 1,
                None => *report.unknown_colors.entry(Color::from_packed(color)).or_default() += 1,
            }
        });
        let voted = votes.iter().filter(|&&v| v > 0).count();
        if voted > 1 {
            report.split_triangles += 1;
            split_area += triangle_area(mesh.corners(t));
        }
        let best =
            (0..votes.len()).filter(|&p| votes[p] > 0).max_by_key(|&p| (votes[p], std::cmp::Reverse(p)));
        if best.is_none() {
            report.unmapped_triangles += 1;
        }
        assigned.push(best.map_or(UNMAPPED_PART, |p| map.names[p].as_str()).to_string());
    }
    let total_area = mesh.area();
    report.split_area_share = if total_area > 0.0 { split_area / total_area } else { 0.0 };
    mesh.parts.clear();
    let parts: Vec<u32> = assigned.iter().map(|name| mesh.part(name)).collect();
    mesh.triangle_part = parts;
    Ok(report)
}

/// Every vertex's own UV (NaN where its primitive has none): a loaded
/// model's `own_uvs`, else its `uvs`, else none.
fn own_uvs(mesh: &Mesh) -> Vec<glam::Vec2> {
    if mesh.own_uvs.len() == mesh.positions.len() {
        mesh.own_uvs.clone()
    } else {
        mesh.uvs.clone().unwrap_or_default()
    }
}

/// Calls `f` with the texels (unwrapped indices, any integer) whose centres
/// lie inside the texel-space triangle `uv`, every k-th in each direction
/// for a large one; the texel under the centroid when none does.
fn sample(uv: &[DVec2; 3], mut f: impl FnMut(i64, i64)) {
    let min = uv[0].min(uv[1]).min(uv[2]);
    let max = uv[0].max(uv[1]).max(uv[2]);
    let area = (uv[1] - uv[0]).perp_dot(uv[2] - uv[0]);
    let finite = min.is_finite() && max.is_finite();
    let mut any = false;
    if finite && area != 0.0 {
        let span = (max - min).max(DVec2::ONE);
        let [stride_x, stride_y] = strides(span);
        let (x0, y0) = ((min.x - 0.5).ceil() as i64, (min.y - 0.5).ceil() as i64);
        let (x1, y1) = ((max.x - 0.5).floor() as i64, (max.y - 0.5).floor() as i64);
        for y in (y0..=y1).step_by(stride_y) {
            for x in (x0..=x1).step_by(stride_x) {
                let p = DVec2::new(x as f64 + 0.5, y as f64 + 0.5);
                let inside =
                    (0..3).all(|k| (uv[(k + 1) % 3] - uv[k]).perp_dot(p - uv[k]) * area.signum() >= 0.0);
                if inside {
                    any = true;
                    f(x, y);
                }
            }
        }
    }
    if !any && finite {
        let centroid = (uv[0] + uv[1] + uv[2]) / 3.0;
        f(centroid.x.floor() as i64, centroid.y.floor() as i64);
    }
}

/// The steps (texels) along u and v that put at most about [`MAX_SAMPLES`]
/// grid points in a UV box of `span` texels (each side at least 1): each
/// axis gets its share of the grid, so a thin box long in u (a sliver, or
/// UVs repeating far outside 0..1) is sampled along its length at about
/// [`MAX_SAMPLES`] points, not at a square stride that left it millions
/// (one stride for both axes from the box's area: a 2·10¹⁰ × 1 texel box
/// took 9·10⁶ samples).
fn strides(span: DVec2) -> [usize; 2] {
    if span.x * span.y <= MAX_SAMPLES {
        return [1, 1];
    }
    // Points per axis in the box's proportions, none below one.
    let ratio = span.x / span.y;
    let along_x = (MAX_SAMPLES * ratio).sqrt().clamp(1.0, MAX_SAMPLES);
    let along_y = (MAX_SAMPLES / along_x).max(1.0);
    // `as` saturates: a span past i64 (the loop bounds saturate too) takes one point.
    let step = |length: f64, points: f64| (length / points).ceil().max(1.0) as usize;
    [step(span.x, along_x), step(span.y, along_y)]
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{Vec2, vec3};

    /// A 4×2 part map: left half red (door), right half blue (plate), one
    /// green texel (#00FF00) the legend does not list at the bottom right.
    fn write_map(dir: &Path) {
        let (red, blue, green) = (0xFF0000u32, 0x0000FF, 0x00FF00);
        let colors = [red, red, blue, blue, red, red, blue, green];
        let rgb: Vec<u8> = colors.iter().flat_map(|&c| Color::from_packed(c).rgb()).collect();
        ufcsr::files::write_rgb_png(&dir.join("map.png"), [4, 2], &rgb, png::Compression::Fast).unwrap();
        std::fs::write(dir.join("parts.csv"), "name,color\ndoor,#FF0000\nplate,#0000FF\n").unwrap();
    }

    /// Three unit squares far apart in space, two triangles each; squares 0
    /// and 1 map to the SAME left half of the map (overlapping UVs, as
    /// mirrored doors have), square 2 to the right half.
    fn overlapping_mesh() -> Mesh {
        let mut mesh = Mesh { uvs: Some(Vec::new()), ..Mesh::default() };
        let halves = [[0.0, 0.5], [0.0, 0.5], [0.5, 1.0]];
        for (k, [u0, u1]) in halves.into_iter().enumerate() {
            let x = k as f32 * 3.0;
            mesh.add_quad(
                "any",
                vec3(x, 0.0, 0.0),
                vec3(x + 1.0, 0.0, 0.0),
                vec3(x + 1.0, 0.0, 1.0),
                vec3(x, 0.0, 1.0),
            );
            let uv = [Vec2::new(u0, 1.0), Vec2::new(u1, 1.0), Vec2::new(u1, 0.0), Vec2::new(u0, 0.0)];
            // add_quad adds a-b-c and a-c-d, six corners.
            mesh.uvs.as_mut().unwrap().extend([uv[0], uv[1], uv[2], uv[0], uv[2], uv[3]]);
        }
        mesh
    }

    #[test]
    fn overlapping_uvs_take_their_parts_from_the_map_and_unlisted_colors_are_counted() {
        let dir = tempfile::tempdir().unwrap();
        write_map(dir.path());
        let mut mesh = overlapping_mesh();
        let spec =
            PartMapSpec { part_map: "map.png".into(), legend: "parts.csv".into(), names: PartSource::Node };
        let report = apply(&mut mesh, &spec, dir.path(), Path::new("scene.json")).unwrap();
        let parts: Vec<&str> = mesh.triangle_part.iter().map(|&p| mesh.parts[p as usize].as_str()).collect();
        assert_eq!(parts, ["door", "door", "door", "door", "plate", "plate"]);
        // Square 2's two triangles hold the right half's centres: texels
        // (2,0), (3,0), (2,1), (3,1) split between them on the diagonal; the
        // green one (3,1) does not vote.
        assert_eq!(report.unknown_colors, BTreeMap::from([(Color::from_rgb(0, 255, 0), 1)]));
        assert_eq!((report.split_triangles, report.unmapped_triangles), (0, 0));
        let warnings = report.warnings();
        assert!(warnings[0].contains("#00FF00 ×1") && warnings[0].contains("parts.csv"), "{warnings:?}");
    }

    #[test]
    fn straddling_unmapped_and_repeating_uvs_follow_the_rule() {
        let dir = tempfile::tempdir().unwrap();
        write_map(dir.path());
        let mut mesh = Mesh { uvs: Some(Vec::new()), ..Mesh::default() };
        // Straddling: 3 texel centres red, 1 blue → door.
        mesh.add_triangle("t", vec3(0.0, 0.0, 0.0), vec3(1.0, 0.0, 0.0), vec3(0.0, 0.0, 1.0));
        // Tiny, over the green texel: no centre inside, the centroid's texel is green → unmapped.
        mesh.add_triangle("t", vec3(2.0, 0.0, 0.0), vec3(3.0, 0.0, 0.0), vec3(2.0, 0.0, 1.0));
        // UVs one period to the left (u in -0.5..-0.4): repeats onto blue.
        mesh.add_triangle("t", vec3(4.0, 0.0, 0.0), vec3(5.0, 0.0, 0.0), vec3(4.0, 0.0, 1.0));
        mesh.uvs.as_mut().unwrap().extend([
            Vec2::new(0.0, 0.0),
            Vec2::new(1.0, 0.0),
            Vec2::new(0.0, 1.0),
            Vec2::new(0.9, 0.8),
            Vec2::new(0.92, 0.8),
            Vec2::new(0.9, 0.82),
            Vec2::new(-0.5, 0.0),
            Vec2::new(-0.3, 0.0),
            Vec2::new(-0.5, 0.4),
        ]);
        let spec =
            PartMapSpec { part_map: "map.png".into(), legend: "parts.csv".into(), names: PartSource::Node };
        let report = apply(&mut mesh, &spec, dir.path(), Path::new("scene.json")).unwrap();
        let parts: Vec<&str> = mesh.triangle_part.iter().map(|&p| mesh.parts[p as usize].as_str()).collect();
        assert_eq!(parts, ["door", UNMAPPED_PART, "plate"]);
        assert_eq!((report.split_triangles, report.unmapped_triangles), (1, 1));
        assert!((report.split_area_share - 1.0 / 3.0).abs() < 1e-9);
        // A primitive without UVs keeps its name's part; none with UVs is refused.
        let mut partial = mesh.clone();
        partial.uvs = None;
        partial.parts = vec!["body".into(), "glass".into()];
        partial.triangle_part = vec![0, 0, 1];
        partial.own_uvs = partial.positions.iter().map(|_| Vec2::new(0.1, 0.1)).collect();
        partial.own_uvs[6..9].fill(Vec2::NAN);
        partial.missing_uvs = vec!["primitive 0 of mesh 1 (\"glass\")".into()];
        let report = apply(&mut partial, &spec, dir.path(), Path::new("scene.json")).unwrap();
        let parts: Vec<&str> =
            partial.triangle_part.iter().map(|&p| partial.parts[p as usize].as_str()).collect();
        assert_eq!(parts, ["door", "door", "glass"]);
        assert_eq!(report.without_uvs, 1);
        assert!(report.warnings().iter().any(|w| w.contains("\"glass\"") && w.contains("keep the part")));
        let mut bare = Mesh { uvs: None, ..mesh };
        let error = apply(&mut bare, &spec, dir.path(), Path::new("scene.json")).unwrap_err().to_string();
        assert!(error.contains("scene.json") && error.contains("own UVs"), "{error}");
    }

    #[test]
    fn a_thin_or_far_repeating_uv_triangle_takes_about_max_samples() {
        // Long in u (UVs repeating far outside 0..1), one to a few texels tall, and a thin diagonal.
        let triangles = [
            [DVec2::new(0.0, 0.0), DVec2::new(2e10, 0.0), DVec2::new(0.0, 3.0)],
            [DVec2::new(0.0, 0.0), DVec2::new(1e7, 0.0), DVec2::new(0.0, 1.2)],
            [DVec2::new(0.0, 0.0), DVec2::new(0.0, 1e9), DVec2::new(40.0, 0.0)],
            [DVec2::new(0.0, 0.0), DVec2::new(16384.0, 16384.0), DVec2::new(16384.0, 16383.0)],
            [DVec2::new(0.0, 0.0), DVec2::new(5000.0, 0.0), DVec2::new(0.0, 5000.0)],
        ];
        for uv in triangles {
            let mut samples = 0u64;
            sample(&uv, |_, _| samples += 1);
            assert!((1..=2 * MAX_SAMPLES as u64).contains(&samples), "{uv:?}: {samples} samples");
        }
        // A small one is sampled on every texel: a 10 × 10 right triangle holds 55 centres.
        let mut samples = 0u64;
        sample(&[DVec2::ZERO, DVec2::new(10.0, 0.0), DVec2::new(0.0, 10.0)], |_, _| samples += 1);
        assert_eq!(samples, 55);
    }
}
