//! The vehicle's surface as texels: the UV unwrap that gives every triangle
//! its own texels of the palette ([`uv_islands`]), an external palette image
//! instead of the canonical one ([`external_palette`]), and the Part
//! Identification Texture that labels the texels ([`pidt`]: painted from the
//! parts, or the user's own).

pub(crate) mod external_palette;
pub(crate) mod pidt;
pub(crate) mod uv_islands;

pub use external_palette::ExternalPalette;
pub use pidt::{OwnLabels, PaintedPidt, UNLABELLED_COLOR, paint_pidt};
pub use uv_islands::{
    Unwrapped, background_texel, footprint, keep_uvs, parse_palette_size, unwrap_islands,
    unwrap_islands_avoiding,
};
