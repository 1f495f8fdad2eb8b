//! Where display patches of a given size can go, and which surface samples
//! each one covers.
//!
//! The layout (which patches exist, their centres, normals, height axes,
//! names and mirrors) is read from the vehicle's mesh alone, with the
//! display size and the spacing ([`super::surface`]): never from the texel
//! samples. Two measures of one vehicle with another seed, `--exact-sample`
//! fraction or palette therefore name the same patches at the same places,
//! and tables of different units can be compared display by display.
//!
//! 1. **Centres.** The vehicle's space is cut into cubes of the spacing
//!    (10 cm by default); for every cube, the point of the vehicle's
//!    surface nearest the cube's centre is a candidate centre when it lies
//!    in that cube (so each cube the surface passes through near its middle
//!    gives one centre, and no point is claimed by two cubes). Its face's
//!    normal is the patch's, its face's part names it.
//! 2. **Outward-facing.** A centre is kept when a ray from it along its
//!    face's normal (or, failing that, against it) leaves the vehicle
//!    without hitting it again; that direction is the patch's outward
//!    normal. Surfaces enclosed by the vehicle (a face between two boxes,
//!    the floor of a recess both ways blocked) cannot carry a display.
//! 3. **Footprint (an approximation).** The patch is a W × H rectangle in
//!    the centre's tangent plane: H along the world-vertical direction
//!    projected into that plane (along the vehicle's length on surfaces
//!    within 25° of horizontal, e.g. the hood), W across it. Its footprint
//!    is the box of the rectangle and H/2 either side of its plane; surface
//!    in it that faces within 45° of the patch's normal (either side:
//!    surfaces are two-sided) and is of the centre's kind ([`Mountability`]:
//!    mountable, or glass and wheels under the default list) is the patch's,
//!    so a display may span two body panels but never reach onto a window or
//!    a tyre it would cover (before, 7–15 % of the truck's and the family
//!    bodies' patches did, named and judged by their centre's part alone).
//!    On curved surfaces this projected footprint is a little larger than
//!    the geodesic one (by 1 − cos of the curvature angle).
//! 4. **Fit, exact.** A patch is kept only if the surface covers its
//!    rectangle: the area of the footprint's faces inside the box (each
//!    triangle clipped by the box), projected onto the patch's plane, is at
//!    least 90 % of W × H, and none of the other kind's facing surface in the
//!    box shows from outside (looked for every 5 mm and at every clipped
//!    piece's corner, along the normal to the box's front): a display
//!    overhanging an edge of the body is no candidate, nor one that would
//!    hide the edge of a window or a tyre, while a tyre or glass that the
//!    body in front already hides (glass run down inside a door) is no reason
//!    to drop it. The parts of its kind covering it are the patch's `covers`,
//!    so `placement` judges it by every part under it. The cover is the
//!    mesh's area, not the samples': an estimate from
//!    a texel sample would keep or drop a patch near the 90 % line by the
//!    luck of the sample (with `--exact-sample 1/16`, by a few per cent
//!    either way), and the set of candidates would differ between units.
//! 5. **Members.** The samples of a measure that lie in the footprint
//!    (centre inside the box, facing within 45°, on surface of its kind)
//!    are the patch's: its visible area is measured on them. With a texel
//!    sample a patch may hold few samples (or none, then it is never seen);
//!    its place and name stay.
//!
//! Names: `PART@W.WWxH.HH@xX.XXyY.YYzZ.ZZ` (the display's width and height
//! and the centre in the vehicle frame, metres, x forward, y left, z up), so
//! runs with different display sizes never share a candidate; the mirror of
//! a patch is the kept patch nearest its centre mirrored in the plane y = 0,
//! within half a spacing, when each is the other's.
//!
//! Each kept patch's footprint (centre, normal, height axis, W and H) and the
//! parts it covers are written as `placement-patches.csv`
//! ([`write_patch_table`]), so the analyzer can draw the chosen patches on
//! the vehicle and judge each by every part under it.

use std::collections::HashMap;

use glam::DVec3;

use super::ExactInputs;
use super::surface::{Cell, Surface, area_in_box, cell_of, polygon_in_box};
use crate::exact::types::{SURFACE_LIFT_RELATIVE, SurfaceSample};

/// The footprint table's name and columns: the analyzer's, which reads it.
pub use ufcsr::{placement::PLACEMENT_PATCHES_COLUMNS, placement::PLACEMENT_PATCHES_FILE};

/// A kept patch must be covered by at least this share of its W × H.
pub(crate) const MIN_COVER: f64 = 0.9;
/// Member surfaces face within this angle of the patch normal, degrees.
pub(crate) const MAX_MEMBER_TILT_DEG: f64 = 45.0;
/// A part whose surface covers at most this share of W × H (rounding dust
/// where a face only touches the box) is not under the display.
const DUST: f64 = 1e-6;
/// Surface of the other kind under a display is looked for at points this
/// far apart, m, and at every clipped piece's corners: a sliver of it that
/// shows between them, narrower than this, would go unseen.
const SIGHT_PITCH_M: f64 = 0.005;

/// Points of the convex polygon `piece` no further than `pitch` apart: each
/// triangle of its fan on a barycentric lattice, corners and edges included,
/// each point moved a millionth of the way to its triangle's centroid so that
/// none lies exactly on a neighbouring face's edge.
fn points_of(piece: &[DVec3], pitch: f64) -> impl Iterator<Item = DVec3> + '_ {
    (1..piece.len().saturating_sub(1)).flat_map(move |i| {
        let [a, b, c] = [piece[0], piece[i], piece[i + 1]];
        let longest = (b - a).length().max((c - b).length()).max((a - c).length());
        // At most 4,096 steps a side (a 20 m edge at 5 mm).
        let n = (longest / pitch).ceil().clamp(1.0, 4096.0) as u32;
        let centroid = (a + b + c) / 3.0;
        (0..=n).flat_map(move |i| {
            (0..=n - i).map(move |j| {
                let [u, v] = [f64::from(i) / f64::from(n), f64::from(j) / f64::from(n)];
                let q = a + (b - a) * u + (c - a) * v;
                q + (centroid - q) * 1e-6
            })
        })
    })
}

/// One display patch.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct PlacedPatch {
    pub name: String,
    pub mirror: Option<String>,
    /// Vehicle frame, metres.
    pub centre: DVec3,
    /// Outward unit normal.
    pub normal: DVec3,
    /// Unit vector of the height (H) side.
    pub up: DVec3,
    /// The display's width and height, m.
    pub size_m: [f64; 2],
    /// Indices into the samples.
    pub members: Vec<u32>,
    /// The parts the display covers (its centre's among them), sorted:
    /// `placement` judges it mountable only if every one is
    /// (`placement-patches.csv`'s `covers`).
    pub covers: Vec<String>,
}

impl PlacedPatch {
    /// The W × H rectangle's corners in the vehicle frame, in order around it: the display's
    /// exact outline, which its angular height is measured from (not its samples).
    pub(crate) fn outline(&self) -> [DVec3; 4] {
        let across = self.normal.cross(self.up).normalize_or_zero() * (self.size_m[0] / 2.0);
        let up = self.up * (self.size_m[1] / 2.0);
        let c = self.centre;
        [c - across - up, c + across - up, c + across + up, c - across + up]
    }
}

/// The outward normal at `point` of a face with normal `normal`, if either
/// side escapes the vehicle.
fn outward(inputs: &ExactInputs, point: DVec3, normal: DVec3) -> Option<DVec3> {
    let lift = inputs.obstacles.lift_m;
    let far = 4.0 * lift / SURFACE_LIFT_RELATIVE; // four bounding-box diagonals
    [normal, -normal]
        .into_iter()
        .find(|&n| !inputs.obstacles.vehicle.blocks(point + n * lift, point + n * far))
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

/// A patch's footprint: the box of its W × H rectangle, H/2 either side.
#[derive(Debug, Clone, Copy)]
struct Footprint {
    centre: DVec3,
    normal: DVec3,
    up: DVec3,
    across: DVec3,
    half: [f64; 3],
    /// Whether it lies on mountable surface (its centre's part's
    /// [`Mountability`]): only surface of the same kind is its.
    mountable: bool,
}

/// Per part of the vehicle, whether a display may be mounted on it under
/// the default list ([`ufcsr::placement::DEFAULT_NOT_MOUNTABLE`]: wheels turn,
/// glazing stays transparent): a patch holds only surface of its centre's
/// kind, so no display candidate overlaps glass or a wheel, and no glass
/// candidate reaches onto the body.
struct Mountability<'m> {
    of_part: Vec<bool>,
    /// The mesh's part of each triangle (a sample's kind is its triangle's).
    triangle_part: &'m [u32],
}

impl Mountability<'_> {
    fn new(mesh: &crate::scene::Mesh) -> Mountability<'_> {
        let list = ufcsr::placement::default_not_mountable();
        Mountability {
            of_part: mesh.parts.iter().map(|part| ufcsr::placement::mountable(part, &list)).collect(),
            triangle_part: &mesh.triangle_part,
        }
    }

    fn of(&self, part: u32) -> bool {
        self.of_part.get(part as usize).copied().unwrap_or(true)
    }

    fn of_triangle(&self, triangle: u32) -> bool {
        self.triangle_part.get(triangle as usize).is_none_or(|&part| self.of(part))
    }
}

impl Footprint {
    fn new(centre: DVec3, normal: DVec3, [w, h]: [f64; 2], mountable: bool) -> Footprint {
        let up = up_of(normal);
        Footprint {
            centre,
            normal,
            up,
            across: up.cross(normal),
            half: [w / 2.0, h / 2.0, h / 2.0],
            mountable,
        }
    }

    /// Half the box's diagonal: every point of it is this near the centre.
    fn radius(&self) -> f64 {
        DVec3::from(self.half).length()
    }

    fn faces(&self, normal: DVec3) -> bool {
        normal.dot(self.normal).abs() >= MAX_MEMBER_TILT_DEG.to_radians().cos()
    }

    fn holds(&self, point: DVec3) -> bool {
        let d = point - self.centre;
        d.dot(self.across).abs() <= self.half[0]
            && d.dot(self.up).abs() <= self.half[1]
            && d.dot(self.normal).abs() <= self.half[2]
    }

    /// Per part with facing surface in the box, the share of W × H it
    /// covers, projected onto the patch's plane (exact: each face clipped
    /// by the box), in part order.
    fn cover_by_part(&self, surface: &Surface) -> Vec<(u32, f64)> {
        let reach = DVec3::splat(self.radius());
        let axes = [self.across, self.up, self.normal];
        let whole = 4.0 * self.half[0] * self.half[1];
        let mut shares: std::collections::BTreeMap<u32, f64> = std::collections::BTreeMap::new();
        for index in surface.near(self.centre - reach, self.centre + reach) {
            let face = &surface.faces[index as usize];
            if self.faces(face.normal) {
                let area = area_in_box(face.corners, self.centre, axes, self.half);
                *shares.entry(face.part).or_default() += area * face.normal.dot(self.normal).abs() / whole;
            }
        }
        shares.into_iter().filter(|&(_, share)| share > DUST).collect()
    }

    /// The parts a display here would cover, when it fits: surface of the
    /// patch's kind ([`Mountability`]) covers at least [`MIN_COVER`] of
    /// W × H, and no surface of the other kind shows under it (a door display
    /// reaching over the window's edge, a fender display over the tyre, is
    /// no candidate, nor is glass reaching onto the body). The other kind's
    /// surface hidden behind the display's own (a tyre inside the wheel arch
    /// behind the fender) is neither a reason to drop it nor among its parts.
    fn fit(&self, surface: &Surface, kinds: &Mountability, inputs: &ExactInputs) -> Option<Vec<u32>> {
        let (own, other): (Vec<_>, Vec<_>) =
            self.cover_by_part(surface).into_iter().partition(|&(part, _)| kinds.of(part) == self.mountable);
        let cover: f64 = own.iter().map(|&(_, share)| share).sum();
        let other: Vec<u32> = other.into_iter().map(|(part, _)| part).collect();
        if cover < MIN_COVER || self.shows(&other, surface, inputs) {
            return None;
        }
        Some(own.into_iter().map(|(part, _)| part).collect())
    }

    /// Whether any facing surface of `parts` in the box shows from outside
    /// along the normal, rather than lying behind other surface in the box:
    /// points of it within [`SIGHT_PITCH_M`] of each other (every clipped
    /// piece's corners among them) are looked at from the box's front face.
    fn shows(&self, parts: &[u32], surface: &Surface, inputs: &ExactInputs) -> bool {
        if parts.is_empty() {
            return false;
        }
        let reach = DVec3::splat(self.radius());
        let axes = [self.across, self.up, self.normal];
        let lift = inputs.obstacles.lift_m;
        surface.near(self.centre - reach, self.centre + reach).into_iter().any(|index| {
            let face = &surface.faces[index as usize];
            if !parts.contains(&face.part) || !self.faces(face.normal) {
                return false;
            }
            let piece = polygon_in_box(face.corners, self.centre, axes, self.half);
            points_of(&piece, SIGHT_PITCH_M).any(|q| {
                // To the box's front face, and a lift past it.
                let front = self.half[2] - (q - self.centre).dot(self.normal) + lift;
                !inputs
                    .obstacles
                    .vehicle
                    .blocks(q + self.normal * lift, q + self.normal * front.max(2.0 * lift))
            })
        })
    }

    /// The samples in the box that face the patch and lie on surface of
    /// its kind, ascending.
    fn members(&self, samples: &[SurfaceSample], grid: &Grid, kinds: &Mountability) -> Vec<u32> {
        let mut members: Vec<u32> = grid
            .near(self.centre, self.radius())
            .filter(|&index| {
                let s = &samples[index as usize];
                self.holds(s.position)
                    && self.faces(s.normal)
                    && kinds.of_triangle(s.triangle) == self.mountable
            })
            .collect();
        members.sort_unstable();
        members
    }
}

/// The layout: every patch of size `display` that fits on the
/// outward-facing surface, from the mesh alone (members left empty).
fn lay_out(
    inputs: &ExactInputs,
    display: [f64; 2],
    spacing: f64,
    kinds: &Mountability,
) -> Vec<(String, Footprint, Vec<String>)> {
    let mesh = &inputs.scene.vehicle;
    let centres = Surface::new(mesh, spacing);
    let fits = Surface::new(mesh, spacing.max(display[0].max(display[1]) / 4.0));
    let mut cubes: Vec<Cell> = centres.cells.keys().copied().collect();
    cubes.sort_unstable();
    let mut placed = Vec::new();
    let mut names = std::collections::HashSet::new();
    for cube in cubes {
        let Some((p, face)) = centres.nearest_in_cube(cube) else { continue };
        let face = &centres.faces[face as usize];
        let Some(normal) = outward(inputs, p, face.normal) else { continue };
        let footprint = Footprint::new(p, normal, display, kinds.of(face.part));
        let Some(covered) = footprint.fit(&fits, kinds, inputs) else { continue };
        let part = &mesh.parts[face.part as usize];
        // The display size in the name: runs with different sizes are never one candidate.
        let name = format!("{part}@{:.2}x{:.2}@x{:.2}y{:.2}z{:.2}", display[0], display[1], p.x, p.y, p.z);
        // Two centres on either side of a cube's face can round to one name:
        // they are within a centimetre, so the first stands for both (a name
        // twice would make the table ambiguous).
        if names.insert(name.clone()) {
            let mut covers: Vec<String> = covered.iter().map(|&c| mesh.parts[c as usize].clone()).collect();
            covers.sort();
            covers.dedup();
            placed.push((name, footprint, covers));
        }
    }
    placed
}

/// Every patch of size `display` that fits on the outward-facing surface,
/// with the samples it holds.
pub(crate) fn place_patches(inputs: &ExactInputs, display: [f64; 2], spacing: f64) -> Vec<PlacedPatch> {
    let samples = &inputs.samples.samples;
    let grid = Grid::new(samples, spacing.max(display[0].max(display[1]) / 4.0));
    let kinds = Mountability::new(&inputs.scene.vehicle);
    let mut placed: Vec<PlacedPatch> = lay_out(inputs, display, spacing, &kinds)
        .into_iter()
        .map(|(name, footprint, covers)| PlacedPatch {
            name,
            covers,
            mirror: None,
            centre: footprint.centre,
            normal: footprint.normal,
            up: footprint.up,
            size_m: display,
            members: footprint.members(samples, &grid, &kinds),
        })
        .collect();
    pair_mirrors(&mut placed, spacing);
    placed
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
/// unit normal, unit height axis, display width and height (m), mirror and
/// the parts it covers, so the footprint can be drawn where the frames table
/// names the patch.
pub(crate) fn write_patch_table(
    path: &std::path::Path,
    placed: &[PlacedPatch],
    [w, h]: [f64; 2],
) -> crate::error::Result<()> {
    ufcsr::files::write_atomically(path, |writer| {
        let mut table = csv::Writer::from_writer(writer);
        table.write_record(PLACEMENT_PATCHES_COLUMNS).map_err(std::io::Error::other)?;
        for patch in placed {
            let mut record = vec![patch.name.clone()];
            for v in [patch.centre, patch.normal, patch.up] {
                record.extend([v.x, v.y, v.z].map(|c| c.to_string()));
            }
            record.extend([w.to_string(), h.to_string(), patch.mirror.clone().unwrap_or_default()]);
            record.push(ufcsr::placement::covers_field(&patch.covers));
            table.write_record(&record).map_err(std::io::Error::other)?;
        }
        table.flush()
    })?;
    Ok(())
}
