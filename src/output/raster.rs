//! The one CPU triangle rasterizer: a z-buffer that fills triangles at
//! pixel centres, nearest wins. The analyzer's eight views of the heatmap
//! ([`crate::output::heatmap_views`]) and the capture's `inspect` pictures
//! draw with it; what a pixel becomes (a texel's colour through the
//! interpolated UVs, a part's flat colour) is the caller's, given the
//! pixel's barycentric weights.
//!
//! No GPU, so pictures render wherever analyses run, and the same inputs
//! give the same bytes on every machine (plain `f64` arithmetic in a fixed
//! order).

/// A depth buffer of `width` × `height` pixels (row 0 at the top), every
/// pixel infinitely far until a triangle covers it.
#[derive(Debug, Clone)]
pub struct ZBuffer {
    width: u32,
    height: u32,
    depth: Vec<f64>,
}

impl ZBuffer {
    pub fn new(width: u32, height: u32) -> ZBuffer {
        ZBuffer { width, height, depth: vec![f64::INFINITY; (width as usize) * (height as usize)] }
    }

    pub fn width(&self) -> u32 {
        self.width
    }

    pub fn height(&self) -> u32 {
        self.height
    }

    /// Rasterizes a triangle whose corners are `[x, y, depth]` in pixels
    /// (x right, y down; smaller depth is nearer). For every pixel whose
    /// centre lies inside it (on an edge counts) and that is nearer than what
    /// the pixel shows, records the depth and calls `fill(pixel, weights)`:
    /// the pixel's index (`y * width + x`) and its barycentric weights of the
    /// three corners. Triangles seen edge-on (area below 10⁻¹² pixel²) draw
    /// nothing.
    pub fn triangle(&mut self, corners: [[f64; 3]; 3], mut fill: impl FnMut(usize, [f64; 3])) {
        let [p0, p1, p2] = corners;
        let area = (p1[0] - p0[0]) * (p2[1] - p0[1]) - (p1[1] - p0[1]) * (p2[0] - p0[0]);
        if area.abs() < 1e-12 {
            return;
        }
        let lowest = |axis: usize| corners.iter().map(|c| c[axis]).fold(f64::MAX, f64::min);
        let highest = |axis: usize| corners.iter().map(|c| c[axis]).fold(f64::MIN, f64::max);
        // `as u32` saturates: a bound left of or above the picture is 0.
        let xs = (lowest(0).floor().max(0.0) as u32)..(highest(0).ceil().min(f64::from(self.width)) as u32);
        let ys = (lowest(1).floor().max(0.0) as u32)..(highest(1).ceil().min(f64::from(self.height)) as u32);
        // The signed area of (a, b, q) over the triangle's: q's weight of
        // the corner opposite the edge a → b.
        let weight = |a: [f64; 3], b: [f64; 3], q: [f64; 2]| {
            ((b[0] - a[0]) * (q[1] - a[1]) - (b[1] - a[1]) * (q[0] - a[0])) / area
        };
        for y in ys {
            for x in xs.clone() {
                let q = [f64::from(x) + 0.5, f64::from(y) + 0.5];
                let w = [weight(p1, p2, q), weight(p2, p0, q), weight(p0, p1, q)];
                if w.iter().any(|&w| w < 0.0) {
                    continue;
                }
                let z = w[0] * p0[2] + w[1] * p1[2] + w[2] * p2[2];
                let pixel = y as usize * self.width as usize + x as usize;
                if z < self.depth[pixel] {
                    self.depth[pixel] = z;
                    fill(pixel, w);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_nearer_of_two_overlapping_triangles_wins_whatever_the_order() {
        let far = [[0.0, 0.0, 2.0], [8.0, 0.0, 2.0], [0.0, 8.0, 2.0]];
        let near = [[0.0, 0.0, 1.0], [8.0, 0.0, 1.0], [0.0, 8.0, 1.0]];
        for order in [[far, near], [near, far]] {
            let mut buffer = ZBuffer::new(4, 4);
            let mut shown = [0u8; 16];
            for (which, corners) in order.into_iter().enumerate() {
                buffer.triangle(corners, |pixel, _| shown[pixel] = which as u8 + 1);
            }
            let nearer = if order[0] == near { 1 } else { 2 };
            assert!(shown.iter().all(|&s| s == nearer), "{shown:?}");
        }
    }

    #[test]
    fn pixel_centres_inside_are_filled_with_weights_that_add_to_one() {
        // A right triangle over the top-left half of a 4×4 picture: the
        // centres with x + y < 4 (x + y = 3 lies on the hypotenuse: inside).
        let mut buffer = ZBuffer::new(4, 4);
        let mut filled = Vec::new();
        buffer.triangle([[0.0, 0.0, 0.0], [4.0, 0.0, 0.0], [0.0, 4.0, 0.0]], |pixel, w| {
            assert!((w.iter().sum::<f64>() - 1.0).abs() < 1e-12);
            filled.push(pixel);
        });
        let expected: Vec<usize> = (0..16).filter(|p| p % 4 + p / 4 < 4).collect();
        assert_eq!(filled, expected);
    }

    #[test]
    fn triangles_seen_edge_on_or_off_the_picture_draw_nothing() {
        let mut buffer = ZBuffer::new(4, 4);
        let mut calls = 0;
        buffer.triangle([[0.0, 0.0, 0.0], [2.0, 2.0, 0.0], [4.0, 4.0, 0.0]], |_, _| calls += 1);
        buffer.triangle([[-9.0, -9.0, 0.0], [-5.0, -9.0, 0.0], [-9.0, -5.0, 0.0]], |_, _| calls += 1);
        buffer.triangle([[9.0, 9.0, 0.0], [15.0, 9.0, 0.0], [9.0, 15.0, 0.0]], |_, _| calls += 1);
        assert_eq!(calls, 0);
    }
}
