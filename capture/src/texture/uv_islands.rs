//! The unwrap: every triangle gets its own island of palette texels.
//!
//! This automates the Blender step of the paper ("every edge a seam"): each
//! triangle is laid flat with its longest edge along the palette's x axis and
//! packed, at one texel density for the whole vehicle, into shelves of the
//! palette. Each island's rectangle leaves room for the triangle's
//! conservative footprint dilated by one texel (what a pixel can show, given
//! interpolation error at the island's edge) plus one unlabelled texel on
//! every side, so two labelled footprints are always at least two texels
//! apart. The density is the largest for which everything fits (bisection).
//! The texel of the background colour (palette index 4095) is never used.
//! A mesh whose UVs are already unique and non-overlapping can keep them.

use std::collections::HashMap;

use glam::{DVec2, dvec2};

use crate::error::{CaptureError, Result};
use crate::scene::mesh::{Mesh, triangle_area};
use crate::texture::uv_overlaps::{UvOverlaps, summarize_overlaps};

/// Palette index of the background colour `#000FFF`.
pub(crate) const BACKGROUND_INDEX: u64 = 0x000FFF;

/// Texels reserved around an island's triangle: 2 before it (gutter + dilation)
/// and 3 after it (dilation of a footprint that may touch the next texel, plus
/// gutter).
const MARGIN_BEFORE: u32 = 2;
const MARGIN_TOTAL: u32 = 5;

/// An unwrapped vehicle: per triangle, its corners in texel coordinates
/// (x in `[0, W]`, y in `[0, H]`, y = 0 at the palette's top row).
#[derive(Debug, Clone)]
pub struct Unwrapped {
    pub palette: [u32; 2],
    pub texel_uvs: Vec<[DVec2; 3]>,
    /// Texels per m² of vehicle surface (island mode: exact; kept UVs: mean).
    pub texels_per_m2: f64,
    /// `"islands"` or `"kept"`.
    pub method: &'static str,
}

impl Unwrapped {
    /// Normalised UV (0..1) of corner `k` of `triangle`, for the renderer.
    pub fn uv(&self, triangle: usize, k: usize) -> [f32; 2] {
        let t = self.texel_uvs[triangle][k];
        [(t.x / f64::from(self.palette[0])) as f32, (t.y / f64::from(self.palette[1])) as f32]
    }
}

/// The texel coordinates of the background colour in a `palette`, if it has one.
pub fn background_texel(palette: [u32; 2]) -> Option<(u32, u32)> {
    let [w, h] = palette;
    (BACKGROUND_INDEX < u64::from(w) * u64::from(h))
        .then(|| ((BACKGROUND_INDEX % u64::from(w)) as u32, (BACKGROUND_INDEX / u64::from(w)) as u32))
}

/// Lays every triangle flat: corners in metres, longest edge on the x axis,
/// the third corner above it, bounding box starting at the origin.
fn flatten(corners: [glam::Vec3; 3]) -> [DVec2; 3] {
    let p = corners.map(|c| c.as_dvec3());
    let lengths = [(p[1] - p[0]).length(), (p[2] - p[1]).length(), (p[0] - p[2]).length()];
    let longest = (0..3).max_by(|&a, &b| lengths[a].total_cmp(&lengths[b])).unwrap_or(0);
    let (i0, i1, i2) = (longest, (longest + 1) % 3, (longest + 2) % 3);
    let axis = (p[i1] - p[i0]).normalize_or_zero();
    let rel = p[i2] - p[i0];
    let along = rel.dot(axis);
    let up = (rel - axis * along).length();
    let mut flat = [DVec2::ZERO; 3];
    flat[i0] = dvec2(0.0, 0.0);
    flat[i1] = dvec2(lengths[longest], 0.0);
    flat[i2] = dvec2(along, up);
    let min_x = along.min(0.0);
    flat.map(|q| dvec2(q.x - min_x, q.y))
}

/// Shelf-packs rectangles; returns their top-left corners, or `None` if they
/// do not fit. `order` lists rectangles by decreasing height.
fn shelf_pack(
    sizes: &[(u32, u32)],
    order: &[usize],
    palette: [u32; 2],
    background: Option<(u32, u32)>,
) -> Option<Vec<(u32, u32)>> {
    let [w, h] = palette;
    let mut at = vec![(0, 0); sizes.len()];
    let (mut x, mut y, mut shelf) = (0u32, 0u32, 0u32);
    for &i in order {
        let (rw, rh) = sizes[i];
        if rw > w || rh > h {
            return None;
        }
        loop {
            if x + rw > w {
                // A shelf still empty here is blocked by the background texel
                // (the only thing that moves `x` without placing anything):
                // start the next one below that texel, or this loops forever.
                y = match background {
                    Some((_, by)) if shelf == 0 && by >= y => by + 1,
                    _ => y + shelf,
                };
                x = 0;
                shelf = 0;
            }
            if y + rh.max(shelf) > h {
                return None;
            }
            // Step past the background texel rather than cover it.
            if let Some((bx, by)) = background
                && (x..x + rw).contains(&bx)
                && (y..y + rh).contains(&by)
            {
                x = bx + 1;
                continue;
            }
            break;
        }
        at[i] = (x, y);
        x += rw;
        shelf = shelf.max(rh);
    }
    Some(at)
}

/// Unwraps `mesh` into islands at the highest density that fits the
/// canonical `palette`.
pub fn unwrap_islands(mesh: &Mesh, palette: [u32; 2]) -> Result<Unwrapped> {
    unwrap_islands_avoiding(mesh, palette, background_texel(palette))
}

/// Unwraps `mesh` into islands, leaving the texel `background` (the one that
/// holds the background colour in the palette, if any) unused.
pub fn unwrap_islands_avoiding(
    mesh: &Mesh,
    palette: [u32; 2],
    background: Option<(u32, u32)>,
) -> Result<Unwrapped> {
    let flat: Vec<[DVec2; 3]> = (0..mesh.triangles.len()).map(|t| flatten(mesh.corners(t))).collect();
    let extent = |tri: &[DVec2; 3]| {
        let max = tri.iter().fold(DVec2::ZERO, |m, p| m.max(*p));
        (max.x, max.y)
    };
    let extents: Vec<(f64, f64)> = flat.iter().map(extent).collect();
    let sizes_at = |scale: f64| -> Vec<(u32, u32)> {
        extents
            .iter()
            .map(|&(ew, eh)| {
                ((ew * scale).ceil() as u32 + MARGIN_TOTAL, (eh * scale).ceil() as u32 + MARGIN_TOTAL)
            })
            .collect()
    };
    let mut order: Vec<usize> = (0..flat.len()).collect();
    // Heights sort the same at every scale (up to rounding), so sort once.
    order.sort_by(|&a, &b| extents[b].1.total_cmp(&extents[a].1).then(extents[b].0.total_cmp(&extents[a].0)));
    let area = mesh.area();
    if area <= 0.0 {
        return Err(CaptureError::Unwrap("the vehicle has no surface area".into()));
    }
    let texels = f64::from(palette[0]) * f64::from(palette[1]);
    // Bisection on texels per metre: `hi` is the density of a perfect packing.
    let (mut lo, mut hi) = (0.0, (texels / area).sqrt());
    if shelf_pack(&sizes_at(lo), &order, palette, background).is_none() {
        return Err(CaptureError::Unwrap(format!(
            "{} triangles do not fit a {}×{} palette even at zero size (each needs {MARGIN_TOTAL}×{MARGIN_TOTAL} texels of gutter); use a larger --palette-size",
            flat.len(),
            palette[0],
            palette[1]
        )));
    }
    for _ in 0..40 {
        let mid = (lo + hi) / 2.0;
        if shelf_pack(&sizes_at(mid), &order, palette, background).is_some() {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let scale = lo;
    let at = shelf_pack(&sizes_at(scale), &order, palette, background)
        .ok_or_else(|| CaptureError::Unwrap("packing failed at the density that fitted".into()))?;
    let offset = f64::from(MARGIN_BEFORE);
    let texel_uvs: Vec<[DVec2; 3]> = flat
        .iter()
        .zip(&at)
        .map(|(tri, &(x, y))| {
            tri.map(|p| dvec2(f64::from(x) + offset + p.x * scale, f64::from(y) + offset + p.y * scale))
        })
        .collect();
    refuse_no_texels(&texel_uvs, palette)?;
    Ok(Unwrapped { palette, texel_uvs, texels_per_m2: scale * scale, method: "islands" })
}

/// Refuses an unwrap in which no triangle covers a texel centre (a palette so small that only
/// the gutters fit): nothing could be counted or measured, and a study would score every
/// setting 100 pp off instead of saying why.
fn refuse_no_texels(texel_uvs: &[[DVec2; 3]], palette: [u32; 2]) -> Result<()> {
    let mut covered = 0u64;
    for tri in texel_uvs {
        for_texel_centres(tri, palette, |_, _| covered += 1);
    }
    if covered > 0 {
        return Ok(());
    }
    Err(CaptureError::Unwrap(format!(
        "{} triangles fit a {}×{} palette only so small that no texel centre lies on the surface; use a larger --palette-size",
        texel_uvs.len(),
        palette[0],
        palette[1]
    )))
}

/// Keeps the mesh's own UVs after checking that they are inside the palette,
/// that no two triangles share a texel centre and that none covers the
/// background texel.
pub fn keep_uvs(mesh: &Mesh, palette: [u32; 2]) -> Result<Unwrapped> {
    keep_uvs_avoiding(mesh, palette, background_texel(palette))
}

/// [`keep_uvs`] for a palette whose background colour sits at `background`.
pub(crate) fn keep_uvs_avoiding(
    mesh: &Mesh,
    palette: [u32; 2],
    background: Option<(u32, u32)>,
) -> Result<Unwrapped> {
    let Some(uvs) = &mesh.uvs else {
        return Err(CaptureError::Unwrap(match mesh.missing_uvs.as_slice() {
            [] => "--keep-uvs: the mesh has no UVs (TEXCOORD_0 / vt)".into(),
            missing => format!(
                "--keep-uvs: every part needs its own UVs, but {} {} none: {}; unwrap those in Blender (or capture without --keep-uvs)",
                missing.len(),
                if missing.len() == 1 { "has" } else { "have" },
                missing.join("; ")
            ),
        }));
    };
    let size = dvec2(f64::from(palette[0]), f64::from(palette[1]));
    let texel_uvs: Vec<[DVec2; 3]> =
        mesh.triangles.iter().map(|tri| tri.map(|i| uvs[i as usize].as_dvec2() * size)).collect();
    let [w, h] = palette;
    let mut uv_area = 0.0;
    for (number, tri) in texel_uvs.iter().enumerate() {
        if tri.iter().any(|p| !(p.x >= 0.0 && p.y >= 0.0 && p.x <= size.x && p.y <= size.y)) {
            return Err(CaptureError::Unwrap(format!("--keep-uvs: triangle {number} has UVs outside 0..1")));
        }
        uv_area += ((tri[1] - tri[0]).perp_dot(tri[2] - tri[0]) / 2.0).abs();
        if let Some((bx, by)) = background {
            let mut covers = false;
            footprint(tri, palette, 0, |x, y| covers |= (x, y) == (bx, by));
            if covers {
                return Err(CaptureError::Unwrap(format!(
                    "--keep-uvs: triangle {number} covers the background colour's texel ({bx}, {by})"
                )));
            }
        }
    }
    let (overlaps, pairs) = overlap_pairs(&texel_uvs, palette);
    if overlaps > 0 {
        let lines = summarize_overlaps(mesh, palette, overlaps, pairs).lines();
        return Err(CaptureError::Unwrap(format!(
            "--keep-uvs: {overlaps} texels of the {w}×{h} palette are covered by more than one triangle; the UVs must \
             not overlap. Where (parts, texels, example triangle numbers):\n  {}\nCapture without --keep-uvs (the \
             capture unwraps the mesh itself) and, to label parts by a map painted over these UVs, give the scene's \
             vehicle \"parts_from\": {{\"part_map\": PNG, \"legend\": CSV}}; or remove the duplicate faces and \
             separate the overlapping islands in Blender",
            lines.join("\n  ")
        )));
    }
    Ok(Unwrapped { palette, texel_uvs, texels_per_m2: uv_area / mesh.area(), method: "kept" })
}

/// The triangles (texel-space UVs) that share texel centres on `palette`:
/// the texels covered more than once, and per pair (earlier triangle, the
/// one that covered it again) the texels they share.
fn overlap_pairs(texel_uvs: &[[DVec2; 3]], palette: [u32; 2]) -> (u64, HashMap<(u32, u32), u64>) {
    let width = palette[0] as usize;
    let mut owner = vec![u32::MAX; width * palette[1] as usize];
    let mut pairs: HashMap<(u32, u32), u64> = HashMap::new();
    let mut texels = 0u64;
    for (number, tri) in texel_uvs.iter().enumerate() {
        for_texel_centres(tri, palette, |x, y| {
            let slot = &mut owner[y as usize * width + x as usize];
            if *slot != u32::MAX && *slot != number as u32 {
                texels += 1;
                *pairs.entry((*slot, number as u32)).or_default() += 1;
            }
            *slot = number as u32;
        });
    }
    (texels, pairs)
}

/// Where the mesh's own UVs overlap on `palette`, by pair of parts (for
/// `inspect`; `--keep-uvs` refuses with the same lines). `None` without UVs.
pub fn uv_overlaps(mesh: &Mesh, palette: [u32; 2]) -> Option<UvOverlaps> {
    let uvs = mesh.uvs.as_ref()?;
    let size = dvec2(f64::from(palette[0]), f64::from(palette[1]));
    let texel_uvs: Vec<[DVec2; 3]> = mesh
        .triangles
        .iter()
        .map(|tri| tri.map(|i| uvs.get(i as usize).map_or(DVec2::ZERO, |uv| uv.as_dvec2() * size)))
        .collect();
    let (texels, pairs) = overlap_pairs(&texel_uvs, palette);
    Some(summarize_overlaps(mesh, palette, texels, pairs))
}

/// Calls `f` for every texel whose centre lies strictly inside `tri`.
pub(crate) fn for_texel_centres(tri: &[DVec2; 3], palette: [u32; 2], mut f: impl FnMut(u32, u32)) {
    let (lo, hi) = texel_range(tri, palette, 0);
    let area = (tri[1] - tri[0]).perp_dot(tri[2] - tri[0]);
    if area == 0.0 {
        return;
    }
    for y in lo.1..hi.1 {
        for x in lo.0..hi.0 {
            let p = dvec2(f64::from(x) + 0.5, f64::from(y) + 0.5);
            let inside = (0..3).all(|k| {
                let (a, b) = (tri[k], tri[(k + 1) % 3]);
                (b - a).perp_dot(p - a) * area.signum() > 1e-9
            });
            if inside {
                f(x, y);
            }
        }
    }
}

/// Texel index ranges `[lo, hi)` covering `tri`'s bounding box grown by `grow`.
fn texel_range(tri: &[DVec2; 3], palette: [u32; 2], grow: u32) -> ((u32, u32), (u32, u32)) {
    let min = tri[0].min(tri[1]).min(tri[2]);
    let max = tri[0].max(tri[1]).max(tri[2]);
    let g = f64::from(grow);
    let clamp = |v: f64, limit: u32| v.max(0.0).min(f64::from(limit)) as u32;
    (
        (clamp(min.x.floor() - g, palette[0]), clamp(min.y.floor() - g, palette[1])),
        (clamp(max.x.floor() + g + 1.0, palette[0]), clamp(max.y.floor() + g + 1.0, palette[1])),
    )
}

/// Calls `f` for every texel whose square, grown by `dilate` texels on every
/// side, touches `tri`: the conservative footprint (dilated).
pub fn footprint(tri: &[DVec2; 3], palette: [u32; 2], dilate: u32, mut f: impl FnMut(u32, u32)) {
    let (lo, hi) = texel_range(tri, palette, dilate);
    let d = f64::from(dilate);
    for y in lo.1..hi.1 {
        for x in lo.0..hi.0 {
            let square_lo = dvec2(f64::from(x) - d, f64::from(y) - d);
            let square_hi = dvec2(f64::from(x) + 1.0 + d, f64::from(y) + 1.0 + d);
            if triangle_touches_rect(tri, square_lo, square_hi) {
                f(x, y);
            }
        }
    }
}

/// Separating-axis test between a triangle and an axis-aligned rectangle
/// (touching counts as overlapping).
pub(crate) fn triangle_touches_rect(tri: &[DVec2; 3], lo: DVec2, hi: DVec2) -> bool {
    let min = tri[0].min(tri[1]).min(tri[2]);
    let max = tri[0].max(tri[1]).max(tri[2]);
    if max.x < lo.x || min.x > hi.x || max.y < lo.y || min.y > hi.y {
        return false;
    }
    let corners = [lo, dvec2(hi.x, lo.y), hi, dvec2(lo.x, hi.y)];
    for k in 0..3 {
        let (a, b, c) = (tri[k], tri[(k + 1) % 3], tri[(k + 2) % 3]);
        let edge = b - a;
        let side = edge.perp_dot(c - a);
        if side == 0.0 {
            continue;
        }
        // All rectangle corners strictly on the far side of this edge: separated.
        if corners.iter().all(|&q| edge.perp_dot(q - a) * side.signum() < 0.0) {
            return false;
        }
    }
    true
}

/// Sum of triangle areas (m²) per part, for the report.
pub(crate) fn part_areas(mesh: &Mesh) -> Vec<f64> {
    let mut areas = vec![0.0; mesh.parts.len()];
    for t in 0..mesh.triangles.len() {
        areas[mesh.triangle_part[t] as usize] += triangle_area(mesh.corners(t));
    }
    areas
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::demo;

    #[test]
    fn demo_truck_islands_never_overlap_and_skip_the_background_texel() {
        let truck = demo::truck();
        for palette in [[256, 256], [512, 256], [1024, 1024]] {
            let unwrapped = unwrap_islands(&truck, palette).unwrap();
            let [w, h] = palette;
            let mut owner = vec![u32::MAX; (w * h) as usize];
            for (t, tri) in unwrapped.texel_uvs.iter().enumerate() {
                // Island in the palette, flat copy of the 3D triangle at the density.
                let area2d = ((tri[1] - tri[0]).perp_dot(tri[2] - tri[0]) / 2.0).abs();
                let area3d = triangle_area(truck.corners(t));
                assert!((area2d - area3d * unwrapped.texels_per_m2).abs() < 1e-6 * (1.0 + area2d));
                // Dilated footprint plus one gutter texel is disjoint from all others.
                footprint(tri, palette, 2, |x, y| {
                    let slot = &mut owner[(y * w + x) as usize];
                    assert!(
                        *slot == u32::MAX,
                        "palette {palette:?}: triangles {} and {t} overlap at ({x}, {y})",
                        *slot
                    );
                    *slot = t as u32;
                });
            }
            if let Some((bx, by)) = background_texel(palette) {
                assert_eq!(owner[(by * w + bx) as usize], u32::MAX);
            }
        }
    }

    #[test]
    fn a_rectangle_too_wide_to_pass_the_background_texel_goes_below_it_instead_of_looping() {
        // A single wide quad (two triangles, each nearly the palette's width
        // at the fitting density) used to loop forever here.
        let mut plate = Mesh::default();
        let corner = |y: f32, z: f32| glam::Vec3::new(0.0, y, z);
        plate.add_quad("plate", corner(-0.2, 1.5), corner(0.2, 1.5), corner(0.2, 1.7), corner(-0.2, 1.7));
        let unwrapped = unwrap_islands(&plate, [128, 128]).unwrap();
        assert!(unwrapped.texels_per_m2 > 0.0);
        let blocked = shelf_pack(&[(128, 10)], &[0], [128, 64], Some((5, 3)));
        assert_eq!(blocked, Some(vec![(0, 4)]));
    }

    #[test]
    fn a_palette_where_no_texel_lies_on_the_truck_is_refused_naming_the_option() {
        let error = unwrap_islands(&demo::truck(), [128, 128]).unwrap_err().to_string();
        assert!(error.contains("no texel centre") && error.contains("--palette-size"), "{error}");
    }

    #[test]
    fn the_background_texel_is_index_4095() {
        assert_eq!(background_texel([4096, 4096]), Some((4095, 0)));
        assert_eq!(background_texel([256, 256]), Some((255, 15)));
        assert_eq!(background_texel([32, 32]), None);
    }

    #[test]
    fn keep_uvs_accepts_disjoint_and_rejects_overlapping_uvs() {
        let mut mesh = Mesh::default();
        mesh.add_triangle("a", glam::Vec3::ZERO, glam::Vec3::X, glam::Vec3::Y);
        mesh.add_triangle("b", glam::Vec3::Z, glam::Vec3::X + glam::Vec3::Z, glam::Vec3::Y + glam::Vec3::Z);
        let v = glam::Vec2::new;
        mesh.uvs =
            Some(vec![v(0.0, 0.5), v(0.25, 0.5), v(0.0, 0.75), v(0.5, 0.5), v(0.75, 0.5), v(0.5, 0.75)]);
        let kept = keep_uvs(&mesh, [64, 64]).unwrap();
        assert_eq!(kept.method, "kept");
        mesh.uvs =
            Some(vec![v(0.0, 0.5), v(0.25, 0.5), v(0.0, 0.75), v(0.0, 0.5), v(0.25, 0.5), v(0.0, 0.75)]);
        let refused = keep_uvs(&mesh, [64, 64]).unwrap_err().to_string();
        // 16 × 16 texels under a right triangle: 120 centres strictly inside, shared by a and b.
        assert!(
            refused.contains("120 texels of the 64×64 palette") && refused.contains("a × b: 120 texels"),
            "{refused}"
        );
        assert!(refused.contains("triangles 0 & 1") && refused.contains("part_map"), "{refused}");
    }

    #[test]
    fn overlaps_are_named_by_part_pair_and_duplicate_faces_are_told_apart() {
        use glam::{Vec2, vec3};
        let mut mesh = Mesh { uvs: Some(Vec::new()), ..Mesh::default() };
        let uv = |mesh: &mut Mesh, corners: [[f32; 2]; 3]| {
            mesh.uvs.as_mut().unwrap().extend(corners.map(|[u, v]| Vec2::new(u, v)));
        };
        // 0: body over the left half of the palette; 1: a plate elsewhere in
        // space mapped over the same texels; 2: an exact duplicate of 0.
        mesh.add_triangle("body", vec3(0.0, 0.0, 0.0), vec3(1.0, 0.0, 0.0), vec3(0.0, 0.0, 1.0));
        uv(&mut mesh, [[0.0, 0.0], [0.5, 0.0], [0.0, 0.5]]);
        mesh.add_triangle("plate", vec3(5.0, 0.0, 0.0), vec3(6.0, 0.0, 0.0), vec3(5.0, 0.0, 1.0));
        uv(&mut mesh, [[0.0, 0.0], [0.5, 0.0], [0.0, 0.5]]);
        mesh.add_triangle("body", vec3(0.0, 0.0, 0.0), vec3(1.0, 0.0, 0.0), vec3(0.0, 0.0, 1.0));
        uv(&mut mesh, [[0.0, 0.0], [0.5, 0.0], [0.0, 0.5]]);
        // 3: its own texels.
        mesh.add_triangle("roof", vec3(0.0, 2.0, 0.0), vec3(1.0, 2.0, 0.0), vec3(0.0, 2.0, 1.0));
        uv(&mut mesh, [[0.6, 0.6], [1.0, 0.6], [0.6, 1.0]]);
        let overlaps = uv_overlaps(&mesh, [16, 16]).unwrap();
        // Texel centres strictly inside an 8-texel right triangle: 28.
        let inside = 28;
        assert_eq!(overlaps.texels, 2 * inside, "plate over body, then the duplicate over the plate");
        let pairs: Vec<(&str, &str, u64, u64)> = overlaps
            .by_parts
            .iter()
            .map(|o| (o.parts.0.as_str(), o.parts.1.as_str(), o.texels, o.duplicate_texels))
            .collect();
        assert_eq!(pairs, [("body", "plate", 2 * inside, inside)]);
        let lines = overlaps.lines();
        assert!(
            lines[0].contains("body × plate: 56 texels, 28 of them made by coincident duplicate faces"),
            "{lines:?}"
        );
        assert!(lines[0].contains("0 & 1") && lines[0].contains("1 & 2"), "{lines:?}");
    }
}
