//! Rendering tiles: the device ([`gpu`]), the renderer that draws the unlit
//! palette-coloured vehicle and its occluders into a tile ([`renderer`]),
//! its pipeline and `shader.wgsl` ([`pipeline`]), the render targets and
//! their readback ([`target`]), the occlusion query that skips tiles the
//! occluders hide ([`occlusion`]) and the part of a tile the vehicle can
//! cover ([`scissor`]).

pub mod gpu;
pub(crate) mod occlusion;
pub(crate) mod pipeline;
pub mod renderer;
pub mod scissor;
pub mod target;

pub use renderer::*;
