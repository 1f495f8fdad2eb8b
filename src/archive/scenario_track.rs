//! Where everything was, frame by frame, as a capture's manifest records it:
//! the vehicle's pose, the eyes (or, in older manifests, the rig's fixed
//! pedestrian at eye height), a walking pedestrian's ground point and the
//! moving occluders' poses. The figures that show the scenario read it —
//! the views' pedestrian marker and the top-down map — so they say what the
//! manifest says and nothing else.

use crate::format::manifest::{FrameEntry, Manifest, PedestrianSetting};

/// One frame of the scenario (world metres, z up).
#[derive(Debug, Clone, PartialEq)]
pub struct TrackFrame {
    pub frame: u64,
    pub time_s: f64,
    pub vehicle_position: [f64; 3],
    /// The vehicle's heading, degrees counter-clockwise from +x seen from above.
    pub vehicle_yaw_deg: f64,
    /// Every eye's position.
    pub eyes: Vec<[f64; 3]>,
    /// A walking pedestrian's ground point (absent when the pedestrian stands).
    pub pedestrian: Option<[f64; 3]>,
    /// Moving occluders: name, position and yaw in degrees.
    pub occluders: Vec<(String, [f64; 3], f64)>,
}

impl TrackFrame {
    /// `point` (world) in the vehicle's frame (x forward, y left, z up).
    pub fn in_vehicle_frame(&self, point: [f64; 3]) -> [f64; 3] {
        let (sin, cos) = self.vehicle_yaw_deg.to_radians().sin_cos();
        let [dx, dy, dz] = [0, 1, 2].map(|k| point[k] - self.vehicle_position[k]);
        [cos * dx + sin * dy, -sin * dx + cos * dy, dz]
    }

    /// The eyes' mean position (world), when there are eyes.
    pub fn eye_centre(&self) -> Option<[f64; 3]> {
        if self.eyes.is_empty() {
            return None;
        }
        let count = self.eyes.len() as f64;
        Some([0, 1, 2].map(|k| self.eyes.iter().map(|eye| eye[k]).sum::<f64>() / count))
    }

    /// Where the pedestrian's eyes were seen from the vehicle: degrees
    /// counter-clockwise from its front (0 = ahead, 90 = to its left).
    pub fn pedestrian_azimuth_deg(&self) -> Option<f64> {
        let [x, y, _] = self.in_vehicle_frame(self.eye_centre()?);
        (x != 0.0 || y != 0.0).then(|| y.atan2(x).to_degrees())
    }
}

/// The scenario's frames in order, and its name.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ScenarioTrack {
    /// The scenario's name (`scenario.name`), when the manifest gives one.
    pub name: Option<String>,
    pub frames: Vec<TrackFrame>,
    /// The scenario and the rig in words, for the report: label and value
    /// (see `summary_rows`).
    pub summary: Vec<(String, String)>,
}

fn metres(point: [f64; 3]) -> String {
    format!("({:.1}, {:.1}) m", point[0], point[1])
}

/// The scenario and the rig in words: what the manifest's `scenario`,
/// `scene` and `rig.settings` say, and where the pedestrian was.
pub(crate) fn summary_rows(manifest: &Manifest, frames: &[TrackFrame]) -> Vec<(String, String)> {
    let mut rows = Vec::new();
    if let Some(scenario) = &manifest.scenario {
        rows.push(("scenario".into(), format!("{}, {:.1} s", scenario.name, scenario.duration_s)));
    }
    if let Some(scene) = &manifest.scene {
        for (key, value) in [("environment", &scene.environment), ("vehicle", &scene.vehicle)] {
            if let Some(value) = value {
                rows.push((key.into(), value.clone()));
            }
        }
        if let Some(measured) = &scene.measured {
            rows.push((
                "measured vehicle".into(),
                format!(
                    "{} ({}), one of the {} the scene measures ({}), each in an archive of its own with the \
                     others as occluders",
                    measured.name,
                    measured.source,
                    measured.fleet.len(),
                    measured.fleet.join(", ")
                ),
            ));
        }
    }
    if let (Some(first), Some(last)) = (frames.first(), frames.last()) {
        rows.push((
            "frames in the manifest".into(),
            format!(
                "{} (frame {} at {:.2} s to frame {} at {:.2} s)",
                frames.len(),
                first.frame,
                first.time_s,
                last.frame,
                last.time_s
            ),
        ));
        let eyes = (first.eye_centre(), last.eye_centre());
        if let (Some(start), Some(end)) = eyes {
            let place = if start == end {
                format!("standing, eyes at {}", metres(start))
            } else {
                format!("walking from {} to {}", metres(start), metres(end))
            };
            rows.push(("pedestrian".into(), format!("{place}, {:.2} m high", start[2])));
        }
        let moving: Vec<&str> = first.occluders.iter().map(|o| o.0.as_str()).collect();
        if !moving.is_empty() {
            rows.push(("moving occluders".into(), moving.join(", ")));
        }
    }
    rows.extend(rig_rows(manifest));
    rows
}

/// The rig in words: the eyes, pixels per degree and eye separation.
fn rig_rows(manifest: &Manifest) -> Vec<(String, String)> {
    let mut rows = Vec::new();
    let settings = manifest.rig_settings();
    if let Some((fov, [width, height])) = settings.and_then(|s| Some((s.horizontal_fov_deg?, s.eye_pixels?)))
    {
        rows.push(("eyes".into(), format!("{fov:.0}° wide, {width}×{height} pixels each")));
    }
    if let Some(ppd) = manifest.rig.as_ref().and_then(|rig| rig.pixels_per_degree) {
        rows.push(("pixels per degree".into(), format!("{ppd:.2}")));
    }
    if let Some(ipd) = settings.and_then(|s| s.ipd_m) {
        rows.push(("eye separation".into(), format!("{:.1} mm", ipd * 1000.0)));
    }
    rows
}

/// The rig's standing pedestrian at eye height (`rig.settings`), for
/// manifests whose frames carry no eyes.
fn standing_eye(manifest: &Manifest) -> Option<[f64; 3]> {
    let settings = manifest.rig_settings()?;
    let Some(PedestrianSetting::Point([x, y, z])) = settings.pedestrian else { return None };
    Some([x, y, z + settings.eye_height_m.unwrap_or(1.75)])
}

fn track_frame(record: &FrameEntry, standing: Option<[f64; 3]>) -> Option<TrackFrame> {
    let vehicle = record.vehicle?;
    let eyes: Vec<[f64; 3]> = match &record.eyes {
        Some(eyes) => eyes.values().map(|eye| eye.position).collect(),
        None => standing.into_iter().collect(),
    };
    let occluders = record.occluders.iter().flatten();
    Some(TrackFrame {
        frame: u64::from(record.frame),
        time_s: record.time_s?,
        vehicle_position: vehicle.position,
        vehicle_yaw_deg: vehicle.yaw_deg,
        eyes,
        pedestrian: record.pedestrian,
        occluders: occluders.map(|o| (o.name.clone(), o.position, o.yaw_deg)).collect(),
    })
}

impl ScenarioTrack {
    /// The track of a manifest's `frames` (records without a vehicle pose or
    /// time are left out); `None` when no frame has one.
    pub fn from_manifest(manifest: &Manifest) -> Option<ScenarioTrack> {
        let standing = standing_eye(manifest);
        let mut frames: Vec<TrackFrame> =
            manifest.frame_records().iter().filter_map(|record| track_frame(record, standing)).collect();
        frames.sort_by_key(|frame| frame.frame);
        let name = manifest.scenario.as_ref().map(|scenario| scenario.name.clone());
        let summary = summary_rows(manifest, &frames);
        (!frames.is_empty()).then_some(ScenarioTrack { name, frames, summary })
    }

    /// The track of the archive at `archive` (its manifest), when it has one
    /// that can be read; figures that need it are left out otherwise.
    pub fn from_archive(archive: &std::path::Path) -> Option<ScenarioTrack> {
        crate::Manifest::load_from_dir(archive).ok().flatten().as_ref().and_then(ScenarioTrack::from_manifest)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_point_ahead_and_left_of_a_vehicle_heading_north_has_azimuth_45() {
        let frame = TrackFrame {
            frame: 0,
            time_s: 0.0,
            vehicle_position: [10.0, 0.0, 0.0],
            vehicle_yaw_deg: 90.0,
            eyes: vec![[9.0, 1.0, 1.75], [7.0, 3.0, 1.75]],
            pedestrian: None,
            occluders: Vec::new(),
        };
        // Heading +y; the eyes' centre (8, 2) is 2 m ahead and 2 m to the left.
        let [x, y, z] = frame.in_vehicle_frame(frame.eye_centre().unwrap());
        assert!((x - 2.0).abs() < 1e-12 && (y - 2.0).abs() < 1e-12 && z == 1.75);
        assert!((frame.pedestrian_azimuth_deg().unwrap() - 45.0).abs() < 1e-9);
    }

    #[test]
    fn frames_without_eyes_use_the_rigs_standing_pedestrian_at_eye_height() {
        let text = r#"{"tiles": [], "rig": {"settings": {"pedestrian": [1, 2, 0], "eye_height_m": 1.5}},
            "scenario": {"name": "A", "duration_s": 2.0},
            "frames": [{"frame": 1, "time_s": 0.5, "vehicle": {"position": [0, 0, 0], "yaw_deg": 0}},
                       {"frame": 0, "time_s": 0.0, "vehicle": {"position": [0, 0, 0], "yaw_deg": 0}},
                       {"frame": 2}]}"#;
        let manifest = crate::Manifest::parse(std::path::Path::new("m.json"), text.as_bytes()).unwrap();
        let track = ScenarioTrack::from_manifest(&manifest).unwrap();
        assert_eq!(track.name.as_deref(), Some("A"));
        assert_eq!(track.frames.iter().map(|f| f.frame).collect::<Vec<_>>(), [0, 1]);
        assert_eq!(track.frames[0].eyes, [[1.0, 2.0, 1.5]]);
        let summary: Vec<String> =
            track.summary.iter().map(|(label, value)| format!("{label}: {value}")).collect();
        assert_eq!(
            summary,
            [
                "scenario: A, 2.0 s",
                "frames in the manifest: 2 (frame 0 at 0.00 s to frame 1 at 0.50 s)",
                "pedestrian: standing, eyes at (1.0, 2.0) m, 1.50 m high"
            ]
        );
    }
}
