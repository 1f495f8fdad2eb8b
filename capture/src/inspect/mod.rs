//! Looking at a vehicle or a result: [`inspection`] the `inspect` command's
//! report (size, triangle quality, UVs, parts) with [`pictures`] of the
//! vehicle drawn on the CPU, and [`heatmap_views_gpu`] a result's heatmap
//! views drawn with the GPU renderer (the `views` command).

pub mod heatmap_views_gpu;
pub mod inspection;
pub mod pictures;

pub use inspection::*;
