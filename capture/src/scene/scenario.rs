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

/// A scenario's duration: finite, not negative, within the tracks' bounds.
pub fn check_duration(duration_s: f64) -> std::result::Result<(), String> {
    let limit = crate::scene::track::MAX_TRACK_MAGNITUDE;
    if duration_s.is_finite() && (0.0..=limit).contains(&duration_s) {
        Ok(())
    } else {
        let shown = if duration_s.abs() < 1e9 { duration_s.to_string() } else { format!("{duration_s:e}") };
        Err(format!("duration_s {shown} must be between 0 and {limit:e} s"))
    }
}
