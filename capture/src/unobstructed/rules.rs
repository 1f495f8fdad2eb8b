//! The visibility rules of one surface sample in one eye-frame, and the
//! solid angle it then covers. `visibility.wgsl` does the same steps in the
//! same order; change both together.
//!
//! A sample is visible when
//! 1. the eye is not edge-on to its surface: its height above the surface's
//!    plane exceeds [`EDGE_ON_RELATIVE`] of its distance plus the triangle's
//!    f32 tolerance (`edge_on_m`); surfaces are two-sided, as the renderer
//!    draws them;
//! 2. it is inside the eye's view frustum, between the near and the far
//!    plane (a point nearer than the near plane is clipped, as rendered);
//! 3. the segment from it (lifted off its surface towards the eye) to the
//!    near plane crosses no triangle of the vehicle or the scene (a moving
//!    occluder: the segment taken into its own frame). Geometry
//!    nearer to the eye than the near plane hides nothing, because the
//!    renderer clips it away too.
//!
//! Its solid angle is `area · |n·d| / r³` (area × cos θ / r²), steradians.

use glam::DVec3;

use super::geometry::Obstacles;
use super::types::{EDGE_ON_RELATIVE, EyeFrame, SurfaceSample, transform_point};

/// How the segment queries are answered.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Tracer {
    /// Through the hierarchies (the measure).
    Hierarchy,
    /// Against every triangle (for tests).
    BruteForce,
}

/// The solid angle (sr) `sample` covers in `eye_frame` if it is visible,
/// else `None` (see the module documentation for the rules).
pub fn visible_solid_angle(
    sample: &SurfaceSample,
    eye_frame: &EyeFrame,
    obstacles: &Obstacles,
    tracer: Tracer,
) -> Option<f64> {
    let towards_eye = eye_frame.eye_in_vehicle - sample.position;
    let distance_squared = towards_eye.dot(towards_eye);
    let distance = distance_squared.sqrt();
    let side = sample.normal.dot(towards_eye);
    if side.abs() <= EDGE_ON_RELATIVE * distance + sample.edge_on_m {
        return None;
    }
    let clip = transform_point(&eye_frame.vehicle_to_clip, sample.position);
    // Reversed Z: depth runs from w (near plane) down to 0 (far plane).
    let in_view =
        clip.w > 0.0 && clip.x.abs() <= clip.w && clip.y.abs() <= clip.w && clip.z >= 0.0 && clip.z <= clip.w;
    if !in_view {
        return None;
    }
    let lifted = sample.position + sample.normal * (eye_frame.lift_m * side.signum());
    // The near plane on the segment: w − z falls linearly from the point's
    // margin (≥ 0) to the eye's (< 0); beyond `to_near` everything is clipped.
    let margin = clip.w - clip.z;
    let to_near = margin / (margin - eye_frame.eye_near_margin);
    let end = lifted + (eye_frame.eye_in_vehicle - lifted) * to_near;
    if blocks(obstacles, Frame::Vehicle, lifted, end, tracer) {
        return None;
    }
    let lifted_local = transform_point(&eye_frame.vehicle_to_local, lifted).truncate();
    let end_local = lifted_local + (eye_frame.eye_local - lifted_local) * to_near;
    if blocks(obstacles, Frame::Local, lifted_local, end_local, tracer) {
        return None;
    }
    // Moving occluders: the same segment in each one's own frame.
    for (k, local_to_moving) in eye_frame.local_to_moving.iter().enumerate() {
        // Summed as `transform` in visibility.wgsl sums, so both round alike.
        let from = transform_point(local_to_moving, lifted_local).truncate();
        let to = transform_point(local_to_moving, end_local).truncate();
        if blocks(obstacles, Frame::Moving(k), from, to, tracer) {
            return None;
        }
    }
    Some(sample.area_m2 * side.abs() / (distance_squared * distance))
}

#[derive(Clone, Copy)]
enum Frame {
    Vehicle,
    Local,
    /// Moving occluder `k`'s own frame.
    Moving(usize),
}

fn blocks(obstacles: &Obstacles, frame: Frame, from: DVec3, to: DVec3, tracer: Tracer) -> bool {
    let bvh = match frame {
        Frame::Vehicle => &obstacles.vehicle,
        Frame::Local => &obstacles.world,
        Frame::Moving(k) => &obstacles.moving[k],
    };
    match tracer {
        Tracer::Hierarchy => bvh.blocks(from, to),
        Tracer::BruteForce => bvh.blocks_brute_force(from, to),
    }
}
