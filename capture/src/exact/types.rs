//! What the exact measure works on: surface samples grouped by texel, one
//! eye at one frame, the options, and the tolerances both paths (hierarchy, brute
//! force) apply the same way. `docs/science-exact.md` explains the
//! tolerances and why they have these values.

use glam::{DMat4, DVec3, DVec4};

/// Edge-on, relative part: the eye is edge-on to a surface when its height
/// above the surface's plane is at most this share of its distance (plus the
/// geometry's own f32 uncertainty, [`EDGE_ON_F32_ULPS`]). 1e-6 rad ≈ 0.2″: a
/// surface seen that flat projects to a band < 1e-4 px high even at 480 px/°,
/// and the renderer's f32 arithmetic cannot tell its side either.
pub const EDGE_ON_RELATIVE: f64 = 1e-6;
/// Edge-on, geometric part: a triangle's plane is known only to the f32
/// rounding of its corners, this many units of f32 (2⁻²⁴) of their largest
/// coordinate, plus [`EDGE_ON_RELATIVE`] of its longest edge.
pub const EDGE_ON_F32_ULPS: f64 = 4.0;
/// The surface lift, relative to the vehicle's size: a point is moved this
/// share of the vehicle's bounding-box diagonal off its surface towards the
/// eye so that its ray does not hit its own triangle (1e-5: 0.1 mm on a 10 m
/// truck; a model ×0.01 or ×100 gets the same relative lift). The scene
/// checks call surfaces this near one another coincident: the same number.
pub const SURFACE_LIFT_RELATIVE: f64 = crate::scene::coincident::COINCIDENT_RELATIVE;
/// Square degrees per steradian.
pub const DEG2_PER_SR: f64 = (180.0 / std::f64::consts::PI) * (180.0 / std::f64::consts::PI);

/// One sample point of a texel's footprint: the centroid of one piece of
/// (texel sub-cell ∩ triangle), mapped onto the vehicle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfaceSample {
    /// Vehicle frame, metres.
    pub position: DVec3,
    /// Unit normal of its triangle.
    pub normal: DVec3,
    /// Area of the surface this sample stands for, m².
    pub area_m2: f64,
    /// The geometric part of the edge-on tolerance of its triangle, metres.
    pub edge_on_m: f64,
    /// The vehicle triangle it lies on.
    pub triangle: u32,
}

/// A sampled texel: its index in the palette, its part and its samples
/// (`samples[first..first + count]` of [`SurfaceSamples`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SampledTexel {
    pub texel: u32,
    pub part: u32,
    pub first: u32,
    pub count: u32,
}

/// Every sampled texel with its sample points, in texel order.
#[derive(Debug, Clone, Default)]
pub struct SurfaceSamples {
    pub texels: Vec<SampledTexel>,
    pub samples: Vec<SurfaceSample>,
    /// Per part: texels with a footprint on the mesh (sampled or not).
    pub texels_per_part: Vec<u64>,
    /// Per part: the surface area those texels cover, m² (all of them).
    pub area_per_part_m2: Vec<f64>,
    /// K: samples per side of a texel (K × K sub-cells).
    pub samples_per_side: u32,
}

impl SurfaceSamples {
    /// The samples of one texel.
    pub fn of(&self, texel: &SampledTexel) -> &[SurfaceSample] {
        &self.samples[texel.first as usize..(texel.first + texel.count) as usize]
    }
}

/// One eye at one frame, with everything a ray needs precomputed in f64.
#[derive(Debug, Clone)]
pub struct EyeFrame {
    /// The eye in the vehicle frame.
    pub eye_in_vehicle: DVec3,
    /// The eye in the scene's local frame (world minus the scene anchor).
    pub eye_local: DVec3,
    /// Vehicle frame → local frame.
    pub vehicle_to_local: DMat4,
    /// Vehicle frame → the eye's clip space (reversed Z).
    pub vehicle_to_clip: DMat4,
    /// `w − z` of the eye itself in clip space (negative): with a point's
    /// `w − z` it places the near plane on the segment between them.
    pub eye_near_margin: f64,
    /// How far a point is lifted off its surface, metres.
    pub lift_m: f64,
    /// Local frame → each moving occluder's own frame at this frame (in
    /// `Obstacles::moving` order).
    pub local_to_moving: Vec<DMat4>,
}

/// `m · (p, 1)` summed column by column in a fixed order, so every path
/// that moves a point rounds alike.
pub(crate) fn transform_point(m: &DMat4, p: DVec3) -> DVec4 {
    m.x_axis * p.x + m.y_axis * p.y + m.z_axis * p.z + m.w_axis
}

/// How to measure: which share of the texels, seeded how, how finely each
/// texel is sampled, on which device.
#[derive(Debug, Clone, Copy)]
pub struct MeasureOptions {
    /// Share of the texels to measure, in (0, 1].
    pub sample: f64,
    pub seed: u64,
    /// K: each texel's footprint is sampled on K × K sub-cells (1 ≤ K ≤ 16).
    pub texel_samples: u32,
    /// `--placement`: also measure candidate eHMI placements
    /// (`placement-frames.csv`, `docs/placement.md`).
    pub placement: Option<PlacementCandidates>,
}

/// Candidate patch centres are this far apart by default, metres.
pub const DEFAULT_PATCH_SPACING_M: f64 = 0.10;

/// What `--placement` measures.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlacementCandidates {
    /// Display patches of width × height, metres (`--display WxH`); none:
    /// the parts only.
    pub display_m: Option<[f64; 2]>,
    /// Spacing of the patch centres, metres (`--patch-spacing`).
    pub spacing_m: f64,
}

impl PlacementCandidates {
    /// The spacing is at least 1 cm (a finer grid only multiplies the
    /// patches); the display size was checked when it was parsed.
    pub fn check(&self) -> crate::error::Result<()> {
        if !(self.spacing_m.is_finite() && self.spacing_m >= 0.01) {
            return Err(crate::error::CaptureError::BadOptions(format!(
                "--patch-spacing {}: must be at least 0.01 m",
                self.spacing_m
            )));
        }
        Ok(())
    }
}

impl Default for PlacementCandidates {
    fn default() -> PlacementCandidates {
        PlacementCandidates { display_m: None, spacing_m: DEFAULT_PATCH_SPACING_M }
    }
}

/// The default K (`docs/science-exact.md`): on demo scenario A at the
/// default 4096² palette, K = 1 is within 0.46 pp (share L1) of K = 4 and its
/// angular area within 3e-4, at a quarter of the rays; K = 1 still samples
/// every texel piece (edge texels included), so it has the any-part meaning.
pub const DEFAULT_TEXEL_SAMPLES: u32 = 1;

impl Default for MeasureOptions {
    fn default() -> MeasureOptions {
        MeasureOptions { sample: 1.0, seed: 1, texel_samples: DEFAULT_TEXEL_SAMPLES, placement: None }
    }
}

/// Per texel, what the eye-frames saw.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct TexelVisibility {
    /// Per sampled texel: eye-frames in which any of its samples is visible.
    pub counts: Vec<u32>,
    /// Per sampled texel: solid angle of its visible samples summed over the
    /// eye-frames, steradians.
    pub solid_angle_sr: Vec<f64>,
    /// Per part, per eye-frame (`part * eye_frames + eye_frame`): seen at all.
    pub part_seen: Vec<bool>,
    /// Per part and eye-frame, what its sampled texels add up to (the CPU
    /// fills it; the study compares settings eye-frame by eye-frame with it).
    pub per_eye_frame: Option<PartEyeFrames>,
}

/// Per part and eye-frame (`part * eye_frames + eye_frame`): sampled texels
/// visible (any sample) and the solid angle of their visible samples, sr.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PartEyeFrames {
    pub texels: Vec<u32>,
    pub solid_angle_sr: Vec<f64>,
}
