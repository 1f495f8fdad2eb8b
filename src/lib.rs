//! # ufcsr — Unwrapped Full Color Space Recording
//!
//! Counts how often each texel of a vehicle's unwrapped surface is visible in
//! captured frames, joins the counts with a Part Identification Texture into
//! per-part statistics, and renders a heatmap texture.

pub mod color;
pub mod error;
pub mod manifest;
pub mod output;

pub use color::{COLOR_COUNT, Color, ParseColorError};
pub use error::{Error, Result};
pub use manifest::{MANIFEST_FILE, MANIFEST_SCHEMA, Manifest, PaletteSpec, TileEntry};
pub use output::{write_atomically, write_bytes_atomically};
