//! The Part Identification Texture (PIdT) and its legend.
//!
//! Each triangle's island is painted in its part's colour over its
//! conservative footprint dilated by one texel, so that every texel a pixel
//! of that triangle can name — including the neighbour an interpolated UV may
//! reach at the island's edge — is labelled. Texels of no island stay black
//! (`#000000`, which no part uses). The legend (`parts.csv`) lists each
//! part's name and colour.

use std::io::Write;
use std::path::Path;

use ufcsr::Color;

use crate::error::Result;
use crate::scene::mesh::Mesh;
use crate::texture::uv_islands::{Unwrapped, footprint};

/// Colour of texels that belong to no part.
pub const UNLABELLED_COLOR: Color = Color::from_rgb(0, 0, 0);

/// A PIdT as the image an archive carries (`pidt.png`): painted from the
/// parts ([`paint`]) or the user's own ([`super::own`]). The analyzer reads
/// it back resolved against the legend, a part per texel ([`ufcsr::Pidt`]).
#[derive(Debug, Clone)]
pub struct PidtImage {
    pub size: [u32; 2],
    /// RGB, row 0 at the top.
    pub rgb: Vec<u8>,
    pub part_colors: Vec<Color>,
    /// Texels labelled.
    pub labelled: u64,
    /// Texels claimed by two different parts (only possible with kept UVs;
    /// the first part keeps them).
    pub conflicts: u64,
}

impl PidtImage {
    /// The colour at texel (x, y).
    pub fn at(&self, x: u32, y: u32) -> Color {
        let i = ((y as usize) * (self.size[0] as usize) + x as usize) * 3;
        Color::from_rgb(self.rgb[i], self.rgb[i + 1], self.rgb[i + 2])
    }

    /// Share of the palette labelled.
    pub fn share(&self) -> f64 {
        self.labelled as f64 / (f64::from(self.size[0]) * f64::from(self.size[1]))
    }
}

/// Distinct, saturated legend colours: hues spread by the golden angle, with
/// alternating saturation and value so that neighbours differ.
pub(crate) fn part_colors(count: usize) -> Vec<Color> {
    let mut colors: Vec<Color> = Vec::with_capacity(count);
    let mut i = 0usize;
    while colors.len() < count {
        let hue = (i as f64 * 0.618_033_988_75).fract();
        let saturation = [0.85, 0.55, 1.0][i % 3];
        let value = [0.95, 0.75, 0.55][(i / 3) % 3];
        let color = hsv(hue, saturation, value);
        if color != UNLABELLED_COLOR && color != Color::DEFAULT_BACKGROUND && !colors.contains(&color) {
            colors.push(color);
        }
        i += 1;
    }
    colors
}

fn hsv(h: f64, s: f64, v: f64) -> Color {
    let sector = (h * 6.0).floor();
    let f = h * 6.0 - sector;
    let (p, q, t) = (v * (1.0 - s), v * (1.0 - f * s), v * (1.0 - (1.0 - f) * s));
    let (r, g, b) = match sector as i64 % 6 {
        0 => (v, t, p),
        1 => (q, v, p),
        2 => (p, v, t),
        3 => (p, q, v),
        4 => (t, p, v),
        _ => (v, p, q),
    };
    let byte = |c: f64| (c * 255.0).round().clamp(0.0, 255.0) as u8;
    Color::from_rgb(byte(r), byte(g), byte(b))
}

/// Paints the PIdT of an unwrapped mesh.
pub fn paint(mesh: &Mesh, unwrapped: &Unwrapped) -> PidtImage {
    let [w, h] = unwrapped.palette;
    let part_colors = part_colors(mesh.parts.len());
    let mut rgb = vec![0u8; (w as usize) * (h as usize) * 3];
    let (mut labelled, mut conflicts) = (0u64, 0u64);
    for (t, tri) in unwrapped.texel_uvs.iter().enumerate() {
        let color = part_colors[mesh.triangle_part[t] as usize];
        footprint(tri, unwrapped.palette, 1, |x, y| {
            let i = ((y as usize) * (w as usize) + x as usize) * 3;
            let old = Color::from_rgb(rgb[i], rgb[i + 1], rgb[i + 2]);
            if old == UNLABELLED_COLOR {
                rgb[i..i + 3].copy_from_slice(&color.rgb());
                labelled += 1;
            } else if old != color {
                conflicts += 1;
            }
        });
    }
    PidtImage { size: [w, h], rgb, part_colors, labelled, conflicts }
}

/// Writes the PIdT as an 8-bit RGB PNG.
pub(crate) fn write_png(pidt: &PidtImage, path: &Path) -> Result<()> {
    ufcsr::files::write_rgb_png(path, [pidt.size[0], pidt.size[1]], &pidt.rgb, png::Compression::Fast)?;
    Ok(())
}

/// Writes the legend `name,color`.
pub(crate) fn write_legend(mesh: &Mesh, pidt: &PidtImage, path: &Path) -> Result<()> {
    ufcsr::files::write_atomically(path, |w| {
        writeln!(w, "name,color")?;
        for (name, color) in mesh.parts.iter().zip(&pidt.part_colors) {
            writeln!(w, "{},{color}", ufcsr::output::csv_field(name))?;
        }
        Ok(())
    })?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::demo;
    use crate::texture::uv_islands::{background_texel, unwrap_islands};

    #[test]
    fn every_island_texel_is_labelled_with_its_part() {
        let truck = demo::truck();
        let palette = [512, 512];
        let unwrapped = unwrap_islands(&truck, palette).unwrap();
        let pidt = paint(&truck, &unwrapped);
        assert_eq!(pidt.conflicts, 0);
        for (t, tri) in unwrapped.texel_uvs.iter().enumerate() {
            let color = pidt.part_colors[truck.triangle_part[t] as usize];
            footprint(tri, palette, 1, |x, y| {
                assert_eq!(pidt.at(x, y), color, "triangle {t} texel ({x}, {y})")
            });
        }
        let (bx, by) = background_texel(palette).unwrap();
        assert_eq!(pidt.at(bx, by), UNLABELLED_COLOR);
        assert!(pidt.share() > 0.2 && pidt.share() < 1.0, "{}", pidt.share());
        let colors = part_colors(80);
        let mut unique = colors.clone();
        unique.sort();
        unique.dedup();
        assert_eq!(unique.len(), 80);
    }
}
