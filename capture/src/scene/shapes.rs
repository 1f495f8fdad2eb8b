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
pub struct WheelSize {
    /// Tyre radius (the wheel's centre stands this high).
    pub radius: f32,
    /// Rim radius (the inner edge of the sidewall ring).
    pub rim_radius: f32,
    /// Half the tyre's width.
    pub half_width: f32,
}

/// The demo truck's wheels (a 0.84 m tyre on a 0.54 m rim, 0.28 m wide).
pub const TRUCK_WHEEL: WheelSize = WheelSize { radius: 0.42, rim_radius: 0.27, half_width: 0.14 };

/// How far the rim disc stands proud of the tyre's outer sidewall, metres (so
/// that the two never share a plane).
pub const RIM_PROUD_M: f32 = 0.01;

/// A wheel at `centre`; `s` = +1 on the left (outer face towards +y): the
/// tyre's tread and outer sidewall ring, and the rim disc
/// [`RIM_PROUD_M`] outside it.
pub fn wheel(m: &mut Mesh, centre: Vec3, s: f32, [tyre, rim]: [&str; 2], size: WheelSize) {
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
pub fn facing(m: &mut Mesh, name: &str, corners: [Vec3; 4], outward: Vec3) {
    let [a, b, c, d] = corners;
    if (b - a).cross(c - a).dot(outward) >= 0.0 {
        m.add_quad(name, a, b, c, d);
    } else {
        m.add_quad(name, d, c, b, a);
    }
}

/// Pairs of parts with two triangles that lie in one plane and overlap
/// (share more than an edge): each such pair would fight in the depth buffer.
#[cfg(test)]
pub fn coplanar_overlaps(mesh: &Mesh) -> Vec<(String, String)> {
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
