//! STUB of the parametric vehicle family (issue 36 item 4), replaced by the
//! `family` branch's file at merge: the same API (body types, their
//! dimensions, the mesh of a body) so the design code builds against it.
//! Here every body is the demo pickup and `typical` returns truck-like numbers.

use crate::scene::demo;

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
    /// Every body type, in this order.
    pub const ALL: [BodyType; 5] =
        [BodyType::Sedan, BodyType::Suv, BodyType::Van, BodyType::Pickup, BodyType::Bus];

    /// The body type's name in files and reports.
    pub fn name(self) -> &'static str {
        match self {
            BodyType::Sedan => "sedan",
            BodyType::Suv => "suv",
            BodyType::Van => "van",
            BodyType::Pickup => "pickup",
            BodyType::Bus => "bus",
        }
    }

    /// The body type called `s`.
    pub fn parse(s: &str) -> Option<BodyType> {
        BodyType::ALL.into_iter().find(|b| b.name() == s)
    }
}

/// The dimensions a body is built from, metres and degrees.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BodyDims {
    pub length_m: f64,
    pub width_m: f64,
    pub height_m: f64,
    pub bonnet_length_m: f64,
    pub bonnet_height_m: f64,
    pub windshield_rake_deg: f64,
    pub wheelbase_m: f64,
}

impl BodyDims {
    /// Typical dimensions of the body type (stub: the demo pickup's for all).
    pub fn typical(_body: BodyType) -> BodyDims {
        BodyDims {
            length_m: 5.9,
            width_m: 2.0,
            height_m: 1.9,
            bonnet_length_m: 1.2,
            bonnet_height_m: 1.15,
            windshield_rake_deg: 60.0,
            wheelbase_m: 3.7,
        }
    }
}

/// The mesh of `body` with `dims` (stub: the demo pickup).
pub fn body_mesh(_body: BodyType, _dims: &BodyDims) -> crate::error::Result<crate::scene::mesh::Mesh> {
    Ok(demo::truck())
}
