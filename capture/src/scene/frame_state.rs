//! Everything that moves, at one instant of a scenario: the vehicle's pose,
//! where the (possibly walking) pedestrian stands, and each moving
//! occluder's pose. The renderer, the exact measure, the scene checks and
//! the manifest all read a frame through this one place, so they agree on
//! where everything was.

use glam::DVec3;

use crate::error::{CaptureError, Result};
use crate::scene::rig::vehicle_to_world;
use crate::scene::scenario::Scenario;
use crate::scene::scene_file::Scene;
use crate::scene::track::Pose;

/// The scene at one frame.
#[derive(Debug, Clone, PartialEq)]
pub struct FrameState {
    pub frame: u32,
    pub time_s: f64,
    /// The measured vehicle: the scenario's, or in a pass of a
    /// several-vehicle scene the one that pass measures.
    pub vehicle: Pose,
    /// The pedestrian's ground point (world metres).
    pub pedestrian: DVec3,
    /// Each moving occluder's pose, in `Occluders::moving` order.
    pub moving: Vec<Pose>,
}

impl FrameState {
    /// The state of `scene` at `frame` of `scenario` (time clamped to the
    /// scenario's end); an error naming what is not finite.
    pub fn at(scene: &Scene, scenario: &Scenario, frame: u32) -> Result<FrameState> {
        let time_s = (f64::from(frame) / scene.rig.fps).min(scenario.duration_s);
        // The scenario's motion; the measured vehicle's own path, in a pass
        // of a several-vehicle scene, and every follower are relative to it.
        let reference = scenario.motion.pose(time_s);
        let vehicle = scene.vehicle_path.as_ref().map_or(reference, |path| path.pose(time_s, &reference));
        let moving: Vec<Pose> =
            scene.occluders.moving.iter().map(|occluder| occluder.pose(time_s, &reference)).collect();
        let pedestrian = scene.rig.pedestrian_at(time_s);
        let finite = |pose: &Pose| pose.position.is_finite() && pose.yaw_deg.is_finite();
        if !finite(&vehicle) {
            return Err(CaptureError::BadOptions(format!(
                "scenario {}: the vehicle's pose at {time_s} s is not finite",
                scenario.name
            )));
        }
        if let Some(k) = moving.iter().position(|pose| !finite(pose)) {
            return Err(CaptureError::BadOptions(format!(
                "scenario {}: the pose of moving occluder {} at {time_s} s is not finite",
                scenario.name, scene.occluders.moving[k].name
            )));
        }
        Ok(FrameState { frame, time_s, vehicle, pedestrian, moving })
    }

    /// The horizontal distance from the pedestrian to the vehicle, metres.
    pub fn distance_m(&self) -> f64 {
        (self.vehicle.position.truncate() - self.pedestrian.truncate()).length()
    }

    /// Each moving occluder's own frame → world.
    pub fn moving_to_world(&self) -> Vec<glam::DMat4> {
        self.moving.iter().map(vehicle_to_world).collect()
    }
}

/// "0-3, 60, 120" (runs joined; at most 12 items, then how many in all).
pub(crate) fn list_frames(frames: &[u32]) -> String {
    let mut runs: Vec<(u32, u32)> = Vec::new();
    for &frame in frames {
        match runs.last_mut() {
            Some((_, last)) if frame == *last + 1 => *last = frame,
            _ => runs.push((frame, frame)),
        }
    }
    let mut text: Vec<String> =
        runs.iter().take(12).map(|&(a, b)| if a == b { a.to_string() } else { format!("{a}-{b}") }).collect();
    if runs.len() > 12 {
        text.push(format!("… ({} frames in all)", frames.len()));
    }
    text.join(", ")
}
