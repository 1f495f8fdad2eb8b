//! Orthographic pictures of the vehicle with its parts coloured, for
//! `inspect`, drawn with the analyzer's CPU rasterizer ([`ufcsr::output::ZBuffer`],
//! the one its eight heatmap views use) and written as PNG.
//!
//! Faces take their part's PIdT colour (the same [`crate::texture::pidt::part_colors`]
//! a capture paints), shaded a little by how squarely they face the viewer
//! so that the shape reads. A black cross marks the vehicle's origin, a grey
//! line the ground (z = 0) and ticks every metre along the edges give scale.
//! Under each picture a legend ([`with_legend`], the analyzer's
//! [`ufcsr::output::TextLayout`]) says which way it looks, what the marks are, and
//! names every part beside its colour (issue 35: the pictures had no key).

use std::path::{Path, PathBuf};

use glam::{DVec2, DVec3, dvec2};
use ufcsr::{Color, output::LEGEND_TEXT_PX, output::LegendEntry, output::TextLayout, output::ZBuffer};

use crate::error::Result;
use crate::scene::mesh::Mesh;

/// Which way the picture looks.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum View {
    /// From the vehicle's right (−y), front to the right of the picture.
    Side,
    /// From above, front to the right, the vehicle's left at the top.
    Top,
    /// From the front (+x), the vehicle's left on the picture's right.
    Front,
}

impl View {
    /// The file-name word.
    pub(crate) fn name(self) -> &'static str {
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

    /// What the picture shows, for its legend.
    fn title(self) -> &'static str {
        match self {
            View::Side => "From the vehicle's right (−y), front to the right.",
            View::Top => "From above, front to the right, the vehicle's left at the top.",
            View::Front => "From the front (+x), the vehicle's left on the right.",
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
pub(crate) fn default_pixels_per_metre(mesh: &Mesh) -> f64 {
    let (min, max) = mesh.bounds();
    let extent = (max - min).max_element().max(min.abs().max_element()).max(max.abs().max_element());
    (1200.0 / extent.max(1e-3)).min(200.0)
}

/// The legend entries of the parts: each part's colour and name.
pub(crate) fn part_entries(names: &[String], colors: &[Color]) -> Vec<LegendEntry> {
    names
        .iter()
        .zip(colors)
        .map(|(name, color)| LegendEntry { color: color.rgb(), label: name.clone() })
        .collect()
}

/// What the marks of the views are, for their legend.
const MARKS: &str = "Black cross: the vehicle's origin; grey line: the ground (z = 0); ticks every metre along the \
     left and bottom edges. Parts in their pidt.png colours (as in inspect-parts.csv):";

/// Narrowest picture with a legend, pixels (a narrow front view is widened
/// with paper on the right so its legend has room).
pub(crate) const LEGEND_MIN_WIDTH: u32 = 480;

/// A picture with a legend band appended below it: `title` wrapped to the
/// width, then a swatch and label per entry. Returns the picture, its size
/// and where the legend's texts and swatches are.
pub(crate) fn with_legend(
    rgb: &[u8],
    [width, height]: [u32; 2],
    title: &str,
    entries: &[LegendEntry],
) -> (Vec<u8>, [u32; 2], TextLayout) {
    let wide = width.max(LEGEND_MIN_WIDTH);
    let room = f64::from(wide - 16);
    let mut layout = TextLayout::new(LEGEND_TEXT_PX);
    let y = layout.paragraph(title, 8, height + 6, room);
    let tall = layout.entries(entries, 8, y, room) + 6;
    let mut out = PAPER.repeat((wide * tall) as usize);
    let row = width as usize * 3;
    for y in 0..height as usize {
        let to = y * wide as usize * 3;
        out[to..to + row].copy_from_slice(&rgb[y * row..(y + 1) * row]);
    }
    layout.draw(&mut out, [wide, tall]);
    (out, [wide, tall], layout)
}

/// Writes `inspect-side.png`, `inspect-top.png` and `inspect-front.png`
/// into `dir`, each with its legend; returns their paths.
pub(crate) fn write_views(
    mesh: &Mesh,
    colors: &[Color],
    dir: &Path,
    pixels_per_metre: f64,
) -> Result<Vec<PathBuf>> {
    let mut written = Vec::new();
    let entries = part_entries(&mesh.parts, colors);
    for view in [View::Side, View::Top, View::Front] {
        let canvas = draw(mesh, colors, view, pixels_per_metre);
        let title = format!("{} {MARKS}", view.title());
        let (rgb, size, _) = with_legend(&canvas.rgb, [canvas.width, canvas.height], &title, &entries);
        let path = dir.join(format!("inspect-{}.png", view.name()));
        ufcsr::files::write_rgb_png(&path, size, &rgb, png::Compression::Fast)?;
        written.push(path);
    }
    Ok(written)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::vec3;

    /// A 4 × 2 × 2 m box whose right side (y = −1, red) is in front of its
    /// left side (y = +1, green) seen from the right; the two parts' colours.
    fn two_sided_box() -> (Mesh, [Color; 2]) {
        let mut mesh = Mesh::default();
        mesh.add_box(
            vec3(-2.0, -1.0, 0.0),
            vec3(2.0, 1.0, 2.0),
            [None, None, Some("left"), Some("right"), None, None],
        );
        (mesh, [Color::from_rgb(0, 200, 0), Color::from_rgb(200, 0, 0)])
    }

    #[test]
    fn nearer_faces_hide_farther_ones_and_the_picture_has_the_vehicle_size() {
        let (mesh, colors) = two_sided_box();
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

    #[test]
    fn the_legend_grows_the_picture_and_shows_every_part_in_its_color() {
        let (mesh, colors) = two_sided_box();
        let canvas = draw(&mesh, &colors, View::Side, 10.0);
        let entries = part_entries(&mesh.parts, &colors);
        assert_eq!(entries.len(), mesh.parts.len());
        let (rgb, [width, height], layout) =
            with_legend(&canvas.rgb, [canvas.width, canvas.height], View::Side.title(), &entries);
        assert_eq!(width, LEGEND_MIN_WIDTH, "a narrow picture is widened for its legend");
        assert!(height > canvas.height + 2 * ufcsr::output::LEGEND_LINE, "{height}");
        // The drawing is unchanged at the top left.
        let at = |x: i32, y: i32| {
            let i = ((y as u32 * width + x as u32) * 3) as usize;
            [rgb[i], rgb[i + 1], rgb[i + 2]]
        };
        assert_eq!(at(MARGIN as i32 + 5, MARGIN as i32 + 5), [200, 0, 0]);
        // A swatch in each part's colour, below the drawing, and its name.
        assert_eq!(layout.swatches.len(), mesh.parts.len());
        for (index, (part, expected)) in mesh.parts.iter().zip(&colors).enumerate() {
            let (_, y, color) = layout.swatches[index];
            assert!(y as u32 >= canvas.height);
            assert_eq!(color, expected.rgb());
            let (cx, cy) = layout.swatch_centre(index);
            assert_eq!(at(cx, cy), expected.rgb());
            assert!(layout.texts.iter().any(|(_, _, t)| t == part), "{part} not in the legend");
        }
    }
}
