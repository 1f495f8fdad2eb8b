//! A scenario: a named, timed vehicle motion, whatever scene it came from
//! (the built-in demo, a scene file, or a Unity export).

use crate::scene::track::Motion;

/// A scenario ready to capture.
#[derive(Debug, Clone, PartialEq)]
pub struct Scenario {
    pub name: String,
    pub duration_s: f64,
    pub motion: Motion,
}
