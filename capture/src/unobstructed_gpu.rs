//! The exact measure on the GPU: [`crate::unobstructed`]'s per-point test,
//! in f64 through a wgpu compute shader (`unobstructed.wgsl`).
//!
//! The CPU version stays the reference: both cast the same segments through
//! the same hierarchies ([`TriangleBvh::flatten`]) with the same arithmetic,
//! and the tests compare them on every sampled point. The GPU needs
//! `SHADER_F64` (Mesa's lavapipe and data-centre GPUs have it; many consumer
//! and mobile GPUs do not): without it [`count_unobstructed_gpu`] is an
//! error that says to use the CPU. f64 matters here: a point lifted 0.1 mm
//! off its surface and rays of tens of metres leave f32 no digits to spare.

use bytemuck::{Pod, Zeroable};

use crate::error::{CaptureError, Result};
use crate::unobstructed::{EyeFrame, Obstacles, SURFACE_OFFSET_M, SurfacePoint};

/// Where to run the exact measure.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
pub enum MeasureDevice {
    /// Every core of the CPU (the reference).
    Cpu,
    /// The GPU, through wgpu compute in f64.
    Gpu,
}

/// Points per dispatch: small enough for any dispatch limit and for a
/// driver's patience, large enough to fill a GPU.
const POINTS_PER_DISPATCH: u32 = 1 << 16;
const WORKGROUP: u32 = 64;
/// The shader's traversal stack (`STACK` in unobstructed.wgsl).
const STACK: usize = 64;
/// f64s per eye-frame in the shader's layout.
const EYE_FRAME_WORDS: usize = 40;

#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
struct Params {
    first_point: u32,
    point_count: u32,
    eye_frame_count: u32,
    vehicle_nodes: u32,
    world_nodes: u32,
    vehicle_triangles: u32,
    world_triangles: u32,
    world_node_base: u32,
    vehicle_node_count: u32,
    world_node_count: u32,
    _pad: [u32; 2],
}

/// Counts, per point, the eye-frames in which it is unobstructed, on the GPU.
pub fn count_unobstructed_gpu(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    points: &[SurfacePoint],
    eye_frames: &[EyeFrame],
    obstacles: &Obstacles,
) -> Result<Vec<u32>> {
    if !device.features().contains(wgpu::Features::SHADER_F64) {
        return Err(CaptureError::Gpu(
            "this GPU has no f64 in shaders (SHADER_F64), which the exact measure needs: use --measure-on cpu".into(),
        ));
    }
    if points.is_empty() || eye_frames.is_empty() {
        return Ok(vec![0; points.len()]);
    }
    for (name, bvh) in [("vehicle", &obstacles.vehicle), ("scene", &obstacles.world)] {
        if bvh.depth() + 1 > STACK {
            return Err(CaptureError::BadOptions(format!(
                "the {name}'s hierarchy is {} levels deep, more than the GPU traversal holds ({STACK}): use --measure-on cpu",
                bvh.depth()
            )));
        }
    }
    let point_count = u32::try_from(points.len()).map_err(|_| {
        CaptureError::BadOptions(format!("{} points: too many for one GPU measure", points.len()))
    })?;
    let point_words: Vec<f64> =
        points.iter().flat_map(|p| p.position.to_array().into_iter().chain(p.normal.to_array())).collect();
    let eye_words: Vec<f64> = eye_frames
        .iter()
        .flat_map(|e| {
            let mut words = [0.0f64; EYE_FRAME_WORDS];
            words[0..3].copy_from_slice(&e.eye_in_vehicle.to_array());
            words[3..6].copy_from_slice(&e.eye.to_array());
            words[6..22].copy_from_slice(&e.to_world.to_cols_array());
            words[22..38].copy_from_slice(&e.view_proj.to_cols_array());
            words[38] = SURFACE_OFFSET_M;
            words
        })
        .collect();
    let (vehicle_bounds, vehicle_links, vehicle_triangles) = obstacles.vehicle.flatten();
    let (world_bounds, world_links, world_triangles) = obstacles.world.flatten();
    let offset = |words: usize| {
        u32::try_from(words)
            .map_err(|_| CaptureError::BadOptions("the scene is too large for the GPU measure".into()))
    };
    let params = Params {
        first_point: 0,
        point_count,
        eye_frame_count: offset(eye_frames.len())?,
        vehicle_nodes: 0,
        world_nodes: offset(vehicle_bounds.len())?,
        vehicle_triangles: offset(vehicle_bounds.len() + world_bounds.len())?,
        world_triangles: offset(vehicle_bounds.len() + world_bounds.len() + vehicle_triangles.len())?,
        world_node_base: offset(vehicle_links.len() / 2)?,
        vehicle_node_count: offset(vehicle_links.len() / 2)?,
        world_node_count: offset(world_links.len() / 2)?,
        _pad: [0; 2],
    };
    let geometry: Vec<f64> =
        [vehicle_bounds, world_bounds, vehicle_triangles, world_triangles].into_iter().flatten().collect();
    let links: Vec<u32> = vehicle_links.into_iter().chain(world_links).collect();

    let storage = |label: &str, bytes: &[u8]| -> Result<wgpu::Buffer> {
        // Storage bindings may not be empty; one zero word stands for "none".
        let bytes: &[u8] = if bytes.is_empty() { &[0; 8] } else { bytes };
        let limit = device.limits().max_storage_buffer_binding_size;
        if bytes.len() as u64 > limit {
            return Err(CaptureError::Gpu(format!(
                "{label}: {} bytes exceed the GPU's storage binding limit of {limit}: sample fewer texels \
                 (--sample) or use --measure-on cpu",
                bytes.len()
            )));
        }
        let buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size: bytes.len().next_multiple_of(8) as u64,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        queue.write_buffer(&buffer, 0, bytes);
        Ok(buffer)
    };
    let points_buffer = storage("points", bytemuck::cast_slice(&point_words))?;
    let eyes_buffer = storage("eye-frames", bytemuck::cast_slice(&eye_words))?;
    let geometry_buffer = storage("geometry", bytemuck::cast_slice(&geometry))?;
    let links_buffer = storage("nodes", bytemuck::cast_slice(&links))?;
    let counts_size = u64::from(point_count) * 4;
    let counts_buffer = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("counts"),
        size: counts_size,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let readback = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("counts readback"),
        size: counts_size,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let params_buffer = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("params"),
        size: std::mem::size_of::<Params>() as u64,
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });

    // A driver that rejects the shader (an f64 feature it lacks) is an
    // error for the caller, not wgpu's default panic.
    let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
    let shader = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("unobstructed measure"),
        source: wgpu::ShaderSource::Wgsl(include_str!("unobstructed.wgsl").into()),
    });
    let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some("unobstructed measure"),
        layout: None,
        module: &shader,
        entry_point: Some("count_points"),
        compilation_options: Default::default(),
        cache: None,
    });
    if let Some(error) = pollster::block_on(scope.pop()) {
        return Err(CaptureError::Gpu(format!(
            "the unobstructed measure's shader: {error}: use --measure-on cpu"
        )));
    }
    let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("unobstructed measure"),
        layout: &pipeline.get_bind_group_layout(0),
        entries: &[
            wgpu::BindGroupEntry { binding: 0, resource: params_buffer.as_entire_binding() },
            wgpu::BindGroupEntry { binding: 1, resource: points_buffer.as_entire_binding() },
            wgpu::BindGroupEntry { binding: 2, resource: eyes_buffer.as_entire_binding() },
            wgpu::BindGroupEntry { binding: 3, resource: geometry_buffer.as_entire_binding() },
            wgpu::BindGroupEntry { binding: 4, resource: links_buffer.as_entire_binding() },
            wgpu::BindGroupEntry { binding: 5, resource: counts_buffer.as_entire_binding() },
        ],
    });
    // One submission per batch of points, waited for, so that no single
    // submission runs for minutes.
    let mut first = 0u32;
    while first < point_count {
        let batch = POINTS_PER_DISPATCH.min(point_count - first);
        queue.write_buffer(&params_buffer, 0, bytemuck::bytes_of(&Params { first_point: first, ..params }));
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: None });
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor::default());
            pass.set_pipeline(&pipeline);
            pass.set_bind_group(0, &bind_group, &[]);
            pass.dispatch_workgroups(batch.div_ceil(WORKGROUP), 1, 1);
        }
        queue.submit([encoder.finish()]);
        device.poll(wgpu::PollType::wait_indefinitely()).map_err(|e| CaptureError::Gpu(e.to_string()))?;
        first += batch;
    }
    let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: None });
    encoder.copy_buffer_to_buffer(&counts_buffer, 0, &readback, 0, counts_size);
    queue.submit([encoder.finish()]);
    crate::gpu::map_for_reading(device, &readback.slice(..), "counts")?;
    let counts = {
        let mapped = readback
            .slice(..)
            .get_mapped_range()
            .map_err(|e| CaptureError::Gpu(format!("counts readback mapping: {e}")))?;
        bytemuck::cast_slice::<u8, u32>(&mapped).to_vec()
    };
    readback.unmap();
    Ok(counts)
}
