//! The scene as the rays see it: the vehicle's triangles in its own frame,
//! the still occluders in a local frame centred on the pedestrian, each
//! moving occluder in its own frame, and one
//! [`EyeFrame`] per eye and frame.
//!
//! Why a local frame: a scene 10 km from the origin must measure exactly as
//! at the origin. Occluders, eyes and the vehicle pose are taken relative to
//! the pedestrian's feet (the scene's anchor) in f64 before any ray is cast,
//! so the coordinates a ray meets are metres, not ten thousands of them.

use glam::{DMat4, DVec3};

use super::bvh::TriangleBvh;
use super::types::{EyeFrame, SURFACE_LIFT_RELATIVE, transform_point};
use crate::error::Result;
use crate::scene::Scene;
use crate::scene::frame_state::FrameState;
use crate::scene::rig::vehicle_to_world;
use crate::scene::scenario::Scenario;

/// The scene's geometry for ray casts.
pub struct Obstacles {
    /// The vehicle, in its own frame.
    pub vehicle: TriangleBvh,
    /// The still occluders, in the local frame (world minus [`Obstacles::anchor`]).
    pub world: TriangleBvh,
    /// Each moving occluder in its own frame (an eye-frame places it).
    pub moving: Vec<TriangleBvh>,
    /// The world point the local frame is centred on (the pedestrian's feet).
    pub anchor: DVec3,
    /// How far a point is lifted off its surface ([`SURFACE_LIFT_RELATIVE`]
    /// of the vehicle's bounding-box diagonal), metres.
    pub lift_m: f64,
}

impl Obstacles {
    pub fn new(scene: &Scene) -> Obstacles {
        let mesh = &scene.vehicle;
        let anchor = scene.rig.anchor() * DVec3::new(1.0, 1.0, 0.0);
        let vehicle = (0..mesh.triangles.len()).map(|t| mesh.corners(t).map(|c| c.as_dvec3())).collect();
        let world = scene
            .occluders
            .positions
            .chunks_exact(3)
            .map(|t| [t[0] - anchor, t[1] - anchor, t[2] - anchor])
            .collect();
        let (min, max) = mesh.bounds();
        Obstacles {
            vehicle: TriangleBvh::new(vehicle),
            world: TriangleBvh::new(world),
            moving: scene.occluders.moving.iter().map(|m| TriangleBvh::new(m.triangles())).collect(),
            anchor,
            lift_m: SURFACE_LIFT_RELATIVE * (max - min).length(),
        }
    }
}

/// One eye-frame from the eye's world position and clip transform, the
/// vehicle's placement in the world and each moving occluder's
/// (`moving_to_world`, in [`Obstacles::moving`] order).
pub fn eye_frame(
    obstacles: &Obstacles,
    to_world: &DMat4,
    moving_to_world: &[DMat4],
    eye: DVec3,
    view_proj: &DMat4,
) -> EyeFrame {
    let vehicle_to_local = DMat4::from_translation(-obstacles.anchor) * *to_world;
    // Inverted in the local frame too: metres, not the world's offsets.
    let local_to_moving =
        moving_to_world.iter().map(|m| (DMat4::from_translation(-obstacles.anchor) * *m).inverse()).collect();
    let eye_local = eye - obstacles.anchor;
    // Inverted in the local frame: metres, not the world's 10 km offsets.
    let eye_in_vehicle = vehicle_to_local.inverse().transform_point3(eye_local);
    let vehicle_to_clip = *view_proj * *to_world;
    let eye_clip = transform_point(&vehicle_to_clip, eye_in_vehicle);
    EyeFrame {
        eye_in_vehicle,
        eye_local,
        vehicle_to_local,
        vehicle_to_clip,
        eye_near_margin: eye_clip.w - eye_clip.z,
        lift_m: obstacles.lift_m,
        local_to_moving,
    }
}

/// The eye-frames of a scenario's selected frames (both eyes per frame, in
/// frame order), with each frame's record for the manifest.
pub fn eye_frames(
    scene: &Scene,
    scenario: &Scenario,
    frames: &[u32],
    obstacles: &Obstacles,
) -> Result<(Vec<EyeFrame>, Vec<ufcsr::format::FrameEntry>)> {
    let rig = &scene.rig;
    let mut eye_frames = Vec::with_capacity(frames.len() * 2);
    let mut records = Vec::with_capacity(frames.len());
    for &frame in frames {
        let state = FrameState::at(scene, scenario, frame)?;
        let to_world = vehicle_to_world(&state.vehicle);
        let moving = state.moving_to_world();
        for camera in rig.cameras(state.time_s, &state.vehicle) {
            eye_frames.push(eye_frame(obstacles, &to_world, &moving, camera.position, &camera.view_proj));
        }
        records.push(crate::job::manifest_builder::frame_record(scene, &state));
    }
    Ok((eye_frames, records))
}

/// Seconds one eye-frame stands for: the smallest step between the selected
/// frame numbers over the rig's fps, as the analyzer's `FrameClock` reads it
/// from a rendered capture, so both measures integrate time alike.
pub fn seconds_per_frame(scene: &Scene, frames: &[u32]) -> f64 {
    let step = frames.windows(2).map(|pair| pair[1].abs_diff(pair[0])).filter(|&s| s > 0).min().unwrap_or(1);
    f64::from(step) / scene.rig.fps
}
