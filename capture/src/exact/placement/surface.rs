//! The vehicle's surface as the patch layout needs it: its triangles in the
//! vehicle frame (f64 of the mesh's f32 corners, as the sampler has them),
//! bucketed by cube, with the two exact queries the layout is made of, the
//! surface point nearest a point and the surface area inside a box. Both
//! read the mesh only, never the texel samples, so the patch layout is the
//! same whatever the seed, the `--exact-sample` fraction or the palette.
//!
//! A triangle without area and a face an earlier face covers whole (a
//! duplicate, [`crate::scene::coincident::covered_triangles`]) are left out,
//! as the sampler gives them no area: the surface counts once.

use std::collections::HashMap;

use glam::DVec3;

use crate::scene::Mesh;

pub(crate) type Cell = [i64; 3];

pub(crate) fn cell_of(p: DVec3, size: f64) -> Cell {
    [(p.x / size).floor() as i64, (p.y / size).floor() as i64, (p.z / size).floor() as i64]
}

/// The centre of cube `cell` of edge `size`.
pub(crate) fn middle_of(cell: Cell, size: f64) -> DVec3 {
    DVec3::new(cell[0] as f64 + 0.5, cell[1] as f64 + 0.5, cell[2] as f64 + 0.5) * size
}

/// One counted triangle.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Face {
    pub corners: [DVec3; 3],
    /// Unit normal (the sampler's: (b − a) × (c − a), normalised).
    pub normal: DVec3,
    pub part: u32,
}

/// Counted faces bucketed by the cubes of edge `size` they pass near.
pub(crate) struct Surface {
    pub faces: Vec<Face>,
    pub size: f64,
    /// Per cube: indices into `faces`, ascending.
    pub cells: HashMap<Cell, Vec<u32>>,
}

impl Surface {
    pub(crate) fn new(mesh: &Mesh, size: f64) -> Surface {
        let covered = crate::scene::coincident::covered_triangles(mesh);
        let faces: Vec<Face> = (0..mesh.triangles.len())
            .filter(|&t| !covered[t])
            .filter_map(|t| {
                let corners = mesh.corners(t).map(|c| c.as_dvec3());
                let normal = (corners[1] - corners[0]).cross(corners[2] - corners[0]).normalize_or_zero();
                (normal != DVec3::ZERO).then(|| Face { corners, normal, part: mesh.triangle_part[t] })
            })
            .collect();
        let mut cells: HashMap<Cell, Vec<u32>> = HashMap::new();
        for (index, face) in faces.iter().enumerate() {
            bucket(face.corners, size, &mut |cell| {
                let list = cells.entry(cell).or_default();
                if list.last() != Some(&(index as u32)) {
                    list.push(index as u32);
                }
            });
        }
        for list in cells.values_mut() {
            list.sort_unstable();
            list.dedup();
        }
        Surface { faces, size, cells }
    }

    /// Every face that may come within the box `lo..hi` (and some more),
    /// ascending and each once.
    pub(crate) fn near(&self, lo: DVec3, hi: DVec3) -> Vec<u32> {
        let [a, b] = [cell_of(lo, self.size), cell_of(hi, self.size)];
        let mut out = Vec::new();
        for x in a[0]..=b[0] {
            for y in a[1]..=b[1] {
                for z in a[2]..=b[2] {
                    out.extend(self.cells.get(&[x, y, z]).into_iter().flatten());
                }
            }
        }
        out.sort_unstable();
        out.dedup();
        out
    }

    /// The surface point nearest the centre of cube `cell` (edge `size` of
    /// this surface), with its face, when that point lies in the cube. Ties
    /// go to the face first in the mesh.
    pub(crate) fn nearest_in_cube(&self, cell: Cell) -> Option<(DVec3, u32)> {
        let middle = middle_of(cell, self.size);
        // A point in the cube is within √3/2 edges of its centre; every face
        // that close passes through the 3 × 3 × 3 cubes around it.
        let reach = DVec3::splat(self.size);
        let mut best: Option<(f64, DVec3, u32)> = None;
        for index in self.near(middle - reach, middle + reach) {
            let point = closest_on_triangle(middle, self.faces[index as usize].corners);
            let d = (point - middle).length_squared();
            if best.is_none_or(|(b, _, _)| d < b) {
                best = Some((d, point, index));
            }
        }
        let (_, point, index) = best?;
        (cell_of(point, self.size) == cell).then_some((point, index))
    }
}

/// Calls `visit` for the cubes a triangle passes through (and some more):
/// the triangle is halved until its bounding box spans at most two cubes a
/// side, so a large slanted face costs its area in cubes, not its volume.
fn bucket(corners: [DVec3; 3], size: f64, visit: &mut impl FnMut(Cell)) {
    let lo = corners[0].min(corners[1]).min(corners[2]);
    let hi = corners[0].max(corners[1]).max(corners[2]);
    let [a, b] = [cell_of(lo, size), cell_of(hi, size)];
    if (0..3).all(|i| b[i] - a[i] <= 1) {
        for x in a[0]..=b[0] {
            for y in a[1]..=b[1] {
                for z in a[2]..=b[2] {
                    visit([x, y, z]);
                }
            }
        }
        return;
    }
    // Halve at the longest edge's midpoint.
    let edges = [(0, 1, 2), (1, 2, 0), (2, 0, 1)];
    let longest = edges
        .into_iter()
        .max_by(|p, q| {
            let lp = (corners[p.0] - corners[p.1]).length_squared();
            let lq = (corners[q.0] - corners[q.1]).length_squared();
            lp.total_cmp(&lq)
        })
        .unwrap_or((0, 1, 2));
    let (i, j, k) = longest;
    let mid = (corners[i] + corners[j]) / 2.0;
    bucket([corners[i], mid, corners[k]], size, visit);
    bucket([mid, corners[j], corners[k]], size, visit);
}

/// The point of triangle `[a, b, c]` nearest `p` (Ericson, Real-Time
/// Collision Detection §5.1.5: by the Voronoi region of `p`).
pub(crate) fn closest_on_triangle(p: DVec3, [a, b, c]: [DVec3; 3]) -> DVec3 {
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return a;
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return a + ab * (d1 / (d1 - d3));
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return a + ac * (d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    let denominator = 1.0 / (va + vb + vc);
    a + ab * (vb * denominator) + ac * (vc * denominator)
}

/// The area of triangle `corners` inside the box `|(x − centre)·axes[i]| ≤
/// half[i]` (orthonormal axes): the area of [`polygon_in_box`].
pub(crate) fn area_in_box(corners: [DVec3; 3], centre: DVec3, axes: [DVec3; 3], half: [f64; 3]) -> f64 {
    let polygon = polygon_in_box(corners, centre, axes, half);
    let mut twice = DVec3::ZERO;
    for i in 1..polygon.len().saturating_sub(1) {
        twice += (polygon[i] - polygon[0]).cross(polygon[i + 1] - polygon[0]);
    }
    twice.length() / 2.0
}

/// Triangle `corners` clipped by the box `|(x − centre)·axes[i]| ≤ half[i]`
/// (orthonormal axes; its six planes, Sutherland–Hodgman): a convex polygon,
/// empty when less than one is left.
pub(crate) fn polygon_in_box(
    corners: [DVec3; 3],
    centre: DVec3,
    axes: [DVec3; 3],
    half: [f64; 3],
) -> Vec<DVec3> {
    let mut polygon: Vec<DVec3> = corners.to_vec();
    for (axis, half) in axes.into_iter().zip(half) {
        for sign in [1.0, -1.0] {
            // Keep sign · (x − centre) · axis ≤ half.
            let outside = |x: DVec3| sign * (x - centre).dot(axis) - half;
            polygon = clip(&polygon, outside);
            if polygon.len() < 3 {
                return Vec::new();
            }
        }
    }
    polygon
}

/// The part of a convex polygon where `outside(x) ≤ 0`.
fn clip(polygon: &[DVec3], outside: impl Fn(DVec3) -> f64) -> Vec<DVec3> {
    let mut out = Vec::with_capacity(polygon.len() + 1);
    for (i, &p) in polygon.iter().enumerate() {
        let q = polygon[(i + 1) % polygon.len()];
        let (dp, dq) = (outside(p), outside(q));
        if dp <= 0.0 {
            out.push(p);
        }
        if (dp <= 0.0) != (dq <= 0.0) {
            out.push(p + (q - p) * (dp / (dp - dq)));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use glam::dvec3;

    use super::*;

    #[test]
    fn the_nearest_point_of_a_triangle_is_its_foot_inside_and_its_rim_outside() {
        let t = [dvec3(0.0, 0.0, 0.0), dvec3(1.0, 0.0, 0.0), dvec3(0.0, 1.0, 0.0)];
        assert!((closest_on_triangle(dvec3(0.2, 0.3, 5.0), t) - dvec3(0.2, 0.3, 0.0)).length() < 1e-12);
        assert_eq!(closest_on_triangle(dvec3(-1.0, -1.0, 1.0), t), t[0]);
        assert_eq!(closest_on_triangle(dvec3(0.5, -2.0, 0.0), t), dvec3(0.5, 0.0, 0.0));
        assert!((closest_on_triangle(dvec3(1.0, 1.0, 0.0), t) - dvec3(0.5, 0.5, 0.0)).length() < 1e-12);
    }

    #[test]
    fn the_area_in_a_box_is_the_clipped_triangle() {
        // The unit right triangle (area 1/2) in a box of half-width 0.25 about
        // (0.25, 0.25): the square [0, 0.5]² of which the triangle holds all.
        let t = [dvec3(0.0, 0.0, 0.0), dvec3(1.0, 0.0, 0.0), dvec3(0.0, 1.0, 0.0)];
        let axes = [DVec3::X, DVec3::Y, DVec3::Z];
        let area = area_in_box(t, dvec3(0.25, 0.25, 0.0), axes, [0.25, 0.25, 0.1]);
        assert!((area - 0.25).abs() < 1e-12, "{area}");
        // About (0.5, 0.5): the square [0.25, 0.75]² below x + y = 1 is half of it.
        let area = area_in_box(t, dvec3(0.5, 0.5, 0.0), axes, [0.25, 0.25, 0.1]);
        assert!((area - 0.125).abs() < 1e-12, "{area}");
        assert_eq!(area_in_box(t, dvec3(0.2, 0.2, 1.0), axes, [0.25, 0.25, 0.1]), 0.0);
        let whole = area_in_box(t, DVec3::ZERO, axes, [5.0; 3]);
        assert!((whole - 0.5).abs() < 1e-12);
    }
}
