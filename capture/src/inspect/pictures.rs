//! Orthographic pictures of the vehicle with its parts coloured, for
//! `inspect`, drawn with the analyzer's CPU rasterizer ([`ufcsr::ZBuffer`],
//! the one its eight heatmap views use) and written as PNG.
//!
//! Faces take their part's PIdT colour (the same [`crate::texture::pidt::part_colors`]
//! a capture paints), shaded a little by how squarely they face the viewer
//! so that the shape reads. A black cross marks the vehicle's origin, a grey
//! line the ground (z = 0) and ticks every metre along the edges give scale.

use std::path::{Path, PathBuf};

use glam::{DVec2, DVec3, dvec2};
use ufcsr::{Color, ZBuffer};

use crate::error::Result;
use crate::scene::mesh::Mesh;

/// Which way the picture looks.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum View {
    /// From the vehicle's right (−y), front to the right of the picture.
    Side,
    /// From above, front to the right, the vehicle's left at the top.
    Top,
    /// From the front (+x), the vehicle's left on the picture's right.
    Front,
}

impl View {
    /// The file-name word.
    pub fn name(self) -> &'static str {
        match self {
            View::Side => "side",
            View::Top => "top",
            View::Front => "front",
        }
    }

    /// Picture coordinates (right, up) and depth (smaller is nearer).
    fn project(self, p: DVec3) -> (DVec2, f64) {
        match self {
            View::Side => (dvec2(p.x, p.z), p.y),
            View::Top => (dvec2(p.x, p.y), -p.z),
            View::Front => (dvec2(-p.y, p.z), -p.x),
        }
    }

    /// The direction towards the viewer.
    fn towards_viewer(self) -> DVec3 {
        match self {
            View::Side => -DVec3::Y,
            View::Top => DVec3::Z,
            View::Front => DVec3::X,
        }
    }
}

const PAPER: [u8; 3] = [255, 255, 255];
const GROUND: [u8; 3] = [150, 150, 150];
const INK: [u8; 3] = [0, 0, 0];
const MARGIN: u32 = 24;

/// An RGB picture with a depth buffer (the analyzer's CPU rasterizer).
struct Canvas {
    width: u32,
    height: u32,
    rgb: Vec<u8>,
    depth: ZBuffer,
}

impl Canvas {
    fn new(width: u32, height: u32) -> Canvas {
        let n = (width as usize) * (height as usize);
        Canvas { width, height, rgb: PAPER.repeat(n), depth: ZBuffer::new(width, height) }
    }

    fn put(&mut self, x: i64, y: i64, rgb: [u8; 3]) {
        if x >= 0 && y >= 0 && (x as u32) < self.width && (y as u32) < self.height {
            let i = (y as usize * self.width as usize + x as usize) * 3;
            self.rgb[i..i + 3].copy_from_slice(&rgb);
        }
    }

    /// Fills a triangle (picture pixels) at pixel centres, nearest wins.
    fn triangle(&mut self, p: [DVec2; 3], depth: [f64; 3], rgb: [u8; 3]) {
        let corners = [0, 1, 2].map(|k| [p[k].x, p[k].y, depth[k]]);
        let pixels = &mut self.rgb;
        self.depth.triangle(corners, |pixel, _| pixels[pixel * 3..pixel * 3 + 3].copy_from_slice(&rgb));
    }
}

/// Draws `mesh` seen from `view` at `pixels_per_metre`, parts in `colors`.
fn draw(mesh: &Mesh, colors: &[Color], view: View, pixels_per_metre: f64) -> Canvas {
    let (bmin, bmax) = mesh.bounds();
    // The picture covers the vehicle and its origin (which may lie outside it).
    let mut lo = DVec2::splat(f64::INFINITY);
    let mut hi = DVec2::splat(f64::NEG_INFINITY);
    for x in [bmin.x, bmax.x, 0.0] {
        for y in [bmin.y, bmax.y, 0.0] {
            for z in [bmin.z, bmax.z, 0.0] {
                let (q, _) = view.project(DVec3::new(x, y, z));
                lo = lo.min(q);
                hi = hi.max(q);
            }
        }
    }
    let margin = f64::from(MARGIN);
    let width = ((hi.x - lo.x) * pixels_per_metre + 2.0 * margin).ceil().max(1.0) as u32;
    let height = ((hi.y - lo.y) * pixels_per_metre + 2.0 * margin).ceil().max(1.0) as u32;
    let to_pixel =
        |q: DVec2| dvec2((q.x - lo.x) * pixels_per_metre + margin, (hi.y - q.y) * pixels_per_metre + margin);
    let mut canvas = Canvas::new(width, height);

    if view != View::Top {
        let ground = to_pixel(dvec2(0.0, 0.0)).y.round() as i64;
        for x in 0..i64::from(width) {
            canvas.put(x, ground, GROUND);
        }
    }
    let towards = view.towards_viewer();
    for t in 0..mesh.triangles.len() {
        let corners = mesh.corners(t).map(|c| c.as_dvec3());
        let normal = (corners[1] - corners[0]).cross(corners[2] - corners[0]).normalize_or_zero();
        let shade = 0.6 + 0.4 * normal.dot(towards).abs();
        let color =
            colors.get(mesh.triangle_part[t] as usize).copied().unwrap_or(Color::from_rgb(128, 128, 128));
        let rgb = color.rgb().map(|c| (f64::from(c) * shade).round() as u8);
        let projected = corners.map(|c| view.project(c));
        canvas.triangle(projected.map(|(q, _)| to_pixel(q)), projected.map(|(_, d)| d), rgb);
    }

    // Origin cross, drawn over the vehicle so it is always seen.
    let origin = to_pixel(dvec2(0.0, 0.0));
    let (ox, oy) = (origin.x.round() as i64, origin.y.round() as i64);
    for d in -8..=8 {
        canvas.put(ox + d, oy, INK);
        canvas.put(ox, oy + d, INK);
    }
    // Metre ticks from the origin along the bottom and left edges.
    let ticks = |from: f64, to: f64| {
        let first = from.ceil() as i64;
        let last = to.floor() as i64;
        first..=last
    };
    for metre in ticks(lo.x, hi.x) {
        let x = to_pixel(dvec2(metre as f64, 0.0)).x.round() as i64;
        let length = if metre == 0 { 10 } else { 5 };
        for y in 0..length {
            canvas.put(x, i64::from(height) - 1 - y, INK);
        }
    }
    for metre in ticks(lo.y, hi.y) {
        let y = to_pixel(dvec2(0.0, metre as f64)).y.round() as i64;
        let length = if metre == 0 { 10 } else { 5 };
        for x in 0..length {
            canvas.put(x, y, INK);
        }
    }
    canvas
}

/// A picture size that keeps the longest view under ~1200 pixels.
pub fn default_pixels_per_metre(mesh: &Mesh) -> f64 {
    let (min, max) = mesh.bounds();
    let extent = (max - min).max_element().max(min.abs().max_element()).max(max.abs().max_element());
    (1200.0 / extent.max(1e-3)).min(200.0)
}

/// Writes `inspect-side.png`, `inspect-top.png` and `inspect-front.png`
/// into `dir`; returns their paths.
pub fn write_views(mesh: &Mesh, colors: &[Color], dir: &Path, pixels_per_metre: f64) -> Result<Vec<PathBuf>> {
    let mut written = Vec::new();
    for view in [View::Side, View::Top, View::Front] {
        let canvas = draw(mesh, colors, view, pixels_per_metre);
        let path = dir.join(format!("inspect-{}.png", view.name()));
        ufcsr::write_rgb_png(&path, [canvas.width, canvas.height], &canvas.rgb, png::Compression::Fast)?;
        written.push(path);
    }
    Ok(written)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::vec3;

    #[test]
    fn nearer_faces_hide_farther_ones_and_the_picture_has_the_vehicle_size() {
        let mut mesh = Mesh::default();
        // Right side (y = −1) red in front of a left side (y = +1) green.
        mesh.add_box(
            vec3(-2.0, -1.0, 0.0),
            vec3(2.0, 1.0, 2.0),
            [None, None, Some("left"), Some("right"), None, None],
        );
        let colors = [Color::from_rgb(0, 200, 0), Color::from_rgb(200, 0, 0)];
        let canvas = draw(&mesh, &colors, View::Side, 10.0);
        assert_eq!((canvas.width, canvas.height), (40 + 2 * MARGIN, 20 + 2 * MARGIN));
        let at = |x: u32, y: u32| {
            let i = ((y * canvas.width + x) * 3) as usize;
            [canvas.rgb[i], canvas.rgb[i + 1], canvas.rgb[i + 2]]
        };
        // A face seen square on keeps its colour exactly.
        assert_eq!(at(MARGIN + 5, MARGIN + 5), [200, 0, 0]);
        assert_eq!(at(2, 2), PAPER);
        let top = draw(&mesh, &colors, View::Top, 10.0);
        assert_eq!((top.width, top.height), (40 + 2 * MARGIN, 20 + 2 * MARGIN));
    }
}
