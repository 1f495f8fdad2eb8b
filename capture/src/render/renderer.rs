//! The renderer: one tile at a time, unlit, exact by construction.
//!
//! Every fragment's colour is the palette colour of the texel its UV falls in
//! (see `shader.wgsl`). The target is `Rgba8Unorm` (never sRGB, which would
//! re-encode the colours), one sample per pixel, no blending, no mipmaps,
//! cleared to the background colour. Depth is `Depth32Float` with reversed Z
//! (cleared to 0, `Greater` wins), so a 0.3 m near plane and a 1000 m far
//! plane keep sub-millimetre depth resolution at street distances.
//! Readback rows are padded to 256 bytes as wgpu requires and unpadded
//! ([`crate::render::target`]); the pipeline and palette are built once
//! ([`crate::render::pipeline`]). Getting a device is [`crate::render::gpu`]'s job:
//! the renderer only ever takes a device and queue it is given.

use glam::{DMat4, DVec3};
use ufcsr::Color;

use crate::error::{CaptureError, Result};
use crate::render::occlusion::OcclusionTest;
use crate::render::pipeline::{PalettePipeline, UNIFORM_STRIDE, Uniforms, draw_mode};
use crate::render::target::{PixelRect, TileTarget};
use crate::render::vertex::{GpuPalette, Vertex};
use crate::scene::occluders::Occluders;

/// Everything the renderer needs once.
pub struct RenderSetup<'a> {
    pub tile_size: [u32; 2],
    pub palette: &'a GpuPalette,
    pub background: Color,
    /// Vehicle triangles (three vertices each), in the vehicle frame.
    pub vehicle: &'a [Vertex],
    /// Occluders in world coordinates.
    pub occluders: &'a Occluders,
    /// Where the occluders are uploaded relative to (in f32): the
    /// pedestrian's head, so that precision is kept where the eyes are,
    /// however far the scene is from the world's origin.
    pub origin: DVec3,
}

/// What to draw in one tile.
pub struct TileDraw<'a> {
    /// Vehicle frame → tile clip space.
    pub clip_from_vehicle: DMat4,
    /// World → tile clip space (the renderer moves it to its origin).
    pub clip_from_world: DMat4,
    /// Indices into `Occluders::objects` that may be visible in the tile.
    pub occluders: &'a [usize],
    /// The moving occluders that may be visible in the tile: their index in
    /// `Occluders::moving` and their own frame → tile clip space.
    pub moving: &'a [(usize, DMat4)],
}

/// A GPU renderer of tiles: built once for a device and a setup, then
/// [`Renderer::render_tile`] per tile with the same device and queue.
pub struct Renderer {
    pipeline: PalettePipeline,
    geometry: Geometry,
    occlusion: OcclusionTest,
    target: TileTarget,
    palette: [u32; 2],
    background: Color,
    /// The occluders' origin (see [`RenderSetup::origin`]).
    origin: DVec3,
}

/// The uploaded vertices: the vehicle's, and the occluders'.
struct Geometry {
    vehicle: Option<(wgpu::Buffer, u32)>,
    occluders: OccluderGeometry,
}

/// The occluders' vertices with each object's vertex range, and the moving
/// occluders' vertices in their own frames.
struct OccluderGeometry {
    standing: Option<wgpu::Buffer>,
    /// `(first vertex, vertex count)` per occluder object.
    objects: Vec<(u32, u32)>,
    /// Each moving occluder's vertices in its own frame, and their count.
    moving: Vec<Option<(wgpu::Buffer, u32)>>,
}

/// Whether a render pass counts samples for the occlusion query (the bounds test of hidden tiles).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Occlusion {
    Counted,
    NotCounted,
}

impl OccluderGeometry {
    /// Uploads `occluders`, the standing ones relative to `origin` (see [`RenderSetup::origin`]).
    fn upload(device: &wgpu::Device, queue: &wgpu::Queue, occluders: &Occluders, origin: DVec3) -> Self {
        // Occluders carry a UV and chart but the background mode never reads them.
        let standing_vertices: Vec<Vertex> = occluders
            .positions
            .iter()
            .map(|p| Vertex {
                position: (*p - origin).as_vec3().to_array(),
                uv: [0.0, 0.0],
                chart: [[0.0; 2]; 3],
            })
            .collect();
        let standing = vertex_buffer(device, queue, "occluders", bytemuck::cast_slice(&standing_vertices));
        let objects = occluders.objects.iter().map(|o| (o.first_vertex, o.vertex_count)).collect();
        let moving = occluders
            .moving
            .iter()
            .map(|occluder| {
                let vertices: Vec<Vertex> = occluder
                    .mesh
                    .triangles
                    .iter()
                    .flat_map(|t| t.map(|i| occluder.mesh.positions[i as usize]))
                    .map(|p| Vertex { position: p.to_array(), uv: [0.0, 0.0], chart: [[0.0; 2]; 3] })
                    .collect();
                vertex_buffer(device, queue, "moving occluder", bytemuck::cast_slice(&vertices))
                    .map(|buffer| (buffer, vertices.len() as u32))
            })
            .collect();
        OccluderGeometry { standing, objects, moving }
    }
}

impl Geometry {
    fn upload(device: &wgpu::Device, queue: &wgpu::Queue, setup: &RenderSetup) -> Geometry {
        let vehicle = vertex_buffer(device, queue, "vehicle", bytemuck::cast_slice(setup.vehicle))
            .map(|b| (b, setup.vehicle.len() as u32));
        let occluders = OccluderGeometry::upload(device, queue, setup.occluders, setup.origin);
        Geometry { vehicle, occluders }
    }
}

fn to_f32(m: &DMat4) -> [[f32; 4]; 4] {
    m.as_mat4().to_cols_array_2d()
}

fn vertex_buffer(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    label: &str,
    bytes: &[u8],
) -> Option<wgpu::Buffer> {
    if bytes.is_empty() {
        return None;
    }
    let buffer = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: bytes.len() as u64,
        usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    queue.write_buffer(&buffer, 0, bytes);
    Some(buffer)
}

/// The most moving occluders a scene may have (a uniform block each: 256 kB).
pub(crate) const MAX_MOVING_OCCLUDERS: usize = 1000;

/// The tile and palette must fit the device's textures.
fn check_sizes(device: &wgpu::Device, setup: &RenderSetup) -> Result<()> {
    check_tile(device, setup.tile_size)?;
    let limit = device.limits().max_texture_dimension_2d;
    let [pw, ph] = setup.palette.size();
    if pw > limit || ph > limit {
        return Err(CaptureError::Gpu(format!(
            "palette {pw}×{ph} exceeds the device's texture limit {limit}"
        )));
    }
    // One uniform block per moving occluder, after the vehicle's and the world's.
    let moving = setup.occluders.moving.len();
    if moving > MAX_MOVING_OCCLUDERS {
        return Err(CaptureError::BadOptions(format!(
            "{moving} moving occluders: the renderer takes at most {MAX_MOVING_OCCLUDERS}"
        )));
    }
    Ok(())
}

/// A tile must be at least a pixel and fit the device's textures.
fn check_tile(device: &wgpu::Device, [width, height]: [u32; 2]) -> Result<()> {
    let limit = device.limits().max_texture_dimension_2d;
    if width == 0 || height == 0 || width > limit || height > limit {
        return Err(CaptureError::Gpu(format!(
            "tile {width}×{height} exceeds the device's texture limit {limit}"
        )));
    }
    Ok(())
}

impl Renderer {
    /// Builds the pipeline, uploads the palette and the geometry, and
    /// creates the tile's targets.
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue, setup: &RenderSetup) -> Result<Renderer> {
        check_sizes(device, setup)?;
        Ok(Renderer {
            pipeline: PalettePipeline::new(device, queue, setup.palette, setup.occluders.moving.len())?,
            geometry: Geometry::upload(device, queue, setup),
            occlusion: OcclusionTest::new(device, queue, setup.vehicle),
            target: TileTarget::new(device, setup.tile_size),
            palette: setup.palette.size(),
            background: setup.background,
            origin: setup.origin,
        })
    }

    /// Makes this renderer what [`Renderer::new`] would have built for
    /// `tile_size` tiles and `occluders` placed relative to `origin`, with the
    /// palette and vehicle it was built with: what changes between the
    /// captures of one scene in a study (the rig's resolution, the
    /// pedestrian). The pipeline, the palette texture and the vehicle stay
    /// uploaded; the tile's targets are made again when their size changes,
    /// and the occluders (a few thousand vertices) are uploaded again.
    /// `occluders` must have as many moving occluders as the renderer was
    /// built for (a uniform block each).
    pub fn retarget(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        tile_size: [u32; 2],
        origin: DVec3,
        occluders: &Occluders,
    ) -> Result<()> {
        check_tile(device, tile_size)?;
        if occluders.moving.len() != self.pipeline.moving_groups.len() {
            return Err(CaptureError::BadOptions(format!(
                "the renderer was built for {} moving occluders, not {}",
                self.pipeline.moving_groups.len(),
                occluders.moving.len()
            )));
        }
        if tile_size != self.target.size() {
            self.target = TileTarget::new(device, tile_size);
        }
        self.geometry.occluders = OccluderGeometry::upload(device, queue, occluders, origin);
        self.origin = origin;
        Ok(())
    }

    /// Tile size in pixels.
    pub fn tile_size(&self) -> [u32; 2] {
        self.target.size()
    }

    /// Renders one tile and returns its pixels, RGBA8, rows top to bottom.
    pub fn render_tile(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        draw: &TileDraw,
    ) -> Result<Vec<u8>> {
        self.render_region(device, queue, draw, PixelRect::whole(self.tile_size()))
    }

    /// Renders only `region` of a tile (a scissor rectangle; see
    /// [`crate::render::scissor`]) and returns that region's pixels, RGBA8, tightly
    /// packed rows top to bottom.
    pub fn render_region(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        draw: &TileDraw,
        region: PixelRect,
    ) -> Result<Vec<u8>> {
        self.check_region(region)?;
        self.write_uniforms(queue, draw);
        let mut encoder =
            device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("tile") });
        {
            let mut pass =
                self.begin_pass(&mut encoder, region, wgpu::LoadOp::Clear(()), Occlusion::NotCounted);
            self.draw_occluders(&mut pass, draw);
            self.draw_vehicle(&mut pass);
        }
        self.target.copy_to_readback(&mut encoder, region);
        queue.submit([encoder.finish()]);
        self.target.read_back(device, region)
    }

    /// [`Renderer::render_region`], unless the occluders hide the vehicle's
    /// bounding box in `region`: then `None`, and the vehicle is neither drawn
    /// nor read back (see `render_occlusion.rs`). The caller must know
    /// the box to be wholly in front of the near plane. The pixels are the
    /// same as `render_region`'s: the occluders are drawn first either way.
    pub fn render_region_unless_hidden(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        draw: &TileDraw,
        region: PixelRect,
    ) -> Result<Option<Vec<u8>>> {
        let Some(box_vertices) = &self.occlusion.box_vertices else {
            return self.render_region(device, queue, draw, region).map(Some);
        };
        self.check_region(region)?;
        self.write_uniforms(queue, draw);
        let mut encoder =
            device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("occluders") });
        {
            let mut pass = self.begin_pass(&mut encoder, region, wgpu::LoadOp::Clear(()), Occlusion::Counted);
            self.draw_occluders(&mut pass, draw);
            pass.set_pipeline(&self.pipeline.bounds_test);
            pass.set_bind_group(0, &self.pipeline.vehicle_group, &[]);
            pass.set_vertex_buffer(0, box_vertices.slice(..));
            pass.begin_occlusion_query(0);
            pass.draw(0..36, 0..1);
            pass.end_occlusion_query();
        }
        self.occlusion.resolve(&mut encoder);
        queue.submit([encoder.finish()]);
        if self.occlusion.samples(device)? == 0 {
            return Ok(None);
        }
        // Visible: draw the vehicle over the occluders already there.
        let mut encoder =
            device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("vehicle") });
        {
            let mut pass = self.begin_pass(&mut encoder, region, wgpu::LoadOp::Load, Occlusion::NotCounted);
            self.draw_vehicle(&mut pass);
        }
        self.target.copy_to_readback(&mut encoder, region);
        queue.submit([encoder.finish()]);
        self.target.read_back(device, region).map(Some)
    }

    fn check_region(&self, region: PixelRect) -> Result<()> {
        let [tw, th] = self.tile_size();
        if region.width == 0
            || region.height == 0
            || region.x + region.width > tw
            || region.y + region.height > th
        {
            return Err(CaptureError::Gpu(format!("region {region:?} is not inside the {tw}×{th} tile")));
        }
        Ok(())
    }

    /// The vehicle's and the world's transforms for this tile.
    fn write_uniforms(&self, queue: &wgpu::Queue, draw: &TileDraw) {
        let vehicle = Uniforms {
            clip_from_model: to_f32(&draw.clip_from_vehicle),
            palette: self.palette,
            mode: self.pipeline.mode,
            background: self.background.packed(),
        };
        // The occluders were uploaded relative to the origin: move it back in f64.
        let world = Uniforms {
            clip_from_model: to_f32(&(draw.clip_from_world * DMat4::from_translation(self.origin))),
            mode: draw_mode::BACKGROUND,
            ..vehicle
        };
        queue.write_buffer(&self.pipeline.uniforms, 0, bytemuck::bytes_of(&vehicle));
        queue.write_buffer(&self.pipeline.uniforms, UNIFORM_STRIDE, bytemuck::bytes_of(&world));
        // Moving occluders: own frame → clip, computed in f64 like the vehicle's.
        for &(k, clip_from_moving) in draw.moving {
            let uniforms = Uniforms { clip_from_model: to_f32(&clip_from_moving), ..world };
            let offset = UNIFORM_STRIDE * (2 + k as u64);
            queue.write_buffer(&self.pipeline.uniforms, offset, bytemuck::bytes_of(&uniforms));
        }
    }

    /// Begins the tile's render pass, scissored to `region`: colour and
    /// depth cleared (to the background and to "infinitely far") or loaded
    /// from the previous pass, with the occlusion query set when `query` counts.
    fn begin_pass<'e>(
        &'e self,
        encoder: &'e mut wgpu::CommandEncoder,
        region: PixelRect,
        load: wgpu::LoadOp<()>,
        query: Occlusion,
    ) -> wgpu::RenderPass<'e> {
        let [r, g, b] = self.background.rgb().map(|c| f64::from(c) / 255.0);
        let (color_load, depth_load) = match load {
            wgpu::LoadOp::Clear(()) => {
                (wgpu::LoadOp::Clear(wgpu::Color { r, g, b, a: 1.0 }), wgpu::LoadOp::Clear(0.0))
            }
            _ => (wgpu::LoadOp::Load, wgpu::LoadOp::Load),
        };
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("tile"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &self.target.color_view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations { load: color_load, store: wgpu::StoreOp::Store },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &self.target.depth_view,
                depth_ops: Some(wgpu::Operations { load: depth_load, store: wgpu::StoreOp::Store }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: (query == Occlusion::Counted).then_some(&self.occlusion.query_set),
            multiview_mask: None,
        });
        pass.set_scissor_rect(region.x, region.y, region.width, region.height);
        pass
    }

    /// The occluders visible in the tile, in the background colour.
    fn draw_occluders(&self, pass: &mut wgpu::RenderPass, draw: &TileDraw) {
        let geometry = &self.geometry.occluders;
        if let Some(buffer) = &geometry.standing {
            pass.set_pipeline(&self.pipeline.pipeline);
            pass.set_bind_group(0, &self.pipeline.world_group, &[]);
            pass.set_vertex_buffer(0, buffer.slice(..));
            for &object in draw.occluders {
                if let Some(&(first, count)) = geometry.objects.get(object) {
                    pass.draw(first..first + count, 0..1);
                }
            }
        }
        for &(k, _) in draw.moving {
            let (Some(Some((buffer, count))), Some(group)) =
                (geometry.moving.get(k), self.pipeline.moving_groups.get(k))
            else {
                continue;
            };
            pass.set_pipeline(&self.pipeline.pipeline);
            pass.set_bind_group(0, group, &[]);
            pass.set_vertex_buffer(0, buffer.slice(..));
            pass.draw(0..*count, 0..1);
        }
    }

    /// The vehicle, in its palette.
    fn draw_vehicle(&self, pass: &mut wgpu::RenderPass) {
        if let Some((buffer, count)) = &self.geometry.vehicle {
            pass.set_pipeline(&self.pipeline.pipeline);
            pass.set_bind_group(0, &self.pipeline.vehicle_group, &[]);
            pass.set_vertex_buffer(0, buffer.slice(..));
            pass.draw(0..*count, 0..1);
        }
    }
}
