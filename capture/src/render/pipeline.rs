//! The renderer's GPU state that never changes during a capture: the palette
//! shader's pipeline, the palette texture and the uniform buffer with its
//! bind groups (vehicle, world, and one per moving occluder).
//!
//! Split from [`crate::render`] so that the renderer reads as "draw a tile":
//! everything here is built once by [`PalettePipeline::new`].

use crate::error::{CaptureError, Result};
use crate::render::{GpuPalette, Vertex};

/// What the fragment shader draws (`Uniforms::mode`); the same numbers are
/// spelled `MODE_*` in `shader.wgsl` — change both together.
pub(crate) mod draw_mode {
    /// The canonical palette colour of the texel, computed.
    pub(crate) const CANONICAL_PALETTE: u32 = 0;
    /// The texel of the external palette texture.
    pub(crate) const EXTERNAL_PALETTE: u32 = 1;
    /// The background colour (occluders).
    pub(crate) const BACKGROUND: u32 = 2;
}

/// Uniforms as laid out in the shader (80 bytes).
#[repr(C)]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct Uniforms {
    pub clip_from_model: [[f32; 4]; 4],
    pub palette: [u32; 2],
    pub mode: u32,
    pub background: u32,
}

/// Where the two uniform blocks of a tile live in the uniform buffer
/// (256 = the largest minimum uniform offset alignment).
pub(crate) const UNIFORM_STRIDE: u64 = 256;

/// The pipeline, its uniforms and the palette, ready to draw with.
pub(crate) struct PalettePipeline {
    pub pipeline: wgpu::RenderPipeline,
    pub uniforms: wgpu::Buffer,
    /// Uniforms at offset 0: the vehicle, in its palette mode.
    pub vehicle_group: wgpu::BindGroup,
    /// Uniforms at [`UNIFORM_STRIDE`]: the occluders, in the background colour.
    pub world_group: wgpu::BindGroup,
    /// Uniforms at `(2 + k) ×` [`UNIFORM_STRIDE`]: moving occluder `k`, in its
    /// own frame, in the background colour.
    pub moving_groups: Vec<wgpu::BindGroup>,
    /// The vehicle's draw mode (`draw_mode::CANONICAL_PALETTE` or `EXTERNAL_PALETTE`).
    pub mode: u32,
    /// The same pipeline writing neither colour nor depth: draws the
    /// vehicle's bounding box under an occlusion query (see [`crate::render`]).
    pub bounds_test: wgpu::RenderPipeline,
}

impl PalettePipeline {
    /// Compiles the shader, builds the pipeline and uploads the palette,
    /// with uniforms for the vehicle, the still occluders and `moving`
    /// moving occluders.
    pub(crate) fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        palette: &GpuPalette,
        moving: usize,
    ) -> Result<PalettePipeline> {
        let layout = bind_group_layout(device);
        let pipeline = render_pipeline(device, &layout, Writes::ColorAndDepth);
        let bounds_test = render_pipeline(device, &layout, Writes::Nothing);
        let (mode, palette_view) = palette_texture(device, queue, palette)?;
        let uniforms = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("uniforms"),
            size: UNIFORM_STRIDE * (2 + moving as u64),
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let group = |offset: u64| bind_group(device, &layout, &uniforms, offset, &palette_view);
        let vehicle_group = group(0);
        let world_group = group(UNIFORM_STRIDE);
        let moving_groups = (0..moving as u64).map(|k| group(UNIFORM_STRIDE * (2 + k))).collect();
        Ok(PalettePipeline {
            pipeline,
            uniforms,
            vehicle_group,
            world_group,
            moving_groups,
            mode,
            bounds_test,
        })
    }
}

/// Uniforms (vertex and fragment) and the palette texture (fragment).
fn bind_group_layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
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
    })
}

/// What a pipeline writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Writes {
    /// Colour and depth: the frame.
    ColorAndDepth,
    /// Nothing: it only tests depth (for occlusion queries).
    Nothing,
}

/// The unlit palette pipeline: no culling, reversed-Z depth, no blending,
/// one sample, an `Rgba8Unorm` target.
fn render_pipeline(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    writes: Writes,
) -> wgpu::RenderPipeline {
    let shader = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("palette shader"),
        source: wgpu::ShaderSource::Wgsl(include_str!("shader.wgsl").into()),
    });
    let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("palette pipeline"),
        bind_group_layouts: &[Some(layout)],
        immediate_size: 0,
    });
    let vertex_layout = wgpu::VertexBufferLayout {
        array_stride: std::mem::size_of::<Vertex>() as u64,
        step_mode: wgpu::VertexStepMode::Vertex,
        // Position, UV (unused by the shader) and the triangle's chart (three
        // texel-space corners).
        attributes: &wgpu::vertex_attr_array![
            0 => Float32x3, 1 => Float32x2, 2 => Float32x2, 3 => Float32x2, 4 => Float32x2
        ],
    };
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(if writes == Writes::ColorAndDepth {
            "palette pipeline"
        } else {
            "bounds test pipeline"
        }),
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
            depth_write_enabled: Some(writes == Writes::ColorAndDepth),
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
                write_mask: if writes == Writes::ColorAndDepth {
                    wgpu::ColorWrites::ALL
                } else {
                    wgpu::ColorWrites::empty()
                },
            })],
        }),
        multiview_mask: None,
        cache: None,
    })
}

/// Uploads the palette texture: the external palette, or a 1×1 stand-in that
/// the canonical mode never reads. Returns the vehicle's draw mode and the view.
fn palette_texture(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    palette: &GpuPalette,
) -> Result<(u32, wgpu::TextureView)> {
    let (mode, size, texels): (u32, [u32; 2], &[u8]) = match palette {
        GpuPalette::Canonical(_) => (draw_mode::CANONICAL_PALETTE, [1, 1], &[0; 4]),
        GpuPalette::External { size, rgba } => {
            if rgba.len() != (size[0] as usize) * (size[1] as usize) * 4 {
                return Err(CaptureError::BadOptions("external palette data does not match its size".into()));
            }
            (draw_mode::EXTERNAL_PALETTE, *size, rgba)
        }
    };
    let extent = wgpu::Extent3d { width: size[0], height: size[1], depth_or_array_layers: 1 };
    let texture = device.create_texture(&wgpu::TextureDescriptor {
        label: Some("palette"),
        size: extent,
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::Rgba8Unorm,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    });
    queue.write_texture(
        wgpu::TexelCopyTextureInfo {
            texture: &texture,
            mip_level: 0,
            origin: wgpu::Origin3d::ZERO,
            aspect: wgpu::TextureAspect::All,
        },
        texels,
        wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(size[0] * 4), rows_per_image: None },
        extent,
    );
    Ok((mode, texture.create_view(&Default::default())))
}

/// One uniform block (at `offset`) with the palette.
fn bind_group(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    uniforms: &wgpu::Buffer,
    offset: u64,
    palette_view: &wgpu::TextureView,
) -> wgpu::BindGroup {
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("uniforms + palette"),
        layout,
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                    buffer: uniforms,
                    offset,
                    size: wgpu::BufferSize::new(std::mem::size_of::<Uniforms>() as u64),
                }),
            },
            wgpu::BindGroupEntry { binding: 1, resource: wgpu::BindingResource::TextureView(palette_view) },
        ],
    })
}
