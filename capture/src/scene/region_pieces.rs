//! Cutting each triangle into the convex pieces the region rules need
//! ([`crate::scene::regions`]), with work that grows about linearly in the
//! rules.
//!
//! Cutting the whole mesh triangle by triangle along every boundary made
//! the pieces multiply: a triangle cut by a plane leaves a quad, fanned into
//! two triangles that both reach the next parallel plane, and so on (140
//! region rules on a 12-triangle cube ran past 40 s into the budget of four
//! million triangles). Here each triangle is cut as a **convex polygon**: a
//! plane splits one polygon into two, never a fan, and a piece that a rule
//! takes (first match wins) is *settled* and not cut by later rules, which
//! could not change its part. Only at the end is each piece fanned into
//! triangles. A new corner on one of the triangle's own edges is computed
//! from that edge's two corners in a fixed order, as [`crate::scene::cut`]
//! does, so two triangles sharing the edge and cut by the same plane get
//! the same point; a settled neighbour not cut there leaves a T-junction on
//! the edge's own line. New corners interpolate the UVs (kept and own).

use glam::{DVec3, Vec2, Vec3};

use crate::scene::cut::{CutPlane, ON_PLANE_M};
use crate::scene::mesh::Mesh;

/// Whether a rule takes a piece of a part (by name) with a centroid.
pub(crate) type Takes<'a> = Box<dyn Fn(&str, DVec3) -> bool + 'a>;

/// One rule as the cutting sees it: its boundaries and whether it takes a
/// piece of a part (by name, after rename) with a centroid.
pub(crate) struct RuleCut<'a> {
    pub label: String,
    pub planes: Vec<CutPlane>,
    /// The box outside which the rule takes nothing and its planes cut nothing.
    pub within: (DVec3, DVec3),
    pub takes: Takes<'a>,
}

/// What cutting did.
#[derive(Debug, Default)]
pub(crate) struct Pieces {
    /// Splits of a piece by a plane.
    pub cut: usize,
    /// Piece–plane tests made: the work, for the test of its growth.
    pub tests: usize,
    /// Rules (labels) whose boundary crossed pieces left whole (budget spent), with their parts.
    pub left_whole: Vec<(String, Vec<String>)>,
}

/// A corner of a piece: where, its weights of the triangle's three corners,
/// which of the triangle's edges (bit k: corner k to k + 1) it lies on, and
/// the mesh vertex when it is one of the triangle's own corners.
#[derive(Debug, Clone, Copy)]
struct Corner {
    position: DVec3,
    weights: DVec3,
    edges: u8,
    vertex: Option<u32>,
}

type Polygon = Vec<Corner>;

/// The triangle being cut: its corners' positions as stored (f32) and as f64.
struct Triangle {
    stored: [Vec3; 3],
    corners: [DVec3; 3],
}

impl Triangle {
    /// The point where `plane` crosses the piece's edge `a`–`b`.
    fn crossing(&self, plane: &CutPlane, a: &Corner, b: &Corner) -> Corner {
        let side = |p: DVec3| plane.normal.dot(p) - plane.offset;
        let common = a.edges & b.edges;
        if common != 0 {
            // On the triangle's own edge k: from its two corners in lexicographic order.
            let k = common.trailing_zeros() as usize;
            let (mut i, mut j) = (k, (k + 1) % 3);
            if self.stored[i].to_array() > self.stored[j].to_array() {
                (i, j) = (j, i);
            }
            let (pi, pj) = (self.corners[i], self.corners[j]);
            let t = side(pi) / (side(pi) - side(pj));
            let (wi, wj) = (DVec3::AXES[i], DVec3::AXES[j]);
            return Corner {
                position: pi + (pj - pi) * t,
                weights: wi + (wj - wi) * t,
                edges: common,
                vertex: None,
            };
        }
        let t = side(a.position) / (side(a.position) - side(b.position));
        Corner {
            position: a.position + (b.position - a.position) * t,
            weights: a.weights + (b.weights - a.weights) * t,
            edges: 0,
            vertex: None,
        }
    }
}

/// The two pieces of `polygon` on either side of `plane`, if it crosses it.
fn split(triangle: &Triangle, polygon: &Polygon, plane: &CutPlane) -> Option<(Polygon, Polygon)> {
    let class: Vec<i32> = polygon
        .iter()
        .map(|c| {
            let s = plane.normal.dot(c.position) - plane.offset;
            if s > ON_PLANE_M {
                1
            } else if s < -ON_PLANE_M {
                -1
            } else {
                0
            }
        })
        .collect();
    if !(class.contains(&1) && class.contains(&-1)) {
        return None;
    }
    let (mut above, mut below) =
        (Vec::with_capacity(polygon.len() + 1), Vec::with_capacity(polygon.len() + 1));
    for k in 0..polygon.len() {
        let next = (k + 1) % polygon.len();
        if class[k] >= 0 {
            above.push(polygon[k]);
        }
        if class[k] <= 0 {
            below.push(polygon[k]);
        }
        if class[k] * class[next] == -1 {
            let corner = triangle.crossing(plane, &polygon[k], &polygon[next]);
            above.push(corner);
            below.push(corner);
        }
    }
    Some((above, below))
}

fn bounds(polygon: &Polygon) -> (DVec3, DVec3) {
    polygon
        .iter()
        .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), c| (lo.min(c.position), hi.max(c.position)))
}

fn overlaps((lo, hi): (DVec3, DVec3), (min, max): (DVec3, DVec3)) -> bool {
    !(lo.cmpgt(max).any() || hi.cmplt(min).any())
}

fn centroid(polygon: &Polygon) -> DVec3 {
    polygon.iter().map(|c| c.position).sum::<DVec3>() / polygon.len() as f64
}

/// The budget, the report and where a crossed piece left whole is noted.
struct Cutting<'r> {
    budget: usize,
    pieces: Pieces,
    whole: Vec<Vec<String>>,
    rules: &'r [RuleCut<'r>],
}

impl Cutting<'_> {
    /// The pieces triangle `t` (of part `part`) is cut into, in winding order each.
    fn triangle(&mut self, mesh: &Mesh, t: usize, part: &str) -> Vec<Polygon> {
        let ids = mesh.triangles[t];
        let stored = ids.map(|i| mesh.positions[i as usize]);
        let triangle = Triangle { stored, corners: stored.map(Vec3::as_dvec3) };
        let mut open: Vec<Polygon> = vec![
            (0..3)
                .map(|k| Corner {
                    position: triangle.corners[k],
                    weights: DVec3::AXES[k],
                    edges: (1 << k) | (1 << ((k + 2) % 3)),
                    vertex: Some(ids[k]),
                })
                .collect(),
        ];
        let mut settled = Vec::new();
        let extent = bounds(&open[0]);
        for (r, rule) in self.rules.iter().enumerate() {
            if open.is_empty() {
                break;
            }
            if !overlaps(extent, rule.within) {
                continue;
            }
            for plane in &rule.planes {
                open = self.cut_all(&triangle, open, plane, (r, part));
            }
            let (taken, left): (Vec<Polygon>, Vec<Polygon>) =
                open.into_iter().partition(|piece| (rule.takes)(part, centroid(piece)));
            settled.extend(taken);
            open = left;
        }
        settled.extend(open);
        settled
    }

    /// Every piece of `open` that `plane` crosses near its region, split in two.
    fn cut_all(
        &mut self,
        triangle: &Triangle,
        open: Vec<Polygon>,
        plane: &CutPlane,
        (rule, part): (usize, &str),
    ) -> Vec<Polygon> {
        let mut next = Vec::with_capacity(open.len() + 1);
        for piece in open {
            self.pieces.tests += 1;
            if !overlaps(bounds(&piece), plane.within) {
                next.push(piece);
                continue;
            }
            match split(triangle, &piece, plane) {
                Some(_) if self.budget < 2 => {
                    if !self.whole[rule].iter().any(|p| p == part) {
                        self.whole[rule].push(part.to_string());
                    }
                    next.push(piece);
                }
                Some((above, below)) => {
                    self.budget -= 2;
                    self.pieces.cut += 1;
                    next.extend([above, below]);
                }
                None => next.push(piece),
            }
        }
        next
    }
}

/// Cuts every triangle of `mesh` into the pieces `rules` need (adding at
/// most `budget` triangles' worth), and replaces the triangles by the
/// pieces' fans, each keeping its triangle's part and winding.
pub(crate) fn cut_into_pieces(mesh: &mut Mesh, rules: &[RuleCut], budget: usize) -> Pieces {
    let mut cutting =
        Cutting { budget, pieces: Pieces::default(), whole: vec![Vec::new(); rules.len()], rules };
    let mut triangles = Vec::with_capacity(mesh.triangles.len());
    let mut parts = Vec::with_capacity(mesh.triangles.len());
    for t in 0..mesh.triangles.len() {
        let part = mesh.triangle_part[t];
        let name = mesh.parts[part as usize].clone();
        let pieces = cutting.triangle(mesh, t, &name);
        if pieces.len() == 1 && pieces[0].iter().all(|c| c.vertex.is_some()) {
            triangles.push(mesh.triangles[t]);
            parts.push(part);
            continue;
        }
        let ids = mesh.triangles[t];
        let mut added: Vec<(DVec3, u32)> = Vec::new();
        for piece in &pieces {
            let index: Vec<u32> = piece.iter().map(|c| vertex_of(mesh, ids, c, &mut added)).collect();
            for k in 1..index.len().saturating_sub(1) {
                triangles.push([index[0], index[k], index[k + 1]]);
                parts.push(part);
            }
        }
    }
    mesh.triangles = triangles;
    mesh.triangle_part = parts;
    let mut pieces = cutting.pieces;
    pieces.left_whole = rules
        .iter()
        .zip(cutting.whole)
        .filter(|(_, parts)| !parts.is_empty())
        .map(|(rule, parts)| (rule.label.clone(), parts))
        .collect();
    pieces
}

/// The mesh vertex of `corner` of a piece of the triangle `ids`: its own
/// corner, or a new vertex (one per point within the triangle) with
/// interpolated UVs.
fn vertex_of(mesh: &mut Mesh, ids: [u32; 3], corner: &Corner, added: &mut Vec<(DVec3, u32)>) -> u32 {
    if let Some(vertex) = corner.vertex {
        return vertex;
    }
    if let Some(&(_, index)) = added.iter().find(|(p, _)| *p == corner.position) {
        return index;
    }
    let w = corner.weights;
    let blend = |uvs: &[Vec2]| -> Vec2 {
        let [a, b, c] = ids.map(|i| uvs[i as usize].as_dvec2());
        (a * w.x + b * w.y + c * w.z).as_vec2()
    };
    mesh.positions.push(corner.position.as_vec3());
    if let Some(uvs) = &mesh.uvs {
        let uv = blend(uvs);
        mesh.uvs.as_mut().expect("checked above").push(uv);
    }
    if !mesh.own_uvs.is_empty() {
        let uv = blend(&mesh.own_uvs);
        mesh.own_uvs.push(uv);
    }
    let index = (mesh.positions.len() - 1) as u32;
    added.push((corner.position, index));
    index
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::mesh::triangle_area;
    use glam::vec3;

    fn everywhere(normal: DVec3, offset: f64) -> CutPlane {
        CutPlane { normal, offset, within: (DVec3::splat(-1e9), DVec3::splat(1e9)) }
    }

    /// `mesh` cut along one plane by a rule that takes nothing.
    fn cut_by(mesh: &mut Mesh, plane: CutPlane, budget: usize) -> Pieces {
        let everywhere = (DVec3::NEG_INFINITY, DVec3::INFINITY);
        let rule = RuleCut {
            label: "plane".into(),
            planes: vec![plane],
            within: everywhere,
            takes: Box::new(|_, _| false),
        };
        cut_into_pieces(mesh, &[rule], budget)
    }

    #[test]
    fn a_cut_keeps_area_winding_part_and_uvs() {
        let mut mesh = Mesh { uvs: Some(Vec::new()), ..Mesh::default() };
        mesh.add_triangle("wall", vec3(0.0, 0.0, 0.0), vec3(4.0, 0.0, 0.0), vec3(0.0, 0.0, 2.0));
        mesh.uvs = Some(vec![Vec2::new(0.0, 0.0), Vec2::new(1.0, 0.0), Vec2::new(0.0, 1.0)]);
        let normal_before = {
            let [a, b, c] = mesh.corners(0);
            (b - a).cross(c - a).normalize()
        };
        assert_eq!(cut_by(&mut mesh, everywhere(DVec3::X, 1.0), 100).cut, 1);
        assert_eq!(mesh.triangles.len(), 3);
        let area = |keep: &dyn Fn(f64) -> bool| -> f64 {
            (0..mesh.triangles.len())
                .filter(|&t| {
                    let c = mesh.corners(t);
                    keep(f64::from(c[0].x + c[1].x + c[2].x) / 3.0)
                })
                .map(|t| triangle_area(mesh.corners(t)))
                .sum()
        };
        // x ≥ 1 of the triangle (0,0)-(4,0)-(0,2): a triangle 3 × 1.5.
        assert!((area(&|x| x >= 1.0) - 2.25).abs() < 1e-6);
        assert!((area(&|x| x < 1.0) - 1.75).abs() < 1e-6);
        for t in 0..3 {
            let [a, b, c] = mesh.corners(t);
            assert!((b - a).cross(c - a).normalize().dot(normal_before) > 0.999, "piece {t} flipped");
            assert_eq!(mesh.triangle_part[t], 0);
        }
        // The new corner on the bottom edge at x = 1 has u = 1/4.
        let uvs = mesh.uvs.as_ref().unwrap();
        let at = mesh.positions.iter().position(|p| (*p - vec3(1.0, 0.0, 0.0)).length() < 1e-6).unwrap();
        assert!((uvs[at] - Vec2::new(0.25, 0.0)).length() < 1e-6);
    }

    #[test]
    fn neighbours_share_the_new_corner_and_far_or_grazing_triangles_stay() {
        let mut mesh = Mesh::default();
        // Two parts sharing the edge (0,0,0)-(2,0,2) with their own vertices.
        mesh.add_triangle("a", vec3(0.0, 0.0, 0.0), vec3(2.0, 0.0, 0.0), vec3(2.0, 0.0, 2.0));
        mesh.add_triangle("b", vec3(2.0, 0.0, 2.0), vec3(0.0, 0.0, 2.0), vec3(0.0, 0.0, 0.0));
        // One touching the plane at a corner only, one far outside `within`.
        mesh.add_triangle("a", vec3(1.0, 5.0, 0.0), vec3(3.0, 5.0, 0.0), vec3(3.0, 5.0, 1.0));
        mesh.add_triangle("a", vec3(0.0, 50.0, 0.0), vec3(2.0, 50.0, 0.0), vec3(2.0, 50.0, 1.0));
        let plane =
            CutPlane { normal: DVec3::X, offset: 1.0, within: (DVec3::splat(-10.0), DVec3::splat(10.0)) };
        let done = cut_by(&mut mesh, plane, 100);
        assert_eq!((done.cut, done.left_whole.len()), (2, 0));
        let on_diagonal: Vec<_> =
            mesh.positions.iter().filter(|p| (**p - vec3(1.0, 0.0, 1.0)).length() < 1e-6).collect();
        assert_eq!(on_diagonal.len(), 2, "one new corner per triangle on the shared edge");
        assert_eq!(on_diagonal[0], on_diagonal[1], "bit for bit the same point");
        assert_eq!(mesh.triangles.len(), 4 + 2 + 2);
    }

    #[test]
    fn an_exhausted_budget_leaves_triangles_whole_and_names_their_part() {
        let mut mesh = Mesh::default();
        mesh.add_triangle("a", vec3(0.0, 0.0, 0.0), vec3(2.0, 0.0, 0.0), vec3(2.0, 0.0, 2.0));
        mesh.add_triangle("b", vec3(0.0, 1.0, 0.0), vec3(2.0, 1.0, 0.0), vec3(2.0, 1.0, 2.0));
        let plane =
            CutPlane { normal: DVec3::X, offset: 1.0, within: (DVec3::splat(-9.0), DVec3::splat(9.0)) };
        let done = cut_by(&mut mesh, plane, 2);
        assert_eq!(done.cut, 1);
        assert_eq!(done.left_whole, vec![("plane".to_string(), vec!["b".to_string()])]);
        assert_eq!(mesh.triangles.len(), 4);
    }
}
