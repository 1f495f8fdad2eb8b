//! Scenes that cannot give a meaningful capture: refused, or warned about by
//! name, before any frame is rendered.
//!
//! Bounds (each an error naming the value): at most [`MAX_FRAMES`] frames
//! and [`MAX_TILES`] tiles in one capture (the rig's own bounds are in
//! [`Rig::check`], a mesh's in [`ufcsr::files::check_coordinates`]).
//!
//! Impossible scenes, checked over the selected frames with the vehicle's
//! own triangles and the eyes where the (possibly walking) pedestrian is at
//! each frame (warnings go to stderr, the summary and the manifest's
//! `warnings`):
//! - the near plane cuts the vehicle inside the view (the renderer then shows
//!   its inside): a warning naming the frames;
//! - part of the vehicle lies beyond the far plane (never drawn): a warning
//!   naming the frames;
//! - an eye inside the vehicle: an **error** naming the frames — every count
//!   would be of the vehicle's inside, and plausible-looking;
//! - an eye inside a moving occluder (a car driving through the pedestrian,
//!   or the pedestrian walking into one): a warning naming it and the frames;
//! - an occluder lying on the vehicle (coplanar with and overlapping its
//!   faces, [`crate::scene::coincident`]): a warning naming the occluder,
//!   the parts and the frames — the renderer hides those faces or not as
//!   depth ties fall, the exact measure never;
//! - faces of the vehicle lying on one another (within a part or across
//!   two): a warning naming the parts — the exact measure would count that
//!   surface twice (it counts a face covered whole by an earlier one once);
//! - between frames (at the rig's fps) the vehicle moves faster than
//!   [`MAX_SPEED_M_S`] or accelerates more than [`MAX_ACCELERATION_M_S2`]: a
//!   warning naming the position keys (in the pass of one vehicle of a
//!   fleet, of that vehicle's own track, naming it, so that each pass warns
//!   of its own vehicle's motion and the scene's track is not repeated); where the speed jumps at a key (in
//!   and out slopes differ, as in the paper's Unity clips), the warning says
//!   which frames a 3 g vehicle would spend changing speed, how far from the
//!   keyed path it would be, those frames' share of the scenario and what
//!   to do.
//!
//! Refused before any check: a frame (1/fps) longer than the scenario
//! ([`crate::scene::scenario::check_frame_time`]).

use std::collections::BTreeMap;

use glam::{DMat4, DVec3, DVec4, dvec3};

use crate::error::{CaptureError, Result};
use crate::job::options::CaptureOptions;
use crate::scene::Scene;
use crate::scene::coincident;
use crate::scene::frame_state::{FrameState, list_frames};
use crate::scene::mesh::Mesh;
use crate::scene::moving::OccluderPath;
use crate::scene::rig::{Eye, Rig, vehicle_to_world};
use crate::scene::scenario::Scenario;
use crate::scene::track::{Track, ValueOrTrack};

/// Most frames in a scenario: 1,000,000 (4.6 h at 60 fps).
pub const MAX_FRAMES: f64 = 1.0e6;
/// Most tiles in one capture: 10 million (the paper's 50 a frame for 55 min at 60 fps).
pub const MAX_TILES: u64 = 10_000_000;
/// Fastest plausible road vehicle, m/s (360 km/h).
pub(crate) const MAX_SPEED_M_S: f64 = 100.0;
/// Hardest plausible acceleration or braking: 3 g.
pub(crate) const MAX_ACCELERATION_M_S2: f64 = 3.0 * 9.80665;

/// The frames of `scenario` the options select, after checking that the
/// scenario's frame count and the capture's tile count are bounded.
pub(crate) fn selected_frames(
    scene: &Scene,
    scenario: &Scenario,
    options: &CaptureOptions,
) -> Result<Vec<u32>> {
    let rig = &scene.rig;
    let frames = scenario.duration_s * rig.fps;
    if !(frames.is_finite() && frames < MAX_FRAMES) {
        return Err(CaptureError::BadOptions(format!(
            "scenario {}: {} s at {} fps is {frames:e} frames, more than the {MAX_FRAMES:e} a capture may have: \
             lower the rig's fps or the duration",
            scenario.name, scenario.duration_s, rig.fps
        )));
    }
    crate::scene::scenario::check_frame_time(scenario, rig.fps, "fps").map_err(CaptureError::BadOptions)?;
    let frame_count = rig.frame_count(scenario.duration_s);
    let selected = options.frames.frames(frame_count);
    if selected.is_empty() {
        return Err(CaptureError::BadOptions(format!(
            "no frame selected: scenario {} has frames 0-{}, and the frame selection names none of them",
            scenario.name,
            frame_count.saturating_sub(1)
        )));
    }
    let tiles = selected.len() as u64 * 2 * u64::from(rig.tiles[0]) * u64::from(rig.tiles[1]);
    if tiles > MAX_TILES {
        return Err(CaptureError::BadOptions(format!(
            "scenario {}: {} frames × 2 eyes × {}×{} tiles is {tiles} tiles, more than the {MAX_TILES} one capture \
             may have: select fewer frames (--frames) or use fewer tiles",
            scenario.name,
            selected.len(),
            rig.tiles[0],
            rig.tiles[1]
        )));
    }
    Ok(selected)
}

/// The impossible-scene checks over `frames`: the warnings, or an error
/// when an eye is inside the vehicle.
pub(crate) fn scene_warnings(scene: &Scene, scenario: &Scenario, frames: &[u32]) -> Result<Vec<String>> {
    let rig = &scene.rig;
    let mut found = ViewFindings::default();
    for &frame in frames {
        // The eyes where the (possibly walking) pedestrian is at this frame.
        let state = FrameState::at(scene, scenario, frame)?;
        let to_world = vehicle_to_world(&state.vehicle);
        let world: Vec<DVec3> =
            scene.vehicle.positions.iter().map(|p| to_world.transform_point3(p.as_dvec3())).collect();
        for (eye, camera) in Eye::BOTH.into_iter().zip(rig.cameras(state.time_s, &state.vehicle)) {
            found.look(&scene.vehicle, rig, frame, &world, &camera.view_proj);
            let local = to_world.inverse().transform_point3(camera.position);
            if inside_mesh(&scene.vehicle, local) {
                found.inside.push((frame, eye));
            }
            found.look_out_of_moving(scene, &state, camera.position);
        }
    }
    if !found.inside.is_empty() {
        let mut frames: Vec<u32> = found.inside.iter().map(|&(frame, _)| frame).collect();
        frames.dedup();
        let both = found.inside.iter().any(|&(_, eye)| eye == Eye::Left)
            && found.inside.iter().any(|&(_, eye)| eye == Eye::Right);
        let eyes = if both {
            "both eyes are".to_string()
        } else {
            format!("the {} eye is", found.inside[0].1.name())
        };
        return Err(CaptureError::BadOptions(format!(
            "scenario {}: {eyes} inside the vehicle in frames {} (pedestrian {:?} at frame {}, eye height {} m): \
             every count would be of the vehicle's inside; move the pedestrian or the vehicle's track",
            scenario.name,
            list_frames(&frames),
            FrameState::at(scene, scenario, frames[0])?.pedestrian.to_array(),
            frames[0],
            rig.eye_height_m
        )));
    }
    let mut warnings = found.warnings(rig);
    let vehicle = coincident::vehicle_index(&scene.vehicle);
    warnings.extend(coincident::occluder_warnings(scene, scenario, frames, &vehicle)?);
    warnings.extend(coincident::shared_surface_warnings(&scene.vehicle, &vehicle));
    if let Some((track, who)) = measured_track(scene, scenario) {
        warnings.extend(motion_warnings(rig, scenario, (track, &who)));
    }
    Ok(warnings)
}

/// What the views of the selected frames showed.
#[derive(Default)]
struct ViewFindings {
    near_cut: Vec<u32>,
    beyond_far: Vec<u32>,
    farthest_m: f64,
    inside: Vec<(u32, Eye)>,
    /// Per moving occluder (by name): the frames an eye is inside it.
    inside_moving: BTreeMap<String, Vec<u32>>,
}

impl ViewFindings {
    /// One eye's view of the vehicle (`world`: its vertices this frame).
    fn look(&mut self, mesh: &Mesh, rig: &Rig, frame: u32, world: &[DVec3], view_proj: &DMat4) {
        let clip: Vec<DVec4> = world.iter().map(|p| *view_proj * p.extend(1.0)).collect();
        // Depth along the view axis is clip w for this projection.
        let farthest = clip.iter().map(|c| c.w).fold(f64::NEG_INFINITY, f64::max);
        let nearest = clip.iter().map(|c| c.w).fold(f64::INFINITY, f64::min);
        let once = |frames: &mut Vec<u32>| {
            if frames.last() != Some(&frame) {
                frames.push(frame);
            }
        };
        if farthest > rig.far_m {
            once(&mut self.beyond_far);
            self.farthest_m = self.farthest_m.max(farthest);
        }
        if nearest < rig.near_m
            && mesh.triangles.iter().any(|t| near_plane_cuts(t.map(|i| clip[i as usize]), rig.near_m))
        {
            once(&mut self.near_cut);
        }
    }

    /// Whether the eye at `eye` (world) is inside a moving occluder this frame.
    fn look_out_of_moving(&mut self, scene: &Scene, state: &FrameState, eye: DVec3) {
        for (occluder, to_world) in scene.occluders.moving.iter().zip(state.moving_to_world()) {
            if inside_mesh(&occluder.mesh, to_world.inverse().transform_point3(eye)) {
                let frames = self.inside_moving.entry(occluder.name.clone()).or_default();
                if frames.last() != Some(&state.frame) {
                    frames.push(state.frame);
                }
            }
        }
    }

    fn warnings(&self, rig: &Rig) -> Vec<String> {
        let mut warnings = Vec::new();
        for (name, frames) in &self.inside_moving {
            warnings.push(format!(
                "an eye is inside the moving occluder {name} in frames {}: it hides the whole vehicle then; \
                 check its track (or follow offset) and the pedestrian's",
                list_frames(frames)
            ));
        }
        if !self.near_cut.is_empty() {
            warnings.push(format!(
                "the near plane ({} m) cuts the vehicle open in frames {}: those frames show (and count) its \
                 inside; keep the vehicle farther from the eyes or lower near_m",
                rig.near_m,
                list_frames(&self.near_cut)
            ));
        }
        if !self.beyond_far.is_empty() {
            warnings.push(format!(
                "the vehicle reaches beyond the far plane ({} m) in frames {} (up to {:.1} m away): what lies \
                 beyond is never drawn nor counted; raise far_m or bring the vehicle closer",
                rig.far_m,
                list_frames(&self.beyond_far),
                self.farthest_m
            ));
        }
        warnings
    }
}

/// True when the plane at depth `near` crosses the triangle (clip corners)
/// inside the view: the cut the renderer would show.
fn near_plane_cuts(corners: [DVec4; 3], near: f64) -> bool {
    let depth = corners.map(|c| c.w - near);
    if depth.iter().all(|&d| d > 0.0) || depth.iter().all(|&d| d < 0.0) {
        return false;
    }
    let mut ends = Vec::with_capacity(3);
    for (a, b) in [(0, 1), (1, 2), (2, 0)] {
        let (da, db) = (depth[a], depth[b]);
        if (da <= 0.0) != (db <= 0.0) || da == 0.0 {
            let s = if da == db { 0.0 } else { da / (da - db) };
            let point = corners[a] + (corners[b] - corners[a]) * s;
            ends.push(glam::dvec2(point.x / near, point.y / near));
        }
    }
    match ends[..] {
        [a] => a.x.abs() <= 1.0 && a.y.abs() <= 1.0,
        [a, b, ..] => segment_meets_square(a, b),
        [] => false,
    }
}

/// Liang–Barsky: does the segment a→b meet the square [-1, 1]²?
fn segment_meets_square(a: glam::DVec2, b: glam::DVec2) -> bool {
    let d = b - a;
    let (mut enter, mut leave) = (0.0_f64, 1.0_f64);
    for (p, q) in [(-d.x, a.x + 1.0), (d.x, 1.0 - a.x), (-d.y, a.y + 1.0), (d.y, 1.0 - a.y)] {
        if p == 0.0 {
            if q < 0.0 {
                return false;
            }
        } else {
            let r = q / p;
            if p < 0.0 {
                enter = enter.max(r);
            } else {
                leave = leave.min(r);
            }
        }
    }
    enter <= leave
}

/// Point-in-mesh by ray parity: inside when three rays in unrelated
/// directions all cross the surface an odd number of times (a mesh with
/// holes then gives no false alarm). The bounding box is the quick test.
pub(crate) fn inside_mesh(mesh: &Mesh, point: DVec3) -> bool {
    let (min, max) = mesh.bounds();
    if point.cmplt(min).any() || point.cmpgt(max).any() {
        return false;
    }
    let directions =
        [dvec3(0.5773, 0.5774, 0.5775), dvec3(-0.8017, 0.2673, 0.5345), dvec3(0.1, -0.97, -0.22)];
    directions.iter().all(|&direction| {
        let direction = direction.normalize();
        let crossings = (0..mesh.triangles.len())
            .filter(|&t| ray_hits(point, direction, mesh.corners(t).map(|c| c.as_dvec3())))
            .count();
        crossings % 2 == 1
    })
}

/// Does the ray from `origin` along `direction` cross the triangle (ahead of `origin`)?
/// The exact measure's Möller–Trumbore test, so both agree on what a crossing is.
fn ray_hits(origin: DVec3, direction: DVec3, corners: [DVec3; 3]) -> bool {
    let triangle = crate::scene::ray_triangle::StoredTriangle::from_corners(&corners);
    crate::scene::ray_triangle::ray_triangle_parameter(origin, direction, &triangle)
        .is_some_and(|along| along > 0.0)
}

/// Where on a position track a bound was broken.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
enum Place {
    /// At a key (its slopes differ on either side: the velocity jumps).
    Key(usize),
    /// Between keys: the number of the first key after (0 before the first,
    /// the key count after the last).
    Segment(usize),
}

/// The track the measured vehicle drives and how the warnings name it: the
/// scenario's, or, in the pass of another vehicle of a fleet
/// ([`Scene::measuring`]), that vehicle's own (`None`: it stands still). A
/// fleet's vehicles are named, so that each pass warns about its own
/// vehicle's motion, once, and not about the scene's vehicle again.
pub(crate) fn measured_track<'s>(scene: &'s Scene, scenario: &'s Scenario) -> Option<(&'s Track<3>, String)> {
    let name = scene.info.measured.as_ref().map(|measured| measured.name.as_str());
    match (&scene.vehicle_path, name) {
        (None, None) => Some((&scenario.motion.position, "the vehicle".to_string())),
        (None, Some(name)) => Some((&scenario.motion.position, format!("the vehicle {name}"))),
        (Some(OccluderPath::Follow(_)), name) => Some((
            &scenario.motion.position,
            format!("the vehicle {}, which follows the scenario's track,", name.unwrap_or("measured")),
        )),
        (Some(OccluderPath::Tracks { position: ValueOrTrack::Keys(track), .. }), name) => {
            Some((track, format!("the vehicle {} on its own track", name.unwrap_or("measured"))))
        }
        (Some(OccluderPath::Tracks { position: ValueOrTrack::Fixed(_), .. }), _) => None,
    }
}

/// Speeds and accelerations between consecutive frames (at the rig's fps,
/// every frame, not only the selected ones) beyond physical bounds, of
/// `track`, the measured vehicle's (`who` names it, see [`measured_track`]).
pub(crate) fn motion_warnings(
    rig: &Rig,
    scenario: &Scenario,
    (track, who): (&Track<3>, &str),
) -> Vec<String> {
    let count = rig.frame_count(scenario.duration_s);
    let at = |frame: u32| {
        let time_s = (f64::from(frame) / rig.fps).min(scenario.duration_s);
        (time_s, DVec3::from(track.eval(time_s)))
    };
    let mut too_fast: BTreeMap<Place, f64> = BTreeMap::new();
    let mut too_hard: BTreeMap<Place, f64> = BTreeMap::new();
    let record = |found: &mut BTreeMap<Place, f64>, place: Place, value: f64| {
        let entry = found.entry(place).or_default();
        *entry = entry.max(value);
    };
    let mut before: Option<(f64, DVec3)> = None;
    let mut current = at(0);
    for frame in 1..count {
        let next = at(frame);
        let dt = next.0 - current.0;
        if dt > 0.0 {
            let speed = (next.1 - current.1).length() / dt;
            if speed > MAX_SPEED_M_S {
                record(&mut too_fast, Place::Segment(segment(track, current.0)), speed);
            }
            if let Some((t0, p0)) = before.filter(|&(t0, _)| current.0 > t0) {
                let previous_dt = current.0 - t0;
                let change = (next.1 - current.1) / dt - (current.1 - p0) / previous_dt;
                let acceleration = change.length() / ((dt + previous_dt) / 2.0);
                if acceleration > MAX_ACCELERATION_M_S2 {
                    record(&mut too_hard, place(track, t0, next.0, current.0), acceleration);
                }
            }
        }
        before = Some(current);
        current = next;
    }
    let mut warnings = Vec::new();
    if let Some(fastest) = too_fast.values().copied().reduce(f64::max) {
        warnings.push(format!(
            "scenario {}: {who} moves faster than {MAX_SPEED_M_S} m/s between frames (up to {fastest:.1} m/s) \
             at position {}: a mistyped or teleporting track?",
            scenario.name,
            list_places(track, &too_fast)
        ));
    }
    let (at_keys, between): (BTreeMap<Place, f64>, BTreeMap<Place, f64>) =
        too_hard.into_iter().partition(|(place, _)| matches!(place, Place::Key(_)));
    if let Some(hardest) = between.values().copied().reduce(f64::max) {
        warnings.push(format!(
            "scenario {}: {who} accelerates or brakes harder than 3 g ({MAX_ACCELERATION_M_S2:.2} m/s²) \
             between frames (up to {hardest:.1} m/s², {:.1} g) at position {}",
            scenario.name,
            hardest / G_M_S2,
            list_places(track, &between)
        ));
    }
    if !at_keys.is_empty() {
        warnings.push(speed_jump_warning(rig, scenario, (track, who), &at_keys));
    }
    warnings
}

/// Standard gravity, m/s².
const G_M_S2: f64 = 9.80665;

/// The speed jumps at position keys (`at_keys`: the accelerations between
/// frames there): how large, which frames even a 3 g vehicle would spend
/// changing speed that much and how far from this path it would be, how much
/// of the scenario those frames are, and what to do.
fn speed_jump_warning(
    rig: &Rig,
    scenario: &Scenario,
    (track, who): (&Track<3>, &str),
    at_keys: &BTreeMap<Place, f64>,
) -> String {
    let count = rig.frame_count(scenario.duration_s);
    let mut affected: Vec<u32> = Vec::new();
    let mut jumps = Vec::new();
    let mut farthest_m = 0.0_f64;
    for place in at_keys.keys() {
        let Place::Key(k) = *place else { continue };
        let (arriving, leaving) = track.slopes_at(k);
        let jump = (DVec3::from(leaving) - DVec3::from(arriving)).length();
        // Changing speed by `jump` at the bound takes `window` s, centred on
        // the key, and leaves the vehicle jump²/(8a) from the kinked path.
        let window = jump / MAX_ACCELERATION_M_S2;
        farthest_m = farthest_m.max(jump * window / 8.0);
        jumps.push(format!("{k} (t {:.3} s, {jump:.1} m/s)", track.keys[k].t));
        let first = ((track.keys[k].t - window / 2.0) * rig.fps).ceil().max(0.0) as u32;
        let last = (((track.keys[k].t + window / 2.0) * rig.fps).floor().max(0.0) as u32).min(count - 1);
        affected.extend(first..=last);
    }
    affected.sort_unstable();
    affected.dedup();
    // Each frame's weight: the vehicle's apparent size, 1 / distance² from the head.
    let weight = |frame: u32| {
        let time_s = (f64::from(frame) / rig.fps).min(scenario.duration_s);
        let distance = (DVec3::from(track.eval(time_s)) - rig.head_at(time_s)).length().max(1.0);
        1.0 / (distance * distance)
    };
    let total: f64 = (0..count).map(weight).sum();
    let share: f64 = affected.iter().map(|&frame| weight(frame)).sum::<f64>() / total;
    let hardest = at_keys.values().copied().fold(0.0, f64::max);
    let linear = if track.is_piecewise_linear() {
        " The keys are linear (no slopes, or each slope its segment's secant: Unity's Linear tangents): the \
         vehicle drives at constant speed from key to key, in Unity too."
    } else {
        ""
    };
    format!(
        "scenario {}: {who} accelerates or brakes harder than 3 g ({MAX_ACCELERATION_M_S2:.2} m/s²) between \
         frames (up to {hardest:.1} m/s², {:.0} g) where its speed jumps at position keys {}: the replay follows \
         the keys as Unity's AnimationCurve does (a cubic Hermite from the left key's out slope to the right \
         key's in slope), and the slopes on either side of these keys differ.{linear} Even a vehicle changing \
         speed at 3 g would be up to {farthest_m:.2} m from this path, in frames {} ({} of {count} frames: \
         {:.0} % of the time, about {:.0} % of the vehicle's apparent size summed over frames, a proxy of their \
         share of the result). To see how much that matters, compare with a capture of the other frames \
         (--frames) or with the keys smoothed (equal in and out slopes at each key).",
        scenario.name,
        hardest / G_M_S2,
        jumps.join(", "),
        list_frames(&affected),
        affected.len(),
        100.0 * affected.len() as f64 / f64::from(count),
        100.0 * share
    )
}

/// The key within `(from, to)` if there is one, else the segment of `time_s`.
fn place(track: &Track<3>, from: f64, to: f64, time_s: f64) -> Place {
    match track.keys.iter().position(|key| key.t > from && key.t < to) {
        Some(key) => Place::Key(key),
        None => Place::Segment(segment(track, time_s)),
    }
}

/// The number of the first key after `time_s` (0: before the first key,
/// the key count: after the last).
fn segment(track: &Track<3>, time_s: f64) -> usize {
    track.keys.partition_point(|key| key.t <= time_s)
}

/// "key 2 (t 1.500 s), keys 1–2 (t 1.300–2.300 s), after key 3 (t 3.000 s)".
fn list_places(track: &Track<3>, places: &BTreeMap<Place, f64>) -> String {
    let keys = &track.keys;
    let names: Vec<String> = places
        .keys()
        .map(|&place| match place {
            Place::Key(key) => format!("key {key} (t {:.3} s)", keys[key].t),
            Place::Segment(0) => format!("before key 0 (t {:.3} s)", keys[0].t),
            Place::Segment(r) if r >= keys.len() => format!("after key {} (t {:.3} s)", r - 1, keys[r - 1].t),
            Place::Segment(r) => format!("keys {}–{r} (t {:.3}–{:.3} s)", r - 1, keys[r - 1].t, keys[r].t),
        })
        .collect();
    names.join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{dvec2, vec3};

    #[test]
    fn parity_finds_points_inside_a_closed_box_only() {
        let mut mesh = Mesh::default();
        mesh.add_box(vec3(-2.0, -1.0, 0.0), vec3(2.0, 1.0, 2.0), [Some("body"); 6]);
        assert!(inside_mesh(&mesh, dvec3(0.3, 0.2, 1.0)));
        assert!(!inside_mesh(&mesh, dvec3(0.3, 0.2, 2.5)));
        // Open on top: no surface above, so no false alarm.
        let mut open = Mesh::default();
        open.add_box(
            vec3(-2.0, -1.0, 0.0),
            vec3(2.0, 1.0, 2.0),
            [Some("body"), Some("body"), Some("body"), Some("body"), None, Some("body")],
        );
        assert!(!inside_mesh(&open, dvec3(0.3, 0.2, 1.0)));
    }

    /// The demo truck standing at (10, 0, 0), seen from the origin, with `occluders`.
    fn truck_scene(occluders: &str, fps: f64, duration_s: f64) -> Result<Scene> {
        let text = format!(
            r#"{{"vehicle": {{"mesh": "demo"}}, "occluders": [{occluders}],
                "rig": {{"eye_pixels": [40, 40], "tiles": [1, 1], "fps": {fps}}},
                "scenarios": {{"S": {{"duration_s": {duration_s}, "position": [{{"t": 0, "value": [10, 0, 0]}}],
                                      "yaw_deg": [{{"t": 0, "value": 0}}]}}}}}}"#
        );
        Scene::parse(std::path::Path::new("scene.json"), text.as_bytes())
    }

    fn warnings_of(scene: &Scene) -> Vec<String> {
        scene_warnings(scene, &scene.scenarios[0], &[0, 30]).unwrap()
    }

    #[test]
    fn each_pass_of_a_fleet_warns_about_its_own_vehicles_motion_once() {
        // A measured van on its own track that jumps 330 m in 10 ms; the
        // scene's own vehicle stands still.
        let van = r#"{"vehicle": {"measure": "van", "model": {"body": "van"}, "yaw_deg": 180, "position": [
            {"t": 0, "value": [30, 8, 0]}, {"t": 0.5, "value": [30, 8, 0]},
            {"t": 0.51, "value": [-300, 8, 0]}, {"t": 1, "value": [-300, 8, 0]}]}}"#;
        let scene = truck_scene(van, 60.0, 1.0).unwrap();
        let motion = |w: &&String| w.contains("moves faster") || w.contains("harder than 3 g");
        let own: Vec<String> =
            warnings_of(&scene.measuring(0).unwrap()).into_iter().filter(|w| motion(&w)).collect();
        assert!(own.is_empty(), "the standing vehicle's pass warns of motion: {own:#?}");
        let pass = scene.measuring(1).unwrap();
        let warnings: Vec<String> = warnings_of(&pass).into_iter().filter(|w| motion(&w)).collect();
        assert!(!warnings.is_empty(), "the van's teleport is not warned about");
        for warning in &warnings {
            assert!(warning.contains("the vehicle van on its own track"), "{warning}");
        }
        let fast =
            warnings.iter().find(|w| w.contains("moves faster than 100 m/s")).expect("no speed warning");
        assert!(fast.contains("keys 1–2 (t 0.500–0.510 s)"), "{fast}");
    }

    #[test]
    fn an_occluder_lying_on_the_vehicle_is_named_with_its_parts_and_frames() {
        // The vehicle's own mesh as an occluder exactly where the vehicle is:
        // rendered, it hid 60 % of the truck (287.8 of 724.0 deg²·s), silently.
        for placed in [
            r#"{"vehicle": {"position": [10, 0, 0]}}"#,
            r#"{"vehicle": {"follow": {"ahead_m": 0, "left_m": 0, "yaw_deg": 0}}}"#,
        ] {
            let scene = truck_scene(placed, 60.0, 1.0).unwrap();
            let warnings = warnings_of(&scene);
            let found: Vec<&String> = warnings.iter().filter(|w| w.contains("lies on the vehicle")).collect();
            assert_eq!(found.len(), 1, "{placed}: {warnings:#?}");
            for needed in ["the occluder vehicle #0", "roof", "hood", "in frames 0, 30", "z-fighting"] {
                assert!(found[0].contains(needed), "{needed} missing: {}", found[0]);
            }
        }
        // Beside the vehicle, or through it 1 cm higher and turned by 1° (its
        // sides then leave the vehicle's planes too): no coincidence.
        let beside = truck_scene(r#"{"vehicle": {"position": [10, 4, 0]}}"#, 60.0, 1.0).unwrap();
        let through = r#"{"vehicle": {"position": [10, 0, 0.01], "yaw_deg": 1}}"#;
        let above = truck_scene(through, 60.0, 1.0).unwrap();
        for scene in [beside, above] {
            assert!(!warnings_of(&scene).iter().any(|w| w.contains("lies on the vehicle")));
        }
        // The demo intersection's ground touches the truck's tyres along an edge only.
        let ground = truck_scene(r#""demo_intersection""#, 60.0, 1.0).unwrap();
        assert!(!warnings_of(&ground).iter().any(|w| w.contains("lies on")), "{:#?}", warnings_of(&ground));
    }

    #[test]
    fn faces_shared_by_two_parts_are_named() {
        let mut scene = truck_scene("", 60.0, 1.0).unwrap();
        assert!(!warnings_of(&scene).iter().any(|w| w.contains("coincident faces")));
        // A badge made of the hood's own triangles.
        let hood = scene.vehicle.parts.iter().position(|p| p == "hood").unwrap() as u32;
        let hood_triangles: Vec<usize> =
            (0..scene.vehicle.triangles.len()).filter(|&t| scene.vehicle.triangle_part[t] == hood).collect();
        for t in hood_triangles {
            let [a, b, c] = scene.vehicle.corners(t);
            scene.vehicle.add_triangle("badge", a, b, c);
        }
        let warnings = warnings_of(&scene);
        let found: Vec<&String> = warnings.iter().filter(|w| w.contains("coincident faces")).collect();
        assert_eq!(found.len(), 1, "{warnings:#?}");
        assert!(found[0].contains("parts hood and badge lie on one another"), "{}", found[0]);
        assert!(found[0].contains("once (for hood)"), "{}", found[0]);
        let covered = crate::scene::coincident::covered_triangles(&scene.vehicle);
        let badge = scene.vehicle.parts.iter().position(|p| p == "badge").unwrap() as u32;
        for (t, &covered) in covered.iter().enumerate() {
            assert_eq!(covered, scene.vehicle.triangle_part[t] == badge, "triangle {t}");
        }
    }

    #[test]
    fn a_frame_longer_than_the_scenario_or_below_one_fps_is_refused_by_file_and_field() {
        // fps 0.001: one frame of 1000 s for a 3 s scenario; fps 0.5: 4 s.
        for (fps, needed) in [(0.001, "fps 0.001 is below 1"), (0.5, "fps 0.5 is below 1")] {
            let error = truck_scene("", fps, 3.0).unwrap_err().to_string();
            assert!(error.contains("scene.json") && error.contains(needed), "{error}");
        }
        // 2 fps for a 0.4 s scenario: a 0.5 s frame outlasts it.
        let error = truck_scene("", 2.0, 0.4).unwrap_err().to_string();
        assert!(error.contains("scene.json") && error.contains("rig.fps 2 makes one frame 0.5 s"), "{error}");
        // The same through a rig changed after loading (`--rig`): refused by the capture.
        let mut scene = truck_scene("", 60.0, 0.4).unwrap();
        scene.rig.fps = 2.0;
        let options = CaptureOptions::default();
        let error = selected_frames(&scene, &scene.scenarios[0], &options).unwrap_err().to_string();
        assert!(error.contains("fps 2 makes one frame 0.5 s"), "{error}");
        // A still scenario of 0 s is one frame, and 1 fps for 1 s is two.
        truck_scene("", 60.0, 0.0).unwrap();
        truck_scene("", 1.0, 1.0).unwrap();
    }

    #[test]
    fn a_speed_jump_at_a_key_names_the_frames_it_carries_and_what_to_do() {
        // Unity's Linear tangents: 5 m/s to 15 m/s at t = 1 s, a 10 m/s jump.
        let position = Track::new(vec![
            crate::scene::track::Key {
                t: 0.0,
                value: [0.0, 0.0, 0.0],
                in_slope: Some([5.0, 0.0, 0.0]),
                out_slope: Some([5.0, 0.0, 0.0]),
            },
            crate::scene::track::Key {
                t: 1.0,
                value: [5.0, 0.0, 0.0],
                in_slope: Some([5.0, 0.0, 0.0]),
                out_slope: Some([15.0, 0.0, 0.0]),
            },
            crate::scene::track::Key {
                t: 2.0,
                value: [20.0, 0.0, 0.0],
                in_slope: Some([15.0, 0.0, 0.0]),
                out_slope: Some([15.0, 0.0, 0.0]),
            },
        ])
        .unwrap();
        assert!(position.is_piecewise_linear());
        let yaw_deg = Track::new(vec![crate::scene::track::Key::linear(0.0, [0.0])]).unwrap();
        let scenario = Scenario {
            name: "J".into(),
            duration_s: 2.0,
            motion: crate::scene::track::Motion { position, yaw_deg },
        };
        let rig =
            Rig { pedestrian: crate::scene::track::ValueOrTrack::Fixed([10.0, 5.0, 0.0]), ..Rig::default() };
        let warnings = motion_warnings(&rig, &scenario, (&scenario.motion.position, "the vehicle"));
        assert_eq!(warnings.len(), 1, "{warnings:#?}");
        let warning = &warnings[0];
        // 10 m/s at 3 g takes 0.34 s: frames 50-70 at 60 fps, 0.42 m off the kinked path.
        for needed in [
            "keys 1 (t 1.000 s, 10.0 m/s)",
            "Linear tangents",
            "up to 0.42 m",
            "frames 50-70",
            "21 of 121 frames",
            "--frames",
        ] {
            assert!(warning.contains(needed), "{needed} missing: {warning}");
        }
    }

    #[test]
    fn segments_meet_the_square_or_not() {
        assert!(segment_meets_square(dvec2(-2.0, 0.0), dvec2(2.0, 0.0)));
        assert!(!segment_meets_square(dvec2(-2.0, 1.5), dvec2(2.0, 1.5)));
        assert!(!segment_meets_square(dvec2(1.5, 3.0), dvec2(3.0, 1.5)));
        assert_eq!(list_frames(&[0, 1, 2, 60, 120]), "0-2, 60, 120");
    }
}
