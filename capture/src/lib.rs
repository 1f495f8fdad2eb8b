//! # ufcsr-capture — record UFCSR archives with a headless, exact wgpu renderer
//!
//! Replaces the Unity project of the UFCSR paper: a vehicle mesh is unwrapped
//! so that every triangle owns its own texels of the canonical palette, a Part
//! Identification Texture (PIdT) labels those texels, and each frame of a
//! scenario is rendered unlit from both eyes of a pedestrian into tiles whose
//! pixels name the texel they show. The archive is what `ufcsr-analyze` reads.
//!
//! Module map: [`track`] keyframes, [`scenario`] a timed vehicle motion,
//! [`unity`] import of Unity scenarios, [`mesh`] geometry and loaders
//! ([`model_files`] reads OBJ/MTL safely; every input goes through the
//! analyzer's bounded, non-blocking readers),
//! [`vehicle`] and [`regions`] vehicle checks and parts by region,
//! [`demo`] the built-in truck and intersection, [`degenerate_mesh`] a
//! generated vehicle of zero-area, needle and sliver triangles, [`scene`] the JSON scene
//! file, [`unwrap`] island packing, [`palette`] external palettes, [`pidt`]
//! label painting, [`own_pidt`] a user's own PIdT, [`rig`] cameras and tiles,
//! [`gpu`] device creation, [`render`] the renderer (with its
//! pipeline and [`render_target`] targets and readback); the capture job:
//! [`options`] what to do, [`archive`] its stages, [`frame_capture`] one
//! frame, [`scissor`] the part of a tile the vehicle can cover, [`tile_sink`]
//! where tiles go, [`scene_checks`] bounds and impossible scenes (near and
//! far plane, eye inside the vehicle, implausible motion), [`encoder_pool`] the PNG sink, [`manifest_builder`] the
//! manifest, [`count_sink`] counting without PNGs, [`capture_shard`] one
//! capture as several jobs;
//! [`study`] and [`study_plot`] the resolution study; [`unobstructed`] the
//! exact ray-traced reference measure (CPU and GPU); [`inspect`] and [`views`] look at a
//! vehicle before capturing.

pub mod archive;
pub mod error;
pub mod inspect;
pub mod render;
pub mod scene;
pub mod study;
pub mod texture;
pub mod unobstructed;

pub use error::{CaptureError, Result};
