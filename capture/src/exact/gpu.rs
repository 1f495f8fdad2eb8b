//! The exact measure on the GPU: the rules of [`super::rules`] in f64
//! through a wgpu compute shader (`visibility.wgsl`), one invocation per
//! sampled texel.
//!
//! The CPU version stays the reference: both cast the same segments through
//! the same hierarchies ([`super::bvh::TriangleBvh::flatten`]) from the same
//! samples with the same arithmetic, and the tests compare them on every
//! sampled texel. The GPU needs `SHADER_F64` (Mesa's lavapipe and
//! data-centre GPUs have it; many consumer and mobile GPUs do not): without
//! it [`texel_visibility_gpu`] is an error that says to use the CPU. Moving
//! occluders are in it as on the CPU: one hierarchy each in its own frame,
//! and per eye-frame the transform into it. f64
//! matters here: a point lifted 0.1 mm off its surface and rays of tens of
//! metres leave f32 no digits to spare.

use bytemuck::{Pod, Zeroable};

use super::bvh::TRAVERSAL_STACK;
use super::geometry::Obstacles;
use super::types::{EyeFrame, SurfaceSamples, TexelVisibility};
use crate::error::{CaptureError, Result};

/// Texels per dispatch: small enough for any dispatch limit and for a
/// driver's patience, large enough to fill a GPU.
const TEXELS_PER_DISPATCH: u32 = 1 << 14;
const WORKGROUP: u32 = 64;
/// f64s per eye-frame in the shader's layout, before the moving occluders'
/// transforms (16 each).
const EYE_FRAME_WORDS: usize = 40;
/// f64s of one moving occluder's transform in an eye-frame.
const MOVING_WORDS: usize = 16;

#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
struct Params {
    first_texel: u32,
    texel_count: u32,
    eye_frame_count: u32,
    vehicle_nodes: u32,
    world_nodes: u32,
    vehicle_triangles: u32,
    world_triangles: u32,
    world_node_base: u32,
    vehicle_node_count: u32,
    world_node_count: u32,
    moving_count: u32,
    eye_frame_words: u32,
}

/// The measure's inputs in the shader's layout.
struct Packed {
    params: Params,
    texels: Vec<u32>,
    samples: Vec<f64>,
    eye_frames: Vec<f64>,
    geometry: Vec<f64>,
    links: Vec<u32>,
    /// Per moving occluder: node base, node count, bounds and triangles offsets.
    moving: Vec<u32>,
    seen_words: usize,
}

fn too_large(what: &str) -> CaptureError {
    CaptureError::BadOptions(format!("{what}: too large for the GPU measure: use --measure-on cpu"))
}

fn pack(
    samples: &SurfaceSamples,
    eye_frames: &[EyeFrame],
    obstacles: &Obstacles,
    parts: usize,
) -> Result<Packed> {
    let word = |n: usize, what: &str| u32::try_from(n).map_err(|_| too_large(what));
    let texels = samples.texels.iter().flat_map(|t| [t.first, t.count, t.part, 0]).collect();
    let sample_words = samples
        .samples
        .iter()
        .flat_map(|s| {
            s.position.to_array().into_iter().chain(s.normal.to_array()).chain([s.area_m2, s.edge_on_m])
        })
        .collect();
    let (vehicle_bounds, vehicle_links, vehicle_triangles) = obstacles.vehicle.flatten();
    let (world_bounds, world_links, world_triangles) = obstacles.world.flatten();
    let bounds_words = vehicle_bounds.len() + world_bounds.len();
    let params = Params {
        first_texel: 0,
        texel_count: word(samples.texels.len(), "sampled texels")?,
        eye_frame_count: word(eye_frames.len(), "eye-frames")?,
        vehicle_nodes: 0,
        world_nodes: word(vehicle_bounds.len(), "the vehicle")?,
        vehicle_triangles: word(bounds_words, "the scene")?,
        world_triangles: word(bounds_words + vehicle_triangles.len(), "the scene")?,
        world_node_base: word(vehicle_links.len() / 2, "the vehicle")?,
        vehicle_node_count: word(vehicle_links.len() / 2, "the vehicle")?,
        world_node_count: word(world_links.len() / 2, "the scene")?,
        moving_count: word(obstacles.moving.len(), "moving occluders")?,
        eye_frame_words: word(EYE_FRAME_WORDS + MOVING_WORDS * obstacles.moving.len(), "moving occluders")?,
    };
    let mut geometry = [vehicle_bounds, world_bounds, vehicle_triangles, world_triangles].concat();
    let mut links = [vehicle_links, world_links].concat();
    let moving = pack_moving(obstacles, &mut geometry, &mut links)?;
    Ok(Packed {
        params,
        texels,
        samples: sample_words,
        eye_frames: eye_frame_words(eye_frames),
        geometry,
        links,
        moving,
        seen_words: (parts * eye_frames.len()).div_ceil(32),
    })
}

/// Each eye-frame's f64s: its 40, then local → each moving occluder's frame.
fn eye_frame_words(eye_frames: &[EyeFrame]) -> Vec<f64> {
    eye_frames
        .iter()
        .flat_map(|e| {
            let mut words = [0.0f64; EYE_FRAME_WORDS];
            words[0..3].copy_from_slice(&e.eye_in_vehicle.to_array());
            words[3..6].copy_from_slice(&e.eye_local.to_array());
            words[6..22].copy_from_slice(&e.vehicle_to_local.to_cols_array());
            words[22..38].copy_from_slice(&e.vehicle_to_clip.to_cols_array());
            words[38] = e.eye_near_margin;
            words[39] = e.lift_m;
            words.into_iter().chain(e.local_to_moving.iter().flat_map(|m| m.to_cols_array()))
        })
        .collect()
}

/// Appends each moving occluder's hierarchy (bounds and triangles to
/// `geometry`, nodes to `links`) and returns where each one starts.
fn pack_moving(obstacles: &Obstacles, geometry: &mut Vec<f64>, links: &mut Vec<u32>) -> Result<Vec<u32>> {
    let word = |n: usize| u32::try_from(n).map_err(|_| too_large("moving occluders"));
    let mut table = Vec::with_capacity(obstacles.moving.len() * 4);
    for bvh in &obstacles.moving {
        let (bounds, own_links, triangles) = bvh.flatten();
        table.extend([
            word(links.len() / 2)?,
            word(own_links.len() / 2)?,
            word(geometry.len())?,
            word(geometry.len() + bounds.len())?,
        ]);
        geometry.extend(bounds);
        geometry.extend(triangles);
        links.extend(own_links);
    }
    Ok(table)
}

/// The GPU buffers of one measure.
struct Buffers {
    params: wgpu::Buffer,
    inputs: [wgpu::Buffer; 5],
    /// The moving occluders' table (binding 9, after the outputs).
    moving: wgpu::Buffer,
    counts: wgpu::Buffer,
    solid_angles: wgpu::Buffer,
    part_seen: wgpu::Buffer,
}

fn storage(device: &wgpu::Device, queue: &wgpu::Queue, label: &str, bytes: &[u8]) -> Result<wgpu::Buffer> {
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
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    queue.write_buffer(&buffer, 0, bytes);
    Ok(buffer)
}

fn upload(device: &wgpu::Device, queue: &wgpu::Queue, packed: &Packed) -> Result<Buffers> {
    let texels = packed.texels.len() / 4;
    Ok(Buffers {
        params: device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("params"),
            size: std::mem::size_of::<Params>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        }),
        inputs: [
            storage(device, queue, "texels", bytemuck::cast_slice(&packed.texels))?,
            storage(device, queue, "samples", bytemuck::cast_slice(&packed.samples))?,
            storage(device, queue, "eye-frames", bytemuck::cast_slice(&packed.eye_frames))?,
            storage(device, queue, "geometry", bytemuck::cast_slice(&packed.geometry))?,
            storage(device, queue, "nodes", bytemuck::cast_slice(&packed.links))?,
        ],
        moving: storage(device, queue, "moving occluders", bytemuck::cast_slice(&packed.moving))?,
        counts: storage(device, queue, "counts", &vec![0u8; texels * 4])?,
        solid_angles: storage(device, queue, "solid angles", &vec![0u8; texels * 8])?,
        part_seen: storage(device, queue, "parts seen", &vec![0u8; packed.seen_words * 4])?,
    })
}

/// The shader's pipeline; a driver that rejects it (an f64 feature it lacks)
/// is an error for the caller, not wgpu's default panic.
fn pipeline(device: &wgpu::Device) -> Result<wgpu::ComputePipeline> {
    let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
    let shader = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("exact visibility"),
        source: wgpu::ShaderSource::Wgsl(include_str!("visibility.wgsl").into()),
    });
    let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some("exact visibility"),
        layout: None,
        module: &shader,
        entry_point: Some("count_texels"),
        compilation_options: Default::default(),
        cache: None,
    });
    match pollster::block_on(scope.pop()) {
        Some(error) => {
            Err(CaptureError::Gpu(format!("the exact measure's shader: {error}: use --measure-on cpu")))
        }
        None => Ok(pipeline),
    }
}

/// One submission per batch of texels, each waited for, so that no single
/// submission runs for minutes.
fn dispatch(device: &wgpu::Device, queue: &wgpu::Queue, packed: &Packed, buffers: &Buffers) -> Result<()> {
    let pipeline = pipeline(device)?;
    let mut entries = vec![wgpu::BindGroupEntry { binding: 0, resource: buffers.params.as_entire_binding() }];
    let outputs = [&buffers.counts, &buffers.solid_angles, &buffers.part_seen];
    for (binding, buffer) in buffers.inputs.iter().chain(outputs).enumerate() {
        entries
            .push(wgpu::BindGroupEntry { binding: binding as u32 + 1, resource: buffer.as_entire_binding() });
    }
    entries.push(wgpu::BindGroupEntry { binding: 9, resource: buffers.moving.as_entire_binding() });
    let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("exact visibility"),
        layout: &pipeline.get_bind_group_layout(0),
        entries: &entries,
    });
    let texel_count = packed.params.texel_count;
    let mut first = 0u32;
    while first < texel_count {
        let batch = TEXELS_PER_DISPATCH.min(texel_count - first);
        let params = Params { first_texel: first, ..packed.params };
        queue.write_buffer(&buffers.params, 0, bytemuck::bytes_of(&params));
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
    Ok(())
}

/// Copies a GPU buffer back to the CPU.
fn read_back(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    buffer: &wgpu::Buffer,
    label: &str,
) -> Result<Vec<u8>> {
    let readback = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: buffer.size(),
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: None });
    encoder.copy_buffer_to_buffer(buffer, 0, &readback, 0, buffer.size());
    queue.submit([encoder.finish()]);
    crate::render::gpu::map_for_reading(device, &readback.slice(..), label)?;
    let bytes = readback
        .slice(..)
        .get_mapped_range()
        .map_err(|e| CaptureError::Gpu(format!("{label} readback mapping: {e}")))?
        .to_vec();
    readback.unmap();
    Ok(bytes)
}

/// [`super::cpu::texel_visibility`] on the GPU.
pub fn texel_visibility_gpu(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    samples: &SurfaceSamples,
    eye_frames: &[EyeFrame],
    obstacles: &Obstacles,
    parts: usize,
) -> Result<TexelVisibility> {
    if !device.features().contains(wgpu::Features::SHADER_F64) {
        return Err(CaptureError::Gpu(
            "this GPU has no f64 in shaders (SHADER_F64), which the exact measure needs: use --measure-on cpu".into(),
        ));
    }
    let texels = samples.texels.len();
    if texels == 0 || eye_frames.is_empty() {
        return Ok(TexelVisibility {
            counts: vec![0; texels],
            solid_angle_sr: vec![0.0; texels],
            part_seen: vec![false; parts * eye_frames.len()],
            per_eye_frame: None,
        });
    }
    // The build bounds the depth (bvh::MAX_DEPTH), so the stack always holds it.
    debug_assert!(obstacles.vehicle.depth().max(obstacles.world.depth()) < TRAVERSAL_STACK);
    let packed = pack(samples, eye_frames, obstacles, parts)?;
    let buffers = upload(device, queue, &packed)?;
    dispatch(device, queue, &packed, &buffers)?;
    let counts = read_back(device, queue, &buffers.counts, "counts")?;
    let solid_angles = read_back(device, queue, &buffers.solid_angles, "solid angles")?;
    let seen = read_back(device, queue, &buffers.part_seen, "parts seen")?;
    // Byte vectors need not be aligned for u32 or f64: read them word by word.
    let words = |bytes: &[u8]| -> Vec<u32> {
        bytes.chunks_exact(4).map(|w| u32::from_le_bytes([w[0], w[1], w[2], w[3]])).collect()
    };
    let seen = words(&seen);
    Ok(TexelVisibility {
        counts: words(&counts)[..texels].to_vec(),
        solid_angle_sr: solid_angles
            .chunks_exact(8)
            .take(texels)
            .map(|w| f64::from_le_bytes(w.try_into().unwrap_or_default()))
            .collect(),
        part_seen: (0..parts * eye_frames.len()).map(|bit| seen[bit / 32] >> (bit % 32) & 1 == 1).collect(),
        // Per-texel sums only: the study's per-eye-frame tallies come from the CPU.
        per_eye_frame: None,
    })
}
