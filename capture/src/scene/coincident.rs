//! Coincident surfaces: triangles that lie in one plane, on top of each other.
//!
//! Why they matter: the renderer cannot tell which of two such surfaces is in
//! front (they tie in the depth buffer — "z-fighting" — and each pixel shows
//! one or the other as the driver's rounding falls), while the exact measure
//! lifts every surface sample off its surface by [`COINCIDENT_RELATIVE`] of
//! the vehicle's size (its `SURFACE_LIFT_RELATIVE`) before casting its ray,
//! and so sees *both*. The two measures then disagree and neither says so:
//! an occluder lying on the vehicle hides part of it in the render and none
//! of it in the exact measure, and two parts sharing faces are counted twice
//! by the exact measure. The scene checks find both here and warn by name;
//! the exact measure counts a face that an earlier face of the mesh covers
//! whole only once ([`covered_triangles`]).
//!
//! Two triangles coincide when each one's corners lie within the tolerance
//! of the other's plane and their interiors overlap in that plane by more
//! than [`MIN_OVERLAP_RELATIVE`] of the smaller one's area (a shared edge
//! is not an overlap). A uniform grid over one set of triangles answers the
//! question for another triangle without testing every pair.

use std::collections::{BTreeMap, HashMap};

use glam::{DMat4, DVec2, DVec3, dvec2};

use crate::error::Result;
use crate::scene::frame_state::FrameState;
use crate::scene::mesh::Mesh;
use crate::scene::rig::{box_corners, vehicle_to_world};
use crate::scene::scenario::Scenario;
use crate::scene::scene_file::Scene;

/// Two surfaces nearer than this share of the vehicle's bounding-box
/// diagonal are coincident: the exact measure's surface lift (1e-5, 0.06 mm
/// on a 6 m truck), within which its rays cannot tell them apart either.
pub(crate) const COINCIDENT_RELATIVE: f64 = 1e-5;
/// An overlap smaller than this share of the smaller triangle's area is a
/// touching edge or rounding, not a shared surface.
pub(crate) const MIN_OVERLAP_RELATIVE: f64 = 1e-6;
/// Grid cells along the indexed set's longest side.
const GRID_CELLS: f64 = 32.0;

/// One set of triangles (one frame, metres) indexed for coincidence queries.
pub(crate) struct CoplanarIndex {
    triangles: Vec<[DVec3; 3]>,
    tolerance: f64,
    min: DVec3,
    max: DVec3,
    cell: f64,
    cells: HashMap<[i64; 3], Vec<u32>>,
}

impl CoplanarIndex {
    /// Indexes `triangles`; `tolerance` (metres) is how far from each
    /// other's plane two surfaces may lie and still coincide.
    pub(crate) fn new(triangles: Vec<[DVec3; 3]>, tolerance: f64) -> CoplanarIndex {
        let (min, max) = triangles
            .iter()
            .flatten()
            .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), p| (lo.min(*p), hi.max(*p)));
        let size = if triangles.is_empty() { 0.0 } else { (max - min).max_element() };
        let cell = (size / GRID_CELLS).max(tolerance).max(f64::MIN_POSITIVE);
        let mut index = CoplanarIndex { triangles, tolerance, min, max, cell, cells: HashMap::new() };
        for (number, triangle) in index.triangles.iter().enumerate() {
            let (lo, hi) = bounds(triangle, tolerance);
            if let Some(range) = index.cell_range(lo, hi) {
                for key in range {
                    index.cells.entry(key).or_default().push(number as u32);
                }
            }
        }
        index
    }

    /// The indexed triangles that coincide with `triangle` (same frame), each
    /// with the area of the overlap, m².
    pub(crate) fn coinciding(&self, triangle: &[DVec3; 3]) -> Vec<(u32, f64)> {
        let (lo, hi) = bounds(triangle, self.tolerance);
        let Some(range) = self.cell_range(lo, hi) else { return Vec::new() };
        let mut candidates: Vec<u32> =
            range.filter_map(|key| self.cells.get(&key)).flatten().copied().collect();
        candidates.sort_unstable();
        candidates.dedup();
        candidates
            .into_iter()
            .filter_map(|number| {
                let other = &self.triangles[number as usize];
                let (other_lo, other_hi) = bounds(other, 0.0);
                if other_hi.cmplt(lo).any() || other_lo.cmpgt(hi).any() {
                    return None;
                }
                let area = overlap_area(other, triangle, self.tolerance);
                (area > 0.0).then_some((number, area))
            })
            .collect()
    }

    /// False when the box around `corners` (same frame) is farther than the
    /// tolerance from every indexed triangle's box: nothing there can coincide.
    pub(crate) fn may_meet(&self, corners: &[DVec3; 8]) -> bool {
        let lo = corners.iter().fold(DVec3::INFINITY, |m, p| m.min(*p)) - DVec3::splat(self.tolerance);
        let hi = corners.iter().fold(DVec3::NEG_INFINITY, |m, p| m.max(*p)) + DVec3::splat(self.tolerance);
        !(self.triangles.is_empty() || hi.cmplt(self.min).any() || lo.cmpgt(self.max).any())
    }

    /// The grid cells a box meets, clamped to the indexed set's bounds;
    /// `None` when the box misses them.
    fn cell_range(&self, lo: DVec3, hi: DVec3) -> Option<impl Iterator<Item = [i64; 3]> + use<>> {
        if self.triangles.is_empty() || hi.cmplt(self.min).any() || lo.cmpgt(self.max).any() {
            return None;
        }
        let to_cell = |p: DVec3| ((p.clamp(self.min, self.max) - self.min) / self.cell).floor();
        let (a, b) = (to_cell(lo), to_cell(hi));
        let (a, b) = ([a.x as i64, a.y as i64, a.z as i64], [b.x as i64, b.y as i64, b.z as i64]);
        Some(
            (a[0]..=b[0])
                .flat_map(move |x| (a[1]..=b[1]).flat_map(move |y| (a[2]..=b[2]).map(move |z| [x, y, z]))),
        )
    }
}

/// The bounding box of a triangle grown by `margin` on every side.
fn bounds(triangle: &[DVec3; 3], margin: f64) -> (DVec3, DVec3) {
    let lo = triangle[0].min(triangle[1]).min(triangle[2]) - DVec3::splat(margin);
    let hi = triangle[0].max(triangle[1]).max(triangle[2]) + DVec3::splat(margin);
    (lo, hi)
}

/// The area (m²) over which `a` and `b` coincide: 0 unless each one's
/// corners lie within `tolerance` of the other's plane and their interiors
/// overlap by more than [`MIN_OVERLAP_RELATIVE`] of the smaller one's area.
pub(crate) fn overlap_area(a: &[DVec3; 3], b: &[DVec3; 3], tolerance: f64) -> f64 {
    let cross = |t: &[DVec3; 3]| (t[1] - t[0]).cross(t[2] - t[0]);
    let (ca, cb) = (cross(a), cross(b));
    let (na, nb) = (ca.normalize_or_zero(), cb.normalize_or_zero());
    if na == DVec3::ZERO || nb == DVec3::ZERO {
        return 0.0;
    }
    let off_plane = |t: &[DVec3; 3], origin: DVec3, normal: DVec3| {
        t.iter().any(|p| (*p - origin).dot(normal).abs() > tolerance)
    };
    if off_plane(b, a[0], na) || off_plane(a, b[0], nb) {
        return 0.0;
    }
    let u = na.any_orthonormal_vector();
    let w = na.cross(u);
    let flat = |t: &[DVec3; 3]| {
        let mut corners = t.map(|p| dvec2((p - a[0]).dot(u), (p - a[0]).dot(w)));
        if (corners[1] - corners[0]).perp_dot(corners[2] - corners[0]) < 0.0 {
            corners.swap(1, 2);
        }
        corners
    };
    let (pa, pb) = (flat(a), flat(b));
    let mut polygon: Vec<DVec2> = pb.to_vec();
    for k in 0..3 {
        polygon = clip_half_plane(&polygon, pa[k], pa[(k + 1) % 3]);
        if polygon.len() < 3 {
            return 0.0;
        }
    }
    let area = polygon_area(&polygon);
    let smaller = (ca.length().min(cb.length())) / 2.0;
    if area > MIN_OVERLAP_RELATIVE * smaller { area } else { 0.0 }
}

/// Sutherland–Hodgman: the part of `polygon` left of the line `from → to`.
fn clip_half_plane(polygon: &[DVec2], from: DVec2, to: DVec2) -> Vec<DVec2> {
    let edge = to - from;
    let side = |p: DVec2| edge.perp_dot(p - from);
    let mut out = Vec::with_capacity(polygon.len() + 1);
    for (k, &p) in polygon.iter().enumerate() {
        let q = polygon[(k + 1) % polygon.len()];
        let (sp, sq) = (side(p), side(q));
        if sp >= 0.0 {
            out.push(p);
        }
        if (sp >= 0.0) != (sq >= 0.0) {
            out.push(p + (q - p) * (sp / (sp - sq)));
        }
    }
    out
}

/// The area of a simple polygon (shoelace), m².
fn polygon_area(polygon: &[DVec2]) -> f64 {
    let twice: f64 = (0..polygon.len()).map(|k| polygon[k].perp_dot(polygon[(k + 1) % polygon.len()])).sum();
    twice.abs() / 2.0
}

/// The vehicle's triangles in its own frame, f64, and the coincidence
/// tolerance for it ([`COINCIDENT_RELATIVE`] of its bounding-box diagonal).
pub(crate) fn vehicle_index(mesh: &Mesh) -> CoplanarIndex {
    let (min, max) = mesh.bounds();
    let triangles = (0..mesh.triangles.len()).map(|t| mesh.corners(t).map(|c| c.as_dvec3())).collect();
    CoplanarIndex::new(triangles, COINCIDENT_RELATIVE * (max - min).length())
}

/// Surface two triangles of one mesh share: the pair (`first` < `second`
/// in mesh order) and the overlap's area, m².
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct SharedSurface {
    pub first: u32,
    pub second: u32,
    pub area_m2: f64,
}

/// Every pair of the indexed triangles that coincide.
pub(crate) fn shared_surfaces(index: &CoplanarIndex) -> Vec<SharedSurface> {
    let mut shared = Vec::new();
    for (second, triangle) in index.triangles.iter().enumerate() {
        let second = second as u32;
        for (first, area_m2) in index.coinciding(triangle) {
            if first < second {
                shared.push(SharedSurface { first, second, area_m2 });
            }
        }
    }
    shared
}

/// Per triangle of `mesh`: true when an earlier triangle covers it whole
/// (a duplicate face: the exact measure counts its surface once, for the
/// earlier triangle).
pub(crate) fn covered_triangles(mesh: &Mesh) -> Vec<bool> {
    let index = vehicle_index(mesh);
    let mut covered = vec![false; mesh.triangles.len()];
    for surface in shared_surfaces(&index) {
        let area = crate::scene::mesh::triangle_area(mesh.corners(surface.second as usize));
        if surface.area_m2 >= area * (1.0 - 1e-6) {
            covered[surface.second as usize] = true;
        }
    }
    covered
}

/// How many coincidences one warning lists by name before it counts the rest.
const LISTED: usize = 8;

/// Warnings for the vehicle's triangles that coincide with one another
/// (within a part or across two), one per pair of parts, largest first.
pub(crate) fn shared_surface_warnings(mesh: &Mesh, index: &CoplanarIndex) -> Vec<String> {
    // (earlier part, later part) → (triangle pairs, shared m², of it covered whole).
    let mut by_parts: BTreeMap<(u32, u32), (usize, f64, f64)> = BTreeMap::new();
    for surface in shared_surfaces(index) {
        let parts = (mesh.triangle_part[surface.first as usize], mesh.triangle_part[surface.second as usize]);
        let area = crate::scene::mesh::triangle_area(mesh.corners(surface.second as usize));
        let entry = by_parts.entry(parts).or_default();
        entry.0 += 1;
        entry.1 += surface.area_m2;
        if surface.area_m2 >= area * (1.0 - 1e-6) {
            entry.2 += surface.area_m2;
        }
    }
    let mut found: Vec<_> = by_parts.into_iter().collect();
    found.sort_by(|a, b| b.1.1.total_cmp(&a.1.1));
    let name = |part: u32| mesh.parts[part as usize].as_str();
    let mut warnings: Vec<String> = found
        .iter()
        .take(LISTED)
        .map(|&((first, second), (pairs, area, covered))| {
            let which = if first == second {
                format!("part {} lies on itself", name(first))
            } else {
                format!("parts {} and {} lie on one another", name(first), name(second))
            };
            format!(
                "coincident faces: {which} over {area:.4} m² ({pairs} pairs of coplanar, overlapping triangles): \
                 the renderer shows one face or the other there as depth ties fall, so its pixels split between \
                 them arbitrarily; the exact measure counts the angular area of the {covered:.4} m² covered whole \
                 by an earlier face once (for {}) and the rest twice, and its counts and exposure for both; \
                 remove the duplicate faces",
                name(first)
            )
        })
        .collect();
    if found.len() > LISTED {
        warnings.push(format!(
            "coincident faces: {} more pairs of parts lie on one another",
            found.len() - LISTED
        ));
    }
    warnings
}

/// What the occluder checks found for one occluder: per vehicle part the
/// largest shared area in one frame (m²), and the frames.
#[derive(Default)]
struct OnTheVehicle {
    parts: BTreeMap<u32, f64>,
    frames: Vec<u32>,
}

/// Warnings for occluders that lie on the vehicle (coplanar with and
/// overlapping its faces) in any of `frames`, one per occluder, naming its
/// parts and the frames. `index` is [`vehicle_index`] of the scene's vehicle.
pub(crate) fn occluder_warnings(
    scene: &Scene,
    scenario: &Scenario,
    frames: &[u32],
    index: &CoplanarIndex,
) -> Result<Vec<String>> {
    let mesh = &scene.vehicle;
    let occluders = &scene.occluders;
    let mut found: BTreeMap<String, OnTheVehicle> = BTreeMap::new();
    for &frame in frames {
        let state = FrameState::at(scene, scenario, frame)?;
        let to_vehicle = vehicle_to_world(&state.vehicle).inverse();
        let mut look = |name: &str, to_vehicle: DMat4, triangles: &mut dyn Iterator<Item = [DVec3; 3]>| {
            let mut shared: BTreeMap<u32, f64> = BTreeMap::new();
            for triangle in triangles {
                let triangle = triangle.map(|p| to_vehicle.transform_point3(p));
                for (number, area) in index.coinciding(&triangle) {
                    *shared.entry(mesh.triangle_part[number as usize]).or_default() += area;
                }
            }
            if !shared.is_empty() {
                let entry = found.entry(name.to_string()).or_default();
                entry.frames.push(frame);
                for (part, area) in shared {
                    let largest = entry.parts.entry(part).or_default();
                    *largest = largest.max(area);
                }
            }
        };
        for (name, objects) in occluders.named_groups() {
            for object in &occluders.objects[objects] {
                let corners = box_corners(object.min, object.max).map(|p| to_vehicle.transform_point3(p));
                if !index.may_meet(&corners) {
                    continue;
                }
                let first = object.first_vertex as usize;
                let positions = &occluders.positions[first..first + object.vertex_count as usize];
                look(&name, to_vehicle, &mut positions.chunks_exact(3).map(|t| [t[0], t[1], t[2]]));
            }
        }
        for (occluder, moving_to_world) in occluders.moving.iter().zip(state.moving_to_world()) {
            let to_vehicle = to_vehicle * moving_to_world;
            let (min, max) = occluder.mesh.bounds();
            if index.may_meet(&box_corners(min, max).map(|p| to_vehicle.transform_point3(p))) {
                look(&occluder.name, to_vehicle, &mut occluder.triangles().into_iter());
            }
        }
    }
    let tolerance_mm = index.tolerance * 1000.0;
    Ok(found
        .into_iter()
        .map(|(name, on)| {
            let mut parts: Vec<(u32, f64)> = on.parts.into_iter().collect();
            parts.sort_by(|a, b| b.1.total_cmp(&a.1));
            let area: f64 = parts.iter().map(|(_, area)| area).sum();
            let mut names: Vec<String> =
                parts.iter().take(LISTED).map(|(part, _)| mesh.parts[*part as usize].clone()).collect();
            if parts.len() > LISTED {
                names.push(format!("{} more", parts.len() - LISTED));
            }
            format!(
                "the occluder {name} lies on the vehicle (within {tolerance_mm:.3} mm of its faces' planes, \
                 overlapping them) over up to {area:.4} m² of {} in frames {}: the renderer shows the occluder or \
                 the vehicle there as depth ties fall (z-fighting) and so hides part of the vehicle, while the \
                 exact measure's rays see the vehicle: the two measures disagree and neither is right; move the \
                 occluder off the vehicle's surface or remove it",
                names.join(", "),
                crate::scene::frame_state::list_frames(&on.frames)
            )
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::dvec3;

    fn square(z: f64, offset: f64) -> [[DVec3; 3]; 2] {
        let (a, b, c, d) = (
            dvec3(offset, 0.0, z),
            dvec3(offset + 1.0, 0.0, z),
            dvec3(offset + 1.0, 1.0, z),
            dvec3(offset, 1.0, z),
        );
        [[a, b, c], [a, c, d]]
    }

    #[test]
    fn coincident_triangles_overlap_by_their_shared_area_and_neighbours_do_not() {
        let [t0, t1] = square(0.0, 0.0);
        // Identical (either winding): the whole area.
        assert!((overlap_area(&t0, &t0, 1e-6) - 0.5).abs() < 1e-12);
        assert!((overlap_area(&t0, &[t0[0], t0[2], t0[1]], 1e-6) - 0.5).abs() < 1e-12);
        // The two halves of a quad share an edge only.
        assert_eq!(overlap_area(&t0, &t1, 1e-6), 0.0);
        // Half a square further along: the part of t0 (0 ≤ y ≤ x ≤ 1) with
        // x ≥ 0.5, ∫ x dx from 0.5 to 1 = 0.375 m², split over both halves.
        let [s0, s1] = square(0.0, 0.5);
        let shared = overlap_area(&t0, &s0, 1e-6) + overlap_area(&t0, &s1, 1e-6);
        assert!((shared - 0.375).abs() < 1e-12, "{shared}");
        // Parallel but 1 mm apart: not coincident at a 0.1 mm tolerance.
        let [u0, _] = square(1e-3, 0.0);
        assert_eq!(overlap_area(&t0, &u0, 1e-4), 0.0);
        assert!(overlap_area(&t0, &u0, 1e-2) > 0.49);
    }

    #[test]
    fn the_index_finds_what_brute_force_finds() {
        let mut triangles = Vec::new();
        for k in 0..20 {
            let [a, b] = square(f64::from(k % 3) * 0.5, f64::from(k) * 0.3);
            triangles.extend([a, b]);
        }
        let index = CoplanarIndex::new(triangles.clone(), 1e-6);
        for query in &triangles {
            let mut found = index.coinciding(query);
            found.sort_by_key(|(n, _)| *n);
            let brute: Vec<(u32, f64)> = (0..triangles.len())
                .filter_map(|n| {
                    let area = overlap_area(&triangles[n], query, 1e-6);
                    (area > 0.0).then_some((n as u32, area))
                })
                .collect();
            assert_eq!(found, brute);
        }
    }
}
