//! Texel sample points: where on the vehicle each texel's footprint lies.
//!
//! A texel's footprint on the mesh is the part of its square (in texel
//! units of the unwrap) that its triangles cover. The renderer names a texel
//! whenever a pixel lands anywhere in that footprint, so the exact measure
//! samples all of it: the square is cut into K × K sub-cells, each sub-cell
//! is clipped against every triangle touching the texel, and each non-empty
//! piece gives one sample at its centroid (always inside its triangle),
//! standing for the piece's area on the surface. The pieces tile the
//! footprint exactly, so their areas add up to the triangles' areas. K = 1
//! keeps the centre of a texel inside one triangle, and samples an edge
//! texel (centre outside every triangle) at the centroid of its piece.
//! A face that an earlier face of the mesh covers whole (a duplicate, the
//! same surface twice) keeps its samples, so its texels still count, but
//! they stand for no area: the angular area counts that surface once.

use glam::{DVec2, DVec3};

use super::types::{EDGE_ON_F32_ULPS, EDGE_ON_RELATIVE, SampledTexel, SurfaceSample, SurfaceSamples};
use crate::scene::mesh::Mesh;
use crate::texture::uv_islands::{Unwrapped, footprint};

/// Below this area (texel² units) a piece is a touching edge, not a footprint.
const EMPTY_PIECE: f64 = 1e-12;

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

/// A vehicle triangle as the sampler needs it.
struct SampledTriangle {
    uv: [DVec2; 3],
    corners: [DVec3; 3],
    normal: DVec3,
    /// Surface m² per texel² of the unwrap.
    area_scale: f64,
    edge_on_m: f64,
}

impl SampledTriangle {
    fn new(mesh: &Mesh, unwrapped: &Unwrapped, triangle: usize) -> Option<SampledTriangle> {
        let f32_corners = mesh.corners(triangle);
        let corners = f32_corners.map(|c| c.as_dvec3());
        let uv = unwrapped.texel_uvs[triangle];
        let cross = (corners[1] - corners[0]).cross(corners[2] - corners[0]);
        let uv_area = (uv[1] - uv[0]).perp_dot(uv[2] - uv[0]).abs() / 2.0;
        let normal = cross.normalize_or_zero();
        if normal == DVec3::ZERO || uv_area == 0.0 {
            return None;
        }
        let largest = corners.iter().map(|c| c.abs().max_element()).fold(0.0, f64::max);
        let longest = (0..3).map(|k| (corners[(k + 1) % 3] - corners[k]).length()).fold(0.0, f64::max);
        let edge_on_m =
            EDGE_ON_F32_ULPS * f64::from(f32::EPSILON) / 2.0 * largest + EDGE_ON_RELATIVE * longest;
        Some(SampledTriangle { uv, corners, normal, area_scale: cross.length() / 2.0 / uv_area, edge_on_m })
    }

    /// The surface point at texel-space point `q` (barycentric through the UVs).
    fn surface_point(&self, q: DVec2) -> DVec3 {
        let uv = &self.uv;
        let area = (uv[1] - uv[0]).perp_dot(uv[2] - uv[0]);
        let w1 = (q - uv[0]).perp_dot(uv[2] - uv[0]) / area;
        let w2 = (uv[1] - uv[0]).perp_dot(q - uv[0]) / area;
        let w0 = 1.0 - w1 - w2;
        self.corners[0] * w0 + self.corners[1] * w1 + self.corners[2] * w2
    }
}

/// Samples every texel (of the `fraction` kept by `seed`) that has a
/// footprint on `mesh`, K × K sub-cells each.
pub fn surface_samples(
    mesh: &Mesh,
    unwrapped: &Unwrapped,
    fraction: f64,
    seed: u64,
    samples_per_side: u32,
) -> SurfaceSamples {
    let [width, _] = unwrapped.palette;
    let triangles: Vec<Option<SampledTriangle>> =
        (0..mesh.triangles.len()).map(|t| SampledTriangle::new(mesh, unwrapped, t)).collect();
    // A face that an earlier face covers whole is the same surface: its
    // samples stand for no area (the scene checks warn by part name).
    let covered = crate::scene::coincident::covered_triangles(mesh);
    // (texel, triangle) for every texel square a triangle touches.
    let mut touching: Vec<(u32, u32)> = Vec::new();
    for (index, triangle) in triangles.iter().enumerate() {
        if let Some(triangle) = triangle {
            footprint(&triangle.uv, unwrapped.palette, 0, |x, y| {
                touching.push((y * width + x, index as u32));
            });
        }
    }
    touching.sort_unstable();
    touching.dedup();
    let mut out = SurfaceSamples {
        texels_per_part: vec![0; mesh.parts.len()],
        area_per_part_m2: vec![0.0; mesh.parts.len()],
        samples_per_side,
        ..SurfaceSamples::default()
    };
    for group in touching.chunk_by(|a, b| a.0 == b.0) {
        let texel = group[0].0;
        let [x, y] = [texel % width, texel / width];
        let first = out.samples.len();
        let mut part = None;
        for &(_, index) in group {
            let Some(triangle) = &triangles[index as usize] else { continue };
            for (centroid, area) in pieces(&triangle.uv, x, y, samples_per_side) {
                let area_m2 = if covered[index as usize] { 0.0 } else { area * triangle.area_scale };
                let triangle_part = mesh.triangle_part[index as usize];
                out.area_per_part_m2[triangle_part as usize] += area_m2;
                part.get_or_insert(triangle_part);
                out.samples.push(SurfaceSample {
                    position: triangle.surface_point(centroid),
                    normal: triangle.normal,
                    area_m2,
                    edge_on_m: triangle.edge_on_m,
                    triangle: index,
                });
            }
        }
        let Some(part) = part else { continue };
        out.texels_per_part[part as usize] += 1;
        if is_sampled(texel as usize, fraction, seed) {
            let count = (out.samples.len() - first) as u32;
            out.texels.push(SampledTexel { texel, part, first: first as u32, count });
        } else {
            out.samples.truncate(first);
        }
    }
    out
}

/// The pieces of triangle `uv` in texel `(x, y)`'s K × K sub-cells:
/// (centroid, area in texel² units) of each non-empty one.
fn pieces(uv: &[DVec2; 3], x: u32, y: u32, k: u32) -> Vec<(DVec2, f64)> {
    let origin = DVec2::new(f64::from(x), f64::from(y));
    let cell = 1.0 / f64::from(k);
    let mut out = Vec::with_capacity((k * k) as usize);
    for j in 0..k {
        for i in 0..k {
            let lo = origin + DVec2::new(f64::from(i), f64::from(j)) * cell;
            let hi = lo + DVec2::splat(cell);
            let corners = [lo, DVec2::new(hi.x, lo.y), hi, DVec2::new(lo.x, hi.y)];
            if corners.iter().all(|&c| inside(uv, c)) {
                // The whole sub-cell: its centre (exactly the texel centre for K = 1).
                out.push(((lo + hi) / 2.0, cell * cell));
                continue;
            }
            let piece = clip_to_box(uv, lo, hi);
            if let Some((centroid, area)) = centroid_and_area(&piece)
                && area > EMPTY_PIECE
            {
                out.push((centroid, area));
            }
        }
    }
    out
}

/// Is `p` inside (or on) the triangle?
fn inside(tri: &[DVec2; 3], p: DVec2) -> bool {
    let area = (tri[1] - tri[0]).perp_dot(tri[2] - tri[0]);
    (0..3).all(|k| (tri[(k + 1) % 3] - tri[k]).perp_dot(p - tri[k]) * area.signum() >= 0.0)
}

/// Sutherland–Hodgman: the triangle clipped to the box `[lo, hi]`.
fn clip_to_box(tri: &[DVec2; 3], lo: DVec2, hi: DVec2) -> Vec<DVec2> {
    let mut polygon: Vec<DVec2> = tri.to_vec();
    // Each edge of the box: keep the side where `sign * (p[axis] - bound) ≥ 0`.
    for (axis, bound, sign) in [(0, lo.x, 1.0), (0, hi.x, -1.0), (1, lo.y, 1.0), (1, hi.y, -1.0)] {
        let distance = |p: DVec2| sign * (p[axis] - bound);
        let mut clipped = Vec::with_capacity(polygon.len() + 2);
        for (i, &current) in polygon.iter().enumerate() {
            let previous = polygon[(i + polygon.len() - 1) % polygon.len()];
            let (dc, dp) = (distance(current), distance(previous));
            if (dc >= 0.0) != (dp >= 0.0) {
                let t = dp / (dp - dc);
                let mut crossing = previous + (current - previous) * t;
                crossing[axis] = bound;
                clipped.push(crossing);
            }
            if dc >= 0.0 {
                clipped.push(current);
            }
        }
        polygon = clipped;
        if polygon.is_empty() {
            break;
        }
    }
    polygon
}

/// Centroid and (unsigned) area of a simple polygon; `None` when degenerate.
fn centroid_and_area(polygon: &[DVec2]) -> Option<(DVec2, f64)> {
    if polygon.len() < 3 {
        return None;
    }
    // Relative to the first vertex, for precision.
    let base = polygon[0];
    let (mut twice_area, mut weighted) = (0.0, DVec2::ZERO);
    for i in 1..polygon.len() - 1 {
        let (a, b) = (polygon[i] - base, polygon[i + 1] - base);
        let cross = a.perp_dot(b);
        twice_area += cross;
        weighted += (a + b) * cross;
    }
    if twice_area == 0.0 {
        return None;
    }
    Some((base + weighted / (3.0 * twice_area), twice_area.abs() / 2.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_pieces_of_a_triangle_add_up_to_its_area() {
        let uv = [DVec2::new(0.3, 0.2), DVec2::new(5.7, 1.1), DVec2::new(2.2, 4.9)];
        let area = (uv[1] - uv[0]).perp_dot(uv[2] - uv[0]).abs() / 2.0;
        for k in [1, 2, 3, 4] {
            let mut total = 0.0;
            for y in 0..6 {
                for x in 0..6 {
                    for (centroid, piece) in pieces(&uv, x, y, k) {
                        assert!(inside(&uv, centroid), "K = {k}: centroid {centroid:?} outside");
                        total += piece;
                    }
                }
            }
            assert!((total - area).abs() < 1e-9, "K = {k}: {total} against {area}");
        }
    }

    #[test]
    fn a_face_two_parts_share_counts_its_area_once() {
        // A 2 m cube, and a badge made of its +x face's own two triangles:
        // the exact measure counted that 4 m² twice (742.8 vs 723.8 deg²·s rendered).
        let mut mesh = Mesh::default();
        mesh.add_box(glam::vec3(-1.0, -1.0, 0.0), glam::vec3(1.0, 1.0, 2.0), [Some("body"); 6]);
        for t in 0..2 {
            let [a, b, c] = mesh.corners(t);
            mesh.add_triangle("badge", a, b, c);
        }
        let palette = [64, 64];
        let unwrapped =
            crate::texture::uv_islands::unwrap_islands(&mesh, palette).expect("a cube fits a 64² palette");
        let samples = surface_samples(&mesh, &unwrapped, 1.0, 7, 2);
        let [body, badge] = [samples.area_per_part_m2[0], samples.area_per_part_m2[1]];
        assert!((body - 24.0).abs() < 1e-6 && badge == 0.0, "body {body} m², badge {badge} m²");
        // Its texels are still sampled (they count when seen), standing for no area.
        assert!(samples.texels.iter().any(|texel| texel.part == 1));
    }

    #[test]
    fn an_interior_texel_is_sampled_at_its_centre() {
        let uv = [DVec2::new(-10.0, -10.0), DVec2::new(30.0, -10.0), DVec2::new(-10.0, 30.0)];
        assert_eq!(pieces(&uv, 2, 3, 1), vec![(DVec2::new(2.5, 3.5), 1.0)]);
        assert_eq!(pieces(&uv, 2, 3, 2).len(), 4);
    }
}
