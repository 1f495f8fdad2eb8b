//! A generated vehicle made of the triangles real exports are full of:
//! zero-area (collinear and coincident corners), needles, slivers,
//! huge-aspect strips and triangles that share positions or lie on top of
//! each other.
//!
//! A SketchUp truck with 210 zero-area and 2,273 sub-mm² triangles once
//! rendered 48 pixels naming no labelled texel; this mesh reproduces that
//! class of input on demand, so the exactness tests can show that every
//! rendered pixel of *any* mesh names a labelled texel. Deterministic: the
//! same mesh on every call.

use glam::{Vec3, vec3};

use crate::scene::mesh::Mesh;

/// A 4 × 1.8 × 1.6 m box body whose sides are tessellated into normal,
/// sliver, needle, zero-area and overlapping triangles.
pub fn degenerate_vehicle() -> Mesh {
    let mut mesh = Mesh::default();
    let (min, max) = (vec3(-2.0, -0.9, 0.3), vec3(2.0, 0.9, 1.9));
    // A plain body so the vehicle has ordinary surface too.
    mesh.add_box(min, max, [Some("front"), Some("rear"), Some("left"), Some("right"), Some("roof"), None]);
    // Each side is covered again, just outside the body, by strips of bad triangles.
    let eps = 0.002;
    let sides: [(&str, Vec3, Vec3, Vec3); 4] = [
        // (part, corner, along, up): the side's plane spanned by two axes.
        (
            "left_strips",
            vec3(min.x, max.y + eps, min.z),
            Vec3::X * (max.x - min.x),
            Vec3::Z * (max.z - min.z),
        ),
        (
            "right_strips",
            vec3(max.x, min.y - eps, min.z),
            -Vec3::X * (max.x - min.x),
            Vec3::Z * (max.z - min.z),
        ),
        (
            "front_strips",
            vec3(max.x + eps, max.y, min.z),
            -Vec3::Y * (max.y - min.y),
            Vec3::Z * (max.z - min.z),
        ),
        (
            "rear_strips",
            vec3(min.x - eps, min.y, min.z),
            Vec3::Y * (max.y - min.y),
            Vec3::Z * (max.z - min.z),
        ),
    ];
    for (part, corner, along, up) in sides {
        add_bad_strips(&mut mesh, part, corner, along, up);
    }
    mesh
}

/// Fans of sliver and needle triangles, zero-area triangles and
/// shared-position duplicates over one side `corner + s·along + t·up`.
fn add_bad_strips(mesh: &mut Mesh, part: &str, corner: Vec3, along: Vec3, up: Vec3) {
    let at = |s: f32, t: f32| corner + along * s + up * t;
    let rows = 12;
    for row in 0..rows {
        let t0 = row as f32 / rows as f32;
        let t1 = (row as f32 + 1.0) / rows as f32;
        match row % 4 {
            // A fan of slivers: one corner at the left end, the far edge
            // split into many tiny steps (altitude ≪ 1 mm, length ~ 4 m).
            0 => {
                let steps = 40;
                for k in 0..steps {
                    let a = t0 + (t1 - t0) * k as f32 / steps as f32;
                    let b = t0 + (t1 - t0) * (k as f32 + 1.0) / steps as f32;
                    mesh.add_triangle(part, at(0.0, (t0 + t1) / 2.0), at(1.0, a), at(1.0, b));
                }
            }
            // Huge-aspect strips (4 m × 0.05 mm) stacked over the row.
            1 => {
                let strips = 30;
                for k in 0..strips {
                    let t = t0 + (t1 - t0) * k as f32 / strips as f32;
                    let h = 0.00005 / up.length();
                    mesh.add_quad(part, at(0.0, t), at(1.0, t), at(1.0, t + h), at(0.0, t + h));
                }
                // And the row's ordinary surface, split into needles meeting at a point.
                let needles = 25;
                for k in 0..needles {
                    let s0 = k as f32 / needles as f32;
                    let s1 = (k as f32 + 1.0) / needles as f32;
                    mesh.add_triangle(part, at(s0, t0), at(s1, t0), at(0.5, t1));
                    mesh.add_triangle(part, at(s0, t1), at(0.5, t1 - 1e-5), at(s1, t1));
                }
            }
            // Zero-area triangles: collinear corners along the row, a
            // triangle with two coincident corners, and one collapsed to a point.
            2 => {
                for k in 0..20 {
                    let s = k as f32 / 20.0;
                    let t = (t0 + t1) / 2.0;
                    mesh.add_triangle(part, at(s, t), at(s + 0.02, t), at(s + 0.05, t));
                    mesh.add_triangle(part, at(s, t0), at(s, t0), at(s + 0.03, t1));
                    mesh.add_triangle(part, at(s, t1), at(s, t1), at(s, t1));
                    // Collinear in a slanted direction too.
                    mesh.add_triangle(part, at(s, t0), at(s + 0.01, (t0 + t1) / 2.0), at(s + 0.02, t1));
                }
                mesh.add_quad(part, at(0.0, t0), at(1.0, t0), at(1.0, t1), at(0.0, t1));
            }
            // Shared positions: the row's quad twice over (coplanar
            // duplicates) plus a fan of sub-mm² triangles around its centre.
            _ => {
                mesh.add_quad(part, at(0.0, t0), at(1.0, t0), at(1.0, t1), at(0.0, t1));
                mesh.add_quad(part, at(0.0, t0), at(1.0, t0), at(1.0, t1), at(0.0, t1));
                let centre = at(0.5, (t0 + t1) / 2.0);
                for k in 0..24 {
                    let angle = k as f32 / 24.0 * std::f32::consts::TAU;
                    let next = (k + 1) as f32 / 24.0 * std::f32::consts::TAU;
                    let r = 0.0004;
                    let dir = |a: f32| along.normalize() * a.cos() * r + up.normalize() * a.sin() * r;
                    mesh.add_triangle(part, centre, centre + dir(angle), centre + dir(next));
                }
            }
        }
    }
}
