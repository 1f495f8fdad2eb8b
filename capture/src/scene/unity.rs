//! Import of the Unity scenarios and rig (`unity-intersection.json`).
//!
//! Unity's world is left-handed with +Y up; ours is right-handed with +Z up
//! (+X east, +Y north). Swapping Unity's Y and Z is a reflection, so it turns
//! the left-handed frame into a right-handed one: `(x, y, z)_unity → (x, z, y)`.
//! Unity's yaw θ (Euler Y, degrees) turns +Z towards +X, i.e. clockwise seen
//! from above. The F-150 of the Unity project points along its local −X (the
//! keyed motion shows it: at θ = 180° the truck drives towards +X), so the
//! heading in our frame is `ψ = 180° − θ` and its slope is `−dθ/dt`. The
//! small pitch and roll keys of the clips (at most a few degrees, the truck
//! settling on its suspension) are not replayed: the rig and archive only use
//! position and yaw.

use std::collections::BTreeMap;
use std::path::Path;

use serde::Deserialize;

use crate::error::{CaptureError, Result};
use crate::scene::rig::Rig;
use crate::scene::scenario::Scenario;
use crate::scene::track::{Key, Motion, Track, ValueOrTrack};

#[derive(Deserialize)]
struct File {
    pedestrian: Pedestrian,
    capture: Capture,
    scenarios: BTreeMap<String, UnityScenario>,
}

#[derive(Deserialize)]
struct Pedestrian {
    eyes_position: [f64; 3],
    eye_offsets_x: [f64; 2],
    vertical_fov_degrees: f64,
    near: f64,
    far: f64,
    ground_y: f64,
}

#[derive(Deserialize)]
struct Capture {
    fps: f64,
    tiles: [u32; 2],
    eye_resolution: [u32; 2],
}

#[derive(Deserialize)]
struct UnityScenario {
    duration_s: f64,
    vehicle: Vec<UnityTrack>,
}

#[derive(Deserialize)]
struct UnityTrack {
    property: String,
    keys: Vec<Key<3>>,
}

/// Unity position → our world.
pub(crate) fn position_from_unity(p: [f64; 3]) -> [f64; 3] {
    [p[0], p[2], p[1]]
}

/// Unity yaw (Euler Y, degrees) of the F-150 → our heading (degrees CCW from +X).
pub(crate) fn yaw_from_unity(theta_deg: f64) -> f64 {
    180.0 - theta_deg
}

/// Reads the Unity export: the rig (in our frame) and the scenarios.
pub(crate) fn load(path: &Path) -> Result<(Rig, Vec<Scenario>)> {
    let bytes = ufcsr::files::read_limited(path, ufcsr::files::SMALL_INPUT_LIMIT)?;
    parse(path, &bytes)
}

/// The rig and scenarios of a Unity export's bytes; `path` names it in
/// messages. The rig, tracks and durations get the scene file's bounds.
pub(crate) fn parse(path: &Path, bytes: &[u8]) -> Result<(Rig, Vec<Scenario>)> {
    let file: File = serde_json::from_slice(bytes)
        .map_err(|e| CaptureError::bad_file(path, format!("not a Unity scenario export: {e}")))?;
    let ped = &file.pedestrian;
    let eye = position_from_unity(ped.eyes_position);
    let [w, h] = file.capture.eye_resolution;
    let half_v = (ped.vertical_fov_degrees.to_radians() / 2.0).tan();
    let rig = Rig {
        pedestrian: ValueOrTrack::Fixed([eye[0], eye[1], ped.ground_y]),
        eye_height_m: ped.eyes_position[1] - ped.ground_y,
        ipd_m: (ped.eye_offsets_x[1] - ped.eye_offsets_x[0]).abs(),
        horizontal_fov_deg: 2.0 * (half_v * f64::from(w) / f64::from(h)).atan().to_degrees(),
        eye_pixels: [w, h],
        tiles: file.capture.tiles,
        fps: file.capture.fps,
        near_m: ped.near,
        far_m: ped.far,
        look_at_vehicle: [0.0, 0.0, 0.0],
    };
    rig.check().map_err(|e| CaptureError::bad_file(path, format!("rig: {e}")))?;
    let mut scenarios = Vec::new();
    for (name, scenario) in file.scenarios {
        let in_scenario = |e: CaptureError| CaptureError::bad_file(path, format!("scenario {name}: {e}"));
        crate::scene::scenario::check_duration(scenario.duration_s)
            .map_err(|message| CaptureError::bad_file(path, format!("scenario {name}: {message}")))?;
        let track = |property: &str| {
            scenario.vehicle.iter().find(|t| t.property == property).ok_or_else(|| {
                CaptureError::bad_file(path, format!("scenario {name} has no {property:?} track"))
            })
        };
        let position = Track::new(
            track("position")?
                .keys
                .iter()
                .map(|k| Key {
                    t: k.t,
                    value: position_from_unity(k.value),
                    in_slope: k.in_slope.map(position_from_unity),
                    out_slope: k.out_slope.map(position_from_unity),
                })
                .collect(),
        )
        .map_err(in_scenario)?;
        let yaw_deg = Track::new(
            track("euler_degrees")?
                .keys
                .iter()
                .map(|k| Key {
                    t: k.t,
                    value: [yaw_from_unity(k.value[1])],
                    in_slope: k.in_slope.map(|s| [-s[1]]),
                    out_slope: k.out_slope.map(|s| [-s[1]]),
                })
                .collect(),
        )
        .map_err(in_scenario)?;
        let scenario =
            Scenario { name, duration_s: scenario.duration_s, motion: Motion { position, yaw_deg } };
        crate::scene::scenario::check_frame_time(&scenario, rig.fps, "capture.fps")
            .map_err(|message| CaptureError::bad_file(path, message))?;
        scenarios.push(scenario);
    }
    if scenarios.is_empty() {
        return Err(CaptureError::bad_file(path, "the Unity export has no scenarios"));
    }
    Ok((rig, scenarios))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn conversion_is_a_handedness_flip_with_z_up() {
        // Unity +Y (up) becomes +Z, Unity +Z (forward/north) becomes +Y.
        assert_eq!(position_from_unity([1.0, 2.0, 3.0]), [1.0, 3.0, 2.0]);
        // θ = 180° drives towards +X (east): heading 0°. θ = 90° → north.
        assert_eq!(yaw_from_unity(180.0), 0.0);
        assert_eq!(yaw_from_unity(90.0), 90.0);
    }
}
