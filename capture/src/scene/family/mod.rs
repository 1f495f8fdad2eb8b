//! The parametric vehicle family: a sedan, an SUV, a van, a pickup and a bus,
//! each built from seven documented dimensions ([`BodyDims`]) with the demo
//! truck's part vocabulary where it applies (bumpers, grill, hood,
//! windshield and its rails, B-pillars, fenders, doors, windows, mirrors,
//! headlights, tail lights, licence plates, tyres and rims, roof, …), so that
//! a study can span body types without external models.
//!
//! Why a family and not five meshes: the display-placement answer depends on
//! the body type and on the height of its parts relative to the eyes, so a
//! study varies them; dimensions make the variation explicit and testable.
//! The bodies are as exact as the truck: built from axis-aligned boxes and
//! planar quads whose coplanar neighbours share edges only (no two triangles
//! fight in the depth buffer), in the same frame as the truck (x forward,
//! y left, z up, metres, the origin on the ground under the centre), with a
//! bounding box equal to the dimensions (length × width × height; only the
//! side mirrors stand outside the width, as on a real vehicle).
//!
//! [`layout`] turns the dimensions into the positions of the body's breaks
//! (where the windshield starts, where the doors end) and refuses
//! dimensions no body of that type can have, naming the field; [`build`]
//! makes the mesh from the layout. The defaults and their sources are in
//! `docs/vehicles.md`.

mod build;
mod layout;

use crate::error::{CaptureError, Result};
use crate::scene::mesh::Mesh;

/// A body type of the family.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum BodyType {
    Sedan,
    Suv,
    Van,
    Pickup,
    Bus,
}

impl BodyType {
    /// Every body type, in the order the docs list them.
    pub const ALL: [BodyType; 5] =
        [BodyType::Sedan, BodyType::Suv, BodyType::Van, BodyType::Pickup, BodyType::Bus];

    /// The name on the command line and in files: `sedan`, `suv`, `van`, `pickup`, `bus`.
    pub fn name(self) -> &'static str {
        match self {
            BodyType::Sedan => "sedan",
            BodyType::Suv => "suv",
            BodyType::Van => "van",
            BodyType::Pickup => "pickup",
            BodyType::Bus => "bus",
        }
    }

    /// The body type named `s` (case-insensitive), if any.
    pub fn parse(s: &str) -> Option<BodyType> {
        BodyType::ALL.into_iter().find(|b| b.name().eq_ignore_ascii_case(s.trim()))
    }
}

/// The dimensions a body is built from, metres and degrees.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BodyDims {
    /// Overall length, bumper to bumper (the licence plates included).
    pub length_m: f64,
    /// Body width without mirrors.
    pub width_m: f64,
    /// Overall height (the roof).
    pub height_m: f64,
    /// From the front face to the windshield's base, along x.
    pub bonnet_length_m: f64,
    /// Height of the hood, and of the belt line along the sides.
    pub bonnet_height_m: f64,
    /// The windshield's angle from the vertical (0 = upright, as a bus).
    pub windshield_rake_deg: f64,
    /// Between the axles (centred on the body).
    pub wheelbase_m: f64,
}

impl BodyDims {
    /// These dimensions with the ones `overrides` gives in their place (the one type a scene
    /// file's `vehicle.dims` and a design's vehicle level both use).
    pub fn with(self, overrides: &ufcsr::format::BodyDimsOverride) -> BodyDims {
        BodyDims {
            length_m: overrides.length_m.unwrap_or(self.length_m),
            width_m: overrides.width_m.unwrap_or(self.width_m),
            height_m: overrides.height_m.unwrap_or(self.height_m),
            bonnet_length_m: overrides.bonnet_length_m.unwrap_or(self.bonnet_length_m),
            bonnet_height_m: overrides.bonnet_height_m.unwrap_or(self.bonnet_height_m),
            windshield_rake_deg: overrides.windshield_rake_deg.unwrap_or(self.windshield_rake_deg),
            wheelbase_m: overrides.wheelbase_m.unwrap_or(self.wheelbase_m),
        }
    }

    /// Typical dimensions of the class (sources and which figures are ours: `docs/vehicles.md`).
    pub fn typical(body: BodyType) -> BodyDims {
        let dims = |length_m,
                    width_m,
                    height_m,
                    bonnet_length_m,
                    bonnet_height_m,
                    windshield_rake_deg,
                    wheelbase_m| {
            BodyDims {
                length_m,
                width_m,
                height_m,
                bonnet_length_m,
                bonnet_height_m,
                windshield_rake_deg,
                wheelbase_m,
            }
        };
        match body {
            // Toyota Camry XV20 (1997–2001): 4785 × 1780 × 1415 mm, wheelbase 2670 mm.
            BodyType::Sedan => dims(4.785, 1.78, 1.415, 1.2, 0.95, 62.0, 2.67),
            // A compact SUV (about a Toyota RAV4): ours.
            BodyType::Suv => dims(4.6, 1.85, 1.7, 1.1, 1.05, 58.0, 2.69),
            // Ford Transit (2014–): 2113 mm wide, 3300 mm short wheelbase; length and height ours.
            BodyType::Van => dims(5.53, 2.113, 2.5, 0.9, 1.15, 40.0, 3.3),
            // The demo truck (about a 2015 F-150): 5.9 × 2.0 × 1.9 m, axles 3.7 m apart.
            BodyType::Pickup => dims(5.9, 2.0, 1.9, 1.35, 1.2, 43.0, 3.7),
            // Mercedes-Benz Citaro (12 m, two doors): 11950 × 2550 × 3076 mm,
            // wheelbase 5845 mm; the belt at the 370 mm floor + 950 mm waistline.
            BodyType::Bus => dims(11.95, 2.55, 3.076, 0.2, 1.32, 5.0, 5.845),
        }
    }

    /// The fields by name, in declaration order (for messages and files).
    pub fn fields(&self) -> [(&'static str, f64); 7] {
        [
            ("length_m", self.length_m),
            ("width_m", self.width_m),
            ("height_m", self.height_m),
            ("bonnet_length_m", self.bonnet_length_m),
            ("bonnet_height_m", self.bonnet_height_m),
            ("windshield_rake_deg", self.windshield_rake_deg),
            ("wheelbase_m", self.wheelbase_m),
        ]
    }
}

/// The mesh of `body` with `dims`, in the truck's frame ([`crate::scene::demo::truck`]);
/// dimensions no such body can have are a [`CaptureError::BadOptions`] naming the field.
pub fn body_mesh(body: BodyType, dims: &BodyDims) -> Result<Mesh> {
    let layout = layout::Layout::new(body, dims)
        .map_err(|message| CaptureError::BadOptions(format!("{} dimensions: {message}", body.name())))?;
    Ok(build::mesh(&layout))
}

#[cfg(test)]
mod tests;
