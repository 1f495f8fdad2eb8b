//! Where display patches of a given size can go, and which surface samples
//! each one covers.
//!
//! 1. **Centres.** The vehicle's bounding box is cut into cubes of the
//!    spacing (10 cm by default); in every cube holding surface samples the
//!    sample nearest the cube's centre is a candidate centre.
//! 2. **Outward-facing.** A centre is kept when a ray from it along its
//!    triangle's normal (or, failing that, against it) leaves the vehicle
//!    without hitting it again; that direction is the patch's outward
//!    normal. Surfaces enclosed by the vehicle (a face between two boxes,
//!    the floor of a recess both ways blocked) cannot carry a display.
//! 3. **Footprint (an approximation).** The patch is a W × H rectangle in
//!    the centre's tangent plane: H along the world-vertical direction
//!    projected into that plane (along the vehicle's length on surfaces
//!    within 25° of horizontal, e.g. the hood), W across it. A sample
//!    belongs to the patch when its projection onto the plane lies inside
//!    the rectangle, it lies within H/2 of the plane, and its surface faces
//!    within 45° of the patch's normal (either side: surfaces are
//!    two-sided). On curved surfaces this projected footprint is a little
//!    larger than the geodesic one (by 1 − cos of the curvature angle).
//! 4. **Fit.** A patch is kept only if the surface covers its rectangle:
//!    the members' area projected onto the plane, scaled by 1 / the texel
//!    sample fraction, is at least 90 % of W × H. A display overhanging an
//!    edge of the body is no candidate.
//!
//! Names: `PART@W.WWxH.HH@xX.XXyY.YYzZ.ZZ` (the display's width and height
//! and the centre in the vehicle frame, metres, x forward, y left, z up), so
//! runs with different display sizes never share a candidate; the mirror of a patch is the kept patch
//! nearest its centre mirrored in the plane y = 0, within half a spacing.
//!
//! Each kept patch's footprint (centre, normal, height axis, W and H) is
//! written as `placement-patches.csv` ([`write_patch_table`]), so the
//! analyzer can draw the chosen patches on the vehicle.

use std::collections::HashMap;

use glam::DVec3;

use super::ExactInputs;
use crate::exact::types::{SURFACE_LIFT_RELATIVE, SurfaceSample};

/// The footprint table's name and columns: the analyzer's, which reads it.
pub use ufcsr::{PLACEMENT_PATCHES_COLUMNS, PLACEMENT_PATCHES_FILE};

/// A kept patch must be covered by at least this share of its W × H.
pub const MIN_COVER: f64 = 0.9;
/// Member surfaces face within this angle of the patch normal, degrees.
pub const MAX_MEMBER_TILT_DEG: f64 = 45.0;

/// One display patch.
#[derive(Debug, Clone, PartialEq)]
pub struct PlacedPatch {
    pub name: String,
    pub mirror: Option<String>,
    /// Vehicle frame, metres.
    pub centre: DVec3,
    /// Outward unit normal.
    pub normal: DVec3,
    /// Unit vector of the height (H) side.
    pub up: DVec3,
    /// Indices into the samples.
    pub members: Vec<u32>,
}

type Cell = [i64; 3];

fn cell_of(p: DVec3, size: f64) -> Cell {
    [(p.x / size).floor() as i64, (p.y / size).floor() as i64, (p.z / size).floor() as i64]
}

/// The sample index nearest the centre of each occupied cube.
fn centres(samples: &[SurfaceSample], spacing: f64) -> Vec<u32> {
    let mut best: HashMap<Cell, (f64, u32)> = HashMap::new();
    for (index, sample) in samples.iter().enumerate() {
        let cell = cell_of(sample.position, spacing);
        let middle = DVec3::new(cell[0] as f64 + 0.5, cell[1] as f64 + 0.5, cell[2] as f64 + 0.5) * spacing;
        let d = (sample.position - middle).length_squared();
        let entry = best.entry(cell).or_insert((f64::INFINITY, index as u32));
        if d < entry.0 || (d == entry.0 && (index as u32) < entry.1) {
            *entry = (d, index as u32);
        }
    }
    let mut out: Vec<u32> = best.into_values().map(|(_, index)| index).collect();
    out.sort_unstable();
    out
}

/// The outward normal at `sample`, if either side escapes the vehicle.
fn outward(inputs: &ExactInputs, sample: &SurfaceSample) -> Option<DVec3> {
    let lift = inputs.obstacles.lift_m;
    let far = 4.0 * lift / SURFACE_LIFT_RELATIVE; // four bounding-box diagonals
    [sample.normal, -sample.normal].into_iter().find(|&n| {
        let from = sample.position + n * lift;
        !inputs.obstacles.vehicle.blocks(from, sample.position + n * far)
    })
}

/// The height direction of a patch with outward `normal`.
fn up_of(normal: DVec3) -> DVec3 {
    let reference = if normal.z.abs() > 25f64.to_radians().cos() { DVec3::X } else { DVec3::Z };
    (reference - normal * reference.dot(normal)).normalize()
}

/// Samples bucketed by cube for the footprint queries.
struct Grid {
    size: f64,
    cells: HashMap<Cell, Vec<u32>>,
}

impl Grid {
    fn new(samples: &[SurfaceSample], size: f64) -> Grid {
        let mut cells: HashMap<Cell, Vec<u32>> = HashMap::new();
        for (index, sample) in samples.iter().enumerate() {
            cells.entry(cell_of(sample.position, size)).or_default().push(index as u32);
        }
        Grid { size, cells }
    }

    /// Every sample within `radius` of `centre` (and some more).
    fn near(&self, centre: DVec3, radius: f64) -> impl Iterator<Item = u32> + '_ {
        let lo = cell_of(centre - DVec3::splat(radius), self.size);
        let hi = cell_of(centre + DVec3::splat(radius), self.size);
        (lo[0]..=hi[0])
            .flat_map(move |x| (lo[1]..=hi[1]).flat_map(move |y| (lo[2]..=hi[2]).map(move |z| [x, y, z])))
            .filter_map(|cell| self.cells.get(&cell))
            .flatten()
            .copied()
    }
}

/// The members of a W × H patch and the share of W × H they cover.
fn footprint(
    samples: &[SurfaceSample],
    grid: &Grid,
    centre: DVec3,
    normal: DVec3,
    up: DVec3,
    [w, h]: [f64; 2],
) -> (Vec<u32>, f64) {
    let across = up.cross(normal);
    let min_facing = MAX_MEMBER_TILT_DEG.to_radians().cos();
    let radius = 0.5 * (w * w + h * h).sqrt() + h;
    let mut members: Vec<u32> = grid
        .near(centre, radius)
        .filter(|&index| {
            let s = &samples[index as usize];
            let d = s.position - centre;
            d.dot(across).abs() <= w / 2.0
                && d.dot(up).abs() <= h / 2.0
                && d.dot(normal).abs() <= h / 2.0
                && s.normal.dot(normal).abs() >= min_facing
        })
        .collect();
    members.sort_unstable();
    let projected: f64 = members
        .iter()
        .map(|&i| samples[i as usize].area_m2 * samples[i as usize].normal.dot(normal).abs())
        .sum();
    (members, projected / (w * h))
}

/// Every patch of size `display` that fits on the outward-facing surface.
pub fn place_patches(inputs: &ExactInputs, display: [f64; 2], spacing: f64) -> Vec<PlacedPatch> {
    let samples = &inputs.samples.samples;
    let grid = Grid::new(samples, spacing.max(display[0].max(display[1]) / 4.0));
    let part_of = part_of_samples(inputs);
    let mut placed = Vec::new();
    let mut names = std::collections::HashSet::new();
    for centre in centres(samples, spacing) {
        let sample = &samples[centre as usize];
        let Some(normal) = outward(inputs, sample) else { continue };
        let up = up_of(normal);
        let (members, cover) = footprint(samples, &grid, sample.position, normal, up, display);
        if cover / inputs.sample_fraction < MIN_COVER {
            continue;
        }
        let p = sample.position;
        let part = &inputs.scene.vehicle.parts[part_of[centre as usize] as usize];
        // The display size in the name: runs with different sizes are never one candidate.
        let name = format!("{part}@{:.2}x{:.2}@x{:.2}y{:.2}z{:.2}", display[0], display[1], p.x, p.y, p.z);
        // Two centres on either side of a cube's face can round to one name:
        // they are within a centimetre, so the first stands for both (a name
        // twice would make the table ambiguous).
        if !names.insert(name.clone()) {
            continue;
        }
        placed.push(PlacedPatch { name, mirror: None, centre: p, normal, up, members });
    }
    pair_mirrors(&mut placed, spacing);
    placed
}

fn part_of_samples(inputs: &ExactInputs) -> Vec<u32> {
    let mut part_of = vec![0u32; inputs.samples.samples.len()];
    for texel in &inputs.samples.texels {
        part_of[texel.first as usize..(texel.first + texel.count) as usize].fill(texel.part);
    }
    part_of
}

/// Each patch's mirror: the patch nearest its centre mirrored in y = 0.
fn pair_mirrors(placed: &mut [PlacedPatch], spacing: f64) {
    let mirrors: Vec<Option<String>> = placed
        .iter()
        .map(|patch| {
            let target = DVec3::new(patch.centre.x, -patch.centre.y, patch.centre.z);
            placed
                .iter()
                .filter(|other| other.name != patch.name)
                .map(|other| ((other.centre - target).length(), other))
                .filter(|(d, _)| *d <= spacing / 2.0)
                .min_by(|a, b| a.0.total_cmp(&b.0))
                .map(|(_, other)| other.name.clone())
        })
        .collect();
    // Only mutual pairs: A's nearest mirror image may be B while B's is C
    // (near the centre plane), and a one-sided mirror would put one patch
    // in a symmetric pair twice; `placement` refuses such a table.
    let index: std::collections::HashMap<&str, usize> =
        placed.iter().enumerate().map(|(i, patch)| (patch.name.as_str(), i)).collect();
    let mutual: Vec<Option<String>> = mirrors
        .iter()
        .enumerate()
        .map(|(i, mirror)| {
            let other = *index.get(mirror.as_deref()?)?;
            (mirrors[other].as_deref() == Some(placed[i].name.as_str())).then(|| mirror.clone()).flatten()
        })
        .collect();
    for (patch, mirror) in placed.iter_mut().zip(mutual) {
        patch.mirror = mirror;
    }
}

/// Writes one row per patch: its name, centre (vehicle frame, m), outward
/// unit normal, unit height axis, display width and height (m) and mirror,
/// so the footprint can be drawn where the frames table names the patch.
pub fn write_patch_table(
    path: &std::path::Path,
    placed: &[PlacedPatch],
    [w, h]: [f64; 2],
) -> crate::error::Result<()> {
    ufcsr::write_atomically(path, |writer| {
        let mut table = csv::Writer::from_writer(writer);
        table.write_record(PLACEMENT_PATCHES_COLUMNS).map_err(std::io::Error::other)?;
        for patch in placed {
            let mut record = vec![patch.name.clone()];
            for v in [patch.centre, patch.normal, patch.up] {
                record.extend([v.x, v.y, v.z].map(|c| c.to_string()));
            }
            record.extend([w.to_string(), h.to_string(), patch.mirror.clone().unwrap_or_default()]);
            table.write_record(&record).map_err(std::io::Error::other)?;
        }
        table.flush()
    })?;
    Ok(())
}
