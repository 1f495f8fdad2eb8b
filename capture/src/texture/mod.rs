//! The vehicle's surface as texels: the UV unwrap that gives every triangle
//! its own texels of the palette ([`uv_islands`]), and the Part
//! Identification Texture that labels the texels ([`pidt`]: painted from the
//! parts, or the user's own), and where a model's own UVs overlap
//! ([`uv_overlaps`], for `--keep-uvs` and `inspect`). The palette itself, canonical or an image, is
//! the analyzer's [`ufcsr::Fcsp`]: one loader and one check of unique
//! colours for both crates.

pub(crate) mod pidt;
pub(crate) mod uv_islands;
pub(crate) mod uv_overlaps;

pub use pidt::{OwnLabelFiles, PidtImage, UNLABELLED_COLOR, paint_pidt};
pub use uv_islands::{
    Unwrapped, background_texel, footprint, keep_uvs, unwrap_islands, unwrap_islands_avoiding, uv_overlaps,
};
pub use uv_overlaps::{PartOverlap, UvOverlaps};
