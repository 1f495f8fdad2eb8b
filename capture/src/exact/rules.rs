//! The visibility rules of one surface sample in one eye-frame, and the
//! solid angle it then covers.
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

use super::bvh::TriangleBvh;
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
    match sample_visibility(sample, eye_frame, obstacles, tracer, &[]) {
        Sighting::Visible(solid_angle) => Some(solid_angle),
        Sighting::NotInSight | Sighting::Blocked(_) => None,
    }
}

/// A triangle that blocked a segment: which hierarchy, which of its triangles.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Blocker {
    frame: Frame,
    triangle: u32,
}

/// What one sample's rules found in one eye-frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Sighting {
    /// Visible, covering this solid angle, sr.
    Visible(f64),
    /// Edge-on or outside the view (no segment was cast).
    NotInSight,
    /// Hidden by this triangle.
    Blocked(Blocker),
}

/// The rules of [`visible_solid_angle`], trying the triangles in `guesses`
/// first (blockers of earlier eye-frames or of neighbouring samples): one
/// that crosses the segment hides the sample, and the hierarchy would have
/// found a crossing triangle too (its box test is conservative, `bvh.rs`),
/// so the answer is the same whatever the guesses. Otherwise the segment
/// queries run as in [`visible_solid_angle`], vehicle, scene, then each
/// moving occluder, and return the blocker they find.
pub(crate) fn sample_visibility(
    sample: &SurfaceSample,
    eye_frame: &EyeFrame,
    obstacles: &Obstacles,
    tracer: Tracer,
    guesses: &[Option<Blocker>],
) -> Sighting {
    let towards_eye = eye_frame.eye_in_vehicle - sample.position;
    let distance_squared = towards_eye.dot(towards_eye);
    let distance = distance_squared.sqrt();
    let side = sample.normal.dot(towards_eye);
    if side.abs() <= EDGE_ON_RELATIVE * distance + sample.edge_on_m {
        return Sighting::NotInSight;
    }
    let clip = transform_point(&eye_frame.vehicle_to_clip, sample.position);
    // Reversed Z: depth runs from w (near plane) down to 0 (far plane).
    let in_view =
        clip.w > 0.0 && clip.x.abs() <= clip.w && clip.y.abs() <= clip.w && clip.z >= 0.0 && clip.z <= clip.w;
    if !in_view {
        return Sighting::NotInSight;
    }
    let lifted = sample.position + sample.normal * (eye_frame.lift_m * side.signum());
    // The near plane on the segment: w − z falls linearly from the point's
    // margin (≥ 0) to the eye's (< 0); beyond `to_near` everything is clipped.
    let margin = clip.w - clip.z;
    let to_near = margin / (margin - eye_frame.eye_near_margin);
    let segment = Segment { eye_frame, lifted, to_near };
    for guess in guesses.iter().flatten() {
        let (from, to) = segment.in_frame(guess.frame);
        if bvh_of(obstacles, guess.frame).triangle_blocks(guess.triangle, from, to) {
            return Sighting::Blocked(*guess);
        }
    }
    let moving = (0..eye_frame.local_to_moving.len()).map(Frame::Moving);
    for frame in [Frame::Vehicle, Frame::Local].into_iter().chain(moving) {
        let (from, to) = segment.in_frame(frame);
        let bvh = bvh_of(obstacles, frame);
        let blocker = match tracer {
            Tracer::Hierarchy => bvh.first_blocker(from, to),
            Tracer::BruteForce => bvh.first_blocker_brute_force(from, to),
        };
        if let Some(triangle) = blocker {
            return Sighting::Blocked(Blocker { frame, triangle });
        }
    }
    Sighting::Visible(sample.area_m2 * side.abs() / (distance_squared * distance))
}

/// The segment of one sample in one eye-frame: from the lifted sample to
/// the near plane (`to_near` of the way to the eye).
struct Segment<'a> {
    eye_frame: &'a EyeFrame,
    lifted: DVec3,
    to_near: f64,
}

impl Segment<'_> {
    /// Its ends in the frame of `frame`'s hierarchy.
    #[inline(always)]
    fn in_frame(&self, frame: Frame) -> (DVec3, DVec3) {
        let eye_frame = self.eye_frame;
        if let Frame::Vehicle = frame {
            return (self.lifted, self.lifted + (eye_frame.eye_in_vehicle - self.lifted) * self.to_near);
        }
        let lifted_local = transform_point(&eye_frame.vehicle_to_local, self.lifted).truncate();
        let end_local = lifted_local + (eye_frame.eye_local - lifted_local) * self.to_near;
        match frame {
            Frame::Moving(k) => {
                // Moving occluders: the same segment in each one's own frame,
                // summed in `transform_point`'s fixed order.
                let local_to_moving = &eye_frame.local_to_moving[k];
                let from = transform_point(local_to_moving, lifted_local).truncate();
                (from, transform_point(local_to_moving, end_local).truncate())
            }
            _ => (lifted_local, end_local),
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Frame {
    Vehicle,
    Local,
    /// Moving occluder `k`'s own frame.
    Moving(usize),
}

fn bvh_of(obstacles: &Obstacles, frame: Frame) -> &TriangleBvh {
    match frame {
        Frame::Vehicle => &obstacles.vehicle,
        Frame::Local => &obstacles.world,
        Frame::Moving(k) => &obstacles.moving[k],
    }
}
