//! `manifest.json`, the archive's contract: what a capture wrote and how to
//! read it, section by section.
//!
//! `ufcsr capture` writes every section; `ufcsr manifest` writes what
//! is known of external frames; Unity or Blender users may write it by hand.
//! Only `tiles` is required: every other section is optional, but a section
//! that is present must be well-formed — a malformed one is an error naming
//! the file and the field ([`Manifest::parse`]), never a silent default.
//! Fields the analyzer does not know are ignored.
//!
//! The capture's sections are written in the order of their names (the
//! fields below are declared so), which is the order the manifests always
//! had: the same capture writes the same bytes.

use std::borrow::Cow;
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Component, Path, PathBuf};

use schemars::{JsonSchema, Schema, SchemaGenerator, json_schema};
use serde::{Deserialize, Deserializer, Serialize};

use crate::color::Color;
use crate::error::{Error, Result};
use crate::format::is_false;

/// File name of the manifest inside an archive folder.
pub const MANIFEST_FILE: &str = "manifest.json";

/// Schema string written by this version for the archives of 24-bit
/// texel ids (every archive of the paper, of Unity and of ufcsr before
/// 32-bit ids).
pub const MANIFEST_SCHEMA: &str = "ufcsr-manifest/1";

/// Schema string of an archive whose tiles carry 32-bit texel ids
/// (`"texel_ids": "rgba32"`): a new version, so that a ufcsr that knows only
/// `ufcsr-manifest/1` refuses it instead of reading the tiles' RGB alone.
pub const MANIFEST_SCHEMA_RGBA32: &str = "ufcsr-manifest/2";

/// How a tile's pixel names a texel (`manifest.json`'s `texel_ids`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum TexelIds {
    /// The paper's: the pixel's 24-bit RGB colour (alpha ignored), at most
    /// 2^24 texels. What a manifest without `texel_ids` means.
    #[default]
    Rgb24,
    /// 32-bit ids in RGBA tiles: id = (255 − alpha) × 2^24 + 0xRRGGBB, so an
    /// opaque pixel is the 24-bit id of its colour. For canonical palettes of
    /// more than 2^24 texels (at most 2^26, `MAX_RGBA32_TEXELS`); needs
    /// schema `ufcsr-manifest/2`.
    Rgba32,
}

impl TexelIds {
    /// The manifest schema string an archive of these ids is written with.
    pub fn schema(self) -> &'static str {
        match self {
            TexelIds::Rgb24 => MANIFEST_SCHEMA,
            TexelIds::Rgba32 => MANIFEST_SCHEMA_RGBA32,
        }
    }

    /// Its name, as the manifest writes it.
    pub fn name(self) -> &'static str {
        match self {
            TexelIds::Rgb24 => "rgb24",
            TexelIds::Rgba32 => "rgba32",
        }
    }
}

/// ufcsr archive manifest (`ufcsr-manifest/1`): `manifest.json` of an
/// archive, written by ufcsr capture, by `ufcsr manifest` or by hand
/// (Unity, Blender, scripts/manifest-from-tiles.py). Paths are relative to
/// the archive folder. Only `tiles` is required; fields the analyzer does not
/// know are ignored, so the top level and each tile stay open; the sections
/// ufcsr capture writes have a fixed form and are closed. Checked by the
/// analyzer and not expressible here: a tile position (frame, eye, row, col)
/// and a file are listed once each; at most two distinct eyes. Field-by-field
/// prose: docs/archive-format.md. Generated from the types in
/// src/format/manifest.rs.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize, JsonSchema)]
#[schemars(
    title = "ufcsr archive manifest (ufcsr-manifest/1)",
    extend(
        "allOf" = [
            {
                "description": "ufcsr-manifest/2 is the version of 32-bit texel ids.",
                "if": {"required": ["schema"], "properties": {"schema": {"const": MANIFEST_SCHEMA_RGBA32}}},
                "then": {"required": ["texel_ids"], "properties": {"texel_ids": {"const": "rgba32"}}}
            },
            {
                "description": "32-bit texel ids need ufcsr-manifest/2 when a schema is given.",
                "if": {"required": ["schema", "texel_ids"], "properties": {"texel_ids": {"const": "rgba32"}}},
                "then": {"properties": {"schema": {"const": MANIFEST_SCHEMA_RGBA32}}}
            }
        ],
        "if" = {"required": ["capture"]},
        "then" = {
            "description": "A manifest of ufcsr capture records its whole rig.",
            "properties": {"rig": {
                "required": ["settings", "vertical_fov_deg", "pixels_per_degree", "tile_pixels", "frame_count",
                    "eye_offset", "projection"],
                "properties": {"settings": {"required": ["pedestrian", "eye_height_m", "ipd_m",
                    "horizontal_fov_deg", "eye_pixels", "tiles", "fps", "near_m", "far_m", "look_at_vehicle"]}}
            }}
        }
    )
)]
pub struct Manifest {
    /// Schema version, `ufcsr-manifest/1`. Absent in some hand-written
    /// manifests; any other value is refused.
    #[serde(default)]
    #[schemars(with = "Option<ManifestVersion>")]
    pub schema: Option<String>,
    /// The palette the vehicle was rendered with: the canonical W×H palette,
    /// or the relative path of a palette PNG.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub palette: Option<PaletteRecord>,
    /// Part Identification Texture, the palette's size.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(with = "Option<RelativePath>")]
    pub pidt: Option<PathBuf>,
    /// The PIdT's legend: CSV name,color or JSON [{name, color}].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(with = "Option<RelativePath>")]
    pub parts: Option<PathBuf>,
    /// Colours that are not the vehicle (default #000FFF).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(with = "Option<Vec<ColorText>>")]
    pub background: Option<Vec<Color>>,
    /// Every tile of the capture, written or known to be empty.
    pub tiles: Vec<TileEntry>,
    /// ufcsr capture: which tool wrote the archive and what it left out.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub capture: Option<CaptureRecord>,
    /// ufcsr capture (and `ufcsr manifest` given distances): one
    /// record per captured frame.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub frames: Option<Vec<FrameEntry>>,
    /// `ufcsr manifest VERSION` for a manifest it wrote.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub generator: Option<String>,
    /// ufcsr capture: the scene's occluders in world coordinates, glTF axes,
    /// one node per occluder (scene.glb). Static: one file for every frame.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(with = "Option<RelativePath>")]
    pub occluders: Option<PathBuf>,
    /// The rig as used and what follows from it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rig: Option<RigRecord>,
    /// ufcsr capture: the scenario captured.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scenario: Option<ScenarioRecord>,
    /// ufcsr capture: the scene, in words for people; its fields depend on
    /// the kind of scene (demo, unity, scene file).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scene: Option<SceneRecord>,
    /// How a tile's pixel names a texel: `rgb24` (the default: its 24-bit
    /// colour) or `rgba32` (32-bit ids, (255 − alpha) × 2^24 + 0xRRGGBB, for
    /// canonical palettes above 2^24 texels; schema `ufcsr-manifest/2`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub texel_ids: Option<TexelIds>,
    /// ufcsr capture: how the vehicle was laid into the palette.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub unwrap: Option<UnwrapRecord>,
    /// The vehicle as rendered, with its palette UVs and the palette as
    /// texture (vehicle.glb, glTF axes); heatmap.glb and the views come from it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(with = "Option<RelativePath>")]
    pub vehicle: Option<PathBuf>,
    /// ufcsr capture: impossible-scene and label warnings, for the analyzer
    /// and for readers of the archive; written only when there is any.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<String>,
}

/// Which palette a capture used, as `manifest.json` records it (the
/// palette itself, loaded, is [`crate::Fcsp`]; what an analysis is asked
/// for is [`crate::PaletteChoice`]).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(untagged)]
pub enum PaletteRecord {
    /// The canonical palette of the given `[width, height]`.
    Canonical {
        #[schemars(with = "[PaletteSide; 2]")]
        canonical: [u32; 2],
    },
    /// A palette image, relative to the archive folder.
    File(#[schemars(with = "RelativePath")] PathBuf),
}

/// One tile of one eye of one frame.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[schemars(extend(
    "if" = {"required": ["empty"], "properties": {"empty": {"const": true}}},
    "then" = {"not": {"required": ["file"]}},
    "else" = {"required": ["file"]}
))]
pub struct TileEntry {
    /// The PNG (relative path); absent when the tile was not written because
    /// nothing but background could be in it (then `empty` is true).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(with = "Option<RelativePath>")]
    pub file: Option<PathBuf>,
    /// Frame number, starting at 0; (frame, eye) is an eye-frame.
    pub frame: u32,
    /// Which eye: `"left"`/`"right"` (or any two names), or the numbers 0
    /// and 1 (kept as text).
    #[serde(deserialize_with = "eye_as_text")]
    #[schemars(with = "EyeName")]
    pub eye: String,
    /// Tile row, 0 = top.
    pub row: u32,
    /// Tile column, 0 = left.
    pub col: u32,
    /// True when the capture knew the tile is pure background and wrote no file.
    #[serde(default, skip_serializing_if = "is_false")]
    pub empty: bool,
    /// The vehicle's horizontal distance from the pedestrian at this frame.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(range(min = 0.0))]
    pub distance_m: Option<f64>,
    /// The frame's time, seconds.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub time_s: Option<f64>,
}

impl TileEntry {
    /// Where the tile is, for messages: `(frame 20, eye left, row 2, col 2)`.
    pub fn place(&self) -> String {
        format!("(frame {}, eye {}, row {}, col {})", self.frame, self.eye, self.row, self.col)
    }
}

fn eye_as_text<'de, D: Deserializer<'de>>(deserializer: D) -> std::result::Result<String, D::Error> {
    match serde_json::Value::deserialize(deserializer)? {
        serde_json::Value::String(text) => Ok(text),
        serde_json::Value::Number(number) => Ok(number.to_string()),
        other => Err(serde::de::Error::custom(format!("eye must be a string or a number, not {other}"))),
    }
}

/// PNG, --count and --measure archives all write frame, time_s, distance_m,
/// vehicle and eyes (with rig.eye_projection every camera can be rebuilt
/// without the rig code); tiles_with_vehicle only where tiles were rendered.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[schemars(deny_unknown_fields)]
pub struct FrameEntry {
    /// The vehicle's horizontal distance from the pedestrian, metres.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(range(min = 0.0))]
    pub distance_m: Option<f64>,
    /// Per eye name (left, right): where the eye is and where it looks,
    /// world coordinates (+Z up). The camera looks along forward; image x
    /// runs along right, image y along up.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub eyes: Option<BTreeMap<String, EyePose>>,
    /// Frame number.
    pub frame: u32,
    /// Scenes with moving occluders only: each one's pose at this frame, in
    /// the scene's order. Its triangles are in its own frame (scene.glb's
    /// node of the same name); world = position + the rotation by yaw_deg
    /// about +Z.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub occluders: Option<Vec<OccluderPose>>,
    /// A walking pedestrian only: the ground point under the eyes at this
    /// frame, world metres.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pedestrian: Option<[f64; 3]>,
    /// Per eye name: tiles that show the vehicle.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tiles_with_vehicle: Option<BTreeMap<String, u64>>,
    /// The frame's time, seconds.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(range(min = 0.0))]
    pub time_s: Option<f64>,
    /// The vehicle's pose.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub vehicle: Option<PoseRecord>,
}

/// A pose on the ground: position and heading.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[schemars(deny_unknown_fields)]
pub struct PoseRecord {
    /// World metres, +Z up.
    pub position: [f64; 3],
    /// Degrees counter-clockwise from +X, seen from above.
    pub yaw_deg: f64,
}

/// A moving occluder's pose at one frame.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[schemars(deny_unknown_fields)]
pub struct OccluderPose {
    /// The occluder's name (scene.glb's node).
    pub name: String,
    /// World metres, +Z up.
    pub position: [f64; 3],
    /// Degrees counter-clockwise from +X, seen from above.
    pub yaw_deg: f64,
}

/// Where one eye is and where it looks (world coordinates, unit axes).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[schemars(deny_unknown_fields)]
pub struct EyePose {
    /// Unit vector along the optical axis.
    pub forward: [f64; 3],
    /// World metres.
    pub position: [f64; 3],
    /// Unit vector: image x.
    pub right: [f64; 3],
    /// Unit vector: image y.
    pub up: [f64; 3],
}

/// The rig as used (settings) and what follows from it. ufcsr capture
/// writes every field; `ufcsr manifest` writes what is known of
/// external frames (settings.eye_pixels, settings.tiles, tile_pixels, and
/// with --fps/--fov/--rig the rest).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize, JsonSchema)]
#[schemars(deny_unknown_fields)]
pub struct RigRecord {
    /// How the two eyes sit on the head.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub eye_offset: Option<String>,
    /// The eyes' projection: a symmetric rectilinear (pinhole) eye, square
    /// pixels, principal point at the image centre. Each pixel's solid angle
    /// follows from it (docs/science.md).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub eye_projection: Option<EyeProjectionRecord>,
    /// Frames of the scenario at the rig's fps, the last one included.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub frame_count: Option<u64>,
    /// Pixels per degree at the image centre.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(range(min = 0.0))]
    pub pixels_per_degree: Option<f64>,
    /// The projection in words.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub projection: Option<String>,
    /// The scene file's rig fields (see docs/scene-file.md): all of them from
    /// ufcsr capture, those known for external frames.
    pub settings: RigSettings,
    /// Pixels of one tile, `[width, height]`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tile_pixels: Option<[u32; 2]>,
    /// Vertical field of view, degrees.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub vertical_fov_deg: Option<f64>,
}

/// The scene file's rig fields, each optional (docs/scene-file.md#rig).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize, JsonSchema)]
#[schemars(deny_unknown_fields)]
pub struct RigSettings {
    /// Eye height above the ground point, metres.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub eye_height_m: Option<f64>,
    /// Pixels of each eye image, `[width, height]`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub eye_pixels: Option<[u32; 2]>,
    /// Far clipping plane, metres.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(range(min = 0.0))]
    pub far_m: Option<f64>,
    /// Frames per second; the final frame is included.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(range(min = 0.0))]
    pub fps: Option<f64>,
    /// Horizontal field of view of each eye, degrees.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(range(min = 0.0, max = 180.0))]
    pub horizontal_fov_deg: Option<f64>,
    /// Distance between the two eyes, metres.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(range(min = 0.0))]
    pub ipd_m: Option<f64>,
    /// Point the head turns to, in the vehicle's own frame (x forward, y
    /// left, z up from the vehicle origin).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub look_at_vehicle: Option<[f64; 3]>,
    /// Near clipping plane, metres.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(range(min = 0.0))]
    pub near_m: Option<f64>,
    /// Where the pedestrian stands, or a walk.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pedestrian: Option<PedestrianSetting>,
    /// Tiles per eye, `[columns, rows]`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tiles: Option<[u32; 2]>,
}

/// The pedestrian's ground point (world metres): a point, or a walk.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(untagged)]
pub enum PedestrianSetting {
    /// Standing at `[x, y, z]`.
    Point([f64; 3]),
    /// Walking: track keys, as the vehicle's position (docs/scene-file.md).
    Walk(Vec<TrackKey>),
}

/// One key of a track of points.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[schemars(deny_unknown_fields)]
pub struct TrackKey {
    /// Slope arriving at the key (per second); absent for a linear key.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub in_slope: Option<[f64; 3]>,
    /// Slope leaving the key (per second); absent for a linear key.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub out_slope: Option<[f64; 3]>,
    /// Time in seconds.
    pub t: f64,
    /// The point at `t`.
    pub value: [f64; 3],
}

/// The eyes' projection, everything a camera needs beside its pose.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[schemars(deny_unknown_fields)]
pub struct EyeProjectionRecord {
    /// The depth convention in words.
    pub depth: String,
    /// Pixels of each eye image, `[width, height]`.
    pub eye_pixels: [u32; 2],
    /// Far clipping plane, metres.
    pub far_m: f64,
    /// Horizontal field of view, degrees.
    #[schemars(range(min = 0.0, max = 180.0))]
    pub horizontal_fov_deg: f64,
    /// `rectilinear`.
    pub model: String,
    /// Near clipping plane, metres.
    pub near_m: f64,
    /// The principal point, pixels from the image's top-left corner.
    pub principal_point_px: [f64; 2],
    /// Vertical field of view, degrees.
    #[schemars(range(min = 0.0, max = 180.0))]
    pub vertical_fov_deg: f64,
}

/// The scenario captured.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[schemars(deny_unknown_fields)]
pub struct ScenarioRecord {
    /// Seconds.
    #[schemars(range(min = 0.0))]
    pub duration_s: f64,
    /// The scenario's name.
    pub name: String,
}

/// A description of the scene for people; which fields are there depends on
/// the kind of scene (demo, unity, scene file).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct SceneRecord {
    /// The surroundings, in words.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub environment: Option<String>,
    /// A scene file: its path as given.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub file: Option<String>,
    /// A scene file: its moving occluders' names.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub moving_occluders: Option<Vec<String>>,
    /// A scene file that measures several vehicles: which one this archive
    /// measures (each has an archive of its own, `OUT/NAME`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub measured: Option<MeasuredRecord>,
    /// `demo`, `unity` or the scene file's name.
    pub name: String,
    /// A scene file: how many occluder objects it has.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub occluder_objects: Option<u64>,
    /// The demo: its scenarios and where the vehicle arrives from.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scenarios: Option<Vec<DemoScenario>>,
    /// A Unity export: its path as given.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub source: Option<String>,
    /// The demo with traffic: the other vehicle and how it follows.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub traffic: Option<TrafficRecord>,
    /// The vehicle, in words or as its mesh file.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub vehicle: Option<String>,
}

/// The vehicle an archive of a several-vehicle capture measures
/// (docs/scene-file.md#several-measured-vehicles).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[schemars(deny_unknown_fields)]
pub struct MeasuredRecord {
    /// Every vehicle the scene measures, in the scene file's order (the
    /// scene's `vehicle` first); each has its own archive `OUT/NAME`.
    pub fleet: Vec<String>,
    /// This archive's vehicle: its `measure` name.
    pub name: String,
    /// Where the scene file gives it: `vehicle` or `occluders[N]`.
    pub source: String,
}

/// One of the demo's scenarios.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct DemoScenario {
    /// Where the vehicle arrives from, in words.
    pub arrives: String,
    /// The scenario's name.
    pub name: String,
}

/// The demo's traffic: which, and where it follows the vehicle.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct TrafficRecord {
    /// The offset from the vehicle, in the vehicle's frame.
    pub follow: FollowRecord,
    /// The traffic's name.
    pub name: String,
}

/// An offset in a vehicle's frame.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct FollowRecord {
    /// Metres ahead.
    pub ahead_m: f64,
    /// Metres to the left.
    pub left_m: f64,
    /// Degrees counter-clockwise.
    pub yaw_deg: f64,
}

/// How the vehicle was laid into the palette.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[schemars(deny_unknown_fields)]
pub struct UnwrapRecord {
    /// `[x, y]` of the texel that holds the background colour, left out of
    /// the unwrap; null when no texel does.
    pub background_texel: Option<[u32; 2]>,
    /// Texels two parts claimed.
    pub label_conflicts: u64,
    /// Texels with a part.
    pub labelled_texels: u64,
    /// 'painted by part', or the own PIdT and legend given with --pidt/--parts.
    pub labels: LabelsRecord,
    /// The unwrap method.
    pub method: String,
    /// The palette, `[width, height]`.
    pub palette: [u32; 2],
    /// Share of the palette's texels the unwrap uses.
    #[schemars(range(min = 0.0, max = 1.0))]
    pub palette_share_used: f64,
    /// Surface per part, to turn per-part totals into counts per square metre.
    pub part_area_m2: BTreeMap<String, f64>,
    /// One texel's side, millimetres; null when no texel has an area (a
    /// palette too small for the surface gives 0 texels per square metre).
    #[schemars(range(min = 0.0))]
    pub texel_size_mm: Option<f64>,
    /// Texels per square metre of surface.
    #[schemars(range(min = 0.0))]
    pub texels_per_m2: f64,
    /// The vehicle's triangles.
    pub triangles: u64,
    /// The vehicle's surface, square metres.
    #[schemars(range(min = 0.0))]
    pub vehicle_area_m2: f64,
}

/// Where a capture's part labels came from.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(untagged)]
pub enum LabelsRecord {
    /// The capture painted each part of the vehicle.
    Painted(PaintedByPart),
    /// The user's own PIdT and legend (`--pidt`, `--parts`).
    Own {
        /// The legend as given.
        parts: PathBuf,
        /// The PIdT as given.
        pidt: PathBuf,
    },
}

/// `"painted by part"`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
pub enum PaintedByPart {
    /// The capture painted each part.
    #[serde(rename = "painted by part")]
    PaintedByPart,
}

/// Which tool wrote the archive and what it left out. Older archives lack
/// pixels_scissored and tiles_hidden.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize, JsonSchema)]
#[schemars(deny_unknown_fields)]
pub struct CaptureRecord {
    /// Pixels outside the vehicle's projected bounds (scissor), left out
    /// without changing a tile.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pixels_scissored: Option<u64>,
    /// Only in shards/manifest-I-of-N.json of a split capture; assemble removes it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shard: Option<ShardRecord>,
    /// Tiles left out as pure background.
    pub tiles_background_only: u64,
    /// Tiles left out as outside the vehicle's bounds.
    pub tiles_culled: u64,
    /// Tiles occluders hide, left out.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tiles_hidden: Option<u64>,
    /// Tiles rendered.
    pub tiles_rendered: u64,
    /// Present (false) when the tiles were counted while rendering (--count,
    /// --measure) and never written; the analyzer refuses to read their tiles.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(with = "Option<FalseOnly>")]
    pub tiles_written: Option<bool>,
    /// `ufcsr-capture VERSION` (the value the capture records).
    pub tool: String,
}

impl CaptureRecord {
    /// The counters that add up over the shards of one capture (everything
    /// else must agree between them), with `other`'s added.
    pub fn add_tallies(&mut self, other: &CaptureRecord) {
        let sum = |a: Option<u64>, b: Option<u64>| Some(a.unwrap_or(0) + b.unwrap_or(0));
        self.tiles_rendered += other.tiles_rendered;
        self.tiles_culled += other.tiles_culled;
        self.tiles_background_only += other.tiles_background_only;
        self.pixels_scissored = sum(self.pixels_scissored, other.pixels_scissored);
        self.tiles_hidden = sum(self.tiles_hidden, other.tiles_hidden);
    }

    /// The record without its tallies and shard: what the shards of one
    /// capture share.
    pub fn without_tallies(&self) -> CaptureRecord {
        CaptureRecord {
            tool: self.tool.clone(),
            tiles_written: self.tiles_written,
            ..CaptureRecord::default()
        }
    }
}

/// A shard's part of a split capture: which shard it is, the frames the
/// whole capture selected and how many tiles this shard listed.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[schemars(deny_unknown_fields)]
pub struct ShardRecord {
    /// How many shards, 1 or more.
    #[schemars(range(min = 1))]
    pub count: u32,
    /// This shard, from 0.
    pub index: u32,
    /// Every frame the whole capture selected; assemble checks that each
    /// shard holds exactly its share.
    pub selected_frames: Vec<u32>,
    /// The tiles this shard listed; assemble refuses a part that lists others.
    pub tiles: u64,
}

impl Manifest {
    /// Parses and checks a manifest's bytes; `path` is only used in messages.
    pub fn parse(path: &Path, bytes: &[u8]) -> Result<Manifest> {
        let manifest: Manifest = crate::format::parse_json(path, bytes, "manifest")?;
        manifest.check(path)?;
        Ok(manifest)
    }

    /// Rejects manifests that would make the analysis ambiguous.
    fn check(&self, path: &Path) -> Result<()> {
        self.check_schema(path)?;
        self.check_eyes(path)?;
        self.check_tile_places(path)
    }

    /// `ufcsr-manifest/1` (24-bit ids) or `ufcsr-manifest/2` (`texel_ids`
    /// `rgba32`): a version must agree with the ids it declares.
    fn check_schema(&self, path: &Path) -> Result<()> {
        let Some(schema) = &self.schema else { return Ok(()) };
        if schema == MANIFEST_SCHEMA_RGBA32 {
            if self.texel_ids != Some(TexelIds::Rgba32) {
                return Err(Error::bad_file(
                    path,
                    format!(
                        "schema {schema:?} without \"texel_ids\": \"rgba32\": a version this ufcsr does not know \
                         ({schema} is the version of 32-bit texel ids)"
                    ),
                ));
            }
            return Ok(());
        }
        crate::format::check_version(path, schema, MANIFEST_SCHEMA)?;
        if self.texel_ids == Some(TexelIds::Rgba32) {
            return Err(Error::bad_file(
                path,
                format!(
                    "texel_ids \"rgba32\" needs schema {MANIFEST_SCHEMA_RGBA32:?}, not {schema:?} \
                     (a reader of {schema:?} would read the tiles' RGB alone)"
                ),
            ));
        }
        Ok(())
    }

    /// How the tiles' pixels name texels (`rgb24` when not said).
    pub fn texel_ids(&self) -> TexelIds {
        self.texel_ids.unwrap_or_default()
    }

    /// Two eyes: numbered 0 and 1, or two names (left/right, L/R...).
    fn check_eyes(&self, path: &Path) -> Result<()> {
        let mut eyes = BTreeSet::new();
        for (number, tile) in self.tiles.iter().enumerate() {
            let numeric = !tile.eye.is_empty()
                && tile.eye.bytes().all(|b| b.is_ascii_digit() || b == b'.' || b == b'-');
            if (numeric && tile.eye != "0" && tile.eye != "1") || tile.eye.is_empty() {
                return Err(Error::bad_file(
                    path,
                    format!(
                        "tiles[{number}]: eye {:?}: a pedestrian has two eyes, 0 and 1 (or left and right)",
                        tile.eye
                    ),
                ));
            }
            eyes.insert(tile.eye.as_str());
            if eyes.len() > 2 {
                return Err(Error::bad_file(
                    path,
                    format!(
                        "tiles[{number}]: a third eye {:?} besides {:?}: a pedestrian has two eyes",
                        tile.eye,
                        eyes.iter().filter(|e| **e != tile.eye).collect::<Vec<_>>()
                    ),
                ));
            }
        }
        Ok(())
    }

    /// Every tile has a file or is marked empty (not both), no place
    /// (frame, eye, row, col) or file is listed twice, and files stay inside
    /// the archive folder.
    fn check_tile_places(&self, path: &Path) -> Result<()> {
        let mut positions = BTreeSet::new();
        let mut files = BTreeSet::new();
        for (number, tile) in self.tiles.iter().enumerate() {
            let place = format!("tiles[{number}] {}", tile.place());
            match (&tile.file, tile.empty) {
                (None, false) => {
                    return Err(Error::bad_file(
                        path,
                        format!("{place} has no file and is not marked empty"),
                    ));
                }
                (Some(_), true) => {
                    return Err(Error::bad_file(path, format!("{place} names a file but is marked empty")));
                }
                _ => {}
            }
            if !positions.insert((tile.frame, tile.eye.clone(), tile.row, tile.col)) {
                return Err(Error::bad_file(path, format!("{place} is listed twice")));
            }
            if let Some(file) = &tile.file {
                check_tile_file(path, &place, file, &mut files)?;
            }
        }
        Ok(())
    }

    /// The frame records (none for a manifest without them).
    pub fn frame_records(&self) -> &[FrameEntry] {
        self.frames.as_deref().unwrap_or_default()
    }

    /// The rig's settings, when the manifest has a rig.
    pub fn rig_settings(&self) -> Option<&RigSettings> {
        self.rig.as_ref().map(|rig| &rig.settings)
    }

    /// False when the capture counted its tiles while rendering and never
    /// wrote them (`capture.tiles_written`); true otherwise.
    pub fn tiles_written(&self) -> bool {
        self.capture.as_ref().and_then(|capture| capture.tiles_written) != Some(false)
    }
}

/// A tile's file is a relative path inside the archive folder, listed once
/// (`./tiles/./x.png` is `tiles/x.png`; links are resolved by the archive
/// reader). `place` names the tile in messages.
fn check_tile_file(path: &Path, place: &str, file: &Path, files: &mut BTreeSet<PathBuf>) -> Result<()> {
    if file.is_absolute() || file.components().any(|c| matches!(c, Component::ParentDir)) {
        return Err(Error::bad_file(
            path,
            format!("{place}: file {} must be a path inside the archive folder", file.display()),
        ));
    }
    let lexical: PathBuf = file.components().filter(|c| !matches!(c, Component::CurDir)).collect();
    if !files.insert(lexical) {
        return Err(Error::bad_file(path, format!("{place}: file {} is listed twice", file.display())));
    }
    Ok(())
}

// Schema-only types: the JSON forms serde's types do not say by themselves.

/// `ufcsr-manifest/1`, or `ufcsr-manifest/2` with 32-bit texel ids.
struct ManifestVersion;

impl JsonSchema for ManifestVersion {
    fn schema_name() -> Cow<'static, str> {
        "ManifestVersion".into()
    }
    fn json_schema(_: &mut SchemaGenerator) -> Schema {
        json_schema!({ "enum": [MANIFEST_SCHEMA, MANIFEST_SCHEMA_RGBA32] })
    }
}

/// A path inside the archive folder.
struct RelativePath;

impl JsonSchema for RelativePath {
    fn schema_name() -> Cow<'static, str> {
        "RelativePath".into()
    }
    fn json_schema(_: &mut SchemaGenerator) -> Schema {
        json_schema!({
            "description": "A path inside the archive folder: not absolute, no '..' component.",
            "type": "string",
            "minLength": 1,
            "not": { "pattern": "(^/|(^|/)\\.\\.(/|$))" }
        })
    }
}

/// A colour as a manifest may give it.
struct ColorText;

impl JsonSchema for ColorText {
    fn schema_name() -> Cow<'static, str> {
        "ColorText".into()
    }
    fn json_schema(_: &mut SchemaGenerator) -> Schema {
        json_schema!({
            "description": "#RRGGBB (the '#' may be left out; either case).",
            "type": "string",
            "pattern": "^\\s*#?[0-9A-Fa-f]{6}\\s*$"
        })
    }
}

/// A tile's eye.
struct EyeName;

impl JsonSchema for EyeName {
    fn schema_name() -> Cow<'static, str> {
        "EyeName".into()
    }
    fn json_schema(_: &mut SchemaGenerator) -> Schema {
        json_schema!({
            "description": "'left'/'right' (or any two names), or the numbers 0 and 1.",
            "oneOf": [
                { "type": "string", "minLength": 1, "pattern": "^(0|1|.*[^0-9.\\-].*)$" },
                { "enum": [0, 1] }
            ]
        })
    }
}

/// A palette's side in texels.
struct PaletteSide;

impl JsonSchema for PaletteSide {
    fn schema_name() -> Cow<'static, str> {
        "PaletteSide".into()
    }
    fn json_schema(_: &mut SchemaGenerator) -> Schema {
        json_schema!({ "type": "integer", "minimum": 1, "maximum": 16_777_216 })
    }
}

/// `false`, the only value written.
struct FalseOnly;

impl JsonSchema for FalseOnly {
    fn schema_name() -> Cow<'static, str> {
        "FalseOnly".into()
    }
    fn inline_schema() -> bool {
        true
    }
    fn json_schema(_: &mut SchemaGenerator) -> Schema {
        json_schema!({ "const": false })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const EXAMPLE: &str = r##"{
        "schema": "ufcsr-manifest/1",
        "palette": {"canonical": [64, 64]},
        "pidt": "pidt.png",
        "parts": "parts.csv",
        "background": ["#000FFF"],
        "rig": {"settings": {"eye_height_m": 1.75}},
        "camera": "unity",
        "tiles": [
            {"file": "tiles/f0000_left_r0_c0.png", "frame": 0, "eye": "left", "row": 0, "col": 0, "time_s": 0.0},
            {"frame": 0, "eye": 1, "row": 0, "col": 0, "empty": true}
        ]
    }"##;

    fn parse(text: &str) -> Result<Manifest> {
        Manifest::parse(Path::new("m.json"), text.as_bytes())
    }

    #[test]
    fn parses_example_sections_and_ignores_unknown_fields() {
        let manifest = parse(EXAMPLE).unwrap();
        assert_eq!(manifest.palette, Some(PaletteRecord::Canonical { canonical: [64, 64] }));
        assert_eq!(manifest.tiles[1].eye, "1");
        assert!(manifest.tiles[1].empty);
        assert_eq!(manifest.rig_settings().and_then(|s| s.eye_height_m), Some(1.75));
        assert_eq!(manifest.tiles[0].time_s, Some(0.0));
        let again = serde_json::to_string(&manifest).unwrap();
        assert_eq!(parse(&again).unwrap(), manifest);
    }

    #[test]
    fn a_malformed_section_is_an_error_naming_the_file_and_the_field() {
        let text = EXAMPLE.replace(r#""eye_height_m": 1.75"#, r#""eye_height_m": "tall""#);
        let message = parse(&text).unwrap_err().to_string();
        assert!(message.contains("m.json") && message.contains("rig.settings.eye_height_m"), "{message}");
        let text = EXAMPLE.replace(r#""camera": "unity","#, r#""frames": [{"frame": "one"}],"#);
        let message = parse(&text).unwrap_err().to_string();
        assert!(message.contains("frames[0].frame"), "{message}");
    }
}
