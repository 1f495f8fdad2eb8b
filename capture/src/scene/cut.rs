//! Cutting a mesh's triangles along a plane, so that region rules
//! ([`crate::scene::regions`]) follow their boundaries instead of the mesh's.
//!
//! A rule decides by a triangle's centroid; a model of few large triangles
//! (the milk truck's side walls are a handful of triangles each) would give a
//! whole wedge of wall to a "roof" box whose boundary crosses it. Cut along
//! the rule's planes first, every piece lies on one side of each of them, and
//! the centroid test is exact: a part's area is the area inside its region.
//!
//! Every triangle the plane crosses near the region ([`CutPlane::within`])
//! is cut, whatever its part, and the point on a crossed edge is computed
//! from the edge's two positions in a fixed order: two triangles sharing an
//! edge (even of different parts, whose vertices a glTF file keeps apart)
//! get the same new corner, so cutting leaves no T-junction along the plane
//! (only a neighbour lying wholly outside `within` stays whole, at the
//! region's far edge). New corners interpolate the UVs
//! (kept and own) linearly, as the rasteriser would; the pieces keep the
//! triangle's part and winding.

use glam::{DVec3, Vec2, Vec3};

use crate::scene::mesh::Mesh;

/// Distance (metres) within which a corner counts as lying on the plane:
/// no cut passes closer than this to a corner. (A cut near the sharp end of
/// a long triangle can still leave a piece thinner than this, which
/// `inspect` counts as a sliver: the milk truck's rules leave 11, 0.6 cm²
/// in all.)
pub const ON_PLANE_M: f64 = 1e-4;

/// A plane `normal · p = offset` (normal of unit length) and the box
/// (`min`, `max`, already widened by [`ON_PLANE_M`]) outside which no
/// triangle needs cutting: the part of the plane that bounds a region.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CutPlane {
    pub normal: DVec3,
    pub offset: f64,
    pub within: (DVec3, DVec3),
}

/// What one plane did.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Cut {
    /// Triangles cut (each became two or three).
    pub cut: usize,
    /// The parts (indices) of triangles the plane crosses that were left
    /// whole because the budget of new triangles ran out.
    pub left_whole: Vec<u32>,
}

/// Cuts every triangle of `mesh` that `plane` crosses and that reaches into
/// `plane.within`, adding at most `budget` triangles (it is lowered by those
/// added): a file of thousands of rules cannot make the mesh grow without
/// bound.
pub fn cut_mesh(mesh: &mut Mesh, plane: &CutPlane, budget: &mut usize) -> Cut {
    let mut done = Cut::default();
    for t in 0..mesh.triangles.len() {
        let corners = mesh.corners(t).map(Vec3::as_dvec3);
        let low = corners[0].min(corners[1]).min(corners[2]);
        let high = corners[0].max(corners[1]).max(corners[2]);
        if low.cmpgt(plane.within.1).any() || high.cmplt(plane.within.0).any() {
            continue;
        }
        let side = corners.map(|p| plane.normal.dot(p) - plane.offset);
        let class = side.map(|s| {
            if s > ON_PLANE_M {
                1
            } else if s < -ON_PLANE_M {
                -1
            } else {
                0
            }
        });
        if !(class.contains(&1) && class.contains(&-1)) {
            continue;
        }
        if *budget < 2 {
            if !done.left_whole.contains(&mesh.triangle_part[t]) {
                done.left_whole.push(mesh.triangle_part[t]);
            }
            continue;
        }
        let triangle = mesh.triangles[t];
        let (mut above, mut below) = (Vec::with_capacity(4), Vec::with_capacity(4));
        for k in 0..3 {
            let next = (k + 1) % 3;
            if class[k] >= 0 {
                above.push(triangle[k]);
            }
            if class[k] <= 0 {
                below.push(triangle[k]);
            }
            if class[k] * class[next] == -1 {
                let corner = edge_point(mesh, plane, triangle[k], triangle[next]);
                above.push(corner);
                below.push(corner);
            }
        }
        let part = mesh.triangle_part[t];
        let mut pieces = fan(&above).chain(fan(&below));
        mesh.triangles[t] = pieces.next().expect("a crossed triangle has a piece on each side");
        for piece in pieces {
            mesh.triangles.push(piece);
            mesh.triangle_part.push(part);
            *budget -= 1;
        }
        done.cut += 1;
    }
    done
}

/// The triangles of a convex polygon (3 or 4 corners, in winding order).
fn fan(polygon: &[u32]) -> impl Iterator<Item = [u32; 3]> + '_ {
    (1..polygon.len().saturating_sub(1)).map(|k| [polygon[0], polygon[k], polygon[k + 1]])
}

/// A new vertex where the plane crosses the edge `a`–`b`, computed from the
/// two positions in lexicographic order so that every triangle sharing the
/// edge gets the same point.
fn edge_point(mesh: &mut Mesh, plane: &CutPlane, a: u32, b: u32) -> u32 {
    let (pa, pb) = (mesh.positions[a as usize], mesh.positions[b as usize]);
    let (a, b) = if pa.to_array() <= pb.to_array() { (a, b) } else { (b, a) };
    let (pa, pb) = (mesh.positions[a as usize].as_dvec3(), mesh.positions[b as usize].as_dvec3());
    let (sa, sb) = (plane.normal.dot(pa) - plane.offset, plane.normal.dot(pb) - plane.offset);
    let t = sa / (sa - sb);
    let lerp2 = |u: Vec2, v: Vec2| (u.as_dvec2() + (v.as_dvec2() - u.as_dvec2()) * t).as_vec2();
    mesh.positions.push((pa + (pb - pa) * t).as_vec3());
    if let Some(uvs) = &mut mesh.uvs {
        let uv = lerp2(uvs[a as usize], uvs[b as usize]);
        uvs.push(uv);
    }
    if !mesh.own_uvs.is_empty() {
        let uv = lerp2(mesh.own_uvs[a as usize], mesh.own_uvs[b as usize]);
        mesh.own_uvs.push(uv);
    }
    (mesh.positions.len() - 1) as u32
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::mesh::triangle_area;
    use glam::vec3;

    fn everywhere(normal: DVec3, offset: f64) -> CutPlane {
        CutPlane { normal, offset, within: (DVec3::splat(-1e9), DVec3::splat(1e9)) }
    }

    #[test]
    fn a_cut_keeps_area_winding_part_and_uvs() {
        let mut mesh = Mesh { uvs: Some(Vec::new()), ..Mesh::default() };
        mesh.add_triangle("wall", vec3(0.0, 0.0, 0.0), vec3(4.0, 0.0, 0.0), vec3(0.0, 0.0, 2.0));
        mesh.uvs = Some(vec![Vec2::new(0.0, 0.0), Vec2::new(1.0, 0.0), Vec2::new(0.0, 1.0)]);
        let normal_before = {
            let [a, b, c] = mesh.corners(0);
            (b - a).cross(c - a).normalize()
        };
        assert_eq!(cut_mesh(&mut mesh, &everywhere(DVec3::X, 1.0), &mut 100).cut, 1);
        assert_eq!(mesh.triangles.len(), 3);
        let area = |keep: &dyn Fn(f64) -> bool| -> f64 {
            (0..mesh.triangles.len())
                .filter(|&t| {
                    let c = mesh.corners(t);
                    keep(f64::from(c[0].x + c[1].x + c[2].x) / 3.0)
                })
                .map(|t| triangle_area(mesh.corners(t)))
                .sum()
        };
        // x ≥ 1 of the triangle (0,0)-(4,0)-(0,2): a triangle 3 × 1.5.
        assert!((area(&|x| x >= 1.0) - 2.25).abs() < 1e-6);
        assert!((area(&|x| x < 1.0) - 1.75).abs() < 1e-6);
        for t in 0..3 {
            let [a, b, c] = mesh.corners(t);
            assert!((b - a).cross(c - a).normalize().dot(normal_before) > 0.999, "piece {t} flipped");
            assert_eq!(mesh.triangle_part[t], 0);
        }
        // The new corner on the bottom edge at x = 1 has u = 1/4.
        let uvs = mesh.uvs.as_ref().unwrap();
        let at = mesh.positions.iter().position(|p| (*p - vec3(1.0, 0.0, 0.0)).length() < 1e-6).unwrap();
        assert!((uvs[at] - Vec2::new(0.25, 0.0)).length() < 1e-6);
    }

    #[test]
    fn neighbours_share_the_new_corner_and_far_or_grazing_triangles_stay() {
        let mut mesh = Mesh::default();
        // Two parts sharing the edge (0,0,0)-(2,0,2) with their own vertices.
        mesh.add_triangle("a", vec3(0.0, 0.0, 0.0), vec3(2.0, 0.0, 0.0), vec3(2.0, 0.0, 2.0));
        mesh.add_triangle("b", vec3(2.0, 0.0, 2.0), vec3(0.0, 0.0, 2.0), vec3(0.0, 0.0, 0.0));
        // One touching the plane at a corner only, one far outside `within`.
        mesh.add_triangle("a", vec3(1.0, 5.0, 0.0), vec3(3.0, 5.0, 0.0), vec3(3.0, 5.0, 1.0));
        mesh.add_triangle("a", vec3(0.0, 50.0, 0.0), vec3(2.0, 50.0, 0.0), vec3(2.0, 50.0, 1.0));
        let plane =
            CutPlane { normal: DVec3::X, offset: 1.0, within: (DVec3::splat(-10.0), DVec3::splat(10.0)) };
        let mut budget = 100;
        assert_eq!(cut_mesh(&mut mesh, &plane, &mut budget), Cut { cut: 2, left_whole: Vec::new() });
        assert_eq!(budget, 100 - 4, "two new triangles each");
        let on_diagonal: Vec<_> =
            mesh.positions.iter().filter(|p| (**p - vec3(1.0, 0.0, 1.0)).length() < 1e-6).collect();
        assert_eq!(on_diagonal.len(), 2, "one new corner per triangle on the shared edge");
        assert_eq!(on_diagonal[0], on_diagonal[1], "bit for bit the same point");
        assert_eq!(mesh.triangles.len(), 4 + 2 + 2);
    }
}

#[cfg(test)]
mod budget_tests {
    use super::*;
    use glam::vec3;

    #[test]
    fn an_exhausted_budget_leaves_triangles_whole_and_names_their_part() {
        let mut mesh = Mesh::default();
        mesh.add_triangle("a", vec3(0.0, 0.0, 0.0), vec3(2.0, 0.0, 0.0), vec3(2.0, 0.0, 2.0));
        mesh.add_triangle("b", vec3(0.0, 1.0, 0.0), vec3(2.0, 1.0, 0.0), vec3(2.0, 1.0, 2.0));
        let plane =
            CutPlane { normal: DVec3::X, offset: 1.0, within: (DVec3::splat(-9.0), DVec3::splat(9.0)) };
        let mut budget = 2;
        let done = cut_mesh(&mut mesh, &plane, &mut budget);
        assert_eq!(done, Cut { cut: 1, left_whole: vec![1] });
        assert_eq!((budget, mesh.triangles.len()), (0, 4));
    }
}
