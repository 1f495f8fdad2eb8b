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
pub(crate) fn check_duration(duration_s: f64) -> std::result::Result<(), String> {
    let limit = crate::scene::track::MAX_TRACK_MAGNITUDE;
    if duration_s.is_finite() && (0.0..=limit).contains(&duration_s) {
        Ok(())
    } else {
        let shown = if duration_s.abs() < 1e9 { duration_s.to_string() } else { format!("{duration_s:e}") };
        Err(format!("duration_s {shown} must be between 0 and {limit:e} s"))
    }
}

/// A frame may not outlast its scenario: every frame stands for 1/fps
/// seconds of the time totals, the final frame included, so they exceed the
/// duration by one frame — refused when that frame alone is longer than the
/// whole scenario (a still scenario of 0 s is one frame of 1/fps, allowed).
/// `fps` names where the rate came from in the message.
pub(crate) fn check_frame_time(
    scenario: &Scenario,
    fps: f64,
    field: &str,
) -> std::result::Result<(), String> {
    let frame_s = 1.0 / fps;
    if scenario.duration_s > 0.0 && frame_s > scenario.duration_s {
        return Err(format!(
            "scenario {}: {field} {fps} makes one frame {frame_s} s, longer than the scenario's {} s: every time \
             total would count that frame whole (exposure above the duration); raise {field} to at least {}",
            scenario.name,
            scenario.duration_s,
            1.0 / scenario.duration_s
        ));
    }
    Ok(())
}
