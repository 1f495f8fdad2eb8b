//! Looking at a vehicle or a result: [`inspection`] the `inspect` command's
//! report (size, triangle quality, UVs, parts) with [`pictures`] of the
//! vehicle drawn on the CPU, and [`heatmap_views_gpu`] a result's heatmap
//! views drawn with the GPU renderer (the `views` command).

pub(crate) mod heatmap_views_gpu;
pub(crate) mod inspection;
pub(crate) mod pictures;

pub use heatmap_views_gpu::{ViewValues, ViewsOptions, view_values, views_from_results, write_views_gpu};
pub use inspection::{
    InspectOptions, Inspection, PartInfo, Sliver, TriangleQuality, UvState, inspect, triangle_quality,
};
