//! The archive's `manifest.json`: the contract with `ufcsr-analyze`.
//!
//! Built from what the capture knows (rig, scenario, unwrap, per-frame
//! records) and holding no timings, so the same capture always writes the
//! same manifest. Every frame record carries the vehicle's pose and each
//! eye's position and orientation ([`frame_pose`]), and the rig its
//! projection (`rig.eye_projection`), so that a third party can rebuild
//! every camera without the rig code.

use std::path::PathBuf;

use serde_json::{Map, Value, json};
use ufcsr::{Color, MANIFEST_SCHEMA, Manifest, PaletteRecord, TileEntry};

use crate::job::options::{CaptureOptions, TileTally};
use crate::scene::Scene;
use crate::scene::frame_state::FrameState;
use crate::scene::rig::{Eye, Rig, reversed_z_perspective};
use crate::scene::scenario::Scenario;
use crate::scene::track::Pose;
use crate::texture::pidt::PidtImage;
use crate::texture::uv_islands::{self as unwrap, Unwrapped};

/// The counters in the manifest's `capture` object that add up over the
/// shards of one capture (see [`crate::job::capture_shard`]); everything else in
/// it must agree between them.
pub const CAPTURE_TALLIES: [&str; 5] =
    ["tiles_rendered", "tiles_culled", "tiles_background_only", "pixels_scissored", "tiles_hidden"];

/// Everything the manifest describes.
pub struct ManifestParts<'a> {
    pub scene: &'a Scene,
    pub scenario: &'a Scenario,
    pub options: &'a CaptureOptions,
    pub palette: PaletteRecord,
    pub palette_size: [u32; 2],
    pub background_texel: Option<(u32, u32)>,
    pub background: Color,
    pub unwrapped: &'a Unwrapped,
    pub pidt: &'a PidtImage,
    pub tiles: Vec<TileEntry>,
    pub frame_records: Vec<Value>,
    pub tally: TileTally,
    /// False when the tiles were counted while rendering (`--count`) and never written.
    pub tiles_written: bool,
    /// What the capture warned about; written as `warnings` only when there is any.
    pub warnings: Vec<String>,
}

/// The eyes' projection, everything a camera needs beside its pose: a
/// symmetric rectilinear (pinhole) eye, principal point at the image centre,
/// square pixels.
pub fn eye_projection(rig: &Rig) -> Value {
    json!({
        "model": "rectilinear",
        "horizontal_fov_deg": rig.horizontal_fov_deg,
        "vertical_fov_deg": rig.vertical_fov_deg(),
        "eye_pixels": rig.eye_pixels,
        "principal_point_px": [f64::from(rig.eye_pixels[0]) / 2.0, f64::from(rig.eye_pixels[1]) / 2.0],
        "near_m": rig.near_m,
        "far_m": rig.far_m,
        "depth": "reversed Z: clip z = w at the near plane, 0 at the far plane",
    })
}

/// One frame's vehicle pose and each eye's position (world metres) and
/// orientation (unit `right`, `up`, `forward` in world coordinates: the
/// camera looks along `forward`, image x runs along `right`, image y up
/// along `up`), read back from the very view matrices the renderer and the
/// exact measure use.
pub fn frame_pose(rig: &Rig, time_s: f64, pose: &Pose) -> (Value, Value) {
    let aspect = f64::from(rig.eye_pixels[0]) / f64::from(rig.eye_pixels[1]);
    let projection =
        reversed_z_perspective(rig.vertical_fov_deg().to_radians(), aspect, rig.near_m, rig.far_m);
    let to_view = projection.inverse();
    let mut eyes = Map::new();
    for (eye, camera) in Eye::BOTH.into_iter().zip(rig.cameras(time_s, pose)) {
        let view = to_view * camera.view_proj;
        let axis = |row: usize, sign: f64| (view.row(row).truncate() * sign).normalize().to_array();
        eyes.insert(
            eye.name().into(),
            json!({
                "position": camera.position.to_array().map(round6),
                "right": axis(0, 1.0),
                "up": axis(1, 1.0),
                "forward": axis(2, -1.0),
            }),
        );
    }
    (pose_record(pose), Value::Object(eyes))
}

/// A pose as the manifest writes it: position (world metres) and yaw.
fn pose_record(pose: &Pose) -> Value {
    json!({"position": pose.position.to_array().map(round6), "yaw_deg": round6(pose.yaw_deg)})
}

/// A frame's manifest record — frame number, time, vehicle pose, each eye's
/// camera ([`frame_pose`]) and distance — shared by the rendered captures and
/// the exact measure, so both describe a frame alike. A scene with moving
/// occluders adds `occluders` (each one's name and pose: its own frame, as
/// in `scene.glb`, placed by `position` and `yaw_deg`); a walking
/// pedestrian adds `pedestrian` (the ground point, world metres).
pub fn frame_record(scene: &Scene, state: &FrameState) -> Map<String, Value> {
    let rig = &scene.rig;
    let (vehicle, eyes) = frame_pose(rig, state.time_s, &state.vehicle);
    let mut record = Map::new();
    record.insert("frame".into(), json!(state.frame));
    record.insert("time_s".into(), json!(round6(state.time_s)));
    record.insert("vehicle".into(), vehicle);
    record.insert("eyes".into(), eyes);
    record.insert("distance_m".into(), json!(round6(state.distance_m())));
    if rig.walks() {
        record.insert("pedestrian".into(), json!(state.pedestrian.to_array().map(round6)));
    }
    if !state.moving.is_empty() {
        let occluders = scene.occluders.moving.iter().zip(&state.moving).map(|(occluder, pose)| {
            let mut entry = json!({"name": occluder.name});
            if let (Value::Object(entry), Value::Object(pose)) = (&mut entry, pose_record(pose)) {
                entry.extend(pose);
            }
            entry
        });
        record.insert("occluders".into(), Value::Array(occluders.collect()));
    }
    record
}

/// Builds the manifest of a capture.
pub fn build_manifest(parts: ManifestParts) -> Manifest {
    let ManifestParts { scene, scenario, options, unwrapped, pidt, tally, .. } = parts;
    let rig = &scene.rig;
    let mut extra = Map::new();
    extra.insert("scenario".into(), json!({"name": scenario.name, "duration_s": scenario.duration_s}));
    extra.insert("frames".into(), Value::Array(parts.frame_records));
    extra.insert(
        "rig".into(),
        json!({
            "settings": rig,
            "vertical_fov_deg": round6(rig.vertical_fov_deg()),
            "pixels_per_degree": round6(rig.pixels_per_degree()),
            "tile_pixels": rig.tile_pixels(),
            "frame_count": rig.frame_count(scenario.duration_s),
            "eye_offset": "eyes at the head ± ipd/2 along the head's right; both look along the head's direction",
            "projection": "perspective, square pixels, reversed Z (Depth32Float)",
            "eye_projection": eye_projection(rig),
        }),
    );
    extra.insert("scene".into(), scene.info.clone());
    extra.insert("vehicle".into(), json!(crate::job::VEHICLE_FILE));
    extra.insert("occluders".into(), json!(crate::job::SCENE_FILE));
    extra.insert(
        "unwrap".into(),
        json!({
            "method": unwrapped.method,
            "labels": match &options.own_labels {
                None => json!("painted by part"),
                Some(own) => json!({"pidt": own.pidt, "parts": own.parts}),
            },
            "palette": parts.palette_size,
            "background_texel": parts.background_texel,
            "texels_per_m2": round6(unwrapped.texels_per_m2),
            "texel_size_mm": round6(1000.0 / unwrapped.texels_per_m2.sqrt()),
            "palette_share_used": round6(pidt.share()),
            "labelled_texels": pidt.labelled,
            "label_conflicts": pidt.conflicts,
            "triangles": scene.vehicle.triangles.len(),
            "vehicle_area_m2": round6(scene.vehicle.area()),
            // Surface per part, to turn the analyzer's per-part totals into
            // counts per square metre.
            "part_area_m2": scene
                .vehicle
                .parts
                .iter()
                .zip(unwrap::part_areas(&scene.vehicle))
                .map(|(name, area)| (name.clone(), json!(round6(area))))
                .collect::<Map<String, Value>>(),
        }),
    );
    let mut capture = json!({
        "tool": concat!("ufcsr-capture ", env!("CARGO_PKG_VERSION")),
        "tiles_rendered": tally.rendered + tally.resumed,
        "tiles_culled": tally.culled,
        "tiles_background_only": tally.background,
        // Left out without changing a tile: pixels outside the vehicle's
        // projected bounds (scissor) and tiles occluders hide.
        "pixels_scissored": tally.pixels_scissored,
        "tiles_hidden": tally.hidden,
    });
    if !parts.tiles_written {
        // The analyzer refuses to read tiles of such an archive (they do not
        // exist); the manifest still names them, as the results do.
        capture["tiles_written"] = json!(false);
    }
    extra.insert("capture".into(), capture);
    if !parts.warnings.is_empty() {
        // Impossible-scene and label warnings, for the analyzer and for readers of the archive.
        extra.insert("warnings".into(), json!(parts.warnings));
    }
    Manifest {
        schema: Some(MANIFEST_SCHEMA.into()),
        palette: Some(parts.palette),
        pidt: Some(PathBuf::from("pidt.png")),
        parts: Some(PathBuf::from("parts.csv")),
        background: Some(vec![parts.background]),
        tiles: parts.tiles,
        extra,
    }
}

/// Six decimals keep the manifest readable and stable across platforms.
pub fn round6(value: f64) -> f64 {
    (value * 1e6).round() / 1e6
}
