//! Segment-against-triangles queries for the exact measure: a bounding-volume
//! hierarchy built with the surface-area heuristic over binned centroids, its
//! any-hit traversal with a fixed stack (no allocation per ray), and the same
//! question answered by brute force so tests can check one against the other.
//!
//! Nodes are 64 bytes (one cache line): bounds in f64 and `(first, count)`;
//! an inner node's children sit side by side at `first` and `first + 1`.
//! Triangles are stored as `(corner, edge 1, edge 2)`, the form
//! Möller–Trumbore uses, and both paths (BVH, brute force) read those same
//! stored numbers.
//!
//! The box test is conservative, so the hierarchy answers exactly as brute
//! force: every node's bounds are widened at the build by [`BOUNDS_MARGIN`]
//! of their size and distance from the origin (far more than the rounding of
//! Möller–Trumbore or of the slab test), and the slab test accepts a box
//! whose entry and exit parameters are within rounding of each other. A
//! triangle the segment crosses therefore always lies in a visited leaf, and
//! a shortcut that tests one remembered triangle first
//! ([`TriangleBvh::triangle_blocks`], the measure's occluder memory) changes
//! no answer.

use glam::DVec3;

pub(crate) use crate::scene::ray_triangle::StoredTriangle;
use crate::scene::ray_triangle::ray_triangle_parameter;

/// The deepest the build goes; a node at this depth is a leaf whatever its
/// size, so the traversal stack (`TRAVERSAL_STACK`) can never overflow.
pub(crate) const MAX_DEPTH: usize = 48;
/// Entries of the traversal stack: one more than
/// the depth of a push-two-pop-one walk of a `MAX_DEPTH` tree.
pub(crate) const TRAVERSAL_STACK: usize = 64;
/// Triangles at or under which a node is not split.
const LEAF_SIZE: usize = 2;
/// Centroid bins per axis of the SAH sweep.
const BINS: usize = 12;
/// Cost of visiting a node against testing one triangle, for the SAH.
const TRAVERSAL_COST: f64 = 1.0;
/// How far every node's bounds are widened outwards, relative to their
/// largest |coordinate| plus their largest extent: 1e-7 is ≈ 10⁹ units of
/// rounding of f64, so a point Möller–Trumbore finds on a triangle (its
/// rounding included) lies inside every box that holds the triangle, while
/// the boxes grow by 0.1 µm per metre, which the walk does not notice.
pub(crate) const BOUNDS_MARGIN: f64 = 1e-7;
/// The slab test's exit parameter is scaled by 1 + 2γ₃ (γ₃ = 3ε / (1 − 3ε),
/// ε = 2⁻⁵³) before it is compared with the entry: the rounding of
/// `(bound − from) · (1 / direction)` cannot then reject a box the segment
/// touches (Ize, "Robust BVH ray traversal", JCGT 2013).
const SLAB_ROUNDING: f64 = 1.0 + 2.0 * (3.0 * f64::EPSILON / 2.0) / (1.0 - 3.0 * f64::EPSILON / 2.0);

/// One node: 48 bytes of bounds and two u32 (padded to a cache line).
#[derive(Debug, Clone, Copy)]
#[repr(C, align(64))]
struct Node {
    min: [f64; 3],
    max: [f64; 3],
    /// Leaf: `[first, first + count)` of the triangles; inner: children at `first` and `first + 1`.
    first: u32,
    count: u32,
}

/// A triangle soup with a hierarchy over it.
pub struct TriangleBvh {
    triangles: Vec<StoredTriangle>,
    nodes: Vec<Node>,
}

/// A build item: a triangle's bounds and centroid.
#[derive(Clone, Copy)]
struct Item {
    min: DVec3,
    max: DVec3,
    centroid: DVec3,
    index: usize,
}

impl TriangleBvh {
    /// Builds the hierarchy (SAH over `BINS` centroid bins per axis).
    pub fn new(corners: Vec<[DVec3; 3]>) -> TriangleBvh {
        let mut items: Vec<Item> = corners
            .iter()
            .enumerate()
            .map(|(index, t)| {
                let (min, max) = (t[0].min(t[1]).min(t[2]), t[0].max(t[1]).max(t[2]));
                Item { min, max, centroid: (t[0] + t[1] + t[2]) / 3.0, index }
            })
            .collect();
        let mut nodes = Vec::with_capacity(2 * corners.len() / LEAF_SIZE + 1);
        if !items.is_empty() {
            nodes.push(leaf(0, items.len()));
            let mut pending = vec![(0usize, 1usize)];
            while let Some((node, depth)) = pending.pop() {
                let (first, count) = (nodes[node].first as usize, nodes[node].count as usize);
                let slice = &mut items[first..first + count];
                let (min, max) = item_bounds(slice);
                nodes[node].min = min.to_array();
                nodes[node].max = max.to_array();
                if count <= LEAF_SIZE || depth >= MAX_DEPTH {
                    continue;
                }
                let Some(half) = sah_partition(slice, min, max) else { continue };
                let children = nodes.len();
                nodes.push(leaf(first, half));
                nodes.push(leaf(first + half, count - half));
                nodes[node] = Node { first: children as u32, count: 0, ..nodes[node] };
                pending.push((children, depth + 1));
                pending.push((children + 1, depth + 1));
            }
        }
        nodes.iter_mut().for_each(widen);
        let triangles = items.iter().map(|item| StoredTriangle::from_corners(&corners[item.index])).collect();
        TriangleBvh { triangles, nodes }
    }

    /// True when the open segment `from → to` (ends excluded) crosses a
    /// triangle: any hit ends the walk.
    pub fn blocks(&self, from: DVec3, to: DVec3) -> bool {
        self.first_blocker(from, to).is_some()
    }

    /// A triangle the open segment `from → to` crosses (the first the walk
    /// meets, as an index for [`TriangleBvh::triangle_blocks`]), or `None`.
    pub fn first_blocker(&self, from: DVec3, to: DVec3) -> Option<u32> {
        let direction = to - from;
        let inverse = direction.recip();
        let hits = |index: u32| segment_hits_box(from, inverse, &self.nodes[index as usize]);
        if self.nodes.is_empty() || !hits(0) {
            return None;
        }
        // Both children's boxes are tested at their parent (they share a
        // cache line pair); the walk goes down the first one hit and keeps
        // the other on the stack, so the stack grows by at most one a level.
        let mut stack = [0u32; TRAVERSAL_STACK];
        let (mut top, mut node) = (0usize, 0u32);
        loop {
            let Node { first, count, .. } = self.nodes[node as usize];
            let next = if count > 0 {
                let leaf = &self.triangles[first as usize..(first + count) as usize];
                if let Some(offset) = leaf.iter().position(|t| segment_hits_triangle(from, direction, t)) {
                    return Some(first + offset as u32);
                }
                None
            } else {
                match (hits(first), hits(first + 1)) {
                    (true, true) => {
                        stack[top] = first + 1;
                        top += 1;
                        Some(first)
                    }
                    (true, false) => Some(first),
                    (false, true) => Some(first + 1),
                    (false, false) => None,
                }
            };
            node = match next {
                Some(child) => child,
                None if top > 0 => {
                    top -= 1;
                    stack[top]
                }
                None => return None,
            };
        }
    }

    /// True when triangle `index` (from [`TriangleBvh::first_blocker`])
    /// crosses the open segment `from → to`; an index out of range is false.
    #[inline]
    pub fn triangle_blocks(&self, index: u32, from: DVec3, to: DVec3) -> bool {
        self.triangles.get(index as usize).is_some_and(|t| segment_hits_triangle(from, to - from, t))
    }

    /// [`TriangleBvh::first_blocker`] by testing every triangle (for tests).
    pub fn first_blocker_brute_force(&self, from: DVec3, to: DVec3) -> Option<u32> {
        let direction = to - from;
        self.triangles.iter().position(|t| segment_hits_triangle(from, direction, t)).map(|i| i as u32)
    }

    /// The same question by testing every triangle (for tests).
    pub fn blocks_brute_force(&self, from: DVec3, to: DVec3) -> bool {
        let direction = to - from;
        self.triangles.iter().any(|t| segment_hits_triangle(from, direction, t))
    }

    /// How deep the hierarchy is (root = 1); never more than [`MAX_DEPTH`].
    pub fn depth(&self) -> usize {
        let mut deepest = 0;
        let mut pending = if self.nodes.is_empty() { vec![] } else { vec![(0usize, 1usize)] };
        while let Some((index, depth)) = pending.pop() {
            deepest = deepest.max(depth);
            let node = &self.nodes[index];
            if node.count == 0 {
                pending.push((node.first as usize, depth + 1));
                pending.push((node.first as usize + 1, depth + 1));
            }
        }
        deepest
    }

    /// Nodes in the hierarchy.
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }
}

/// Widens a node's bounds outwards by [`BOUNDS_MARGIN`] (see there).
fn widen(node: &mut Node) {
    let (min, max) = (DVec3::from_array(node.min), DVec3::from_array(node.max));
    let margin = BOUNDS_MARGIN * (min.abs().max(max.abs()).max_element() + (max - min).max_element());
    node.min = (min - DVec3::splat(margin)).to_array();
    node.max = (max + DVec3::splat(margin)).to_array();
}

fn leaf(first: usize, count: usize) -> Node {
    Node { min: [0.0; 3], max: [0.0; 3], first: first as u32, count: count as u32 }
}

fn item_bounds(items: &[Item]) -> (DVec3, DVec3) {
    items.iter().fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(min, max), item| {
        (min.min(item.min), max.max(item.max))
    })
}

fn half_area(min: DVec3, max: DVec3) -> f64 {
    let size = (max - min).max(DVec3::ZERO);
    size.x * size.y + size.y * size.z + size.z * size.x
}

/// Partitions `items` by the cheapest SAH split over binned centroids (the
/// axis and bin boundary); returns the size of the first half, or `None`
/// when no split is cheaper than a leaf. Falls back to a median split when
/// every centroid lies in one bin.
fn sah_partition(items: &mut [Item], min: DVec3, max: DVec3) -> Option<usize> {
    let (centroid_min, centroid_max) = items
        .iter()
        .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), i| (lo.min(i.centroid), hi.max(i.centroid)));
    let extent = centroid_max - centroid_min;
    let axis = extent.max_position();
    if extent[axis] <= 0.0 {
        // Every centroid in one place: halve by index.
        return Some(items.len() / 2);
    }
    let bin_of = |item: &Item, axis: usize| {
        let t = (item.centroid[axis] - centroid_min[axis]) / extent[axis];
        ((t * BINS as f64) as usize).min(BINS - 1)
    };
    let mut best: Option<(f64, usize, usize)> = None;
    for axis in 0..3 {
        if extent[axis] <= 0.0 {
            continue;
        }
        let mut bins = [(0usize, DVec3::INFINITY, DVec3::NEG_INFINITY); BINS];
        for item in items.iter() {
            let bin = &mut bins[bin_of(item, axis)];
            *bin = (bin.0 + 1, bin.1.min(item.min), bin.2.max(item.max));
        }
        // Sweep from the right, then from the left.
        let mut right_cost = [0.0f64; BINS];
        let (mut count, mut lo, mut hi) = (0usize, DVec3::INFINITY, DVec3::NEG_INFINITY);
        for split in (1..BINS).rev() {
            count += bins[split].0;
            (lo, hi) = (lo.min(bins[split].1), hi.max(bins[split].2));
            right_cost[split] = count as f64 * half_area(lo, hi);
        }
        let (mut count, mut lo, mut hi) = (0usize, DVec3::INFINITY, DVec3::NEG_INFINITY);
        for split in 1..BINS {
            count += bins[split - 1].0;
            (lo, hi) = (lo.min(bins[split - 1].1), hi.max(bins[split - 1].2));
            let cost = count as f64 * half_area(lo, hi) + right_cost[split];
            if count > 0 && count < items.len() && best.is_none_or(|(b, _, _)| cost < b) {
                best = Some((cost, axis, split));
            }
        }
    }
    let Some((cost, axis, split)) = best else {
        items.sort_unstable_by(|a, b| a.centroid[axis].total_cmp(&b.centroid[axis]));
        return Some(items.len() / 2);
    };
    let leaf_cost = items.len() as f64 * half_area(min, max);
    if cost + TRAVERSAL_COST * half_area(min, max) >= leaf_cost && items.len() <= 4 * LEAF_SIZE {
        return None;
    }
    let mut left = 0;
    for i in 0..items.len() {
        if bin_of(&items[i], axis) < split {
            items.swap(i, left);
            left += 1;
        }
    }
    Some(left)
}

/// Slab test of the segment `from + s·direction`, s ∈ [0, 1], against a box,
/// without branches. An axis the segment runs parallel to gives ±∞ (inside
/// the slab or not). `0 · ∞` gives NaN only when the segment lies in the
/// plane of a face of the widened box, where no triangle lies, so whatever
/// the comparisons then answer is right; every other case is the exact slab
/// test, made conservative by [`SLAB_ROUNDING`].
#[inline(always)]
fn segment_hits_box(from: DVec3, inverse: DVec3, node: &Node) -> bool {
    let to_min = (DVec3::from_array(node.min) - from) * inverse;
    let to_max = (DVec3::from_array(node.max) - from) * inverse;
    let enter = |axis: usize| lesser(to_min[axis], to_max[axis]);
    let leave = |axis: usize| greater(to_min[axis], to_max[axis]);
    let low = greater(greater(enter(0), enter(1)), greater(enter(2), 0.0));
    let high = lesser(lesser(leave(0), leave(1)), lesser(leave(2), 1.0));
    low <= high * SLAB_ROUNDING
}

/// The smaller of two numbers as one `minsd` (a NaN gives either; see
/// [`segment_hits_box`] for why that is safe).
#[inline(always)]
fn lesser(a: f64, b: f64) -> f64 {
    if a < b { a } else { b }
}

/// The larger of two numbers as one `maxsd`.
#[inline(always)]
fn greater(a: f64, b: f64) -> f64 {
    if a > b { a } else { b }
}

/// Möller–Trumbore, segment parameter strictly inside (1e-9, 1 − 1e-9).
#[inline(always)]
fn segment_hits_triangle(from: DVec3, direction: DVec3, t: &StoredTriangle) -> bool {
    ray_triangle_parameter(from, direction, t).is_some_and(|along| along > 1e-9 && along < 1.0 - 1e-9)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn random_numbers() -> impl FnMut() -> f64 {
        let mut state = 0x9E37_79B9_7F4A_7C15u64;
        move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    #[test]
    fn the_hierarchy_answers_like_brute_force() {
        // A grid of small triangles and many random segments.
        let mut triangles = Vec::new();
        for i in 0..20 {
            for j in 0..20 {
                let o = DVec3::new(f64::from(i), f64::from(j), f64::from((i * j) % 3));
                triangles.push([o, o + DVec3::X * 0.8, o + DVec3::Y * 0.8]);
            }
        }
        let bvh = TriangleBvh::new(triangles);
        let mut next = random_numbers();
        let mut hits = 0;
        for _ in 0..2000 {
            let from = DVec3::new(next() * 22.0 - 1.0, next() * 22.0 - 1.0, next() * 6.0 - 2.0);
            let to = DVec3::new(next() * 22.0 - 1.0, next() * 22.0 - 1.0, next() * 6.0 - 2.0);
            let fast = bvh.blocks(from, to);
            assert_eq!(fast, bvh.blocks_brute_force(from, to), "{from:?} → {to:?}");
            hits += usize::from(fast);
        }
        assert!(hits > 100 && hits < 1900, "{hits}");
    }

    /// A tilted sheet of 0.1 m squares (two triangles each), with corners
    /// that are not exact in binary and lie on the faces of the leaves' boxes.
    fn tilted_sheet() -> Vec<[DVec3; 3]> {
        let mut triangles = Vec::new();
        for i in 0..12 {
            for j in 0..12 {
                let corner = |a: i32, b: i32| {
                    let (x, y) = (0.1 * f64::from(i + a), 0.1 * f64::from(j + b));
                    DVec3::new(x, y, 0.3 * x + 0.7 * y + 0.01)
                };
                triangles.push([corner(0, 0), corner(1, 0), corner(0, 1)]);
                triangles.push([corner(1, 0), corner(1, 1), corner(0, 1)]);
            }
        }
        triangles
    }

    #[test]
    fn segments_through_corners_edges_and_box_faces_answer_as_brute_force() {
        // Segments through every corner and edge midpoint of the sheet, along
        // the axes (on the faces of the boxes that hold those corners: a slab
        // test that is not conservative misses them) and obliquely.
        let triangles = tilted_sheet();
        let bvh = TriangleBvh::new(triangles.clone());
        let directions =
            [DVec3::Z, DVec3::X, DVec3::Y, DVec3::new(0.2, -0.3, 1.0), DVec3::new(1.0, 1.0, -0.5)];
        let (mut segments, mut hits) = (0, 0);
        for t in &triangles {
            for target in [t[0], t[1], t[2], (t[0] + t[1]) / 2.0, (t[1] + t[2]) / 2.0, (t[2] + t[0]) / 2.0] {
                for direction in directions {
                    let (from, to) = (target + direction * 0.37, target - direction * 0.61);
                    let fast = bvh.first_blocker(from, to);
                    assert_eq!(fast.is_some(), bvh.blocks_brute_force(from, to), "{from:?} → {to:?}");
                    if let Some(index) = fast {
                        assert!(bvh.triangle_blocks(index, from, to));
                    }
                    segments += 1;
                    hits += usize::from(fast.is_some());
                }
            }
        }
        // Every segment crossing the sheet's inside hits it; those along x
        // or y run in the sheet's tilted plane only at isolated points.
        assert!(hits > segments / 2 && hits < segments, "{hits} of {segments}");
    }

    #[test]
    fn the_blocker_found_is_one_brute_force_finds_and_a_missing_index_blocks_nothing() {
        let bvh = TriangleBvh::new(tilted_sheet());
        let (from, to) = (DVec3::new(0.55, 0.55, 3.0), DVec3::new(0.55, 0.55, -3.0));
        let index = bvh.first_blocker(from, to).unwrap();
        assert_eq!(bvh.first_blocker_brute_force(from, to), Some(index), "only one triangle is crossed");
        assert!(bvh.triangle_blocks(index, from, to));
        assert!(!bvh.triangle_blocks(index, from + DVec3::X, to + DVec3::X));
        assert!(!bvh.triangle_blocks(u32::MAX, from, to));
        assert_eq!(TriangleBvh::new(Vec::new()).first_blocker(from, to), None);
    }

    #[test]
    fn a_degenerate_soup_stays_within_the_stack() {
        // 5000 triangles at one point and a long thin fan: no split helps,
        // the depth must still be bounded and the answers right.
        let mut next = random_numbers();
        let mut triangles = vec![[DVec3::ZERO, DVec3::X * 1e-9, DVec3::Y * 1e-9]; 5000];
        for i in 0..5000 {
            let x = f64::from(i) * 1e-3 + next() * 1e-12;
            triangles.push([DVec3::new(x, 0.0, 0.0), DVec3::new(x, 1.0, 0.0), DVec3::new(x, 0.0, 1.0)]);
        }
        let bvh = TriangleBvh::new(triangles);
        assert!(bvh.depth() <= MAX_DEPTH, "{}", bvh.depth());
        for _ in 0..200 {
            let from = DVec3::new(next() * 6.0 - 0.5, next() * 0.8 + 0.1, next() * 0.1 + 0.05);
            let to = DVec3::new(next() * 6.0 - 0.5, next() * 0.8 + 0.1, next() * 0.1 + 0.05);
            assert_eq!(bvh.blocks(from, to), bvh.blocks_brute_force(from, to));
        }
    }
}
