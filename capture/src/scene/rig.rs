//! The pedestrian rig: two eyes, their cameras, and the 5×5 tile split.
//!
//! World frame: right-handed, metres, +X east, +Y north, +Z up. The head sits
//! `eye_height_m` above the pedestrian's ground point and turns to the vehicle
//! every frame; both eyes look parallel along the head's direction, offset by
//! half the interpupillary distance to either side (as the Unity rig's two
//! child cameras do). Each eye is a symmetric perspective camera whose pixels
//! are square; each tile is rendered with an off-centre sub-frustum of that
//! camera, so the tiles join into exactly the image a single huge render
//! would give. Projections use reversed Z (near → 1, far → 0) so that a
//! 0.3 m near plane and 1000 m far plane keep depth precision where it matters.

use glam::{DMat4, DVec3, DVec4, dvec3, dvec4};
use serde::{Deserialize, Serialize};

use crate::error::{CaptureError, Result};
use crate::scene::track::{MAX_TRACK_MAGNITUDE, Pose, ValueOrTrack};

/// Largest interpupillary distance: a human's is 0.054–0.074 m; 1 m leaves
/// room for a stereo camera rig.
pub(crate) const MAX_IPD_M: f64 = 1.0;
/// Most frames per second: 1000 (high-speed video); beyond is a unit mistake.
pub(crate) const MAX_FPS: f64 = 1000.0;
/// Fewest frames per second: 1. Every frame stands for 1/fps seconds of the
/// time totals (exposure, angular area), the final frame included, so they
/// exceed the scenario's duration by one frame; slower than 1 fps that frame
/// is longer than a pedestrian's glance (fps 0.5 made a 3 s scene 4 s of
/// exposure, fps 0.001 made it 1000 s).
pub(crate) const MIN_FPS: f64 = 1.0;
/// Most pixels per degree: 1000 (an eye of 107,000 pixels, already beyond
/// any GPU's textures at a few tiles); the paper's is 60.
pub(crate) const MAX_PIXELS_PER_DEGREE: f64 = 1000.0;
/// Nearest near plane: a millimetre. Nearer, the reversed-Z depth of f32
/// loses the vehicle (a near plane of 1e-300 m rendered nothing, exit 0).
pub(crate) const MIN_NEAR_M: f64 = 1e-3;

/// Rig settings (the paper's defaults); every field can be overridden.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Rig {
    /// The pedestrian's ground point (world metres): a point, or a walk
    /// (track keys, as the vehicle's position).
    pub pedestrian: ValueOrTrack<3>,
    /// Eye height above the ground point.
    pub eye_height_m: f64,
    /// Distance between the two eyes.
    pub ipd_m: f64,
    /// Horizontal field of view of each eye, degrees.
    pub horizontal_fov_deg: f64,
    /// Pixels of each eye image, `[width, height]`; must divide into the tiles.
    pub eye_pixels: [u32; 2],
    /// Tiles per eye, `[columns, rows]`.
    pub tiles: [u32; 2],
    /// Frames per second; the final frame is included.
    pub fps: f64,
    /// Near and far clipping planes, metres.
    pub near_m: f64,
    pub far_m: f64,
    /// Point the head turns to, in the vehicle's own frame (x forward, y left,
    /// z up from the vehicle origin).
    pub look_at_vehicle: [f64; 3],
}

impl Default for Rig {
    fn default() -> Rig {
        Rig {
            pedestrian: ValueOrTrack::Fixed([0.0, 0.0, 0.0]),
            eye_height_m: 1.75,
            ipd_m: 0.1103594,
            horizontal_fov_deg: 107.0,
            eye_pixels: [6420, 8100],
            tiles: [5, 5],
            fps: 60.0,
            near_m: 0.3,
            far_m: 1000.0,
            look_at_vehicle: [0.0, 0.0, 0.0],
        }
    }
}

/// Which eye.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Eye {
    Left,
    Right,
}

impl Eye {
    pub const BOTH: [Eye; 2] = [Eye::Left, Eye::Right];

    /// `"left"` or `"right"`, as the manifest spells it.
    pub fn name(self) -> &'static str {
        match self {
            Eye::Left => "left",
            Eye::Right => "right",
        }
    }
}

/// One tile of one eye.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct TileId {
    pub row: u32,
    pub col: u32,
}

/// An eye's camera for one frame.
#[derive(Debug, Clone, Copy)]
pub struct EyeCamera {
    pub position: DVec3,
    /// World → clip for the whole eye image (reversed Z).
    pub view_proj: DMat4,
}

impl Rig {
    /// Overrides fields from a JSON object such as `{"eye_height_m": 1.6}`.
    pub fn override_with(&self, json: &str) -> Result<Rig> {
        let bad = |e: serde_json::Error| CaptureError::BadOptions(format!("--rig: {e}"));
        let changes: serde_json::Map<String, serde_json::Value> = serde_json::from_str(json).map_err(bad)?;
        let mut value = serde_json::to_value(self).map_err(bad)?;
        if let Some(fields) = value.as_object_mut() {
            fields.extend(changes);
        }
        let rig: Rig = serde_json::from_value(value).map_err(bad)?;
        rig.check().map_err(|e| CaptureError::BadOptions(format!("--rig: {e}")))?;
        Ok(rig)
    }

    /// Pixels per degree horizontally.
    pub fn pixels_per_degree(&self) -> f64 {
        f64::from(self.eye_pixels[0]) / self.horizontal_fov_deg
    }

    /// Sets the eye size for `ppd` pixels per degree over 107°×135° (the
    /// paper's 60 → 6420×8100), rounded to whole tiles.
    pub fn set_pixels_per_degree(&mut self, ppd: f64) -> Result<()> {
        if !(ppd.is_finite() && ppd > 0.0 && ppd <= MAX_PIXELS_PER_DEGREE) {
            return Err(CaptureError::BadOptions(format!(
                "--ppd {ppd} must be in (0, {MAX_PIXELS_PER_DEGREE}] pixels per degree (the paper's is 60)"
            )));
        }
        let aspect = 135.0 / 107.0;
        let round_to = |pixels: f64, tiles: u32| -> Option<u32> {
            let per_tile = (pixels / f64::from(tiles)).round().max(1.0) as u64;
            per_tile.checked_mul(u64::from(tiles)).and_then(|eye| u32::try_from(eye).ok())
        };
        let width = self.horizontal_fov_deg * ppd;
        match (round_to(width, self.tiles[0]), round_to(width * aspect, self.tiles[1])) {
            (Some(w), Some(h)) => self.eye_pixels = [w, h],
            _ => {
                return Err(CaptureError::BadOptions(format!(
                    "--ppd {ppd} with {:?} tiles: the eye image would have more than 2^32 pixels a side",
                    self.tiles
                )));
            }
        }
        Ok(())
    }

    /// Checks that the settings can be rendered.
    pub fn check(&self) -> Result<()> {
        let [w, h] = self.eye_pixels;
        let [nx, ny] = self.tiles;
        if nx == 0 || ny == 0 || w == 0 || h == 0 || w % nx != 0 || h % ny != 0 {
            return Err(CaptureError::BadOptions(format!(
                "eye image {w}×{h} does not split into {nx}×{ny} whole tiles"
            )));
        }
        if !(self.horizontal_fov_deg > 1.0 && self.horizontal_fov_deg < 179.0) {
            return Err(CaptureError::BadOptions("horizontal field of view must be in (1°, 179°)".into()));
        }
        if !(self.near_m >= MIN_NEAR_M && self.far_m > self.near_m) {
            return Err(CaptureError::BadOptions(format!(
                "near_m {:e} and far_m {:e}: need {MIN_NEAR_M} m ≤ near < far",
                self.near_m, self.far_m
            )));
        }
        if !(self.fps > 0.0 && self.fps.is_finite()) {
            return Err(CaptureError::BadOptions("fps must be positive".into()));
        }
        check_bounds(self)
    }

    /// Tile size in pixels.
    pub fn tile_pixels(&self) -> [u32; 2] {
        [self.eye_pixels[0] / self.tiles[0], self.eye_pixels[1] / self.tiles[1]]
    }

    /// Vertical field of view implied by square pixels, degrees.
    pub fn vertical_fov_deg(&self) -> f64 {
        let half = (self.horizontal_fov_deg.to_radians() / 2.0).tan();
        let ratio = f64::from(self.eye_pixels[1]) / f64::from(self.eye_pixels[0]);
        2.0 * (half * ratio).atan().to_degrees()
    }

    /// Frames for a scenario of `duration_s`, the final frame included.
    pub fn frame_count(&self, duration_s: f64) -> u32 {
        (duration_s * self.fps + 1e-6).floor() as u32 + 1
    }

    /// Where the pedestrian stands, or where their walk starts (its first
    /// key): the scene's anchor, relative to which the renderer and the
    /// exact measure keep their precision.
    pub fn anchor(&self) -> DVec3 {
        DVec3::from(match &self.pedestrian {
            ValueOrTrack::Fixed(point) => *point,
            ValueOrTrack::Keys(walk) => walk.keys.first().map_or([0.0; 3], |key| key.value),
        })
    }

    /// The head position at the anchor ([`Rig::anchor`]).
    pub fn head(&self) -> DVec3 {
        self.anchor() + dvec3(0.0, 0.0, self.eye_height_m)
    }

    /// True when the pedestrian walks (their position is a track).
    pub fn walks(&self) -> bool {
        self.pedestrian.keys().is_some()
    }

    /// The pedestrian's ground point at `time_s` (where they stand, or
    /// where their walk has taken them).
    pub fn pedestrian_at(&self, time_s: f64) -> DVec3 {
        DVec3::from(self.pedestrian.eval(time_s))
    }

    /// The head position at `time_s`.
    pub fn head_at(&self, time_s: f64) -> DVec3 {
        self.pedestrian_at(time_s) + dvec3(0.0, 0.0, self.eye_height_m)
    }

    /// The world point the head turns to for a vehicle pose.
    pub fn look_target(&self, pose: &Pose) -> DVec3 {
        vehicle_to_world(pose).transform_point3(DVec3::from(self.look_at_vehicle))
    }

    /// Both eye cameras at `time_s` (the head where the pedestrian is
    /// then) for a vehicle pose.
    pub fn cameras(&self, time_s: f64, pose: &Pose) -> [EyeCamera; 2] {
        let head = self.head_at(time_s);
        let mut forward = (self.look_target(pose) - head).normalize_or_zero();
        if forward.length_squared() == 0.0 {
            // The point looked at is the head itself (an eye inside the
            // vehicle, which the scene checks refuse): look along +X rather
            // than produce NaNs.
            forward = DVec3::X;
        }
        let up = image_up(forward);
        let right = forward.cross(up).normalize();
        let projection = reversed_z_perspective(
            self.vertical_fov_deg().to_radians(),
            f64::from(self.eye_pixels[0]) / f64::from(self.eye_pixels[1]),
            self.near_m,
            self.far_m,
        );
        Eye::BOTH.map(|eye| {
            let side = if eye == Eye::Left { -0.5 } else { 0.5 };
            let position = head + right * (side * self.ipd_m);
            let view = look_to(position, forward, up);
            EyeCamera { position, view_proj: projection * view }
        })
    }

    /// Clip-space transform that maps the rectangle of `tile` to the whole
    /// viewport (an off-centre sub-frustum of the eye camera).
    pub fn tile_matrix(&self, tile: TileId) -> DMat4 {
        let [nx, ny] = self.tiles.map(f64::from);
        let x_centre = -1.0 + (2.0 * f64::from(tile.col) + 1.0) / nx;
        let y_centre = 1.0 - (2.0 * f64::from(tile.row) + 1.0) / ny;
        DMat4::from_cols(
            dvec4(nx, 0.0, 0.0, 0.0),
            dvec4(0.0, ny, 0.0, 0.0),
            dvec4(0.0, 0.0, 1.0, 0.0),
            dvec4(-nx * x_centre, -ny * y_centre, 0.0, 1.0),
        )
    }

    /// Tiles that the projection of the box `corners` (world) may touch.
    /// Conservative: a box reaching behind the near plane touches every tile.
    pub fn tiles_touched(&self, camera: &EyeCamera, corners: &[DVec3; 8]) -> Vec<TileId> {
        let all = || self.all_tiles();
        let mut min = [f64::INFINITY; 2];
        let mut max = [f64::NEG_INFINITY; 2];
        for corner in corners {
            let clip = camera.view_proj * corner.extend(1.0);
            if clip.w < self.near_m * 0.5 {
                return all();
            }
            for axis in 0..2 {
                let ndc = clip[axis] / clip.w;
                min[axis] = min[axis].min(ndc);
                max[axis] = max[axis].max(ndc);
            }
        }
        // One pixel of slack for rasterisation at the edge of a tile.
        let slack = [2.0 / f64::from(self.eye_pixels[0]), 2.0 / f64::from(self.eye_pixels[1])];
        let [nx, ny] = self.tiles;
        let mut tiles = Vec::new();
        for row in 0..ny {
            let top = 1.0 - 2.0 * f64::from(row) / f64::from(ny);
            let bottom = top - 2.0 / f64::from(ny);
            if max[1] + slack[1] < bottom || min[1] - slack[1] > top {
                continue;
            }
            for col in 0..nx {
                let left = -1.0 + 2.0 * f64::from(col) / f64::from(nx);
                let right = left + 2.0 / f64::from(nx);
                if max[0] + slack[0] < left || min[0] - slack[0] > right {
                    continue;
                }
                tiles.push(TileId { row, col });
            }
        }
        tiles
    }

    /// Every tile, row by row.
    pub fn all_tiles(&self) -> Vec<TileId> {
        let [nx, ny] = self.tiles;
        (0..ny).flat_map(|row| (0..nx).map(move |col| TileId { row, col })).collect()
    }
}

/// The rig's values within physical bounds, with the tracks' street scale
/// ([`MAX_TRACK_MAGNITUDE`]) for positions and distances.
fn check_bounds(rig: &Rig) -> Result<()> {
    let bad = |message: String| Err(CaptureError::BadOptions(message));
    let huge = |v: f64| !(v.is_finite() && v.abs() <= MAX_TRACK_MAGNITUDE);

    let fixed = match &rig.pedestrian {
        ValueOrTrack::Keys(walk) => {
            walk.check().map_err(|e| CaptureError::BadOptions(format!("pedestrian (a walk): {e}")))?;
            None
        }
        ValueOrTrack::Fixed(point) => Some(("pedestrian", *point)),
    };
    for (field, values) in fixed.into_iter().chain([("look_at_vehicle", rig.look_at_vehicle)]) {
        if values.into_iter().any(huge) {
            return bad(format!(
                "{field} {values:?} is beyond ±{MAX_TRACK_MAGNITUDE:e} m: not a street scene"
            ));
        }
    }
    for (field, value) in [("eye_height_m", rig.eye_height_m), ("far_m", rig.far_m)] {
        if huge(value) {
            return bad(format!(
                "{field} {value:e} is beyond ±{MAX_TRACK_MAGNITUDE:e} m: not a street scene"
            ));
        }
    }
    if !(0.0..=MAX_IPD_M).contains(&rig.ipd_m) {
        return bad(format!(
            "ipd_m {} must be between 0 and {MAX_IPD_M} m (a human's is 0.054–0.074 m)",
            rig.ipd_m
        ));
    }
    if !(rig.fps > 0.0 && rig.fps <= MAX_FPS) {
        return bad(format!("fps {} must be in (0, {MAX_FPS}] frames per second", rig.fps));
    }
    if rig.fps < MIN_FPS {
        return bad(format!(
            "fps {} is below {MIN_FPS}: each frame stands for 1/fps = {} s of every time total (exposure, \
             angular area), far longer than a glance; use {MIN_FPS} to {MAX_FPS} frames per second",
            rig.fps,
            1.0 / rig.fps
        ));
    }
    Ok(())
}

/// Right-handed perspective (camera looks down −Z) with reversed depth:
/// the near plane maps to depth 1 and the far plane to 0.
pub fn reversed_z_perspective(vertical_fov: f64, aspect: f64, near: f64, far: f64) -> DMat4 {
    let f = 1.0 / (vertical_fov / 2.0).tan();
    let a = near / (far - near);
    DMat4::from_cols(
        dvec4(f / aspect, 0.0, 0.0, 0.0),
        dvec4(0.0, f, 0.0, 0.0),
        dvec4(0.0, 0.0, a, -1.0),
        dvec4(0.0, 0.0, a * far, 0.0),
    )
}

/// Within this angle of straight up or down (radians, squared sine), the
/// image's up is north instead of the world's up: 0.06°. Nearer, `forward ×
/// up` loses digits; the view then turns to north about the view axis, which
/// changes no solid angle.
const VERTICAL_VIEW_SIN2: f64 = 1e-6;

/// The image's up for a camera looking along `forward`: the world's +Z, or
/// +Y (north) when the view is within [`VERTICAL_VIEW_SIN2`] of vertical, so
/// that the camera basis is well defined for every direction (an eye looking
/// straight up at a plate overhead sees it in the middle of its image).
pub(crate) fn image_up(forward: DVec3) -> DVec3 {
    let f = forward.normalize_or_zero();
    if f.cross(DVec3::Z).length_squared() < VERTICAL_VIEW_SIN2 { DVec3::Y } else { DVec3::Z }
}

/// Right-handed view matrix of a camera at `eye` looking along `dir`; an
/// `up` parallel to `dir` is replaced by [`image_up`]'s.
pub fn look_to(eye: DVec3, dir: DVec3, up: DVec3) -> DMat4 {
    let f = dir.normalize();
    let up =
        if f.cross(up.normalize_or_zero()).length_squared() < VERTICAL_VIEW_SIN2 { image_up(f) } else { up };
    let r = f.cross(up).normalize();
    let u = r.cross(f);
    DMat4::from_cols(
        dvec4(r.x, u.x, -f.x, 0.0),
        dvec4(r.y, u.y, -f.y, 0.0),
        dvec4(r.z, u.z, -f.z, 0.0),
        dvec4(-r.dot(eye), -u.dot(eye), f.dot(eye), 1.0),
    )
}

/// Vehicle frame (x forward, y left, z up) → world, for a pose.
pub fn vehicle_to_world(pose: &Pose) -> DMat4 {
    DMat4::from_translation(pose.position) * DMat4::from_rotation_z(pose.yaw_deg.to_radians())
}

/// True when all `corners` (world) are outside one plane of the frustum
/// `clip_from_world` (reversed Z), so nothing of the box can be seen.
pub fn box_outside(clip_from_world: &DMat4, corners: &[DVec3; 8]) -> bool {
    let clips: Vec<DVec4> = corners.iter().map(|c| *clip_from_world * c.extend(1.0)).collect();
    let outside = |test: &dyn Fn(&DVec4) -> bool| clips.iter().all(test);
    outside(&|c| c.x > c.w)
        || outside(&|c| c.x < -c.w)
        || outside(&|c| c.y > c.w)
        || outside(&|c| c.y < -c.w)
        || outside(&|c| c.z < 0.0)
        || outside(&|c| c.z > c.w)
}

/// The 8 corners of an axis-aligned box.
pub fn box_corners(min: DVec3, max: DVec3) -> [DVec3; 8] {
    std::array::from_fn(|i| {
        dvec3(
            if i & 1 == 0 { min.x } else { max.x },
            if i & 2 == 0 { min.y } else { max.y },
            if i & 4 == 0 { min.z } else { max.z },
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paper_defaults_give_6420_by_8100_tiles_of_1284_by_1620() {
        let rig = Rig::default();
        rig.check().unwrap();
        assert_eq!(rig.tile_pixels(), [1284, 1620]);
        assert!((rig.pixels_per_degree() - 60.0).abs() < 1e-12);
        // The Unity rig's vertical field of view follows from square pixels.
        assert!((rig.vertical_fov_deg() - 119.2178).abs() < 1e-3, "{}", rig.vertical_fov_deg());
        assert_eq!(rig.frame_count(3.0), 181);
        let mut low = rig.clone();
        low.set_pixels_per_degree(2.0).unwrap();
        low.check().unwrap();
        assert_eq!(low.eye_pixels, [215, 270]);
    }

    #[test]
    fn rig_fields_can_be_overridden_from_json() {
        let rig = Rig::default()
            .override_with(r#"{"eye_height_m": 1.6, "tiles": [2, 2], "eye_pixels": [100, 120]}"#);
        let rig = rig.unwrap();
        assert_eq!((rig.eye_height_m, rig.tiles, rig.ipd_m), (1.6, [2, 2], 0.1103594));
        assert!(Rig::default().override_with(r#"{"eye_hieght_m": 1.6}"#).is_err());
        assert!(Rig::default().override_with(r#"{"tiles": [7, 7]}"#).is_err());
    }

    #[test]
    fn reversed_z_and_tiles_cover_the_eye_image() {
        let rig = Rig::default();
        let pose = Pose { position: dvec3(10.0, 0.0, 1.75), yaw_deg: 0.0 };
        let [left, right] = rig.cameras(0.0, &pose);
        assert!(left.position.y > right.position.y, "left eye is to the left (north) when looking east");
        assert!((left.position - right.position).length() - rig.ipd_m < 1e-12);
        let near = left.view_proj * dvec4(left.position.x + rig.near_m, left.position.y, 1.75, 1.0);
        let far = left.view_proj * dvec4(left.position.x + rig.far_m, left.position.y, 1.75, 1.0);
        assert!((near.z / near.w - 1.0).abs() < 1e-9 && (far.z / far.w).abs() < 1e-9);
        // The point looked at is the image centre: tile (2, 2) with 5×5 tiles.
        let target = left.view_proj * dvec4(10.0, left.position.y, 1.75, 1.0);
        let ndc = target / target.w;
        assert!(ndc.x.abs() < 1e-9 && ndc.y.abs() < 1e-9);
        let in_tile = rig.tile_matrix(TileId { row: 2, col: 2 }) * target;
        assert!((in_tile.x / in_tile.w).abs() < 1e-9);
        // The top-left corner of the eye image is the top-left of tile (0, 0).
        let corner = rig.tile_matrix(TileId { row: 0, col: 0 }) * dvec4(-1.0, 1.0, 0.5, 1.0);
        assert!((corner.x + 1.0).abs() < 1e-12 && (corner.y - 1.0).abs() < 1e-12);
        let corners = box_corners(dvec3(9.0, -1.0, 0.0), dvec3(11.0, 1.0, 2.0));
        let touched = rig.tiles_touched(&left, &corners);
        assert!(touched.contains(&TileId { row: 2, col: 2 }) && touched.len() < 25);
    }
}
