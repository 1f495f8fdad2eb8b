//! One ray–triangle test for the whole capture: the exact measure's
//! segment queries (`exact::bvh`) and the eye-inside-the-vehicle check (`job::scene_checks`) must
//! agree on what a crossing is, so both read this Möller–Trumbore. It lives
//! with the scene, which both depend on, so neither depends on the other.

use glam::DVec3;

/// A triangle as Möller–Trumbore reads it: a corner and the two edges from it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct StoredTriangle {
    pub corner: DVec3,
    pub edge1: DVec3,
    pub edge2: DVec3,
}

impl StoredTriangle {
    /// The stored form of the triangle with corners `t`.
    pub(crate) fn from_corners(t: &[DVec3; 3]) -> StoredTriangle {
        StoredTriangle { corner: t[0], edge1: t[1] - t[0], edge2: t[2] - t[0] }
    }
}

/// Möller–Trumbore: where along `direction` (in its own length) the ray from
/// `from` crosses the triangle, or `None` when it misses it or runs parallel.
/// Inlined: the exact measure calls it tens of millions of times a second.
#[inline]
pub(crate) fn ray_triangle_parameter(from: DVec3, direction: DVec3, t: &StoredTriangle) -> Option<f64> {
    let p = direction.cross(t.edge2);
    let determinant = t.edge1.dot(p);
    if determinant.abs() < 1e-15 {
        return None;
    }
    let inverse = 1.0 / determinant;
    let s = from - t.corner;
    let u = s.dot(p) * inverse;
    if !(0.0..=1.0).contains(&u) {
        return None;
    }
    let q = s.cross(t.edge1);
    let v = direction.dot(q) * inverse;
    if v < 0.0 || u + v > 1.0 {
        return None;
    }
    Some(t.edge2.dot(q) * inverse)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_ray_through_a_triangle_gives_its_parameter_and_a_parallel_one_none() {
        let t = StoredTriangle::from_corners(&[DVec3::ZERO, DVec3::X, DVec3::Y]);
        let along = ray_triangle_parameter(DVec3::new(0.25, 0.25, 2.0), DVec3::new(0.0, 0.0, -4.0), &t);
        assert_eq!(along, Some(0.5));
        assert_eq!(ray_triangle_parameter(DVec3::new(0.25, 0.25, 2.0), DVec3::X, &t), None);
        assert_eq!(ray_triangle_parameter(DVec3::new(2.0, 2.0, 2.0), DVec3::NEG_Z, &t), None);
    }
}
