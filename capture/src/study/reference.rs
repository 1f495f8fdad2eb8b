//! The study's reference: the exact measure on **every frame** of the
//! scenario (not only the frames some setting renders), and the per-frame
//! tables ([`StudyTables`]) both sides are compared on. The exact measure over
//! every frame costs little next to the renders, and it is what a setting's
//! error is measured against: what the user wants is the scenario's exposure,
//! not its exposure on the frames a setting happened to keep.

use std::path::Path;

use crate::error::{CaptureError, Result};
use crate::exact::accuracy::PerEyeFrame;
use crate::exact::{MeasureOptions, UnobstructedCapture, measure_unobstructed};
use crate::job::{CaptureOptions, CaptureProgress};
use crate::scene::Scene;
use crate::study::offsets::FrameValues;
use crate::study::{StudyMeasure, StudyOptions};

/// Per-frame part values (both eyes summed per frame, indexed by frame
/// number): the exact measure on every frame and each resolution's renders.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct StudyTables {
    /// The legend parts, in the order of every value vector.
    pub parts: Vec<String>,
    /// The exact measure on every frame of the scenario.
    pub exact: Vec<Vec<f64>>,
    /// Per part, the exact totals' relative standard error from texel
    /// sampling (zeros when every texel was ray traced).
    pub relative_error: Vec<f64>,
    /// Per resolution (px/°), the rendered values on the frames any of its
    /// settings rendered, `None` on the others.
    pub rendered: Vec<(f64, Vec<Option<Vec<f64>>>)>,
}

impl StudyTables {
    /// The values of resolution `ppd`.
    pub fn values(&self, ppd: f64) -> Option<FrameValues<'_>> {
        let (_, rendered) = self.rendered.iter().find(|(p, _)| *p == ppd)?;
        Some(FrameValues { exact: &self.exact, rendered })
    }

    /// Adds a setting's rendered eye-frames to its resolution's table.
    pub(crate) fn add_rendered(&mut self, ppd: f64, values: &PerEyeFrame, out: &Path) -> Result<()> {
        let frames = self.exact.len();
        if !self.rendered.iter().any(|(p, _)| *p == ppd) {
            self.rendered.push((ppd, vec![None; frames]));
        }
        let table = &mut self.rendered.iter_mut().find(|(p, _)| *p == ppd).expect("just added").1;
        let mut fresh = vec![None::<Vec<f64>>; frames];
        for (frame, _, row) in &values.rows {
            let slot = fresh.get_mut(*frame as usize).ok_or_else(|| {
                CaptureError::bad_file(out, format!("frame {frame} is beyond the scenario's {frames} frames"))
            })?;
            let sum = slot.get_or_insert_with(|| vec![0.0; row.len()]);
            sum.iter_mut().zip(row).for_each(|(s, v)| *s += v);
        }
        // Renders are deterministic: a frame two settings of one resolution share is kept once.
        for (slot, new) in table.iter_mut().zip(fresh) {
            if slot.is_none() {
                *slot = new;
            }
        }
        Ok(())
    }
}

/// The exact measure on every frame of the scenario, in `out/exact`.
pub(crate) fn measure_exact(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    scene: &Scene,
    options: &StudyOptions,
    sample: f64,
) -> Result<UnobstructedCapture> {
    let scenario = scene.scenario(&options.scenario)?;
    let frame_count = scene.rig.frame_count(scenario.duration_s);
    // A link planted at out/exact is replaced by a real folder, never written through.
    ufcsr::files::create_output_dir(&options.capture.out)?;
    let out = ufcsr::files::output_sub_dir(&options.capture.out, std::path::Path::new("exact"))?;
    let capture = CaptureOptions {
        out,
        frames: format!("0-{}", frame_count.saturating_sub(1)).parse()?,
        progress: CaptureProgress::default(),
        ..options.capture.clone()
    };
    let measure = MeasureOptions { sample, ..MeasureOptions::default() };
    let measured = measure_unobstructed(device, queue, scene, scenario, &capture, &measure)?;
    eprintln!(
        "study: exact reference of {} of {} texels over all {} eye-frames in {:.2} s ({:.2} s of ray casts)",
        measured.sampled_texels,
        measured.labelled_texels,
        measured.eye_frames,
        measured.seconds,
        measured.visibility_seconds
    );
    Ok(measured)
}

/// The tables of the exact measure (by the rendered table's parts, by name,
/// each part scaled by its texels / sampled texels), before any render is added.
pub fn exact_tables(
    exact: &UnobstructedCapture,
    measure: StudyMeasure,
    parts: &[String],
) -> Result<StudyTables> {
    let sums = exact.per_eye_frame.as_ref().ok_or_else(|| {
        CaptureError::BadOptions(
            "the exact reference kept no per-eye-frame sums (measure it on the CPU)".into(),
        )
    })?;
    let estimates = parts
        .iter()
        .map(|name| {
            exact.estimates.iter().find(|e| &e.part == name).ok_or_else(|| {
                CaptureError::BadOptions(format!("part {name:?} is not in the exact reference"))
            })
        })
        .collect::<Result<Vec<_>>>()?;
    let index: Vec<usize> = estimates
        .iter()
        .map(|e| exact.estimates.iter().position(|x| std::ptr::eq(x, *e)).expect("found above"))
        .collect();
    let scale: Vec<f64> = estimates
        .iter()
        .map(|e| if e.sampled == 0 { 0.0 } else { e.texels as f64 / e.sampled as f64 })
        .collect();
    let eye_frames = exact.eye_frames as usize;
    let frames = exact.frames.iter().max().map_or(0, |f| *f as usize + 1);
    let mut table = vec![vec![0.0; parts.len()]; frames];
    for i in 0..eye_frames {
        let row = &mut table[exact.frames[i / 2] as usize];
        for (slot, (&p, &s)) in row.iter_mut().zip(index.iter().zip(&scale)) {
            *slot += s * match measure {
                StudyMeasure::Count => f64::from(sums.texels[p * eye_frames + i]),
                StudyMeasure::AngularArea => sums.solid_angle_sr[p * eye_frames + i],
            };
        }
    }
    let relative_error = estimates
        .iter()
        .map(|e| match measure {
            StudyMeasure::Count => ratio(e.standard_error, e.estimated_total),
            StudyMeasure::AngularArea => ratio(e.solid_angle_standard_error_sr, e.estimated_solid_angle_sr),
        })
        .collect();
    Ok(StudyTables { parts: parts.to_vec(), exact: table, relative_error, rendered: Vec::new() })
}

fn ratio(error: f64, total: f64) -> f64 {
    if total > 0.0 { error / total } else { 0.0 }
}
