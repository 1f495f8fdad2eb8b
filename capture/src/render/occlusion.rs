//! The hidden-tile test: is the vehicle's bounding box hidden by the
//! occluders in this tile?
//!
//! The renderer draws a tile's occluders, then the vehicle's bounding box
//! (grown a little) with a pipeline that writes nothing, under an occlusion
//! query. Every pixel a vehicle triangle covers is covered by the box, and
//! the box's near face is nearer than the triangle, so when no box fragment
//! passes the depth test no vehicle fragment would either: the tile is pure
//! background and the vehicle is neither drawn nor read back. Only valid
//! when the whole box is in front of the near plane (the caller checks).

use glam::Vec3;

use crate::error::{CaptureError, Result};
use crate::render::Vertex;

/// The box grows by this much plus [`GROW_SHARE`] of its diagonal on every
/// side, so that f32 depth ties between the box and the vehicle's surface
/// cannot hide a visible vehicle.
const GROW_M: f32 = 0.02;
const GROW_SHARE: f32 = 0.002;

/// The query, its resolve and readback buffers, and the box's triangles.
pub(crate) struct OcclusionTest {
    pub query_set: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    readback: wgpu::Buffer,
    /// 36 vertices (12 triangles) in the vehicle frame, or none for an empty vehicle.
    pub box_vertices: Option<wgpu::Buffer>,
}

/// Bytes of one resolved occlusion query (a u64 sample count).
const RESULT_BYTES: u64 = 8;

impl OcclusionTest {
    pub(crate) fn new(device: &wgpu::Device, queue: &wgpu::Queue, vehicle: &[Vertex]) -> OcclusionTest {
        let query_set = device.create_query_set(&wgpu::QuerySetDescriptor {
            label: Some("vehicle bounds occlusion"),
            ty: wgpu::QueryType::Occlusion,
            count: 1,
        });
        let buffer = |label: &str, usage: wgpu::BufferUsages| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: RESULT_BYTES,
                usage,
                mapped_at_creation: false,
            })
        };
        let resolve =
            buffer("occlusion resolve", wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC);
        let readback =
            buffer("occlusion readback", wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST);
        let box_vertices = grown_box(vehicle).map(|vertices| {
            let bytes: &[u8] = bytemuck::cast_slice(&vertices);
            let buffer = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("vehicle bounds"),
                size: bytes.len() as u64,
                usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            queue.write_buffer(&buffer, 0, bytes);
            buffer
        });
        OcclusionTest { query_set, resolve, readback, box_vertices }
    }

    /// Records the resolve of the query and its copy into the readback buffer
    /// (after the pass that ran the query).
    pub(crate) fn resolve(&self, encoder: &mut wgpu::CommandEncoder) {
        encoder.resolve_query_set(&self.query_set, 0..1, &self.resolve, 0);
        encoder.copy_buffer_to_buffer(&self.resolve, 0, &self.readback, 0, RESULT_BYTES);
    }

    /// Waits for the submitted query and returns its sample count.
    pub(crate) fn samples(&self, device: &wgpu::Device) -> Result<u64> {
        let slice = self.readback.slice(..);
        crate::render::gpu::map_for_reading(device, &slice, "occlusion result")?;
        let samples = {
            let mapped =
                slice.get_mapped_range().map_err(|e| CaptureError::Gpu(format!("occlusion mapping: {e}")))?;
            let bytes: [u8; 8] = mapped[..8]
                .try_into()
                .map_err(|_| CaptureError::Gpu("occlusion result is not 8 bytes".into()))?;
            u64::from_le_bytes(bytes)
        };
        self.readback.unmap();
        Ok(samples)
    }
}

/// The 12 triangles of the vehicle's bounding box, grown.
fn grown_box(vehicle: &[Vertex]) -> Option<Vec<Vertex>> {
    let first = Vec3::from(vehicle.first()?.position);
    let (min, max) = vehicle.iter().fold((first, first), |(lo, hi), v| {
        let p = Vec3::from(v.position);
        (lo.min(p), hi.max(p))
    });
    let grow = Vec3::splat(GROW_M + GROW_SHARE * (max - min).length());
    let (min, max) = (min - grow, max + grow);
    let mut mesh = crate::scene::mesh::Mesh::default();
    mesh.add_box(min, max, [Some("box"); 6]);
    Some(
        mesh.triangles
            .iter()
            .flat_map(|t| t.map(|i| mesh.positions[i as usize]))
            .map(|p| Vertex { position: p.to_array(), uv: [0.0, 0.0], chart: [[0.0; 2]; 3] })
            .collect(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_box_encloses_the_vehicle_with_room() {
        let vertex = |p: [f32; 3]| Vertex { position: p, uv: [0.0; 2], chart: [[0.0; 2]; 3] };
        let vehicle = [vertex([0.0, 0.0, 0.0]), vertex([4.0, 2.0, 1.0]), vertex([1.0, -1.0, 2.0])];
        let corners = grown_box(&vehicle).unwrap();
        assert_eq!(corners.len(), 36);
        let lo = corners.iter().fold(Vec3::splat(f32::MAX), |m, v| m.min(Vec3::from(v.position)));
        let hi = corners.iter().fold(Vec3::splat(f32::MIN), |m, v| m.max(Vec3::from(v.position)));
        assert!(
            lo.cmplt(Vec3::new(0.0, -1.0, 0.0) - 0.02).all()
                && hi.cmpgt(Vec3::new(4.0, 2.0, 2.0) + 0.02).all()
        );
        assert!(grown_box(&[]).is_none());
    }
}
