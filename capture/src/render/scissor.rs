//! Which pixels of a tile the vehicle can cover: the scissor rectangle.
//!
//! The vehicle's bounding box, projected into an eye, bounds every pixel a
//! vehicle triangle can cover. Occluders are drawn in the background colour,
//! so every pixel outside that bound is background whatever is drawn there:
//! the renderer draws and reads back only the rectangle (grown by two pixels
//! for rounding) and the rest of the tile is filled with the background
//! without rendering. The tiles come out byte for byte as without it.

use glam::DVec3;

use crate::render::PixelRect;
use crate::scene::rig::{EyeCamera, Rig, TileId};

/// Pixels of slack on every side of the projected bounds: rasterisation
/// covers pixel centres inside a triangle, and the GPU's f32 transform differs
/// from this f64 one by far less than a pixel.
const SLACK_PIXELS: f64 = 2.0;

/// The vehicle's projected bounds in one eye.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum EyeBounds {
    /// The box reaches behind the camera: no bound, draw whole tiles.
    Unbounded,
    /// Eye-image pixel coordinates `[x0, y0, x1, y1]` (x right, y down), slack included.
    Pixels([f64; 4]),
}

impl EyeBounds {
    /// Projects the box `corners` (world) through `camera`.
    pub(crate) fn project(rig: &Rig, camera: &EyeCamera, corners: &[DVec3; 8]) -> EyeBounds {
        let [w, h] = rig.eye_pixels.map(f64::from);
        let mut bounds = [f64::INFINITY, f64::INFINITY, f64::NEG_INFINITY, f64::NEG_INFINITY];
        for corner in corners {
            let clip = camera.view_proj * corner.extend(1.0);
            // Same rule as the tile culling: near the eye plane the
            // projection is unreliable, so do not bound at all.
            if clip.w.is_nan() || clip.w < rig.near_m * 0.5 {
                return EyeBounds::Unbounded;
            }
            let x = (clip.x / clip.w + 1.0) / 2.0 * w;
            let y = (1.0 - clip.y / clip.w) / 2.0 * h;
            bounds = [bounds[0].min(x), bounds[1].min(y), bounds[2].max(x), bounds[3].max(y)];
        }
        if !bounds.iter().all(|b| b.is_finite()) {
            return EyeBounds::Unbounded;
        }
        EyeBounds::Pixels([
            bounds[0] - SLACK_PIXELS,
            bounds[1] - SLACK_PIXELS,
            bounds[2] + SLACK_PIXELS,
            bounds[3] + SLACK_PIXELS,
        ])
    }

    /// The part of `tile` the vehicle may cover (the whole tile when
    /// unbounded), or `None` when it covers none of it.
    pub(crate) fn region(&self, rig: &Rig, tile: TileId) -> Option<PixelRect> {
        let [tw, th] = rig.tile_pixels();
        let EyeBounds::Pixels([x0, y0, x1, y1]) = *self else {
            return Some(PixelRect::whole([tw, th]));
        };
        let (left, top) = (f64::from(tile.col * tw), f64::from(tile.row * th));
        let clamp = |v: f64, limit: u32| v.clamp(0.0, f64::from(limit)) as u32;
        let (ax, ay) = (clamp((x0 - left).floor(), tw), clamp((y0 - top).floor(), th));
        let (bx, by) = (clamp((x1 - left).ceil(), tw), clamp((y1 - top).ceil(), th));
        (bx > ax && by > ay).then_some(PixelRect { x: ax, y: ay, width: bx - ax, height: by - ay })
    }
}

/// A tile of `size` pixels all in the `background` colour (RGBA): one pixel
/// written, then the filled part copied onto the rest, doubling each time
/// (memcpy speed, not a byte at a time).
pub(crate) fn background_tile(size: [u32; 2], background: [u8; 4]) -> Vec<u8> {
    let [tw, th] = size.map(|v| v as usize);
    let total = tw * th * 4;
    let mut tile = vec![0u8; total];
    if total == 0 {
        return tile;
    }
    tile[..4].copy_from_slice(&background);
    let mut filled = 4;
    while filled < total {
        let step = filled.min(total - filled);
        tile.copy_within(..step, filled);
        filled += step;
    }
    tile
}

/// A full tile of `size` pixels in the background colour `rgba` with the
/// rendered `region` pixels (tightly packed rows) copied in.
pub(crate) fn fill_tile(size: [u32; 2], background: [u8; 4], region: PixelRect, pixels: &[u8]) -> Vec<u8> {
    let tw = size[0] as usize;
    let mut tile = background_tile(size, background);
    let row = region.width as usize * 4;
    for (y, source) in pixels.chunks_exact(row).enumerate() {
        let start = ((region.y as usize + y) * tw + region.x as usize) * 4;
        tile[start..start + row].copy_from_slice(source);
    }
    tile
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::track::Pose;
    use glam::dvec3;

    fn rig() -> Rig {
        Rig { eye_pixels: [200, 100], tiles: [2, 2], horizontal_fov_deg: 90.0, ..Rig::default() }
    }

    #[test]
    fn a_box_ahead_bounds_its_tiles_and_one_behind_does_not() {
        let rig = rig();
        let pose = Pose { position: dvec3(10.0, 0.0, 0.0), yaw_deg: 0.0 };
        let camera = rig.cameras(0.0, &pose)[0];
        let look = rig.look_target(&pose);
        let corners = crate::scene::rig::box_corners(look - DVec3::splat(0.5), look + DVec3::splat(0.5));
        let bounds = EyeBounds::project(&rig, &camera, &corners);
        let EyeBounds::Pixels([x0, y0, x1, y1]) = bounds else { panic!("{bounds:?}") };
        // A 1 m box 10 m ahead at the image centre: about 10 px wide at 90°/200 px.
        assert!(x0 > 80.0 && x1 < 120.0 && y0 > 30.0 && y1 < 70.0, "{bounds:?}");
        let regions: Vec<Option<PixelRect>> =
            rig.all_tiles().into_iter().map(|t| bounds.region(&rig, t)).collect();
        for region in regions.iter().flatten() {
            assert!(region.pixels() < 40 * 40, "{region:?}");
            assert!(region.x + region.width <= 100 && region.y + region.height <= 50);
        }
        assert!(regions.iter().all(Option::is_some), "the centre touches all four tiles");
        // Behind the eye: unbounded, whole tiles.
        let behind = crate::scene::rig::box_corners(dvec3(-20.0, -1.0, 0.0), dvec3(1.0, 1.0, 2.0));
        let unbounded = EyeBounds::project(&rig, &camera, &behind);
        assert_eq!(unbounded, EyeBounds::Unbounded);
        assert_eq!(unbounded.region(&rig, TileId { row: 1, col: 1 }), Some(PixelRect::whole([100, 50])));
        // Off to one side: no pixel of the far tiles.
        let side = EyeBounds::Pixels([-30.0, -30.0, 10.0, 10.0]);
        assert_eq!(side.region(&rig, TileId { row: 1, col: 1 }), None);
        assert_eq!(
            side.region(&rig, TileId { row: 0, col: 0 }),
            Some(PixelRect { x: 0, y: 0, width: 10, height: 10 })
        );
    }

    #[test]
    fn a_background_tile_is_the_color_repeated_for_any_size() {
        for size in [[0, 0], [1, 1], [3, 2], [7, 5], [512, 3]] {
            let color = [10, 20, 30, 255];
            let expected: Vec<u8> =
                color.iter().copied().cycle().take((size[0] * size[1] * 4) as usize).collect();
            assert_eq!(background_tile(size, color), expected, "{size:?}");
        }
    }

    #[test]
    fn filled_tiles_hold_the_region_in_place() {
        let region = PixelRect { x: 1, y: 1, width: 2, height: 1 };
        let tile = fill_tile([3, 2], [9, 9, 9, 255], region, &[1, 1, 1, 1, 2, 2, 2, 2]);
        let expected: Vec<u8> =
            [[9, 9, 9, 255], [9, 9, 9, 255], [9, 9, 9, 255], [9, 9, 9, 255], [1; 4], [2; 4]].concat();
        assert_eq!(tile, expected);
    }
}
