//! The vehicle's surface as texels: the UV unwrap that gives every triangle
//! its own texels of the palette ([`uv_islands`]), an external palette image
//! instead of the canonical one ([`external_palette`]), and the Part
//! Identification Texture that labels the texels ([`pidt`]: painted from the
//! parts, or the user's own).

pub mod external_palette;
pub mod pidt;
pub mod uv_islands;
