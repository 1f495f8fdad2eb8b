//! The exact reference: per-point visibility in texture space.
//!
//! What the paper means by a count — "how many times each point is
//! unobstructed to a pedestrian" — measured directly instead of through
//! pixels, so it does not depend on pixels per degree or tiling. For every
//! (sampled) texel of the unwrap, its point on the vehicle (the texel centre
//! mapped through its triangle) counts once per eye-frame in which it lies in
//! the eye's field of view, the eye is not edge-on to its triangle, and the
//! segment from the point to the eye crosses no triangle of the vehicle or
//! the scene. Surfaces are two-sided, as the renderer draws them (no
//! back-face culling), so the measure does not depend on the mesh's winding
//! (the demo truck's is not consistent); on a closed mesh the far side of a
//! panel is hidden by the vehicle itself anyway.
//! Rays are cast in f64: against the vehicle in the vehicle's own frame
//! (so a scene 10 km from the origin loses no precision) and against the
//! occluders in the world frame, each through a [`TriangleBvh`]. The point
//! is lifted 0.1 mm off its surface towards the eye so that it does not hit
//! its own triangle.
//!
//! A random subset of texels (`--sample`, seeded) keeps it fast; per-part
//! totals of the sample are scaled to estimates with standard errors.

use std::collections::BTreeMap;
use std::path::PathBuf;
use std::time::Instant;

use glam::{DVec2, DVec3, DVec4};
use serde_json::json;

use crate::archive::{CaptureOptions, CapturedTiles, TileTally, prepare_archive, summarize, write_manifest};
use crate::error::{CaptureError, Result};
use crate::frame_capture::round6;
use crate::ray_bvh::TriangleBvh;
use crate::rig::{Eye, vehicle_to_world};
use crate::scenario::Scenario;
use crate::scene::Scene;
pub use crate::unobstructed_gpu::MeasureDevice;
use crate::unobstructed_gpu::count_unobstructed_gpu;
use crate::unwrap::{Unwrapped, for_texel_centres};

/// The measure's name in result.json.
pub const MEASURE_UNOBSTRUCTED: &str = "unobstructed";
/// How far a point is lifted off its surface before casting (metres).
pub const SURFACE_OFFSET_M: f64 = 1e-4;
/// The square of the sine of the angle between a surface and the line of
/// sight below which the surface is seen edge-on (not counted): (1e-9 rad)²,
/// far below any pixel. unobstructed.wgsl uses the same literal.
pub const EDGE_ON_SQUARED: f64 = 1e-18;

/// One point of the vehicle: the centre of a texel.
#[derive(Debug, Clone, Copy)]
pub struct SurfacePoint {
    pub texel: usize,
    pub part: u32,
    /// The vehicle triangle it lies on.
    pub triangle: usize,
    /// Vehicle frame, metres.
    pub position: DVec3,
    /// Unit normal of its triangle (the side the palette is drawn on).
    pub normal: DVec3,
}

/// Deterministic per-texel sampling: keeps `fraction` of the texels.
pub fn is_sampled(texel: usize, fraction: f64, seed: u64) -> bool {
    if fraction >= 1.0 {
        return true;
    }
    // SplitMix64 of the texel index: a fixed, well-mixed subset per seed.
    let mut z = (texel as u64) ^ seed.wrapping_mul(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    ((z >> 11) as f64 / (1u64 << 53) as f64) < fraction
}

/// Every texel centre inside a triangle of the unwrap, with the sampled
/// ones' points. Also returns labelled texels per part (sampled or not).
pub fn surface_points(
    scene: &Scene,
    unwrapped: &Unwrapped,
    fraction: f64,
    seed: u64,
) -> (Vec<SurfacePoint>, Vec<u64>) {
    let mesh = &scene.vehicle;
    let [width, _] = unwrapped.palette;
    let mut points = Vec::new();
    let mut per_part = vec![0u64; mesh.parts.len()];
    for (triangle, uv) in unwrapped.texel_uvs.iter().enumerate() {
        let corners = mesh.corners(triangle).map(|c| c.as_dvec3());
        let normal = (corners[1] - corners[0]).cross(corners[2] - corners[0]).normalize_or_zero();
        let part = mesh.triangle_part[triangle];
        let area = (uv[1] - uv[0]).perp_dot(uv[2] - uv[0]);
        if normal == DVec3::ZERO || area == 0.0 {
            continue;
        }
        for_texel_centres(uv, unwrapped.palette, |x, y| {
            let texel = y as usize * width as usize + x as usize;
            per_part[part as usize] += 1;
            if !is_sampled(texel, fraction, seed) {
                return;
            }
            let q = DVec2::new(f64::from(x) + 0.5, f64::from(y) + 0.5);
            // q = uv0 + w1·(uv1 − uv0) + w2·(uv2 − uv0).
            let w1 = (q - uv[0]).perp_dot(uv[2] - uv[0]) / area;
            let w2 = (uv[1] - uv[0]).perp_dot(q - uv[0]) / area;
            let w0 = 1.0 - w1 - w2;
            let position = corners[0] * w0 + corners[1] * w1 + corners[2] * w2;
            points.push(SurfacePoint { texel, part, triangle, position, normal });
        });
    }
    (points, per_part)
}

/// The scene's geometry for ray casts.
pub struct Obstacles {
    /// The vehicle, in its own frame.
    pub vehicle: TriangleBvh,
    /// Everything else, in the world frame.
    pub world: TriangleBvh,
}

impl Obstacles {
    pub fn new(scene: &Scene) -> Obstacles {
        let mesh = &scene.vehicle;
        let vehicle = (0..mesh.triangles.len()).map(|t| mesh.corners(t).map(|c| c.as_dvec3())).collect();
        let world = scene.occluders.positions.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect();
        Obstacles { vehicle: TriangleBvh::new(vehicle), world: TriangleBvh::new(world) }
    }
}

/// One eye at one frame.
pub struct EyeFrame {
    /// The eye in the vehicle frame.
    pub eye_in_vehicle: DVec3,
    /// The eye in the world.
    pub eye: DVec3,
    pub to_world: glam::DMat4,
    pub view_proj: glam::DMat4,
}

/// Is `point` unobstructed to the eye? (In view, facing it, nothing between.)
pub fn unobstructed(
    point: &SurfacePoint,
    eye_frame: &EyeFrame,
    obstacles: &Obstacles,
    brute_force: bool,
) -> bool {
    let towards_eye = eye_frame.eye_in_vehicle - point.position;
    // Two-sided: the side of the triangle the eye is on. Edge-on (the eye in
    // the triangle's plane) is not facing; rounding of the eye's position
    // leaves ±1e-16 there, so anything within 1e-9 rad of the plane is
    // edge-on (compared squared: no square root, the same on the GPU).
    let side = point.normal.dot(towards_eye);
    if side * side <= EDGE_ON_SQUARED * towards_eye.dot(towards_eye) {
        return false;
    }
    let world = eye_frame.to_world.transform_point3(point.position);
    let clip = eye_frame.view_proj * DVec4::new(world.x, world.y, world.z, 1.0);
    // Reversed Z: depth runs from w (near plane) down to 0 (far plane).
    let in_view =
        clip.w > 0.0 && clip.x.abs() <= clip.w && clip.y.abs() <= clip.w && (0.0..=clip.w).contains(&clip.z);
    if !in_view {
        return false;
    }
    let lifted = point.position + point.normal * (SURFACE_OFFSET_M * side.signum());
    let lifted_world = eye_frame.to_world.transform_point3(lifted);
    let (vehicle, world) = if brute_force {
        (
            obstacles.vehicle.blocks_brute_force(lifted, eye_frame.eye_in_vehicle),
            obstacles.world.blocks_brute_force(lifted_world, eye_frame.eye),
        )
    } else {
        (
            obstacles.vehicle.blocks(lifted, eye_frame.eye_in_vehicle),
            obstacles.world.blocks(lifted_world, eye_frame.eye),
        )
    };
    !vehicle && !world
}

/// The eye-frames of a scenario's selected frames, with each frame's record.
pub fn eye_frames(
    scene: &Scene,
    scenario: &Scenario,
    frames: &[u32],
) -> (Vec<EyeFrame>, Vec<serde_json::Value>) {
    let rig = &scene.rig;
    let pedestrian = glam::dvec2(rig.pedestrian[0], rig.pedestrian[1]);
    let mut eye_frames = Vec::with_capacity(frames.len() * 2);
    let mut records = Vec::with_capacity(frames.len());
    for &frame in frames {
        let time_s = (f64::from(frame) / rig.fps).min(scenario.duration_s);
        let pose = scenario.motion.pose(time_s);
        let to_world = vehicle_to_world(&pose);
        let from_world = to_world.inverse();
        for (_, camera) in Eye::BOTH.into_iter().zip(rig.cameras(&pose)) {
            eye_frames.push(EyeFrame {
                eye_in_vehicle: from_world.transform_point3(camera.position),
                eye: camera.position,
                to_world,
                view_proj: camera.view_proj,
            });
        }
        let distance_m = (pose.position.truncate() - pedestrian).length();
        records.push(json!({"frame": frame, "time_s": round6(time_s), "distance_m": round6(distance_m)}));
    }
    (eye_frames, records)
}

/// Counts, per point, the eye-frames in which it is unobstructed (on all cores).
pub fn count_unobstructed(
    points: &[SurfacePoint],
    eye_frames: &[EyeFrame],
    obstacles: &Obstacles,
) -> Vec<u32> {
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let chunk = points.len().div_ceil(threads).max(1);
    std::thread::scope(|scope| {
        let workers: Vec<_> = points
            .chunks(chunk)
            .map(|points| {
                scope.spawn(move || {
                    points
                        .iter()
                        .map(|point| {
                            let seen = eye_frames
                                .iter()
                                .filter(|e| unobstructed(point, e, obstacles, false))
                                .count();
                            u32::try_from(seen).unwrap_or(u32::MAX)
                        })
                        .collect::<Vec<u32>>()
                })
            })
            .collect();
        workers.into_iter().flat_map(|worker| worker.join().unwrap_or_default()).collect()
    })
}

/// What [`measure_unobstructed`] did.
pub struct UnobstructedCapture {
    pub analysis: ufcsr::Analysis,
    pub written: ufcsr::WrittenFiles,
    pub sampled_texels: u64,
    pub labelled_texels: u64,
    pub eye_frames: u64,
    pub seconds: f64,
    /// Per part: name, labelled texels, sampled texels, sampled total,
    /// estimated total and its standard error.
    pub estimates: Vec<PartEstimate>,
    pub estimates_csv: PathBuf,
}

/// A part's total estimated from the sample.
#[derive(Debug, Clone, serde::Serialize)]
pub struct PartEstimate {
    pub part: String,
    pub texels: u64,
    pub sampled: u64,
    pub sampled_total: u64,
    pub estimated_total: f64,
    pub standard_error: f64,
}

/// How to measure: which share of the texels, seeded how, on which device.
#[derive(Debug, Clone, Copy)]
pub struct MeasureOptions {
    /// Share of the texels to measure, in (0, 1].
    pub sample: f64,
    pub seed: u64,
    pub on: MeasureDevice,
}

impl Default for MeasureOptions {
    fn default() -> MeasureOptions {
        MeasureOptions { sample: 1.0, seed: 1, on: MeasureDevice::Cpu }
    }
}

/// Measures one scenario: writes the archive skeleton (manifest, PIdT,
/// legend, vehicle.glb; no tiles) and the analyzer's results for the counts
/// (`measure: "unobstructed"`), plus `results/unobstructed-parts.csv`.
pub fn measure_unobstructed(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    scene: &Scene,
    scenario: &Scenario,
    options: &CaptureOptions,
    measure: &MeasureOptions,
) -> Result<UnobstructedCapture> {
    let MeasureOptions { sample, seed, on } = *measure;
    let start = Instant::now();
    if !(sample > 0.0 && sample <= 1.0) {
        return Err(CaptureError::BadOptions(format!("--sample must be in (0, 1], not {sample}")));
    }
    scene.rig.check()?;
    let prepared = prepare_archive(device, queue, scene, options)?;
    let frames = crate::scene_checks::selected_frames(scene, scenario, options)?;
    let warnings = crate::scene_checks::scene_warnings(scene, scenario, &frames)?;
    let (points, per_part) = surface_points(scene, &prepared.unwrapped, sample, seed);
    let (eye_frames, records) = eye_frames(scene, scenario, &frames);
    let obstacles = Obstacles::new(scene);
    let counts = match on {
        MeasureDevice::Cpu => count_unobstructed(&points, &eye_frames, &obstacles),
        MeasureDevice::Gpu => count_unobstructed_gpu(device, queue, &points, &eye_frames, &obstacles)?,
    };

    let [width, height] = prepared.palette_size;
    let mut texel_counts = vec![0u32; width as usize * height as usize];
    let mut by_part: BTreeMap<u32, (u64, u64, f64)> = BTreeMap::new();
    for (point, &count) in points.iter().zip(&counts) {
        texel_counts[point.texel] = count;
        let entry = by_part.entry(point.part).or_default();
        entry.0 += 1;
        entry.1 += u64::from(count);
        entry.2 += f64::from(count) * f64::from(count);
    }
    let estimates: Vec<PartEstimate> = scene
        .vehicle
        .parts
        .iter()
        .enumerate()
        .map(|(index, name)| {
            let texels = per_part[index];
            let (sampled, total, squares) = by_part.get(&(index as u32)).copied().unwrap_or_default();
            let n = sampled as f64;
            let mean = if sampled > 0 { total as f64 / n } else { 0.0 };
            let variance = if sampled > 1 { (squares - n * mean * mean).max(0.0) / (n - 1.0) } else { 0.0 };
            // Finite-population standard error of N·mean.
            let standard_error = if sampled > 0 {
                texels as f64 * ((1.0 - sample).max(0.0) * variance / n).sqrt()
            } else {
                0.0
            };
            PartEstimate {
                part: name.clone(),
                texels,
                sampled,
                sampled_total: total,
                estimated_total: texels as f64 * mean,
                standard_error,
            }
        })
        .collect();

    let captured = CapturedTiles {
        entries: Vec::new(),
        frame_records: records,
        tally: TileTally::default(),
        frames: frames.len() as u32,
        tiles: 0,
        warnings,
    };
    let _ = summarize(scene, scenario, options, &prepared, &captured, 0.0);
    write_manifest(scene, scenario, options, &prepared, captured, false)?;
    let labelled: u64 = per_part.iter().sum();
    let notes = vec![format!(
        "measure \"unobstructed\": a count is the number of eye-frames ({}) in which the texel's point is in view, \
         faces the eye and nothing is in between (exact ray casts, independent of pixels per degree); {} of {} \
         labelled texels sampled (fraction {sample}, seed {seed}), the others are 0 here: divide totals by the \
         fraction to estimate them (per-part estimates with standard errors in unobstructed-parts.csv); \
         computed on the {}",
        eye_frames.len(),
        points.len(),
        labelled,
        match on {
            MeasureDevice::Cpu => "CPU",
            MeasureDevice::Gpu => "GPU (f64 compute shader)",
        }
    )];
    let analyze_options =
        ufcsr::AnalyzeOptions { archive: options.out.clone(), ..ufcsr::AnalyzeOptions::default() };
    let mut analysis =
        ufcsr::analyze_texel_counts(&analyze_options, texel_counts, MEASURE_UNOBSTRUCTED, notes)?;
    let results = ufcsr::default_output_dir(&options.out);
    let written = ufcsr::write_results(&mut analysis, &results)?;
    let estimates_csv = results.join("unobstructed-parts.csv");
    let mut table = csv::Writer::from_path(&estimates_csv)
        .map_err(|e| CaptureError::bad_input(&estimates_csv, format!("writing CSV: {e}")))?;
    for estimate in &estimates {
        table
            .serialize(estimate)
            .map_err(|e| CaptureError::bad_input(&estimates_csv, format!("writing CSV: {e}")))?;
    }
    table.flush().map_err(|e| CaptureError::io(&estimates_csv, e))?;
    Ok(UnobstructedCapture {
        analysis,
        written,
        sampled_texels: points.len() as u64,
        labelled_texels: labelled,
        eye_frames: eye_frames.len() as u64,
        seconds: start.elapsed().as_secs_f64(),
        estimates,
        estimates_csv,
    })
}
