//! Per candidate and eye-frame, from the visible surface samples (the exact
//! measure's visibility rules, `rules.rs`):
//!
//! * `solid_angle_sr`: Σ area · |cos θ| / r² of the visible samples, divided
//!   by the texel sample fraction (an estimate of the whole candidate's);
//! * `visible_fraction`: visible area / the candidate's area (of the sampled
//!   texels);
//! * `view_angle_deg`: the area-weighted mean of θ, the angle between the
//!   line of sight and the surface normal (two-sided: 0–90°);
//! * `angular_height_deg`: the visible samples' vertical angular extent seen
//!   from the eye: the largest minus the smallest elevation (world up), each
//!   sample widened by its own half-height (√area/2 · √(1 − (e·n)²) / r, e the
//!   direction of rising elevation), so a facing plate of height h at
//!   distance d gives 2·atan(h / 2d). For a *display patch* it is measured
//!   from its exact outline instead (issue 42 §4): the largest minus the
//!   smallest elevation over the W × H rectangle's four edges, each edge's
//!   extremes found in closed form ([`outline_elevations`]), whenever any of
//!   the patch is visible. Sample extents read about one texel too tall
//!   (+3.4 % at a 512² palette on the demo's licence plate, so legible
//!   frames early); the outline has no texel in it. Its limit: the whole
//!   outline is measured even when part of it is hidden (the visible-fraction
//!   rule guards such views), and an eye right below or above a tilted
//!   display, where the elevation's extreme lies inside the rectangle, is
//!   read from the edges.
//!
//! Rows: every part in every eye-frame (zeros included, so the analyzer
//! sees every frame), patches only where something of them is visible.

use std::path::Path;

use glam::{DMat4, DVec3};
use rayon::prelude::*;
use ufcsr::format::PlacementFrameRow;

use super::ExactInputs;
use super::labels::{LabelKind, LabelSet};
use crate::error::{CaptureError, Result};
use crate::exact::rules::{Tracer, visible_solid_angle};
use crate::exact::types::{EyeFrame, SurfaceSample, transform_point};

/// The sums of one candidate in one eye-frame.
#[derive(Debug, Clone, Copy)]
struct Sums {
    area_m2: f64,
    solid_angle_sr: f64,
    angle_area: f64,
    lowest: f64,
    highest: f64,
}

impl Default for Sums {
    fn default() -> Sums {
        Sums {
            area_m2: 0.0,
            solid_angle_sr: 0.0,
            angle_area: 0.0,
            lowest: f64::INFINITY,
            highest: f64::NEG_INFINITY,
        }
    }
}

/// One candidate's numbers in one eye-frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Seen {
    pub solid_angle_sr: f64,
    pub visible_fraction: f64,
    pub view_angle_deg: f64,
    pub angular_height_deg: f64,
}

/// What a visible sample adds: (θ in radians, lowest and highest elevation).
fn sample_view(sample: &SurfaceSample, eye_frame: &EyeFrame, local_to_vehicle: &DMat4) -> (f64, f64, f64) {
    let to_eye = eye_frame.eye_in_vehicle - sample.position;
    let r = to_eye.length();
    let cos = (sample.normal.dot(to_eye).abs() / r).min(1.0);
    // Elevation in the local frame, whose z is world up.
    let local = transform_point(&eye_frame.vehicle_to_local, sample.position).truncate();
    let d = local - eye_frame.eye_local;
    let horizontal = d.truncate().length();
    let elevation = d.z.atan2(horizontal);
    // The direction of rising elevation at the sample, in the vehicle frame.
    let rising_local = if horizontal > 0.0 {
        (DVec3::new(-d.x * d.z / horizontal, -d.y * d.z / horizontal, horizontal) / r).normalize_or_zero()
    } else {
        DVec3::X
    };
    let rising = local_to_vehicle.transform_vector3(rising_local);
    let tilt = rising.dot(sample.normal);
    let half = 0.5 * sample.area_m2.sqrt() * (1.0 - tilt * tilt).max(0.0).sqrt() / r;
    (cos.acos(), elevation - half, elevation + half)
}

/// The elevation (radians above the horizontal of the local frame, whose z
/// is world up) of the point `d` (from the eye).
fn elevation(d: DVec3) -> f64 {
    d.z.atan2(d.truncate().length())
}

/// The lowest and highest elevation over the edges of the polygon `corners`
/// (vehicle frame) seen from the eye: along an edge d(t) = a + t·u, the
/// extremes of sin(elevation) = d_z / |d| lie at its ends or where
/// d/dt (d_z² / |d|²) = 0, which is linear in t:
/// t = (a_z (a·u) − u_z |a|²) / (u_z (a·u) − a_z |u|²).
pub(crate) fn outline_elevations(corners: &[DVec3; 4], eye_frame: &EyeFrame) -> (f64, f64) {
    let local: Vec<DVec3> = corners
        .iter()
        .map(|&c| transform_point(&eye_frame.vehicle_to_local, c).truncate() - eye_frame.eye_local)
        .collect();
    let (mut low, mut high) = (f64::INFINITY, f64::NEG_INFINITY);
    for i in 0..local.len() {
        let (a, b) = (local[i], local[(i + 1) % local.len()]);
        let u = b - a;
        let mut at = vec![elevation(a), elevation(b)];
        let denominator = u.z * a.dot(u) - a.z * u.length_squared();
        if denominator.abs() > 1e-300 {
            let t = (a.z * a.dot(u) - u.z * a.length_squared()) / denominator;
            if t > 0.0 && t < 1.0 {
                at.push(elevation(a + u * t));
            }
        }
        for e in at {
            low = low.min(e);
            high = high.max(e);
        }
    }
    (low, high)
}

/// Every candidate's numbers in one eye-frame (`None` where nothing is visible).
pub(crate) fn measure_eye_frame(
    inputs: &ExactInputs,
    labels: &LabelSet,
    eye_frame: &EyeFrame,
) -> Vec<Option<Seen>> {
    let mut sums = vec![Sums::default(); labels.count()];
    let local_to_vehicle = eye_frame.vehicle_to_local.inverse();
    for (index, sample) in inputs.samples.samples.iter().enumerate() {
        let Some(solid_angle) = visible_solid_angle(sample, eye_frame, inputs.obstacles, Tracer::Hierarchy)
        else {
            continue;
        };
        let (theta, low, high) = sample_view(sample, eye_frame, &local_to_vehicle);
        for label in labels.of_sample(index) {
            let s = &mut sums[label as usize];
            s.area_m2 += sample.area_m2;
            s.solid_angle_sr += solid_angle;
            s.angle_area += theta * sample.area_m2;
            s.lowest = s.lowest.min(low);
            s.highest = s.highest.max(high);
        }
    }
    sums.iter()
        .zip(&labels.area_m2)
        .zip(&labels.outlines)
        .map(|((s, &total), outline)| {
            (s.area_m2 > 0.0).then(|| {
                let (lowest, highest) =
                    outline.as_ref().map_or((s.lowest, s.highest), |o| outline_elevations(o, eye_frame));
                Seen {
                    solid_angle_sr: s.solid_angle_sr / inputs.sample_fraction,
                    visible_fraction: if total > 0.0 { (s.area_m2 / total).min(1.0) } else { 0.0 },
                    view_angle_deg: (s.angle_area / s.area_m2).to_degrees(),
                    angular_height_deg: (highest - lowest).to_degrees(),
                }
            })
        })
        .collect()
}

/// Eye-frames measured at once (in parallel) before their rows are written.
const EYE_FRAMES_PER_BATCH: usize = 32;

/// Measures every eye-frame (in parallel, a batch at a time) and writes the
/// table; the rows written.
pub(crate) fn write_table(inputs: &ExactInputs, labels: &LabelSet, path: &Path) -> Result<u64> {
    if inputs.eye_frames.len() != 2 * inputs.frame_records.len() {
        return Err(CaptureError::BadOptions(format!(
            "placement: {} eye-frames for {} frames (expected two eyes per frame)",
            inputs.eye_frames.len(),
            inputs.frame_records.len()
        )));
    }
    let mut rows = 0u64;
    ufcsr::files::write_atomically(path, |writer| {
        let writer = LimitedWriter { inner: writer, left: ufcsr::format::PLACEMENT_TABLE_LIMIT };
        let mut table = csv::Writer::from_writer(writer);
        for (batch, eye_frames) in inputs.eye_frames.chunks(EYE_FRAMES_PER_BATCH).enumerate() {
            let seen: Vec<Vec<Option<Seen>>> =
                eye_frames.par_iter().map(|eye_frame| measure_eye_frame(inputs, labels, eye_frame)).collect();
            for (offset, per_label) in seen.iter().enumerate() {
                let index = batch * EYE_FRAMES_PER_BATCH + offset;
                rows += write_rows(&mut table, inputs, labels, index, per_label)
                    .map_err(std::io::Error::other)?;
            }
        }
        table.flush()
    })?;
    Ok(rows)
}

/// A writer that fails once more than `left` bytes are written: the table
/// stops at [`ufcsr::format::PLACEMENT_TABLE_LIMIT`], the most `placement` reads, so
/// the capture never writes (and keeps) a table `placement` would refuse
/// (a 40 s scenario with `--display` used to write 420 MB).
struct LimitedWriter<W> {
    inner: W,
    left: u64,
}

impl<W: std::io::Write> std::io::Write for LimitedWriter<W> {
    fn write(&mut self, bytes: &[u8]) -> std::io::Result<usize> {
        let size = bytes.len() as u64;
        if size > self.left {
            return Err(std::io::Error::other(format!(
                "the placement table would be larger than {} MiB, the most `ufcsr placement` \
                 reads: measure fewer frames (--frames 0-END/STEP), larger or fewer displays (--display, \
                 --patch-spacing) or a sample (--sample)",
                ufcsr::format::PLACEMENT_TABLE_LIMIT >> 20
            )));
        }
        self.left -= size;
        self.inner.write(bytes).inspect(|&written| self.left += size - written as u64)
    }

    fn flush(&mut self) -> std::io::Result<()> {
        self.inner.flush()
    }
}

/// The rows of eye-frame `index`.
fn write_rows<W: std::io::Write>(
    table: &mut csv::Writer<W>,
    inputs: &ExactInputs,
    labels: &LabelSet,
    index: usize,
    per_label: &[Option<Seen>],
) -> std::result::Result<u64, csv::Error> {
    // The capture's own records ([`crate::job::manifest_builder::frame_record`]) always carry time and distance.
    let record = &inputs.frame_records[index / 2];
    let none =
        Seen { solid_angle_sr: 0.0, visible_fraction: 0.0, view_angle_deg: 0.0, angular_height_deg: 0.0 };
    let mut rows = 0;
    for (label, seen) in per_label.iter().enumerate() {
        let kind = labels.kinds[label];
        if seen.is_none() && kind == LabelKind::Patch {
            continue;
        }
        let seen = seen.unwrap_or(none);
        table.serialize(PlacementFrameRow {
            frame: u64::from(record.frame),
            time_s: record.time_s.unwrap_or(0.0),
            eye: (if index.is_multiple_of(2) { "left" } else { "right" }).into(),
            distance_m: record.distance_m.unwrap_or(0.0),
            candidate: labels.names[label].as_str().into(),
            kind: kind.name().into(),
            solid_angle_sr: seen.solid_angle_sr,
            visible_fraction: seen.visible_fraction,
            view_angle_deg: seen.view_angle_deg,
            angular_height_deg: seen.angular_height_deg,
            frame_s: inputs.frame_s,
            mirror: labels.mirrors[label].as_deref().unwrap_or("").into(),
        })?;
        rows += 1;
    }
    Ok(rows)
}

#[cfg(test)]
mod limit_tests {
    use std::io::Write;

    #[test]
    fn a_table_beyond_the_limit_fails_instead_of_being_written() {
        let mut writer = super::LimitedWriter { inner: Vec::new(), left: 10 };
        writer.write_all(b"0123456789").unwrap();
        let error = writer.write_all(b"x").unwrap_err().to_string();
        assert!(error.contains("MiB") && error.contains("--frames"), "{error}");
        assert_eq!(writer.inner.len(), 10);
    }
}
