//! What the renderer draws: the vehicle's vertices, each carrying its
//! triangle's chart in the palette, and the palette itself (canonical, made
//! in the shader, or an external image). Shared by the renderer, its
//! pipeline and the occlusion test.

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

/// The palette in the form the renderer draws the vehicle with (the loaded
/// palette is [`ufcsr::Fcsp`]; [`GpuPalette::of`] converts). The canonical
/// palette is computed in the shader and never stored; an image is uploaded
/// as a texture and read with `textureLoad`. Either way the texel holding the
/// background colour is left out of the unwrap.
#[derive(Debug, Clone)]
pub enum GpuPalette {
    /// The canonical palette of this size, computed in the shader.
    Canonical([u32; 2]),
    /// An external palette image: size and RGBA8 texels (row 0 at the top).
    External { size: [u32; 2], rgba: Vec<u8> },
}

impl GpuPalette {
    /// The renderer's form of `palette`, whose texels' colours are
    /// `texel_rgb` (RGB, row 0 at the top, [`ufcsr::Fcsp::texel_rgb`]).
    pub fn of(palette: &ufcsr::Fcsp, texel_rgb: &[u8]) -> GpuPalette {
        let size = [palette.width(), palette.height()];
        match palette {
            ufcsr::Fcsp::Canonical { .. } => GpuPalette::Canonical(size),
            ufcsr::Fcsp::Image { .. } => GpuPalette::External {
                size,
                rgba: texel_rgb.chunks_exact(3).flat_map(|p| [p[0], p[1], p[2], 255]).collect(),
            },
        }
    }

    pub fn size(&self) -> [u32; 2] {
        match self {
            GpuPalette::Canonical(size) | GpuPalette::External { size, .. } => *size,
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
