//! Occluders that move: traffic (a car in the next lane, a lead car) and
//! other pedestrians.
//!
//! A moving occluder keeps its triangles in its own frame (x forward, y left,
//! z up, like the vehicle) and gets a pose per frame, so the renderer draws
//! it with a per-draw transform and the exact measure turns rays into its
//! frame; nothing is re-uploaded or rebuilt per frame. Its pose comes from
//! its own position and yaw tracks (world metres and degrees, the keys of a
//! scenario's vehicle), or it *follows* the scenario's vehicle at an offset
//! in the vehicle's frame.

use glam::{DVec3, dvec3};
use serde::{Deserialize, Serialize};

use crate::scene::mesh::Mesh;
use crate::scene::rig::vehicle_to_world;
use crate::scene::track::{MAX_TRACK_MAGNITUDE, Pose, ValueOrTrack};

/// A pedestrian's body as an occluder: length (x, front to back), width
/// (y, shoulders) and height (z), metres.
pub const PEDESTRIAN_BODY_M: [f64; 3] = [0.3, 0.5, 1.75];

/// An offset in the scenario vehicle's frame: `ahead_m` along its forward
/// axis, `left_m` to its left, and a yaw of its own relative to the
/// vehicle's (180 for an oncoming car).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct FollowOffset {
    pub ahead_m: f64,
    pub left_m: f64,
    pub yaw_deg: f64,
}

impl FollowOffset {
    /// Within the tracks' street scale ([`MAX_TRACK_MAGNITUDE`]), naming the
    /// field that is not.
    pub fn check(&self) -> Result<(), String> {
        for (field, value) in [("ahead_m", self.ahead_m), ("left_m", self.left_m), ("yaw_deg", self.yaw_deg)]
        {
            if !(value.is_finite() && value.abs() <= MAX_TRACK_MAGNITUDE) {
                return Err(format!(
                    "follow.{field} {value:e} is beyond ±{MAX_TRACK_MAGNITUDE:e}: not a street scene"
                ));
            }
        }
        Ok(())
    }

    /// The pose at this offset from the vehicle's `pose`.
    pub fn pose(&self, vehicle: &Pose) -> Pose {
        let heading = vehicle_to_world(&Pose { position: DVec3::ZERO, yaw_deg: vehicle.yaw_deg });
        let offset = heading.transform_vector3(dvec3(self.ahead_m, self.left_m, 0.0));
        Pose { position: vehicle.position + offset, yaw_deg: vehicle.yaw_deg + self.yaw_deg }
    }
}

/// How a moving occluder moves.
#[derive(Debug, Clone, PartialEq)]
pub enum OccluderPath {
    /// Its own position (world metres) and yaw (degrees) over time.
    Tracks { position: ValueOrTrack<3>, yaw_deg: ValueOrTrack<1> },
    /// At an offset from the scenario's vehicle.
    Follow(FollowOffset),
}

impl OccluderPath {
    /// The pose at `time_s`, when the scenario's vehicle stands at `vehicle`.
    pub fn pose(&self, time_s: f64, vehicle: &Pose) -> Pose {
        match self {
            OccluderPath::Tracks { position, yaw_deg } => {
                Pose { position: DVec3::from(position.eval(time_s)), yaw_deg: yaw_deg.eval(time_s)[0] }
            }
            OccluderPath::Follow(offset) => offset.pose(vehicle),
        }
    }
}

/// One moving occluder.
#[derive(Debug, Clone)]
pub struct MovingOccluder {
    /// Its name in the manifest and `scene.glb`.
    pub name: String,
    /// Its triangles in its own frame.
    pub mesh: Mesh,
    pub path: OccluderPath,
}

impl MovingOccluder {
    /// Its pose at `time_s`, when the scenario's vehicle stands at `vehicle`.
    pub fn pose(&self, time_s: f64, vehicle: &Pose) -> Pose {
        self.path.pose(time_s, vehicle)
    }

    /// Its triangles, three corners each, in its own frame (f64).
    pub fn triangles(&self) -> Vec<[DVec3; 3]> {
        (0..self.mesh.triangles.len()).map(|t| self.mesh.corners(t).map(|c| c.as_dvec3())).collect()
    }
}

/// A pedestrian's body: a box of `size` (length, width, height) standing on
/// the ground, centred on the origin of its frame.
pub fn pedestrian_body(size: [f64; 3]) -> Mesh {
    let [length, width, height] = size.map(|v| v as f32);
    let mut body = Mesh::default();
    body.add_box(
        glam::vec3(-length / 2.0, -width / 2.0, 0.0),
        glam::vec3(length / 2.0, width / 2.0, height),
        [Some("body"); 6],
    );
    body
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_follow_offset_is_ahead_and_left_in_the_vehicle_frame() {
        // The vehicle heads north (yaw 90°): ahead is +y, left is −x.
        let vehicle = Pose { position: dvec3(10.0, 20.0, 0.0), yaw_deg: 90.0 };
        let lead = FollowOffset { ahead_m: 8.0, left_m: 3.5, yaw_deg: 180.0 }.pose(&vehicle);
        assert!((lead.position - dvec3(6.5, 28.0, 0.0)).length() < 1e-12, "{lead:?}");
        assert_eq!(lead.yaw_deg, 270.0);
        assert!(
            FollowOffset { left_m: f64::NAN, ..FollowOffset::default() }
                .check()
                .unwrap_err()
                .contains("left_m")
        );
    }
}
