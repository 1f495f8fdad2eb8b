//! # ufcsr-capture — record UFCSR archives with a headless, exact wgpu renderer
//!
//! Replaces the Unity project of the UFCSR paper: a vehicle mesh is unwrapped
//! so that every triangle owns its own texels of the canonical palette, a Part
//! Identification Texture (PIdT) labels those texels, and each frame of a
//! scenario is rendered unlit from both eyes of a pedestrian into tiles whose
//! pixels name the texel they show. The archive is what `ufcsr-analyze` reads.
//!
//! Module map: [`track`] keyframes, [`unity`] import of Unity scenarios,
//! [`mesh`] geometry and loaders, [`demo`] the built-in truck and intersection,
//! [`scene`] the JSON scene file, [`unwrap`] island packing, [`palette`]
//! external palettes, [`pidt`] label painting, [`rig`] cameras and tiles,
//! [`gpu`] device creation, [`render`] the renderer, [`archive`] the capture
//! loop and output files.

pub mod archive;
pub mod demo;
pub mod error;
pub mod gpu;
pub mod inspect;
pub mod mesh;
pub mod own_pidt;
pub mod palette;
pub mod pidt;
pub mod regions;
pub mod render;
pub mod rig;
pub mod scene;
pub mod track;
pub mod unity;
pub mod unwrap;
pub mod vehicle;
pub mod views;

pub use error::{CaptureError, Result};
