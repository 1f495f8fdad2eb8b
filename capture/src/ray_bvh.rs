//! Segment-against-triangles queries for the unobstructed measure: a
//! bounding-volume hierarchy (median split on the longest axis, f64) and the
//! same test done by brute force, so tests can check one against the other.

use glam::DVec3;

/// A triangle soup with a hierarchy over it.
pub struct TriangleBvh {
    triangles: Vec<[DVec3; 3]>,
    nodes: Vec<Node>,
}

struct Node {
    min: DVec3,
    max: DVec3,
    /// Leaf: `[first, first + count)` of `triangles`; inner: children at `first` and `first + 1`.
    first: usize,
    count: usize,
}

const LEAF_SIZE: usize = 4;

impl TriangleBvh {
    pub fn new(mut triangles: Vec<[DVec3; 3]>) -> TriangleBvh {
        let mut nodes = Vec::with_capacity(2 * triangles.len() / LEAF_SIZE + 1);
        if !triangles.is_empty() {
            nodes.push(Node { min: DVec3::ZERO, max: DVec3::ZERO, first: 0, count: triangles.len() });
            let mut stack = vec![0usize];
            while let Some(index) = stack.pop() {
                let (first, count) = (nodes[index].first, nodes[index].count);
                let slice = &mut triangles[first..first + count];
                let (min, max) = bounds(slice);
                nodes[index].min = min;
                nodes[index].max = max;
                if count <= LEAF_SIZE {
                    continue;
                }
                let axis = (max - min).max_position();
                let centre = |t: &[DVec3; 3]| (t[0][axis] + t[1][axis] + t[2][axis]) / 3.0;
                slice.sort_by(|a, b| centre(a).total_cmp(&centre(b)));
                let half = count / 2;
                let children = nodes.len();
                nodes.push(Node { min, max, first, count: half });
                nodes.push(Node { min, max, first: first + half, count: count - half });
                nodes[index].first = children;
                nodes[index].count = 0;
                stack.push(children);
                stack.push(children + 1);
            }
        }
        TriangleBvh { triangles, nodes }
    }

    /// True when the open segment `from → to` (ends excluded) crosses a triangle.
    pub fn blocks(&self, from: DVec3, to: DVec3) -> bool {
        if self.nodes.is_empty() {
            return false;
        }
        let direction = to - from;
        let inverse = direction.recip();
        let mut stack = vec![0usize];
        while let Some(index) = stack.pop() {
            let node = &self.nodes[index];
            if !segment_hits_box(from, inverse, node.min, node.max) {
                continue;
            }
            if node.count > 0 {
                if self.triangles[node.first..node.first + node.count]
                    .iter()
                    .any(|t| segment_hits_triangle(from, direction, t))
                {
                    return true;
                }
            } else {
                stack.push(node.first);
                stack.push(node.first + 1);
            }
        }
        false
    }

    /// The hierarchy as flat arrays for the GPU (`unobstructed.wgsl`): per
    /// node its bounds (min xyz, max xyz) and `(first, count)`, per triangle
    /// its corners (9 values), in the order the queries index them.
    pub fn flatten(&self) -> (Vec<f64>, Vec<u32>, Vec<f64>) {
        let bounds =
            self.nodes.iter().flat_map(|n| n.min.to_array().into_iter().chain(n.max.to_array())).collect();
        let links = self.nodes.iter().flat_map(|n| [n.first as u32, n.count as u32]).collect();
        let triangles = self.triangles.iter().flatten().flat_map(|p| p.to_array()).collect();
        (bounds, links, triangles)
    }

    /// How deep the hierarchy is (root = 1): the GPU's traversal stack must hold it.
    pub fn depth(&self) -> usize {
        fn depth_of(nodes: &[Node], index: usize) -> usize {
            match nodes.get(index) {
                None => 0,
                Some(node) if node.count > 0 => 1,
                Some(node) => 1 + depth_of(nodes, node.first).max(depth_of(nodes, node.first + 1)),
            }
        }
        depth_of(&self.nodes, 0)
    }

    /// The same question by testing every triangle (for tests).
    pub fn blocks_brute_force(&self, from: DVec3, to: DVec3) -> bool {
        let direction = to - from;
        self.triangles.iter().any(|t| segment_hits_triangle(from, direction, t))
    }
}

fn bounds(triangles: &[[DVec3; 3]]) -> (DVec3, DVec3) {
    let mut min = DVec3::splat(f64::INFINITY);
    let mut max = DVec3::splat(f64::NEG_INFINITY);
    for t in triangles {
        for p in t {
            min = min.min(*p);
            max = max.max(*p);
        }
    }
    (min, max)
}

/// Slab test of the segment `from + s·direction`, s ∈ [0, 1], against a box.
fn segment_hits_box(from: DVec3, inverse: DVec3, min: DVec3, max: DVec3) -> bool {
    let (mut low, mut high) = (0.0f64, 1.0f64);
    for axis in 0..3 {
        if inverse[axis].is_infinite() {
            // Parallel to this slab: inside it or never.
            if from[axis] < min[axis] || from[axis] > max[axis] {
                return false;
            }
            continue;
        }
        let a = (min[axis] - from[axis]) * inverse[axis];
        let b = (max[axis] - from[axis]) * inverse[axis];
        low = low.max(a.min(b));
        high = high.min(a.max(b));
        if low > high {
            return false;
        }
    }
    true
}

/// Möller–Trumbore, segment parameter strictly inside (0, 1).
fn segment_hits_triangle(from: DVec3, direction: DVec3, t: &[DVec3; 3]) -> bool {
    let (e1, e2) = (t[1] - t[0], t[2] - t[0]);
    let p = direction.cross(e2);
    let determinant = e1.dot(p);
    if determinant.abs() < 1e-15 {
        return false;
    }
    let inverse = 1.0 / determinant;
    let s = from - t[0];
    let u = s.dot(p) * inverse;
    if !(0.0..=1.0).contains(&u) {
        return false;
    }
    let q = s.cross(e1);
    let v = direction.dot(q) * inverse;
    if v < 0.0 || u + v > 1.0 {
        return false;
    }
    let along = e2.dot(q) * inverse;
    along > 1e-9 && along < 1.0 - 1e-9
}

#[cfg(test)]
mod tests {
    use super::*;

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
        let mut state = 0x9E37_79B9_7F4A_7C15u64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
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
}
