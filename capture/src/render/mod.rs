//! Rendering tiles: the device ([`gpu`]), the renderer that draws the unlit
//! palette-coloured vehicle and its occluders into a tile ([`renderer`]),
//! what it draws ([`vertex`]: vertices and the palette texture), its
//! pipeline and `shader.wgsl` ([`pipeline`]), the render targets and their
//! readback ([`target`]), the occlusion query that skips tiles the occluders
//! hide ([`occlusion`]) and the part of a tile the vehicle can cover
//! ([`scissor`]).

pub(crate) mod gpu;
pub(crate) mod occlusion;
pub(crate) mod pipeline;
pub(crate) mod renderer;
pub(crate) mod scissor;
pub(crate) mod target;
pub(crate) mod vertex;

pub use gpu::{Backend, Gpu};
pub use renderer::{RenderSetup, Renderer, TileDraw};
pub use target::PixelRect;
pub use vertex::{GpuPalette, Vertex, vehicle_vertices};
