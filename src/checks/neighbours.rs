//! Sampling neighbouring pixels: do texels that are side by side on screen
//! lie side by side on the palette?
//!
//! With point sampling, a pixel names the texel under its centre, so inside
//! a UV island the texels of adjacent pixels are equal or a few texels apart
//! (further apart when the vehicle is far away, but then evenly so: a pixel
//! lies between its neighbours). Blending colours breaks that: the canonical
//! palette spells a texel `(u, v)` as the bytes of `v·W + u`, so the average
//! of two vertically adjacent texels, or a ±1 dither of the green byte,
//! names a texel hundreds or thousands of columns away. Such a pixel is far
//! from *both* of its neighbours while they are close to each other; this
//! module counts those "jumps" among triples of adjacent texel pixels (left,
//! middle, right and above, middle, below).
//!
//! It samples one window of three rows every [`WINDOW_STEP`] rows of every
//! image (the same rows whether the tile is decoded from a PNG or counted
//! from memory), in a pass of its own beside the counting kernel, which it
//! does not touch. Only the canonical palette has a layout to measure
//! distances in; image palettes are not sampled.

use crate::archive::palette::Fcsp;
use crate::png::rows::PixelLayout;

/// A window of three consecutive rows starts every this many rows.
pub(crate) const WINDOW_STEP: u32 = 64;

/// A middle texel jumps when it is further than this many times its
/// neighbours' distance from both of them ...
const JUMP_FACTOR: u32 = 4;

/// ... and further than this many texels (Chebyshev distance).
const JUMP_MIN: u32 = 32;

pub use crate::format::result::NeighbourSample;

impl NeighbourSample {
    /// Adds `other`'s triples to these.
    pub fn add(&mut self, other: &NeighbourSample) {
        self.triples += other.triples;
        self.varying += other.varying;
        self.jumps += other.jumps;
    }

    /// `jumps / varying`, when anything varied.
    pub fn jump_share(&self) -> Option<f64> {
        (self.varying > 0).then(|| self.jumps as f64 / self.varying as f64)
    }
}

/// The canonical palette's layout: colour → texel `(u, v)`.
#[derive(Clone)]
pub(crate) struct TexelGrid {
    width: u32,
    texels: u32,
    backgrounds: Vec<u32>,
}

impl TexelGrid {
    /// The grid of `palette` with `backgrounds` (packed colours) left out;
    /// `None` for an image palette (its layout is arbitrary).
    pub(crate) fn new(palette: &Fcsp, backgrounds: &[u32]) -> Option<TexelGrid> {
        match palette {
            Fcsp::Canonical { width, .. } => Some(TexelGrid {
                width: *width,
                texels: palette.texel_count() as u32,
                backgrounds: backgrounds.to_vec(),
            }),
            Fcsp::Image { .. } => None,
        }
    }

    /// The texel `color` names, unless it is background or no texel.
    #[inline(always)]
    fn texel(&self, color: u32) -> Option<(u32, u32)> {
        (color < self.texels && !self.backgrounds.contains(&color))
            .then(|| (color % self.width, color / self.width))
    }

    /// Adds one triple `a`, `p`, `b` (packed colours, `p` in the middle).
    #[inline(always)]
    fn triple(&self, a: u32, p: u32, b: u32, sample: &mut NeighbourSample) {
        if a == p && p == b {
            sample.triples += u64::from(self.texel(p).is_some());
            return;
        }
        let (Some(ta), Some(tp), Some(tb)) = (self.texel(a), self.texel(p), self.texel(b)) else {
            return;
        };
        sample.triples += 1;
        sample.varying += 1;
        let distance = |s: (u32, u32), t: (u32, u32)| s.0.abs_diff(t.0).max(s.1.abs_diff(t.1));
        let limit = (JUMP_FACTOR * distance(ta, tb)).max(JUMP_MIN);
        sample.jumps += u64::from(distance(ta, tp).min(distance(tp, tb)) > limit);
    }
}

/// Samples the rows of one image after another (call
/// [`NeighbourSampler::start_image`] before each).
pub(crate) struct NeighbourSampler {
    grid: TexelGrid,
    /// The window's rows as packed colours; `rows[i]` is row `i` of it.
    rows: [Vec<u32>; 3],
    /// The window row expected next (rows must come in order).
    next: Option<u32>,
    pub sample: NeighbourSample,
}

impl NeighbourSampler {
    pub(crate) fn new(grid: TexelGrid) -> NeighbourSampler {
        NeighbourSampler { grid, rows: Default::default(), next: None, sample: NeighbourSample::default() }
    }

    /// Forgets the rows of the previous image.
    pub(crate) fn start_image(&mut self) {
        self.next = None;
    }

    /// Looks at row `y` (decoded samples of `layout`): copies it when it
    /// belongs to a window, and measures the window at its third row.
    pub(crate) fn row(&mut self, y: u32, row: &[u8], layout: PixelLayout) {
        let phase = y % WINDOW_STEP;
        if phase > 2 || (phase > 0 && self.next != Some(y)) {
            return;
        }
        let bytes = layout.bytes_per_pixel();
        let packed = &mut self.rows[phase as usize];
        packed.clear();
        packed.extend(row.chunks_exact(bytes).map(|pixel| layout.pack(pixel)));
        self.next = Some(y + 1);
        if phase == 2 {
            self.measure_window();
        }
    }

    /// The horizontal triples of the window's middle row and the vertical
    /// triples of its three rows.
    fn measure_window(&mut self) {
        let [above, middle, below] = &self.rows;
        let (grid, sample) = (&self.grid, &mut self.sample);
        for w in middle.windows(3) {
            grid.triple(w[0], w[1], w[2], sample);
        }
        if above.len() == middle.len() && below.len() == middle.len() {
            for ((&a, &p), &b) in above.iter().zip(middle).zip(below) {
                grid.triple(a, p, b, sample);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rgb(colors: &[u32]) -> Vec<u8> {
        colors.iter().flat_map(|&c| [(c >> 16) as u8, (c >> 8) as u8, c as u8]).collect()
    }

    /// Samples a `width`-pixel image whose pixel `(x, y)` is `color(x, y)`.
    fn sample_of(
        grid: &TexelGrid,
        width: u32,
        height: u32,
        color: impl Fn(u32, u32) -> u32,
    ) -> NeighbourSample {
        let mut sampler = NeighbourSampler::new(grid.clone());
        sampler.start_image();
        for y in 0..height {
            let row: Vec<u32> = (0..width).map(|x| color(x, y)).collect();
            sampler.row(y, &rgb(&row), PixelLayout::Rgb);
        }
        sampler.sample
    }

    #[test]
    fn magnified_and_minified_islands_have_no_jumps() {
        let grid = TexelGrid::new(&Fcsp::canonical([4096, 4096]).unwrap(), &[0x000FFF]).unwrap();
        // 3 pixels per texel, and 20 texels per pixel.
        let magnified = sample_of(&grid, 30, 3, |x, y| (100 + y / 3) * 4096 + 50 + x / 3);
        assert_eq!(magnified, NeighbourSample { triples: 28 + 30, varying: 18, jumps: 0 });
        let minified = sample_of(&grid, 30, 3, |x, y| (100 + 20 * y) * 4096 + 20 * x);
        assert_eq!(minified, NeighbourSample { triples: 58, varying: 58, jumps: 0 });
    }

    #[test]
    fn a_blend_of_vertical_neighbours_is_a_jump() {
        let grid = TexelGrid::new(&Fcsp::canonical([4096, 4096]).unwrap(), &[0x000FFF]).unwrap();
        let (t, below) = (100 * 4096 + 50, 101 * 4096 + 50);
        // The byte-wise average of t and the texel below it: green + 8.
        let blend = t + 0x0800;
        let sample = sample_of(&grid, 3, 3, |x, y| {
            if (x, y) == (1, 1) {
                blend
            } else if y == 2 {
                below
            } else {
                t
            }
        });
        // Row 1: t, blend, t (a jump); column 1: t, blend, below (a jump).
        assert_eq!((sample.varying, sample.jumps), (4, 2));
    }

    #[test]
    fn background_and_rows_outside_the_windows_are_not_sampled() {
        let grid = TexelGrid::new(&Fcsp::canonical([64, 64]).unwrap(), &[5]).unwrap();
        // Texel 5 is the background here; rows 3..64 and 67.. are outside
        // the two windows, each with 1 horizontal and 3 vertical triples.
        let sample = sample_of(&grid, 4, 70, |x, _| if x == 0 { 5 } else { 6 });
        assert_eq!(sample, NeighbourSample { triples: 2 * (1 + 3), varying: 0, jumps: 0 });
        assert!(TexelGrid::new(&Fcsp::canonical([64, 64]).unwrap(), &[]).is_some());
    }
}
