//! The exact reference measure: per-texel visibility in texture space,
//! by f64 ray casts instead of pixels.
//!
//! What the paper means by a count — "how many times each point is
//! unobstructed to a pedestrian" — measured directly, so it does not depend
//! on pixels per degree or tiling, and defined so that the rendered measures
//! converge to it as pixels per degree grow (`docs/science-exact.md`):
//!
//! * **count** (any-part visibility): a texel counts once per eye-frame in
//!   which any part of its footprint on the vehicle is visible, tested on
//!   K × K stratified samples of the footprint (`--texel-samples K`);
//! * **angular area** (deg²·s) and **exposure** (s) per part, in the result's
//!   `measures` block under the rendered measures' names: the ray-traced
//!   solid angle Σ area · cos θ / r² of the visible samples, integrated over
//!   time, and the time the part is seen.
//!
//! The folder: [`points`] where the samples lie, [`geometry`] the scene and
//! eye-frames for rays, [`bvh`] the hierarchy, [`rules`] what visible
//! means for one sample (edge-on, frustum and near plane, lift, occlusion),
//! [`cpu`] the measure's loop on every core, [`estimator`] the `--sample`
//! estimates, [`measure`] the command
//! (archive skeleton and results), [`types`] what they share, [`accuracy`]
//! how far a rendered setting is from it (what `study` recommends by),
//! [`placement`] candidate eHMI placements measured with the same rules
//! (`--placement`, `docs/placement.md`).

pub(crate) mod accuracy;
pub(crate) mod bvh;
pub(crate) mod cpu;
pub(crate) mod estimator;
pub(crate) mod geometry;
pub(crate) mod measure;
pub(crate) mod placement;
pub(crate) mod points;
pub(crate) mod rules;
pub(crate) mod types;

pub use bvh::TriangleBvh;
pub use cpu::texel_visibility;
pub use estimator::{PartEstimate, estimate_parts};
pub use geometry::{Obstacles, eye_frame, eye_frames, seconds_per_frame};
pub use measure::{MAX_TEXEL_SAMPLES, UnobstructedCapture, measure_unobstructed};
pub use placement::{
    PLACEMENT_FRAMES_FILE, PLACEMENT_PATCHES_COLUMNS, PLACEMENT_PATCHES_FILE, PlacementWritten, parse_display,
};
pub use points::{is_sampled, surface_samples};
pub use rules::{Tracer, visible_solid_angle};
pub use types::{
    DEFAULT_PATCH_SPACING_M, DEFAULT_TEXEL_SAMPLES, DEG2_PER_SR, EDGE_ON_F32_ULPS, EDGE_ON_RELATIVE,
    EyeFrame, MeasureOptions, PlacementCandidates, SURFACE_LIFT_RELATIVE, SampledTexel, SurfaceSample,
    SurfaceSamples, TexelVisibility,
};
