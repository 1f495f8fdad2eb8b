//! External palettes: a PNG whose texels all have different colours.
//!
//! The canonical palette is computed in the shader and never stored; an
//! external one is uploaded as a texture and read with `textureLoad`. Its
//! texel that holds the background colour (if any) is left out of the
//! unwrap, exactly like index 4095 of the canonical palette.

use std::collections::HashMap;
use std::path::Path;

use ufcsr::Color;

use crate::archive::read_rgb_png;
use crate::error::{CaptureError, Result};

/// A loaded external palette.
#[derive(Debug, Clone)]
pub struct ExternalPalette {
    pub size: [u32; 2],
    /// RGB, row 0 at the top.
    pub rgb: Vec<u8>,
}

impl ExternalPalette {
    /// Loads and checks a palette PNG (8-bit RGB or RGBA, unique colours).
    pub fn load(path: &Path) -> Result<ExternalPalette> {
        let (size, rgb) = read_rgb_png(path)?;
        let palette = ExternalPalette { size, rgb };
        let index = palette.index();
        let texels = (size[0] as usize) * (size[1] as usize);
        if index.len() != texels {
            return Err(CaptureError::bad_input(
                path,
                format!("palette colours must be unique, but only {} of {texels} are", index.len()),
            ));
        }
        Ok(palette)
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
