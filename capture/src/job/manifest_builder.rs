//! The archive's `manifest.json`: the contract with `ufcsr analyze`.
//!
//! Built from what the capture knows (rig, scenario, unwrap, per-frame
//! records) and holding no timings, so the same capture always writes the
//! same manifest. Every frame record carries the vehicle's pose and each
//! eye's position and orientation ([`frame_pose`]), and the rig its
//! projection (`rig.eye_projection`), so that a third party can rebuild
//! every camera without the rig code.

use std::collections::BTreeMap;
use std::path::PathBuf;

use ufcsr::{
    Color, Manifest, PaletteRecord, TileEntry, format::CaptureRecord, format::EyePose,
    format::EyeProjectionRecord, format::FrameEntry, format::LabelsRecord, format::OccluderPose,
    format::PaintedByPart, format::PedestrianSetting, format::PoseRecord, format::RigRecord,
    format::RigSettings, format::ScenarioRecord, format::TexelIds, format::TrackKey, format::UnwrapRecord,
};

use crate::job::options::{CaptureOptions, TileTally};
use crate::scene::Scene;
use crate::scene::frame_state::FrameState;
use crate::scene::rig::{Eye, Rig, reversed_z_perspective};
use crate::scene::scenario::Scenario;
use crate::scene::track::{Pose, ValueOrTrack};
use crate::texture::pidt::PidtImage;
use crate::texture::uv_islands::{self as unwrap, Unwrapped};

/// Everything the manifest describes.
pub(crate) struct ManifestParts<'a> {
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
    pub frame_records: Vec<FrameEntry>,
    pub tally: TileTally,
    /// Whether the tiles were written, or counted while rendering (`--count`, the exact
    /// measure) and never written.
    pub tile_files: TileFiles,
    /// What the capture warned about; written as `warnings` only when there is any.
    pub warnings: Vec<String>,
}

/// The eyes' projection, everything a camera needs beside its pose: a
/// symmetric rectilinear (pinhole) eye, principal point at the image centre,
/// square pixels.
pub(crate) fn eye_projection(rig: &Rig) -> EyeProjectionRecord {
    EyeProjectionRecord {
        model: "rectilinear".into(),
        horizontal_fov_deg: rig.horizontal_fov_deg,
        vertical_fov_deg: rig.vertical_fov_deg(),
        eye_pixels: rig.eye_pixels,
        principal_point_px: [f64::from(rig.eye_pixels[0]) / 2.0, f64::from(rig.eye_pixels[1]) / 2.0],
        near_m: rig.near_m,
        far_m: rig.far_m,
        depth: "reversed Z: clip z = w at the near plane, 0 at the far plane".into(),
    }
}

/// The rig's settings as the manifest records them: the scene file's rig fields.
pub(crate) fn rig_settings(rig: &Rig) -> RigSettings {
    let pedestrian = match &rig.pedestrian {
        ValueOrTrack::Fixed(point) => PedestrianSetting::Point(*point),
        ValueOrTrack::Keys(track) => PedestrianSetting::Walk(
            track
                .keys
                .iter()
                .map(|key| TrackKey {
                    t: key.t,
                    value: key.value,
                    in_slope: key.in_slope,
                    out_slope: key.out_slope,
                })
                .collect(),
        ),
    };
    RigSettings {
        eye_height_m: Some(rig.eye_height_m),
        eye_pixels: Some(rig.eye_pixels),
        far_m: Some(rig.far_m),
        fps: Some(rig.fps),
        horizontal_fov_deg: Some(rig.horizontal_fov_deg),
        ipd_m: Some(rig.ipd_m),
        look_at_vehicle: Some(rig.look_at_vehicle),
        near_m: Some(rig.near_m),
        pedestrian: Some(pedestrian),
        tiles: Some(rig.tiles),
    }
}

/// One frame's vehicle pose and each eye's position (world metres) and
/// orientation (unit `right`, `up`, `forward` in world coordinates: the
/// camera looks along `forward`, image x runs along `right`, image y up
/// along `up`), read back from the very view matrices the renderer and the
/// exact measure use.
pub(crate) fn frame_pose(rig: &Rig, time_s: f64, pose: &Pose) -> (PoseRecord, BTreeMap<String, EyePose>) {
    let aspect = f64::from(rig.eye_pixels[0]) / f64::from(rig.eye_pixels[1]);
    let projection =
        reversed_z_perspective(rig.vertical_fov_deg().to_radians(), aspect, rig.near_m, rig.far_m);
    let to_view = projection.inverse();
    let mut eyes = BTreeMap::new();
    for (eye, camera) in Eye::BOTH.into_iter().zip(rig.cameras(time_s, pose)) {
        let view = to_view * camera.view_proj;
        let axis = |row: usize, sign: f64| (view.row(row).truncate() * sign).normalize().to_array();
        eyes.insert(
            eye.name().into(),
            EyePose {
                position: camera.position.to_array().map(round6),
                right: axis(0, 1.0),
                up: axis(1, 1.0),
                forward: axis(2, -1.0),
            },
        );
    }
    (pose_record(pose), eyes)
}

/// A pose as the manifest writes it: position (world metres) and yaw.
fn pose_record(pose: &Pose) -> PoseRecord {
    PoseRecord { position: pose.position.to_array().map(round6), yaw_deg: round6(pose.yaw_deg) }
}

/// A frame's manifest record — frame number, time, vehicle pose, each eye's
/// camera ([`frame_pose`]) and distance — shared by the rendered captures and
/// the exact measure, so both describe a frame alike. A scene with moving
/// occluders adds `occluders` (each one's name and pose: its own frame, as
/// in `scene.glb`, placed by `position` and `yaw_deg`); a walking
/// pedestrian adds `pedestrian` (the ground point, world metres).
pub(crate) fn frame_record(scene: &Scene, state: &FrameState) -> FrameEntry {
    let rig = &scene.rig;
    let (vehicle, eyes) = frame_pose(rig, state.time_s, &state.vehicle);
    let occluders = (!state.moving.is_empty()).then(|| {
        let moving = scene.occluders.moving.iter().zip(&state.moving);
        moving
            .map(|(occluder, pose)| {
                let PoseRecord { position, yaw_deg } = pose_record(pose);
                OccluderPose { name: occluder.name.clone(), position, yaw_deg }
            })
            .collect()
    });
    FrameEntry {
        distance_m: Some(round6(state.distance_m())),
        eyes: Some(eyes),
        frame: state.frame,
        occluders,
        pedestrian: rig.walks().then(|| state.pedestrian.to_array().map(round6)),
        tiles_with_vehicle: None,
        time_s: Some(round6(state.time_s)),
        vehicle: Some(vehicle),
    }
}

/// The manifest's `rig`: the settings and what follows from them.
fn rig_record(rig: &Rig, scenario: &Scenario) -> RigRecord {
    RigRecord {
        eye_offset: Some(
            "eyes at the head ± ipd/2 along the head's right; both look along the head's direction".into(),
        ),
        eye_projection: Some(eye_projection(rig)),
        frame_count: Some(rig.frame_count(scenario.duration_s).into()),
        pixels_per_degree: Some(round6(rig.pixels_per_degree())),
        projection: Some("perspective, square pixels, reversed Z (Depth32Float)".into()),
        settings: rig_settings(rig),
        tile_pixels: Some(rig.tile_pixels()),
        vertical_fov_deg: Some(round6(rig.vertical_fov_deg())),
    }
}

/// The manifest's `unwrap`: how the vehicle was laid into the palette.
fn unwrap_record(parts: &ManifestParts) -> UnwrapRecord {
    let ManifestParts { scene, options, unwrapped, pidt, .. } = parts;
    UnwrapRecord {
        method: unwrapped.method.into(),
        labels: match &options.own_labels {
            None => LabelsRecord::Painted(PaintedByPart::PaintedByPart),
            Some(own) => LabelsRecord::Own { pidt: own.pidt.clone(), parts: own.parts.clone() },
        },
        palette: parts.palette_size,
        background_texel: parts.background_texel.map(|(x, y)| [x, y]),
        texels_per_m2: round6(unwrapped.texels_per_m2),
        texel_size_mm: (unwrapped.texels_per_m2 > 0.0)
            .then(|| round6(1000.0 / unwrapped.texels_per_m2.sqrt())),
        palette_share_used: round6(pidt.share()),
        labelled_texels: pidt.labelled,
        label_conflicts: pidt.conflicts,
        triangles: scene.vehicle.triangles.len() as u64,
        vehicle_area_m2: round6(scene.vehicle.area()),
        // Surface per part, to turn the analyzer's per-part totals into
        // counts per square metre.
        part_area_m2: scene
            .vehicle
            .parts
            .iter()
            .zip(unwrap::part_areas(&scene.vehicle))
            .map(|(name, area)| (name.clone(), round6(area)))
            .collect(),
    }
}

/// Whether a capture's tiles were written as PNG files.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum TileFiles {
    /// Written: the analyzer can read them.
    Written,
    /// Counted while rendering (`--count`) or measured another way, never written.
    NotWritten,
}

/// The manifest's `capture`: the tool and what it left out.
fn capture_record(tally: &TileTally, tiles: TileFiles) -> CaptureRecord {
    CaptureRecord {
        tool: concat!("ufcsr-capture ", env!("CARGO_PKG_VERSION")).into(),
        tiles_rendered: tally.rendered + tally.resumed,
        tiles_culled: tally.culled,
        tiles_background_only: tally.background,
        // Left out without changing a tile: pixels outside the vehicle's
        // projected bounds (scissor) and tiles occluders hide.
        pixels_scissored: Some(tally.pixels_scissored),
        tiles_hidden: Some(tally.hidden),
        // The analyzer refuses to read tiles of such an archive (they do not
        // exist); the manifest still names them, as the results do.
        tiles_written: (tiles == TileFiles::NotWritten).then_some(false),
        shard: None,
    }
}

/// Builds the manifest of a capture.
pub(crate) fn build_manifest(parts: ManifestParts) -> Manifest {
    let unwrap = unwrap_record(&parts);
    let ManifestParts { scene, scenario, tally, .. } = parts;
    // A canonical palette above 2^24 texels is drawn with 32-bit texel ids.
    let texel_ids = match &parts.palette {
        PaletteRecord::Canonical { canonical: [width, height] }
            if u64::from(*width) * u64::from(*height) > ufcsr::COLOR_COUNT as u64 =>
        {
            TexelIds::Rgba32
        }
        _ => TexelIds::Rgb24,
    };
    Manifest {
        schema: Some(texel_ids.schema().into()),
        palette: Some(parts.palette),
        pidt: Some(PathBuf::from("pidt.png")),
        parts: Some(PathBuf::from("parts.csv")),
        background: Some(vec![parts.background]),
        tiles: parts.tiles,
        capture: Some(capture_record(&tally, parts.tile_files)),
        frames: Some(parts.frame_records),
        generator: None,
        occluders: Some(crate::job::SCENE_FILE.into()),
        rig: Some(rig_record(&scene.rig, scenario)),
        scenario: Some(ScenarioRecord { name: scenario.name.clone(), duration_s: scenario.duration_s }),
        scene: Some(scene.info.clone()),
        texel_ids: (texel_ids == TexelIds::Rgba32).then_some(texel_ids),
        unwrap: Some(unwrap),
        vehicle: Some(crate::job::VEHICLE_FILE.into()),
        // Impossible-scene and label warnings, for the analyzer and for readers of the archive.
        warnings: parts.warnings,
    }
}

/// Six decimals keep the manifest readable and stable across platforms.
pub(crate) fn round6(value: f64) -> f64 {
    (value * 1e6).round() / 1e6
}
