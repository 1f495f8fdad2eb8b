//! What the renderer draws: the vehicle's vertices, each carrying its
//! triangle's chart in the palette, and the palette itself (canonical, made
//! in the shader, or an external image). Shared by the renderer, its
//! pipeline, the occlusion test and the GPU heatmap views.

use crate::scene::mesh::Mesh;
use crate::texture::uv_islands::Unwrapped;

/// A vertex: position (model frame), UV (0..1, v = 0 at the top row; what
/// the archive's `vehicle.glb` records) and its triangle's chart: the three
/// corners in texel coordinates, the same on all three vertices. The shader
/// draws from the chart and clamped barycentrics (so a degenerate
/// triangle's wild barycentrics still name one of its own texels); the UV is
/// the same point, kept for the vehicle model.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Vertex {
    pub position: [f32; 3],
    pub uv: [f32; 2],
    pub chart: [[f32; 2]; 3],
}

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

/// Vehicle vertices for the renderer: three per triangle with their UVs and
/// their triangle's chart.
pub fn vehicle_vertices(mesh: &Mesh, unwrapped: &Unwrapped) -> Vec<Vertex> {
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
