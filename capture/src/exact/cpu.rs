//! The exact measure on the CPU (the reference): every sampled texel against
//! every eye-frame, on all cores.
//!
//! Work is split into chunks of neighbouring texels (rayon); inside a chunk
//! the loop runs eye-frame by eye-frame over the texels in order, so
//! consecutive rays start at neighbouring points of the surface and end at
//! the same eye, and walk the same nodes of the hierarchy while they are in
//! cache. Per texel the sums run over the eye-frames in order, then over its
//! samples in order, so a run rounds alike whatever the chunking.
//!
//! Occluder memory: each sample of a chunk remembers the triangle that hid
//! it last, and the sample before it in the same eye-frame offers its own:
//! both are tried before the hierarchy (`rules::sample_visibility`).
//! Consecutive eye-frames move the eye a little and neighbouring samples lie
//! side by side, so the same triangle (most often the vehicle's own near
//! side hiding its far side) usually hides the sample again, and one
//! triangle test replaces a walk. The hierarchy's box test is conservative,
//! so the answers are the same as without the memory.

use rayon::prelude::*;

use super::geometry::Obstacles;
use super::rules::{Blocker, Sighting, Tracer, sample_visibility};
use super::types::{EyeFrame, PartEyeFrames, SampledTexel, SurfaceSamples, TexelVisibility};

/// Texels per unit of parallel work.
const CHUNK_TEXELS: usize = 256;

/// Per sampled texel, the eye-frames that see any of its samples and the
/// solid angle they cover; per part and eye-frame, whether it is seen, the
/// texels seen and their solid angle (summed chunk by chunk in texel order).
pub fn texel_visibility(
    samples: &SurfaceSamples,
    eye_frames: &[EyeFrame],
    obstacles: &Obstacles,
    parts: usize,
    tracer: Tracer,
) -> TexelVisibility {
    let chunks: Vec<TexelVisibility> = samples
        .texels
        .par_chunks(CHUNK_TEXELS)
        .map(|texels| chunk_visibility(samples, texels, eye_frames, obstacles, parts, tracer))
        .collect();
    let slots = parts * eye_frames.len();
    let mut whole = TexelVisibility {
        counts: Vec::with_capacity(samples.texels.len()),
        solid_angle_sr: Vec::with_capacity(samples.texels.len()),
        part_seen: vec![false; slots],
        per_eye_frame: Some(PartEyeFrames { texels: vec![0; slots], solid_angle_sr: vec![0.0; slots] }),
    };
    for chunk in chunks {
        whole.counts.extend(chunk.counts);
        whole.solid_angle_sr.extend(chunk.solid_angle_sr);
        for (seen, chunk_seen) in whole.part_seen.iter_mut().zip(chunk.part_seen) {
            *seen |= chunk_seen;
        }
        if let (Some(sum), Some(part)) = (whole.per_eye_frame.as_mut(), chunk.per_eye_frame) {
            sum.texels.iter_mut().zip(part.texels).for_each(|(a, b)| *a += b);
            sum.solid_angle_sr.iter_mut().zip(part.solid_angle_sr).for_each(|(a, b)| *a += b);
        }
    }
    whole
}

fn chunk_visibility(
    samples: &SurfaceSamples,
    texels: &[SampledTexel],
    eye_frames: &[EyeFrame],
    obstacles: &Obstacles,
    parts: usize,
    tracer: Tracer,
) -> TexelVisibility {
    let slots = parts * eye_frames.len();
    let mut out = TexelVisibility {
        counts: vec![0; texels.len()],
        solid_angle_sr: vec![0.0; texels.len()],
        part_seen: vec![false; slots],
        per_eye_frame: None,
    };
    let mut per_eye_frame = PartEyeFrames { texels: vec![0; slots], solid_angle_sr: vec![0.0; slots] };
    // The span of `samples.samples` the chunk's texels use (one run, as
    // `surface_samples` lays them out).
    let first_sample = texels.iter().map(|t| t.first as usize).min().unwrap_or(0);
    let sample_span = texels.iter().map(|t| (t.first + t.count) as usize).max().unwrap_or(0) - first_sample;
    let mut remembered: Vec<Option<Blocker>> = vec![None; sample_span];
    for (index, eye_frame) in eye_frames.iter().enumerate() {
        let mut last_blocker: Option<Blocker> = None;
        for (slot, texel) in texels.iter().enumerate() {
            let mut seen = false;
            let mut texel_sr = 0.0;
            for (offset, sample) in samples.of(texel).iter().enumerate() {
                let memory = &mut remembered[texel.first as usize - first_sample + offset];
                let guesses = [*memory, last_blocker.filter(|&blocker| Some(blocker) != *memory)];
                match sample_visibility(sample, eye_frame, obstacles, tracer, &guesses) {
                    Sighting::Visible(solid_angle) => {
                        seen = true;
                        // Added sample by sample, in order.
                        out.solid_angle_sr[slot] += solid_angle;
                        texel_sr += solid_angle;
                    }
                    Sighting::Blocked(blocker) => {
                        *memory = Some(blocker);
                        last_blocker = Some(blocker);
                    }
                    Sighting::NotInSight => {}
                }
            }
            if seen {
                let part_slot = texel.part as usize * eye_frames.len() + index;
                out.counts[slot] += 1;
                out.part_seen[part_slot] = true;
                per_eye_frame.texels[part_slot] += 1;
                per_eye_frame.solid_angle_sr[part_slot] += texel_sr;
            }
        }
    }
    out.per_eye_frame = Some(per_eye_frame);
    out
}
