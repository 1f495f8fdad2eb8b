//! The exact measure on the CPU (the reference): every sampled texel against
//! every eye-frame, on all cores.
//!
//! Work is split into chunks of neighbouring texels (rayon); inside a chunk
//! the loop runs eye-frame by eye-frame over the texels in order, so
//! consecutive rays start at neighbouring points of the surface and end at
//! the same eye, and walk the same nodes of the hierarchy while they are in
//! cache. Per texel the sums run over the eye-frames in order, then over its
//! samples in order — the order `visibility.wgsl` uses, so both round alike.

use rayon::prelude::*;

use super::geometry::Obstacles;
use super::rules::{Tracer, visible_solid_angle};
use super::types::{EyeFrame, SampledTexel, SurfaceSamples, TexelVisibility};

/// Texels per unit of parallel work.
const CHUNK_TEXELS: usize = 256;

/// Per sampled texel, the eye-frames that see any of its samples and the
/// solid angle they cover; per part and eye-frame, whether it is seen.
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
    let mut whole = TexelVisibility {
        counts: Vec::with_capacity(samples.texels.len()),
        solid_angle_sr: Vec::with_capacity(samples.texels.len()),
        part_seen: vec![false; parts * eye_frames.len()],
    };
    for chunk in chunks {
        whole.counts.extend(chunk.counts);
        whole.solid_angle_sr.extend(chunk.solid_angle_sr);
        for (seen, chunk_seen) in whole.part_seen.iter_mut().zip(chunk.part_seen) {
            *seen |= chunk_seen;
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
    let mut out = TexelVisibility {
        counts: vec![0; texels.len()],
        solid_angle_sr: vec![0.0; texels.len()],
        part_seen: vec![false; parts * eye_frames.len()],
    };
    for (index, eye_frame) in eye_frames.iter().enumerate() {
        for (slot, texel) in texels.iter().enumerate() {
            let mut seen = false;
            for sample in samples.of(texel) {
                if let Some(solid_angle) = visible_solid_angle(sample, eye_frame, obstacles, tracer) {
                    seen = true;
                    out.solid_angle_sr[slot] += solid_angle;
                }
            }
            if seen {
                out.counts[slot] += 1;
                out.part_seen[texel.part as usize * eye_frames.len() + index] = true;
            }
        }
    }
    out
}
