//! Looking at a vehicle or a result: [`inspection`] the `inspect` command's
//! report (size, triangle quality, UVs, parts) with [`pictures`] of the
//! vehicle drawn on the CPU, and [`views`] a result's heatmap views redrawn
//! from its folder (the `views` command).

pub(crate) mod inspection;
pub(crate) mod pictures;
pub(crate) mod views;

pub use inspection::{
    InspectOptions, Inspection, PartInfo, Sliver, TriangleQuality, UvState, inspect, inspect_fleet,
    triangle_quality,
};
pub use views::{ViewValues, ViewsOptions, view_values, views_from_results};
