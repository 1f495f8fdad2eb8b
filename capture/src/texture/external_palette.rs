//! External palettes: a PNG whose texels all have different colours.
//!
//! The canonical palette is computed in the shader and never stored; an
//! external one is uploaded as a texture and read with `textureLoad`. Its
//! texel that holds the background colour (if any) is left out of the
//! unwrap, exactly like index 4095 of the canonical palette.

use std::collections::HashMap;
use std::path::Path;

use ufcsr::Color;

use crate::error::Result;

/// A loaded external palette.
#[derive(Debug, Clone)]
pub struct ExternalPalette {
    pub size: [u32; 2],
    /// RGB, row 0 at the top.
    pub rgb: Vec<u8>,
}

impl ExternalPalette {
    /// Loads and checks a palette PNG (unique colours) with the analyzer's
    /// palette loader, whose error names a repeated colour and both places.
    pub fn load(path: &Path) -> Result<ExternalPalette> {
        let palette = ufcsr::Fcsp::from_png(path)?;
        let size = [palette.width(), palette.height()];
        let rgb = (0..palette.texel_count())
            .flat_map(|texel| Color::from_packed(palette.color_of(texel)).rgb())
            .collect();
        Ok(ExternalPalette { size, rgb })
    }

    /// Colour → texel index.
    pub fn index(&self) -> HashMap<Color, u32> {
        self.rgb
            .chunks_exact(3)
            .enumerate()
            .map(|(i, p)| (Color::from_rgb(p[0], p[1], p[2]), i as u32))
            .collect()
    }

    /// The texel that holds `color`, if any.
    pub fn texel_of(&self, color: Color) -> Option<(u32, u32)> {
        let rgb = color.rgb();
        let i = self.rgb.chunks_exact(3).position(|p| p == rgb)? as u32;
        Some((i % self.size[0], i / self.size[0]))
    }

    /// RGBA texels for the GPU.
    pub fn rgba(&self) -> Vec<u8> {
        self.rgb.chunks_exact(3).flat_map(|p| [p[0], p[1], p[2], 255]).collect()
    }

    /// The canonical palette of `size` as an image (for tests and tools).
    pub fn canonical(size: [u32; 2]) -> ExternalPalette {
        let count = (size[0] as usize) * (size[1] as usize);
        let rgb = (0..count as u32).flat_map(|i| Color::from_packed(i).rgb()).collect();
        ExternalPalette { size, rgb }
    }
}
