//! One frame of a capture: both eyes, every tile, into a [`TileSink`].
//!
//! A tile the vehicle's projected bounding box does not touch is neither
//! rendered nor handed on, only listed as empty; in a tile it touches, only
//! the rectangle it covers is rendered and read back (the scissor), the rest
//! is background by construction; where occluders hide the vehicle's box
//! (an occlusion query after drawing them), the vehicle is not drawn at all. A rendered tile that comes
//! out pure background (the vehicle is hidden) is listed as empty too unless
//! background tiles are kept. Occluder objects outside a tile's frustum are
//! not drawn; moving occluders are placed at the frame's poses and culled
//! by their placed bounding boxes the same way. The loop knows nothing of files: the sink decides what a tile
//! becomes.

use glam::{DMat4, DVec3};
use std::collections::BTreeMap;

use ufcsr::{Color, TileEntry, format::FrameEntry};

use crate::error::Result;
use crate::job::manifest_builder::round6;
use crate::job::options::TileTally;
use crate::job::tile_sink::{RenderedTile, TileAddress, TileSink};
use crate::render::scissor::{EyeBounds, background_tile, fill_tile};
use crate::render::{PixelRect, Renderer, TileDraw};
use crate::scene::Scene;
use crate::scene::frame_state::FrameState;
use crate::scene::rig::{Eye, EyeCamera, Rig, box_corners, box_outside, vehicle_to_world};
use crate::scene::scenario::Scenario;

/// Everything a frame needs that does not change from frame to frame.
pub(crate) struct FrameCapture<'a> {
    pub device: &'a wgpu::Device,
    pub queue: &'a wgpu::Queue,
    pub renderer: &'a Renderer,
    pub scene: &'a Scene,
    pub scenario: &'a Scenario,
    pub background: Color,
    /// Render every tile, even those outside the vehicle's projected bounds.
    pub no_cull: bool,
    /// Render whole tiles (no scissor, no hidden-tile skip).
    pub no_scissor: bool,
    /// Hand pure-background tiles to the sink too.
    pub keep_background_tiles: bool,
    /// The vehicle's bounding box corners in the vehicle frame.
    pub vehicle_box: [DVec3; 8],
}

/// What one frame produced.
pub(crate) struct CapturedFrame {
    /// One manifest entry per tile, in archive order (eye, row, column).
    pub entries: Vec<TileEntry>,
    /// The frame's record for the manifest's `frames` list.
    pub record: FrameEntry,
    pub tally: TileTally,
}

impl<'a> FrameCapture<'a> {
    /// The vehicle box for `scene`.
    pub(crate) fn vehicle_box(scene: &Scene) -> [DVec3; 8] {
        let (min, max) = scene.vehicle.bounds();
        box_corners(min, max)
    }

    fn rig(&self) -> &Rig {
        &self.scene.rig
    }

    /// Renders `frame` for both eyes; `first_index` is the archive position of
    /// its first tile. `on_tile` is called once per tile (for progress).
    pub(crate) fn capture(
        &self,
        frame: u32,
        first_index: usize,
        sink: &mut dyn TileSink,
        on_tile: &dyn Fn(),
    ) -> Result<CapturedFrame> {
        let rig = self.rig();
        let state = FrameState::at(self.scene, self.scenario, frame)?;
        let (time_s, pose, distance_m) = (state.time_s, state.vehicle, state.distance_m());
        let to_world = vehicle_to_world(&pose);
        let world_box = self.vehicle_box.map(|c| to_world.transform_point3(c));
        let moving = MovingFrame::new(self.scene, &state);
        let mut entries = Vec::new();
        let mut tally = TileTally::default();
        let mut tiles_with_vehicle = BTreeMap::new();
        for (eye, camera) in Eye::BOTH.into_iter().zip(rig.cameras(time_s, &pose)) {
            let touched = if self.no_cull { rig.all_tiles() } else { rig.tiles_touched(&camera, &world_box) };
            let bounds = if self.no_scissor {
                EyeBounds::Unbounded
            } else {
                EyeBounds::project(rig, &camera, &world_box)
            };
            let test_hidden = !self.no_scissor && wholly_in_front(rig, &camera, &world_box);
            let mut with_vehicle = 0u64;
            let tile_pixels = PixelRect::whole(self.renderer.tile_size()).pixels();
            for tile in rig.all_tiles() {
                on_tile();
                let address = TileAddress { frame, eye, row: tile.row, col: tile.col };
                let mut entry = tile_entry(&address, time_s, distance_m);
                let index = first_index + entries.len();
                let shows_vehicle = if !touched.contains(&tile) {
                    tally.culled += 1;
                    false
                } else if sink.is_done(&address) {
                    tally.resumed += 1;
                    // Counted as if rendered, so a resumed capture's manifest is the same.
                    tally.pixels_scissored += scissored_pixels(tile_pixels, bounds.region(rig, tile));
                    true
                } else {
                    let clip_from_world = rig.tile_matrix(tile) * camera.view_proj;
                    let job = TileJob { address, index, region: bounds.region(rig, tile), test_hidden };
                    let transforms = TileTransforms { clip_from_world, to_world, moving: &moving };
                    self.render_into(sink, job, transforms, &mut tally)?
                };
                if shows_vehicle {
                    with_vehicle += 1;
                    entry.file = Some(address.file());
                    entry.empty = false;
                }
                entries.push(entry);
            }
            tiles_with_vehicle.insert(eye.name().into(), with_vehicle);
        }
        let mut record = crate::job::manifest_builder::frame_record(self.scene, &state);
        record.tiles_with_vehicle = Some(tiles_with_vehicle);
        Ok(CapturedFrame { entries, record, tally })
    }

    /// Renders the `region` of one tile the vehicle may cover (see
    /// [`crate::render::scissor`]) and hands the tile, the rest filled with the
    /// background, to the sink unless it is pure background (and those are
    /// not kept). Returns whether the sink took it.
    fn render_into(
        &self,
        sink: &mut dyn TileSink,
        TileJob { address, index, region, test_hidden }: TileJob,
        TileTransforms { clip_from_world, to_world, moving }: TileTransforms,
        tally: &mut TileTally,
    ) -> Result<bool> {
        let size = self.renderer.tile_size();
        let tile_pixels = PixelRect::whole(size).pixels();
        let pixels = match region {
            // The bounds touch the tile only within the culling's slack:
            // outside the vehicle's projected bounds, so culled.
            None => {
                tally.culled += 1;
                Vec::new()
            }
            Some(region) => {
                let visible: Vec<usize> = self
                    .scene
                    .occluders
                    .objects
                    .iter()
                    .enumerate()
                    .filter(|(_, object)| {
                        !box_outside(&clip_from_world, &box_corners(object.min, object.max))
                    })
                    .map(|(i, _)| i)
                    .collect();
                let moving = moving.visible(&clip_from_world);
                let draw = TileDraw {
                    clip_from_vehicle: clip_from_world * to_world,
                    clip_from_world,
                    occluders: &visible,
                    moving: &moving,
                };
                // Only a tile with occluders in it can hide the vehicle.
                let pixels = if test_hidden && !(visible.is_empty() && moving.is_empty()) {
                    self.renderer.render_region_unless_hidden(self.device, self.queue, &draw, region)?
                } else {
                    Some(self.renderer.render_region(self.device, self.queue, &draw, region)?)
                };
                match pixels {
                    Some(pixels) => {
                        tally.rendered += 1;
                        pixels
                    }
                    None => {
                        tally.hidden += 1;
                        Vec::new()
                    }
                }
            }
        };
        tally.pixels_scissored += scissored_pixels(tile_pixels, region);
        let [r, g, b] = self.background.rgb();
        let all_background = pixels.chunks_exact(4).all(|p| p == [r, g, b, 255]);
        if all_background && !self.keep_background_tiles {
            // Only a rendered tile is "background only": a culled or hidden
            // one is already counted as such (the tally partitions the tiles).
            if !pixels.is_empty() {
                tally.background += 1;
            }
            return Ok(false);
        }
        let rgba = match region {
            // Not rendered (hidden): the tile is background.
            _ if pixels.is_empty() => background_tile(size, [r, g, b, 255]),
            Some(region) if region == PixelRect::whole(size) => pixels,
            Some(region) => fill_tile(size, [r, g, b, 255], region, &pixels),
            None => background_tile(size, [r, g, b, 255]),
        };
        sink.accept(RenderedTile { address, index, size, rgba })?;
        tally.written += 1;
        Ok(true)
    }
}

/// The moving occluders at one frame: each one's own frame → world and its
/// bounding box's corners in the world (for per-tile culling).
struct MovingFrame {
    placed: Vec<(DMat4, [DVec3; 8])>,
}

impl MovingFrame {
    fn new(scene: &Scene, state: &FrameState) -> MovingFrame {
        let placed = scene
            .occluders
            .moving
            .iter()
            .zip(state.moving_to_world())
            .map(|(occluder, to_world)| {
                let (min, max) = occluder.mesh.bounds();
                (to_world, box_corners(min, max).map(|c| to_world.transform_point3(c)))
            })
            .collect();
        MovingFrame { placed }
    }

    /// Those a tile's frustum may see, with their own frame → tile clip space.
    fn visible(&self, clip_from_world: &DMat4) -> Vec<(usize, DMat4)> {
        self.placed
            .iter()
            .enumerate()
            .filter(|(_, (_, corners))| !box_outside(clip_from_world, corners))
            .map(|(k, (to_world, _))| (k, *clip_from_world * *to_world))
            .collect()
    }
}

/// A tile's transforms: world and vehicle to clip, and the moving occluders.
struct TileTransforms<'m> {
    clip_from_world: DMat4,
    to_world: DMat4,
    moving: &'m MovingFrame,
}

/// One tile to render: where it goes and what may be left out.
struct TileJob {
    address: TileAddress,
    index: usize,
    /// The scissor rectangle; `None` when the vehicle covers no pixel of it.
    region: Option<PixelRect>,
    /// Whether the hidden-tile test may run (the vehicle box is wholly in
    /// front of the near plane, and leaving out is allowed).
    test_hidden: bool,
}

/// Metres the vehicle box must stay beyond the near plane for the hidden-tile
/// test: its grown box must not be clipped (it grows by centimetres).
const HIDDEN_TEST_NEAR_MARGIN_M: f64 = 1.0;

/// True when every corner of `corners` (world) is well in front of the
/// camera's near plane, so the occlusion test's box is never clipped.
fn wholly_in_front(rig: &Rig, camera: &EyeCamera, corners: &[DVec3; 8]) -> bool {
    corners.iter().all(|c| (camera.view_proj * c.extend(1.0)).w > rig.near_m + HIDDEN_TEST_NEAR_MARGIN_M)
}

/// Pixels of a tile outside its scissor `region` (all of them without one).
fn scissored_pixels(tile_pixels: u64, region: Option<PixelRect>) -> u64 {
    tile_pixels - region.map_or(0, |r| r.pixels())
}

/// The manifest entry of a tile, empty until the sink takes it.
fn tile_entry(address: &TileAddress, time_s: f64, distance_m: f64) -> TileEntry {
    TileEntry {
        file: None,
        frame: address.frame,
        eye: address.eye.name().into(),
        row: address.row,
        col: address.col,
        empty: true,
        distance_m: Some(round6(distance_m)),
        time_s: Some(round6(time_s)),
    }
}
