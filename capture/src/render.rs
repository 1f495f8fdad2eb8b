//! The renderer: one tile at a time, unlit, exact by construction.
//!
//! Every fragment's colour is the palette colour of the texel its UV falls in
//! (see `shader.wgsl`). The target is `Rgba8Unorm` (never sRGB, which would
//! re-encode the colours), one sample per pixel, no blending, no mipmaps,
//! cleared to the background colour. Depth is `Depth32Float` with reversed Z
//! (cleared to 0, `Greater` wins), so a 0.3 m near plane and a 1000 m far
//! plane keep sub-millimetre depth resolution at street distances.
//! Readback rows are padded to 256 bytes as wgpu requires and unpadded here.

use glam::{DMat4, Vec3};
use ufcsr::Color;

use crate::error::{CaptureError, Result};
use crate::mesh::Occluders;

/// A vertex: position (model frame), UV (0..1, v = 0 at the top row) and
/// its triangle's chart: the three corners in texel coordinates, the same on
/// all three vertices, which the fragment shader clamps the UV into (so a
/// degenerate triangle's wild barycentrics still name one of its own texels).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Vertex {
    pub position: [f32; 3],
    pub uv: [f32; 2],
    pub chart: [[f32; 2]; 3],
}

/// What the fragment shader draws (`Uniforms::mode`); the same numbers are
/// spelled `MODE_*` in `shader.wgsl` — change both together.
mod draw_mode {
    /// The canonical palette colour of the texel, computed.
    pub const CANONICAL_PALETTE: u32 = 0;
    /// The texel of the external palette texture.
    pub const EXTERNAL_PALETTE: u32 = 1;
    /// The background colour (occluders).
    pub const BACKGROUND: u32 = 2;
}

/// Uniforms as laid out in the shader (80 bytes).
#[repr(C)]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct Uniforms {
    clip_from_model: [[f32; 4]; 4],
    palette: [u32; 2],
    mode: u32,
    background: u32,
}

/// Where the two uniform blocks of a tile live in the uniform buffer
/// (256 = the largest minimum uniform offset alignment).
const UNIFORM_STRIDE: u64 = 256;

/// The palette the vehicle is drawn with.
#[derive(Debug, Clone)]
pub enum Palette {
    /// The canonical palette of this size, computed in the shader.
    Canonical([u32; 2]),
    /// An external palette image: size and RGBA8 texels (row 0 at the top).
    External { size: [u32; 2], rgba: Vec<u8> },
}

impl Palette {
    pub fn size(&self) -> [u32; 2] {
        match self {
            Palette::Canonical(size) | Palette::External { size, .. } => *size,
        }
    }
}

/// Everything the renderer needs once.
pub struct RenderSetup<'a> {
    pub tile_size: [u32; 2],
    pub palette: &'a Palette,
    pub background: Color,
    /// Vehicle triangles (three vertices each), in the vehicle frame.
    pub vehicle: &'a [Vertex],
    /// Occluders in world coordinates.
    pub occluders: &'a Occluders,
}

/// What to draw in one tile.
pub struct TileDraw<'a> {
    /// Vehicle frame → tile clip space.
    pub clip_from_vehicle: DMat4,
    /// World → tile clip space.
    pub clip_from_world: DMat4,
    /// Indices into `Occluders::objects` that may be visible in the tile.
    pub occluders: &'a [usize],
}

/// A GPU renderer of tiles.
pub struct Renderer {
    pipeline: wgpu::RenderPipeline,
    uniforms: wgpu::Buffer,
    vehicle_group: wgpu::BindGroup,
    world_group: wgpu::BindGroup,
    vehicle: Option<(wgpu::Buffer, u32)>,
    occluders: Option<wgpu::Buffer>,
    objects: Vec<(u32, u32)>,
    color: wgpu::Texture,
    depth_view: wgpu::TextureView,
    color_view: wgpu::TextureView,
    readback: wgpu::Buffer,
    tile_size: [u32; 2],
    padded_row: u32,
    palette: [u32; 2],
    mode: u32,
    background: Color,
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

impl Renderer {
    /// Builds the pipeline and uploads the geometry.
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue, setup: &RenderSetup) -> Result<Renderer> {
        let [tw, th] = setup.tile_size;
        let limit = device.limits().max_texture_dimension_2d;
        let [pw, ph] = setup.palette.size();
        if tw == 0 || th == 0 || tw > limit || th > limit || pw > limit || ph > limit {
            return Err(CaptureError::Gpu(format!(
                "tile {tw}×{th} or palette {pw}×{ph} exceeds the device's texture limit {limit}"
            )));
        }
        let shader = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("palette shader"),
            source: wgpu::ShaderSource::Wgsl(include_str!("shader.wgsl").into()),
        });
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("uniforms + palette"),
            entries: &[
                wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
                    ty: wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        has_dynamic_offset: false,
                        min_binding_size: None,
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 1,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Float { filterable: false },
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
                    },
                    count: None,
                },
            ],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("palette pipeline"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let vertex_layout = wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<Vertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &wgpu::vertex_attr_array![
                0 => Float32x3, 1 => Float32x2, 2 => Float32x2, 3 => Float32x2, 4 => Float32x2
            ],
        };
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("palette pipeline"),
            layout: Some(&pipeline_layout),
            vertex: wgpu::VertexState {
                module: &shader,
                entry_point: Some("vs_main"),
                compilation_options: Default::default(),
                buffers: &[Some(vertex_layout)],
            },
            primitive: wgpu::PrimitiveState {
                topology: wgpu::PrimitiveTopology::TriangleList,
                // Both sides: imported meshes do not agree on winding, and an
                // unlit surface looks the same from behind.
                cull_mode: None,
                ..Default::default()
            },
            depth_stencil: Some(wgpu::DepthStencilState {
                format: wgpu::TextureFormat::Depth32Float,
                depth_write_enabled: Some(true),
                // Reversed Z: nearer is larger.
                depth_compare: Some(wgpu::CompareFunction::Greater),
                stencil: Default::default(),
                bias: Default::default(),
            }),
            multisample: wgpu::MultisampleState { count: 1, mask: !0, alpha_to_coverage_enabled: false },
            fragment: Some(wgpu::FragmentState {
                module: &shader,
                entry_point: Some("fs_main"),
                compilation_options: Default::default(),
                targets: &[Some(wgpu::ColorTargetState {
                    format: wgpu::TextureFormat::Rgba8Unorm,
                    blend: None,
                    write_mask: wgpu::ColorWrites::ALL,
                })],
            }),
            multiview_mask: None,
            cache: None,
        });

        // The palette texture: the external palette, or a 1×1 stand-in that the
        // canonical mode never reads.
        let (mode, texture_size, texels): (u32, [u32; 2], Vec<u8>) = match setup.palette {
            Palette::Canonical(_) => (draw_mode::CANONICAL_PALETTE, [1, 1], vec![0; 4]),
            Palette::External { size, rgba } => {
                if rgba.len() != (size[0] as usize) * (size[1] as usize) * 4 {
                    return Err(CaptureError::BadOptions(
                        "external palette data does not match its size".into(),
                    ));
                }
                (draw_mode::EXTERNAL_PALETTE, *size, rgba.clone())
            }
        };
        let palette_texture = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("palette"),
            size: wgpu::Extent3d {
                width: texture_size[0],
                height: texture_size[1],
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Rgba8Unorm,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        });
        queue.write_texture(
            wgpu::TexelCopyTextureInfo {
                texture: &palette_texture,
                mip_level: 0,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            &texels,
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(texture_size[0] * 4),
                rows_per_image: None,
            },
            wgpu::Extent3d { width: texture_size[0], height: texture_size[1], depth_or_array_layers: 1 },
        );
        let palette_view = palette_texture.create_view(&Default::default());

        let uniforms = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("uniforms"),
            size: UNIFORM_STRIDE * 2,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let group = |offset: u64| {
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("uniforms + palette"),
                layout: &layout,
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                            buffer: &uniforms,
                            offset,
                            size: wgpu::BufferSize::new(std::mem::size_of::<Uniforms>() as u64),
                        }),
                    },
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: wgpu::BindingResource::TextureView(&palette_view),
                    },
                ],
            })
        };
        let vehicle_group = group(0);
        let world_group = group(UNIFORM_STRIDE);

        let vehicle = vertex_buffer(device, queue, "vehicle", bytemuck::cast_slice(setup.vehicle))
            .map(|b| (b, setup.vehicle.len() as u32));
        // Occluders carry a UV and chart but the background mode never reads them.
        let occluder_vertices: Vec<Vertex> = setup
            .occluders
            .positions
            .iter()
            .map(|p: &Vec3| Vertex { position: p.to_array(), uv: [0.0, 0.0], chart: [[0.0; 2]; 3] })
            .collect();
        let occluders = vertex_buffer(device, queue, "occluders", bytemuck::cast_slice(&occluder_vertices));
        let objects = setup.occluders.objects.iter().map(|o| (o.first_vertex, o.vertex_count)).collect();

        let target = |label: &str, format: wgpu::TextureFormat, usage: wgpu::TextureUsages| {
            device.create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size: wgpu::Extent3d { width: tw, height: th, depth_or_array_layers: 1 },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage,
                view_formats: &[],
            })
        };
        let color = target(
            "tile colour",
            wgpu::TextureFormat::Rgba8Unorm,
            wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
        );
        let depth =
            target("tile depth", wgpu::TextureFormat::Depth32Float, wgpu::TextureUsages::RENDER_ATTACHMENT);
        let padded_row =
            (tw * 4).div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT) * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
        let readback = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("readback"),
            size: u64::from(padded_row) * u64::from(th),
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        Ok(Renderer {
            pipeline,
            uniforms,
            vehicle_group,
            world_group,
            vehicle,
            occluders,
            objects,
            color_view: color.create_view(&Default::default()),
            color,
            depth_view: depth.create_view(&Default::default()),
            readback,
            tile_size: setup.tile_size,
            padded_row,
            palette: setup.palette.size(),
            mode,
            background: setup.background,
        })
    }

    /// Tile size in pixels.
    pub fn tile_size(&self) -> [u32; 2] {
        self.tile_size
    }

    /// Renders one tile and returns its pixels, RGBA8, rows top to bottom.
    pub fn render_tile(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        draw: &TileDraw,
    ) -> Result<Vec<u8>> {
        let vehicle_uniforms = Uniforms {
            clip_from_model: to_f32(&draw.clip_from_vehicle),
            palette: self.palette,
            mode: self.mode,
            background: self.background.packed(),
        };
        let world_uniforms = Uniforms {
            clip_from_model: to_f32(&draw.clip_from_world),
            mode: draw_mode::BACKGROUND,
            ..vehicle_uniforms
        };
        queue.write_buffer(&self.uniforms, 0, bytemuck::bytes_of(&vehicle_uniforms));
        queue.write_buffer(&self.uniforms, UNIFORM_STRIDE, bytemuck::bytes_of(&world_uniforms));

        let mut encoder =
            device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("tile") });
        {
            let [r, g, b] = self.background.rgb().map(|c| f64::from(c) / 255.0);
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("tile"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &self.color_view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color { r, g, b, a: 1.0 }),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &self.depth_view,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(0.0),
                        store: wgpu::StoreOp::Store,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_pipeline(&self.pipeline);
            if let Some(buffer) = &self.occluders {
                pass.set_bind_group(0, &self.world_group, &[]);
                pass.set_vertex_buffer(0, buffer.slice(..));
                for &object in draw.occluders {
                    if let Some(&(first, count)) = self.objects.get(object) {
                        pass.draw(first..first + count, 0..1);
                    }
                }
            }
            if let Some((buffer, count)) = &self.vehicle {
                pass.set_bind_group(0, &self.vehicle_group, &[]);
                pass.set_vertex_buffer(0, buffer.slice(..));
                pass.draw(0..*count, 0..1);
            }
        }
        let [tw, th] = self.tile_size;
        encoder.copy_texture_to_buffer(
            wgpu::TexelCopyTextureInfo {
                texture: &self.color,
                mip_level: 0,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            wgpu::TexelCopyBufferInfo {
                buffer: &self.readback,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(self.padded_row),
                    rows_per_image: Some(th),
                },
            },
            wgpu::Extent3d { width: tw, height: th, depth_or_array_layers: 1 },
        );
        queue.submit([encoder.finish()]);

        let (sender, receiver) = std::sync::mpsc::channel();
        self.readback.slice(..).map_async(wgpu::MapMode::Read, move |result| {
            let _ = sender.send(result);
        });
        device.poll(wgpu::PollType::wait_indefinitely()).map_err(|e| CaptureError::Gpu(e.to_string()))?;
        receiver
            .recv()
            .map_err(|_| CaptureError::Gpu("readback was never mapped".into()))?
            .map_err(|e| CaptureError::Gpu(format!("readback failed: {e}")))?;
        let row = (tw * 4) as usize;
        let mut pixels = Vec::with_capacity(row * th as usize);
        {
            let mapped = self
                .readback
                .slice(..)
                .get_mapped_range()
                .map_err(|e| CaptureError::Gpu(format!("readback mapping: {e}")))?;
            for y in 0..th as usize {
                let start = y * self.padded_row as usize;
                pixels.extend_from_slice(&mapped[start..start + row]);
            }
        }
        self.readback.unmap();
        Ok(pixels)
    }
}

/// Vehicle vertices for the renderer: three per triangle with their UVs and
/// their triangle's chart.
pub fn vehicle_vertices(mesh: &crate::mesh::Mesh, unwrapped: &crate::unwrap::Unwrapped) -> Vec<Vertex> {
    let mut vertices = Vec::with_capacity(mesh.triangles.len() * 3);
    for (t, tri) in mesh.triangles.iter().enumerate() {
        let chart = unwrapped.texel_uvs[t].map(|c| [c.x as f32, c.y as f32]);
        for (k, &i) in tri.iter().enumerate() {
            vertices.push(Vertex {
                position: mesh.positions[i as usize].to_array(),
                uv: unwrapped.uv(t, k),
                chart,
            });
        }
    }
    vertices
}
