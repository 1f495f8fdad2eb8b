//! The solid angle each pixel of a rectilinear (pinhole) eye really subtends.
//!
//! A pixel of a perspective image is a square of the image plane, not of the
//! sphere: at angle θ off the axis it subtends about `cos³θ` of a central
//! pixel's solid angle (at the edge of a 107° eye, a third). Counting pixels
//! / ppd² therefore overstates off-axis surfaces; the rendered angular-area
//! measure sums each pixel's exact solid angle instead, so that it converges
//! to the ray-traced solid angle as pixels per degree grow.
//!
//! Exact: a rectangle `[u0, u1] × [v0, v1]` of the image plane at unit
//! distance subtends `F(u1, v1) − F(u0, v1) − F(u1, v0) + F(u0, v0)` with
//! `F(u, v) = atan(u·v / √(1 + u² + v²))`. A run of equal pixels on one row
//! is such a rectangle, so a row costs two `atan` per run boundary, and the
//! pixels of one whole eye image add up to the frustum's solid angle to
//! rounding.

/// A symmetric rectilinear eye with square pixels: the image plane at unit
/// distance spans `[-tan_half_x, tan_half_x]` over `width` pixels.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EyeProjection {
    pub width: u32,
    pub height: u32,
    /// tan(horizontal field of view / 2).
    pub tan_half_x: f64,
}

/// Where a tile lies in its eye image, for its pixels' solid angles.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TileView {
    pub projection: EyeProjection,
    /// The tile's top-left pixel in the eye image, `[x, y]`.
    pub origin: [u32; 2],
}

/// `F(u, v)`: the solid angle of the image-plane rectangle `[0, u] × [0, v]`.
fn corner(u: f64, v: f64) -> f64 {
    (u * v / (1.0 + u * u + v * v).sqrt()).atan()
}

impl EyeProjection {
    /// The eye of a horizontal field of view (degrees) and image size.
    pub fn new(horizontal_fov_deg: f64, [width, height]: [u32; 2]) -> Option<EyeProjection> {
        let valid = horizontal_fov_deg > 0.0 && horizontal_fov_deg < 180.0 && width > 0 && height > 0;
        valid.then(|| EyeProjection {
            width,
            height,
            tan_half_x: (horizontal_fov_deg.to_radians() / 2.0).tan(),
        })
    }

    /// Image-plane size of one pixel.
    pub fn pitch(&self) -> f64 {
        2.0 * self.tan_half_x / f64::from(self.width)
    }

    /// Image-plane coordinate of the pixel edge `x` (0 = left edge).
    pub fn u(&self, x: f64) -> f64 {
        x * self.pitch() - self.tan_half_x
    }

    /// Image-plane coordinate of the pixel edge `y` (0 = top edge; the sign
    /// does not matter, the eye is symmetric).
    pub fn v(&self, y: f64) -> f64 {
        y * self.pitch() - self.pitch() * f64::from(self.height) / 2.0
    }

    /// Solid angle (sr) of the image-plane rectangle `[u0, u1] × [v0, v1]`.
    pub fn rectangle_sr(u0: f64, u1: f64, v0: f64, v1: f64) -> f64 {
        (corner(u1, v1) - corner(u0, v1) - corner(u1, v0) + corner(u0, v0)).abs()
    }

    /// Solid angle (sr) of the pixel `[x, y]` of the eye image.
    pub fn pixel_sr(&self, x: u32, y: u32) -> f64 {
        let (x, y) = (f64::from(x), f64::from(y));
        Self::rectangle_sr(self.u(x), self.u(x + 1.0), self.v(y), self.v(y + 1.0))
    }

    /// Solid angle (sr) of the whole eye image (its frustum).
    pub fn image_sr(&self) -> f64 {
        let (u, v) = (self.tan_half_x, self.v(0.0).abs());
        4.0 * corner(u, v)
    }
}

/// One row of an eye image: the solid angle of runs of its pixels.
#[derive(Debug, Clone, Copy)]
pub(crate) struct RowWeights {
    projection: EyeProjection,
    x0: u32,
    v0: f64,
    v1: f64,
}

impl RowWeights {
    /// Row `y` (of the tile) of a tile at `view`.
    pub(crate) fn new(view: &TileView, y: u32) -> RowWeights {
        let row = f64::from(view.origin[1] + y);
        let p = view.projection;
        RowWeights { projection: p, x0: view.origin[0], v0: p.v(row), v1: p.v(row + 1.0) }
    }

    /// `G(x) = F(u(x), v1) − F(u(x), v0)` at the pixel edge `x` of the tile:
    /// the solid angle of a run `[a, b)` is `|G(b) − G(a)|`.
    pub(crate) fn edge(&self, x: usize) -> f64 {
        let u = self.projection.u(f64::from(self.x0) + x as f64);
        corner(u, self.v1) - corner(u, self.v0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn eye(ppd: f64) -> EyeProjection {
        let width = (107.0 * ppd).round() as u32;
        EyeProjection::new(107.0, [width, (f64::from(width) * 135.0 / 107.0).round() as u32]).unwrap()
    }

    #[test]
    fn the_pixels_of_an_eye_add_up_to_its_frustum_and_shrink_off_axis() {
        let e = eye(2.0);
        let sum: f64 = (0..e.height)
            .flat_map(|y| (0..e.width).map(move |x| (x, y)))
            .map(|(x, y)| e.pixel_sr(x, y))
            .sum();
        assert!((sum - e.image_sr()).abs() < 1e-9 * e.image_sr(), "{sum} vs {}", e.image_sr());
        // A 107° × 135°-tall eye covers well under the 2π sr of a hemisphere.
        assert!(e.image_sr() < 2.0 * std::f64::consts::PI);
        // Central pixel ≈ pitch² (it spans [0, pitch]², so it is short by
        // about 1.5 · (2 · pitch²/3) = pitch²); the corner pixel ≈ pitch² · cos³θ.
        let centre = e.pixel_sr(e.width / 2, e.height / 2);
        assert!((centre / (e.pitch() * e.pitch()) - 1.0).abs() < 1.5 * e.pitch() * e.pitch());
        let (u, v) = (e.u(0.5), e.v(0.5));
        let cos3 = (1.0 + u * u + v * v).powf(-1.5);
        assert!((e.pixel_sr(0, 0) / (e.pitch() * e.pitch()) / cos3 - 1.0).abs() < 1e-2);
        assert!(e.pixel_sr(0, e.height / 2) < 0.45 * centre);
    }

    #[test]
    fn a_run_of_pixels_weighs_the_sum_of_its_pixels() {
        let e = eye(3.0);
        let view = TileView { projection: e, origin: [40, 100] };
        let row = RowWeights::new(&view, 7);
        let run = (row.edge(25) - row.edge(5)).abs();
        let pixels: f64 = (45..65).map(|x| e.pixel_sr(x, 107)).sum();
        assert!((run - pixels).abs() < 1e-12, "{run} vs {pixels}");
    }

    /// A flat plate facing the eye, `2a × 2b` metres at distance `d`, its
    /// centre off the axis by `(cx, cy)`: pixels whose centre ray hits it,
    /// weighted by their solid angle, against its exact solid angle. The
    /// error is the plate's outline band: O(perimeter × pixel), so it falls
    /// like 1/ppd (with cancellation often faster).
    fn plate_error(ppd: f64) -> (f64, f64) {
        let e = eye(ppd);
        let (d, a, b, cx, cy) = (4.0, 0.9, 0.6, 2.0, -1.1);
        let (u0, u1, v0, v1) = ((cx - a) / d, (cx + a) / d, (cy - b) / d, (cy + b) / d);
        let exact = EyeProjection::rectangle_sr(u0, u1, v0, v1);
        let (mut rendered, mut pixels) = (0.0, 0u64);
        for y in 0..e.height {
            let v = e.v(f64::from(y) + 0.5);
            if v < v0 || v > v1 {
                continue;
            }
            for x in 0..e.width {
                let u = e.u(f64::from(x) + 0.5);
                if u >= u0 && u <= u1 {
                    rendered += e.pixel_sr(x, y);
                    pixels += 1;
                }
            }
        }
        // What `pixels / ppd²` made of it (ppd = pixels / field of view).
        let old = pixels as f64 / (ppd * ppd) * (std::f64::consts::PI / 180.0).powi(2);
        ((rendered - exact).abs() / exact, old / exact)
    }

    #[test]
    fn a_plate_facing_the_eye_converges_to_its_exact_solid_angle_like_one_over_ppd() {
        let ppds = [2.0, 4.0, 8.0, 16.0];
        let results: Vec<(f64, f64)> = ppds.iter().map(|&ppd| plate_error(ppd)).collect();
        // Measured: 8.1e-3, 1.6e-2, 2.0e-3, 2.9e-4 — at most 0.065 / ppd.
        for ((error, _), ppd) in results.iter().zip(ppds) {
            assert!(*error < 0.1 / ppd, "{ppd} px/°: {error}");
        }
        assert!(results[3].0 < 1e-3, "{results:?}");
        // `pixels / ppd²` was 27 % short for this plate at every ppd.
        for (_, old) in &results {
            assert!((old - 0.73).abs() < 0.02, "{old}");
        }
    }
}
