//! What external frames cannot say about themselves, from the command line
//! or files beside them: the rig (a JSON object of the scene file's rig
//! fields), the frame rate, the field of view or pixels per degree, and each
//! frame's time and distance (a CSV). Put into the manifest in the fields
//! ufcsr capture writes, so exposure, deg²·s, the solid-angle and time plots
//! and the resolution diagnostics work for them as for a capture.

use std::collections::BTreeMap;
use std::path::Path;

use serde_json::Value;

use crate::format::manifest::{RigRecord, RigSettings};

use crate::error::{Error, Result};

/// The rig fields of the scene file (docs/scene-file.md#rig).
pub(crate) const RIG_FIELDS: [&str; 10] = [
    "pedestrian",
    "eye_height_m",
    "ipd_m",
    "horizontal_fov_deg",
    "eye_pixels",
    "tiles",
    "fps",
    "near_m",
    "far_m",
    "look_at_vehicle",
];

/// A rig file's fields: `{"rig": {...}}` (a scene file), a manifest's
/// `{"settings": {...}}`, or the fields themselves. Unknown fields and wrong
/// types are errors naming the file and the field.
pub(crate) fn read_rig(path: &Path) -> Result<RigSettings> {
    let bytes = crate::files::read_limited(path, crate::files::SMALL_INPUT_LIMIT)?;
    let value: Value = serde_json::from_slice(&bytes)
        .map_err(|error| Error::bad_file(path, format!("not a JSON rig description: {error}")))?;
    let mut object = value.as_object().cloned();
    for wrapper in ["rig", "settings"] {
        if let Some(inner) = object.as_ref().and_then(|o| o.get(wrapper)).and_then(Value::as_object) {
            object = Some(inner.clone());
        }
    }
    let Some(mut fields) = object else {
        return Err(Error::bad_file(path, "a rig is a JSON object of rig fields, e.g. {\"fps\": 60}"));
    };
    // A manifest's rig records what follows from the settings beside them.
    for derived in ["vertical_fov_deg", "pixels_per_degree", "tile_pixels", "frame_count", "eye_offset"] {
        fields.remove(derived);
    }
    for (name, value) in &fields {
        let ok = match name.as_str() {
            "pedestrian" | "look_at_vehicle" => numbers(value, 3),
            "eye_pixels" | "tiles" => whole_numbers(value, 2),
            "eye_height_m" => value.as_f64().is_some_and(f64::is_finite),
            "ipd_m" => value.as_f64().is_some_and(|v| v.is_finite() && v >= 0.0),
            "horizontal_fov_deg" => value.as_f64().is_some_and(|v| v > 0.0 && v < 180.0),
            "fps" | "near_m" | "far_m" => value.as_f64().is_some_and(|v| v.is_finite() && v > 0.0),
            _ => {
                return Err(Error::bad_file(
                    path,
                    format!("unknown rig field {name:?} (the rig fields are {})", RIG_FIELDS.join(", ")),
                ));
            }
        };
        if !ok {
            return Err(Error::bad_file(
                path,
                format!("rig field {name:?}: {value} is not {}", expected(name)),
            ));
        }
    }
    let text = Value::Object(fields).to_string();
    crate::format::parse_json(path, text.as_bytes(), "rig")
}

/// `count` numbers.
fn numbers(value: &Value, count: usize) -> bool {
    value.as_array().is_some_and(|items| items.len() == count && items.iter().all(Value::is_number))
}

/// `count` whole numbers above 0.
fn whole_numbers(value: &Value, count: usize) -> bool {
    value
        .as_array()
        .is_some_and(|items| items.len() == count && items.iter().all(|v| v.as_u64().is_some_and(|n| n > 0)))
}

fn expected(name: &str) -> &'static str {
    match name {
        "pedestrian" | "look_at_vehicle" => "three numbers [x, y, z]",
        "eye_pixels" | "tiles" => "two whole numbers above 0 [width/columns, height/rows]",
        "horizontal_fov_deg" => "a number of degrees between 0 and 180",
        "eye_height_m" => "a number of metres",
        "ipd_m" => "a number of metres, 0 or more",
        _ => "a number above 0",
    }
}

/// `--fov H` or `HxV` in degrees.
pub fn parse_fov(text: &str) -> Result<(f64, Option<f64>)> {
    let bad = || {
        Error::BadOptions(format!(
            "--fov {text:?}: expected the horizontal field of view in degrees, e.g. 107, or HxV, e.g. 107x119.4 \
             (each between 0 and 180)"
        ))
    };
    let degrees =
        |part: &str| part.trim().parse::<f64>().ok().filter(|v| *v > 0.0 && *v < 180.0).ok_or_else(bad);
    match text.split_once(['x', 'X']) {
        Some((h, v)) => Ok((degrees(h)?, Some(degrees(v)?))),
        None => Ok((degrees(text)?, None)),
    }
}

/// The vertical field of view of a rectilinear eye with square pixels.
pub(crate) fn vertical_fov_deg(horizontal_deg: f64, [width, height]: [u32; 2]) -> f64 {
    let half = (horizontal_deg.to_radians() / 2.0).tan() * f64::from(height) / f64::from(width);
    2.0 * half.atan().to_degrees()
}

/// One frame's time and distance from `--frame-times`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct FrameTime {
    pub time_s: f64,
    pub distance_m: Option<f64>,
}

/// `--frame-times`: a CSV with a header naming `frame` and `time_s` and,
/// optionally, `distance_m`; other columns are ignored. Each frame once.
pub(crate) fn read_frame_times(path: &Path) -> Result<BTreeMap<u32, FrameTime>> {
    let bytes = crate::files::read_limited(path, crate::files::SMALL_INPUT_LIMIT)?;
    let mut reader = csv::ReaderBuilder::new().trim(csv::Trim::All).from_reader(bytes.as_slice());
    let headers =
        reader.headers().map_err(|error| Error::bad_file(path, format!("not a CSV file: {error}")))?;
    let column = |name: &str| headers.iter().position(|h| h == name);
    let (Some(frame_at), Some(time_at)) = (column("frame"), column("time_s")) else {
        return Err(Error::bad_file(
            path,
            format!(
                "the header must name the columns frame and time_s (and optionally distance_m); it is {:?}",
                headers.iter().collect::<Vec<_>>().join(",")
            ),
        ));
    };
    let distance_at = column("distance_m");
    let mut times = BTreeMap::new();
    for (index, record) in reader.records().enumerate() {
        let line = index + 2;
        let record = record.map_err(|error| Error::bad_file(path, format!("line {line}: {error}")))?;
        let field = |at: usize| record.get(at).unwrap_or("");
        let number = |at: usize, name: &str| -> Result<f64> {
            field(at).parse::<f64>().ok().filter(|v| v.is_finite() && *v >= 0.0).ok_or_else(|| {
                Error::bad_file(
                    path,
                    format!("line {line}: {name} {:?} is not a number of 0 or more", field(at)),
                )
            })
        };
        let frame = field(frame_at).parse::<u32>().map_err(|_| {
            Error::bad_file(path, format!("line {line}: frame {:?} is not a whole number", field(frame_at)))
        })?;
        let time = FrameTime {
            time_s: number(time_at, "time_s")?,
            distance_m: distance_at.map(|at| number(at, "distance_m")).transpose()?,
        };
        if times.insert(frame, time).is_some() {
            return Err(Error::bad_file(path, format!("line {line}: frame {frame} is listed twice")));
        }
    }
    Ok(times)
}

/// The manifest's `rig`: the settings as known and what follows from them.
pub(crate) fn rig_record(settings: &RigSettings, tile_pixels: [u32; 2]) -> RigRecord {
    let optics = settings.horizontal_fov_deg.zip(settings.eye_pixels);
    RigRecord {
        settings: settings.clone(),
        vertical_fov_deg: optics.map(|(fov, eye)| vertical_fov_deg(fov, eye)),
        pixels_per_degree: optics.map(|(fov, eye)| f64::from(eye[0]) / fov),
        tile_pixels: Some(tile_pixels),
        ..RigRecord::default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn square_pixels_give_the_capture_rigs_vertical_fov() {
        // The paper's rig: 107° over 640×810 px is 119.373712° vertically.
        assert!((vertical_fov_deg(107.0, [640, 810]) - 119.373712).abs() < 1e-6);
        assert_eq!(parse_fov("90").unwrap(), (90.0, None));
        assert_eq!(parse_fov("90x60").unwrap(), (90.0, Some(60.0)));
        assert!(parse_fov("180").is_err() && parse_fov("wide").is_err());
    }
}
