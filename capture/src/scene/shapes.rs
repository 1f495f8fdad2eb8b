//! Building blocks the procedural vehicles share (the demo truck in
//! [`crate::scene::demo`] and the body family in [`crate::scene::family`]):
//! a wheel of quads, a quad that orders its corners to face a given way, and
//! the test that no two triangles lie on one another in one plane (they
//! would fight in the depth buffer, and which one a pixel shows would depend
//! on the driver). Kept in one place so both vehicles are exact for the same
//! reasons.

use glam::{Vec3, vec3};

use crate::scene::mesh::Mesh;

/// A wheel's size, metres.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct WheelSize {
    /// Tyre radius (the wheel's centre stands this high).
    pub radius: f32,
    /// Rim radius (the inner edge of the sidewall ring).
    pub rim_radius: f32,
    /// Half the tyre's width.
    pub half_width: f32,
}

/// The demo truck's wheels (a 0.84 m tyre on a 0.54 m rim, 0.28 m wide).
pub(crate) const TRUCK_WHEEL: WheelSize = WheelSize { radius: 0.42, rim_radius: 0.27, half_width: 0.14 };

/// How far the rim disc stands proud of the tyre's outer sidewall, metres (so
/// that the two never share a plane).
pub(crate) const RIM_PROUD_M: f32 = 0.01;

/// A wheel at `centre`; `s` = +1 on the left (outer face towards +y): the
/// tyre's tread and outer sidewall ring, and the rim disc
/// [`RIM_PROUD_M`] outside it.
pub(crate) fn wheel(m: &mut Mesh, centre: Vec3, s: f32, [tyre, rim]: [&str; 2], size: WheelSize) {
    const SEGMENTS: usize = 12;
    let WheelSize { radius, rim_radius, half_width } = size;
    let at = |angle: f32, r: f32, y: f32| centre + vec3(r * angle.cos(), y, r * angle.sin());
    let outer = half_width * s;
    for i in 0..SEGMENTS {
        let a0 = i as f32 / SEGMENTS as f32 * std::f32::consts::TAU;
        // Wrap the last angle to 0 exactly, so the seam's vertices match bit for bit.
        let a1 = ((i + 1) % SEGMENTS) as f32 / SEGMENTS as f32 * std::f32::consts::TAU;
        // Tread: outward normal.
        let (p, q) = if s > 0.0 { (a1, a0) } else { (a0, a1) };
        m.add_quad(
            tyre,
            at(p, radius, -outer),
            at(q, radius, -outer),
            at(q, radius, outer),
            at(p, radius, outer),
        );
        // Outer sidewall ring and rim disc, facing ±y.
        let (p, q) = if s > 0.0 { (a0, a1) } else { (a1, a0) };
        m.add_quad(
            tyre,
            at(p, rim_radius, outer),
            at(p, radius, outer),
            at(q, radius, outer),
            at(q, rim_radius, outer),
        );
        m.add_triangle(
            rim,
            centre + vec3(0.0, outer + RIM_PROUD_M * s, 0.0),
            at(q, rim_radius, outer + RIM_PROUD_M * s),
            at(p, rim_radius, outer + RIM_PROUD_M * s),
        );
    }
}

/// Adds the planar quad `corners` as part `name`, its corners ordered so
/// that it faces `outward` (counter-clockwise seen from that side).
pub(crate) fn facing(m: &mut Mesh, name: &str, corners: [Vec3; 4], outward: Vec3) {
    let [a, b, c, d] = corners;
    if (b - a).cross(c - a).dot(outward) >= 0.0 {
        m.add_quad(name, a, b, c, d);
    } else {
        m.add_quad(name, d, c, b, a);
    }
}

/// Splits every triangle at the corners of other triangles that lie inside
/// one of its edges (T-junctions), so that neighbouring triangles share
/// whole edges, vertex for vertex. A rasterizer is watertight only along
/// shared edges: where one panel's edge runs past another's corner, pixel
/// centres on the line can fall between the two and show the body's inside
/// (a back face, a part the pedestrian cannot see). Positions, parts,
/// areas and the bounding box do not change.
pub(crate) fn split_t_junctions(mesh: &mut Mesh) {
    let mut corners: Vec<Vec3> = mesh.positions.clone();
    corners.sort_by(|a, b| a.to_array().partial_cmp(&b.to_array()).unwrap_or(std::cmp::Ordering::Equal));
    corners.dedup();
    let mut split = Mesh { parts: mesh.parts.clone(), ..Mesh::default() };
    let mut queue: Vec<([Vec3; 3], u32)> =
        (0..mesh.triangles.len()).map(|t| (mesh.corners(t), mesh.triangle_part[t])).collect();
    while let Some((tri, part)) = queue.pop() {
        let inside = (0..3).find_map(|k| {
            let (a, b) = (tri[k], tri[(k + 1) % 3]);
            corners.iter().find(|&&p| inside_edge(a, b, p)).map(|&p| (k, p))
        });
        match inside {
            Some((k, p)) => {
                let (a, b, c) = (tri[k], tri[(k + 1) % 3], tri[(k + 2) % 3]);
                queue.push(([a, p, c], part));
                queue.push(([p, b, c], part));
            }
            None => {
                let base = split.positions.len() as u32;
                split.positions.extend(tri);
                split.triangles.push([base, base + 1, base + 2]);
                split.triangle_part.push(part);
            }
        }
    }
    *mesh = split;
}

/// Whether `p` lies on the open segment `a`–`b` (within 1 µm of it, and
/// not at either end).
fn inside_edge(a: Vec3, b: Vec3, p: Vec3) -> bool {
    let lo = a.min(b) - Vec3::splat(1e-6);
    let hi = a.max(b) + Vec3::splat(1e-6);
    if p.cmplt(lo).any() || p.cmpgt(hi).any() || p == a || p == b {
        return false;
    }
    let (a, b, p) = (a.as_dvec3(), b.as_dvec3(), p.as_dvec3());
    let ab = b - a;
    let t = (p - a).dot(ab) / ab.length_squared();
    t > 1e-9 && t < 1.0 - 1e-9 && (a + ab * t - p).length() < 1e-6
}

/// Pairs of parts with two triangles that lie in one plane and overlap
/// (share more than an edge): each such pair would fight in the depth buffer.
#[cfg(test)]
pub(crate) fn coplanar_overlaps(mesh: &Mesh) -> Vec<(String, String)> {
    use glam::{DVec2, DVec3, dvec2};
    let n = mesh.triangles.len();
    let tris: Vec<[DVec3; 3]> = (0..n).map(|t| mesh.corners(t).map(|c| c.as_dvec3())).collect();
    let normal = |t: &[DVec3; 3]| (t[1] - t[0]).cross(t[2] - t[0]).normalize();
    let mut overlaps = Vec::new();
    for a in 0..n {
        let na = normal(&tris[a]);
        for b in a + 1..n {
            let nb = normal(&tris[b]);
            if na.cross(nb).length() > 1e-6 || (tris[b][0] - tris[a][0]).dot(na).abs() > 1e-6 {
                continue;
            }
            // Project both into the plane and look for a separating axis.
            let u = na.any_orthonormal_vector();
            let w = na.cross(u);
            let flat = |t: &[DVec3; 3]| t.map(|p| dvec2(p.dot(u), p.dot(w)));
            let (pa, pb) = (flat(&tris[a]), flat(&tris[b]));
            let separated = [pa, pb].iter().any(|tri| {
                (0..3).any(|k| {
                    let edge = tri[(k + 1) % 3] - tri[k];
                    let axis = dvec2(-edge.y, edge.x);
                    let range = |t: &[DVec2; 3]| {
                        let d = t.map(|p| p.dot(axis));
                        (d[0].min(d[1]).min(d[2]), d[0].max(d[1]).max(d[2]))
                    };
                    let (ra, rb) = (range(&pa), range(&pb));
                    ra.1 <= rb.0 + 1e-9 || rb.1 <= ra.0 + 1e-9
                })
            });
            if !separated {
                overlaps.push((
                    mesh.parts[mesh.triangle_part[a] as usize].clone(),
                    mesh.parts[mesh.triangle_part[b] as usize].clone(),
                ));
            }
        }
    }
    overlaps
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_corner_inside_a_neighbours_edge_splits_that_edge() {
        // A 2 m square beside two 1 m squares: its right edge runs past their shared corner.
        let mut m = Mesh::default();
        let q = |x0: f32, x1: f32, y0: f32, y1: f32| {
            [vec3(x0, y0, 0.0), vec3(x1, y0, 0.0), vec3(x1, y1, 0.0), vec3(x0, y1, 0.0)]
        };
        facing(&mut m, "big", q(0.0, 2.0, 0.0, 2.0), Vec3::Z);
        facing(&mut m, "low", q(2.0, 3.0, 0.0, 1.0), Vec3::Z);
        facing(&mut m, "high", q(2.0, 3.0, 1.0, 2.0), Vec3::Z);
        let area = m.area();
        split_t_junctions(&mut m);
        assert!((m.area() - area).abs() < 1e-9);
        assert_eq!(m.triangles.len(), 7, "the big square's edge is split at (2, 1)");
        let corner = vec3(2.0, 1.0, 0.0);
        let big = m.parts.iter().position(|p| p == "big").unwrap() as u32;
        let touching = (0..m.triangles.len())
            .filter(|&t| m.triangle_part[t] == big && m.corners(t).contains(&corner))
            .count();
        assert_eq!(touching, 2);
        assert!(coplanar_overlaps(&m).is_empty());
    }

    #[test]
    fn facing_orders_corners_to_face_the_given_way_and_overlaps_are_found() {
        let mut m = Mesh::default();
        let square = [vec3(0.0, 0.0, 0.0), vec3(1.0, 0.0, 0.0), vec3(1.0, 1.0, 0.0), vec3(0.0, 1.0, 0.0)];
        facing(&mut m, "down", square, -Vec3::Z);
        let [a, b, c] = m.corners(0);
        assert!((b - a).cross(c - a).z < 0.0);
        assert!(coplanar_overlaps(&m).is_empty());
        // A second square shifted by half a side, in the same plane: they overlap.
        facing(&mut m, "up", square.map(|p| p + vec3(0.5, 0.0, 0.0)), Vec3::Z);
        assert!(coplanar_overlaps(&m).contains(&("down".to_string(), "up".to_string())));
    }
}
