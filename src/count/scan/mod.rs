//! Scanning: the [`Classifier`] (background, palette texel or stray), the
//! row kernels that classify the pixels of one decoded row and record the
//! palette texels they show, and [`scan_image`], one whole PNG.
//!
//! The hot loop of the whole tool, in forms that give identical results
//! (a unit test compares them on random rows):
//!
//! * a portable kernel for every sample layout and palette kind, which scans
//!   blocks of 16 pixels without branches;
//! * vector kernels for RGB and RGBA rows against the canonical palette (the
//!   layout every capture writes), picked at run time ([`Kernel`]): AVX-512
//!   (`simd/scan/avx512.rs`, 16 pixels per instruction) and AVX2
//!   (`simd/scan/avx2.rs`, 8), in [`crate::simd`], the one module allowed
//!   `unsafe` code. They classify whole blocks at once and leave to scalar
//!   code only the texels whose colour differs from their left neighbour's.
//!
//! Every kernel skips a block whose bytes equal the bytes one pixel earlier
//! (a run of background, or of one magnified texel) with one comparison: it
//! repeats the last pixel scanned, so it adds that pixel's class and nothing
//! new.
//!
//! With a per-part tally ([`PartRows`]) the AVX-512 kernel's second form
//! tallies each row by part in the same pass; every other kernel leaves it to
//! [`PartLookup::add_row_at`], a second pass over the row, with the same
//! result.
//!
//! The portable kernel accumulates the bits of one 64-bit word of the
//! [`SeenSet`] in a register and writes it back only when a pixel needs
//! another word ([`WordAccumulator`]): it hands every pixel of a block over,
//! and neighbouring pixels nearly always share a word (see
//! [`crate::color::color_key`]). The vector kernels hand over only texels
//! that differ from their left neighbour, set their bits in memory at once
//! and accumulate the words' marks instead (`simd::scan::MarkAccumulator`).

use std::path::Path;

use crate::archive::palette::Fcsp;
use crate::checks::neighbours::NeighbourSampler;
use crate::color::{AtomicColorSet, SeenSet, color_key};
use crate::count::part_lookup::{PartLookup, PartPixels, RowSpans};
use crate::count::texel_area::{PendingRuns, Shifted, TexelSolidAngles};
use crate::error::{Error, Result};
use crate::optics::solid_angle::TileView;
use crate::png::rows::{PixelLayout, RowReader};
use crate::simd::{Classes, ColorRuns, FusedScan, RowTally, VectorScan};

/// Pixel counts by [`PixelClass`] (indexed by its discriminant).
pub(crate) type ClassCounts = [u64; 3];

/// A portable row kernel (see [`RowScan::scan`]), reporting its runs to `R`.
type SafeKernel<R> = fn(&[u8], &Classifier, &mut SeenSet, &AtomicColorSet, &mut ClassCounts, R);

/// Which portable kernel: the layout, and whether the palette is canonical
/// and there is one background colour.
#[derive(Clone, Copy)]
struct Portable {
    layout: PixelLayout,
    canonical: bool,
    single: bool,
}

impl Portable {
    /// The kernel, reporting runs to an `R`.
    #[inline]
    fn kernel<R: ColorRuns>(self) -> SafeKernel<R> {
        match (self.layout, self.canonical, self.single) {
            (PixelLayout::Rgb, true, true) => scan_row::<3, false, true, true, R>,
            (PixelLayout::Rgb, true, false) => scan_row::<3, false, true, false, R>,
            (PixelLayout::Rgb, false, true) => scan_row::<3, false, false, true, R>,
            (PixelLayout::Rgb, false, false) => scan_row::<3, false, false, false, R>,
            (PixelLayout::Rgba, true, true) => scan_row::<4, false, true, true, R>,
            (PixelLayout::Rgba, true, false) => scan_row::<4, false, true, false, R>,
            (PixelLayout::Rgba, false, true) => scan_row::<4, false, false, true, R>,
            (PixelLayout::Rgba, false, false) => scan_row::<4, false, false, false, R>,
            (PixelLayout::Gray, true, _) => scan_row::<1, true, true, false, R>,
            (PixelLayout::Gray, false, _) => scan_row::<1, true, false, false, R>,
            (PixelLayout::GrayAlpha, true, _) => scan_row::<2, true, true, false, R>,
            (PixelLayout::GrayAlpha, false, _) => scan_row::<2, true, false, false, R>,
        }
    }
}

/// The row kernel chosen for one image.
#[derive(Clone, Copy)]
pub struct RowScan {
    choice: Choice,
    /// Whether a vector kernel's form that also tallies parts may be used
    /// ([`PartRows`]).
    fuse_parts: bool,
}

#[derive(Clone, Copy)]
// Vector kernels exist on x86-64 only.
#[cfg_attr(not(target_arch = "x86_64"), allow(dead_code))]
enum Choice {
    Portable(Portable),
    /// A vector kernel, and the portable one for the pixels it leaves.
    Vector(VectorScan, Portable),
}

impl RowScan {
    /// The row kernel of `kernel` for `layout` and the classifier's palette,
    /// or the portable one where `kernel` has none or the CPU cannot run it
    /// (for benchmarks and tests; [`scan_image`]
    /// uses [`Kernel::selected`]).
    pub fn new(kernel: Kernel, layout: PixelLayout, classifier: &Classifier) -> RowScan {
        vector_row_scan(kernel, layout, classifier).unwrap_or_else(|| portable_row_scan(layout, classifier))
    }

    /// The same kernel with its per-part tally left to a separate pass over
    /// each row ([`PartRows`]), for benchmarks that compare the two.
    pub fn with_separate_parts(self) -> RowScan {
        RowScan { fuse_parts: false, ..self }
    }

    /// Classifies `row` (decoded samples of `layout`), adds its palette
    /// texels (as [`color_key`]s) to `seen`, its stray colours to `strays`,
    /// and its pixels to `by_class`.
    #[inline]
    pub fn scan(
        self,
        row: &[u8],
        classifier: &Classifier,
        seen: &mut SeenSet,
        strays: &AtomicColorSet,
        by_class: &mut ClassCounts,
    ) {
        self.scan_runs(row, classifier, seen, strays, by_class, ());
    }

    /// [`RowScan::scan`], which also reports the row's runs of equal colour
    /// to `runs` (the per-texel solid angles, [`ColorRuns`]).
    #[inline]
    pub(crate) fn scan_runs<R: ColorRuns>(
        self,
        row: &[u8],
        classifier: &Classifier,
        seen: &mut SeenSet,
        strays: &AtomicColorSet,
        by_class: &mut ClassCounts,
        mut runs: R,
    ) {
        match self.choice {
            Choice::Portable(kernel) => kernel.kernel::<R>()(row, classifier, seen, strays, by_class, runs),
            Choice::Vector(vector, rest) => {
                let tally = vector.scan(row, classifier.classes(), seen, strays, &mut runs);
                add_row_classes(by_class, tally);
                // The rest of the row (AVX2: a few pixels), if any.
                let done = tally.pixels * vector.bytes();
                if done < row.len() {
                    let runs = Shifted { runs, by: tally.pixels };
                    rest.kernel::<Shifted<R>>()(&row[done..], classifier, seen, strays, by_class, runs);
                }
            }
        }
    }
}

/// The per-part tally of an image's rows ([`PartLookup::add_row_at`]) beside
/// their count. Where the row kernel has a form that tallies parts (AVX-512)
/// and the slot table a form it reads (a power-of-two width and the
/// palette's texel count of colours: a canonical palette's lookup), the
/// kernel does both in one pass; else the tally is a second pass over each
/// row. Both give the same bits.
pub struct PartRows<'l, 't> {
    scan: RowScan,
    layout: PixelLayout,
    classifier: &'l Classifier<'l>,
    lookup: &'l PartLookup,
    tally: &'t mut PartPixels,
    fused: Option<FusedScan<'l>>,
}

impl<'l, 't> PartRows<'l, 't> {
    /// Rows of `layout` counted with `scan` (built for `classifier`) and
    /// tallied by `lookup`'s parts into `tally`.
    pub fn new(
        scan: RowScan,
        layout: PixelLayout,
        classifier: &'l Classifier<'l>,
        lookup: &'l PartLookup,
        tally: &'t mut PartPixels,
    ) -> PartRows<'l, 't> {
        // The fused kernel's gathers need every palette colour inside the
        // table's grid: checked here, once, against the classifier kept.
        let texels = classifier.palette().texel_count() as u32;
        let slots = lookup.slot_table().block_slots().filter(|slots| slots.len() == texels);
        let fused = match scan.choice {
            Choice::Vector(vector, _) if scan.fuse_parts => {
                slots.and_then(|slots| vector.fused(slots, texels))
            }
            _ => None,
        };
        PartRows { scan, layout, classifier, lookup, tally, fused }
    }

    /// [`RowScan::scan`] of row `y`, and its pixels by part.
    #[inline]
    pub fn scan(
        &mut self,
        row: &[u8],
        y: u32,
        seen: &mut SeenSet,
        strays: &AtomicColorSet,
        by_class: &mut ClassCounts,
    ) {
        self.scan_runs(row, y, (seen, strays, by_class), ());
    }

    /// [`PartRows::scan`], which also reports the row's runs of equal colour
    /// to `runs` ([`ColorRuns`]).
    #[inline]
    pub(crate) fn scan_runs<R: ColorRuns>(
        &mut self,
        row: &[u8],
        y: u32,
        (seen, strays, by_class): (&mut SeenSet, &AtomicColorSet, &mut ClassCounts),
        runs: R,
    ) {
        let classifier = self.classifier;
        match &self.fused {
            Some(fused) => {
                let spans = RowSpans::new(self.tally, y);
                let tally = fused.scan(row, classifier.classes(), seen, strays, (spans, runs));
                add_row_classes(by_class, tally);
            }
            None => {
                self.scan.scan_runs(row, classifier, seen, strays, by_class, runs);
                self.lookup.add_row_at(row, self.layout, y, self.tally);
            }
        }
    }

    /// Whether the kernel tallies parts itself (for tests).
    #[cfg(any(test, feature = "synthetic"))]
    fn fused(&self) -> bool {
        self.fused.is_some()
    }
}

pub use crate::simd::{KERNEL_ENV, Kernel};

/// The row kernel of [`Kernel::selected`] for `layout` and the classifier's
/// palette.
pub(crate) fn row_scan(layout: PixelLayout, classifier: &Classifier) -> RowScan {
    RowScan::new(Kernel::selected(), layout, classifier)
}

/// The vector row kernel of `kernel`, if it has one for `layout` and the
/// palette (RGB or RGBA rows against a canonical palette, whose membership
/// test is one comparison) and this CPU can run it.
pub(crate) fn vector_row_scan(
    kernel: Kernel,
    layout: PixelLayout,
    classifier: &Classifier,
) -> Option<RowScan> {
    if !matches!(classifier.palette(), Fcsp::Canonical { .. }) {
        return None;
    }
    let bytes = match layout {
        PixelLayout::Rgb => 3,
        PixelLayout::Rgba => 4,
        PixelLayout::Gray | PixelLayout::GrayAlpha => return None,
    };
    let vector = VectorScan::new(kernel, bytes, classifier.backgrounds().len() == 1)?;
    Some(RowScan { choice: Choice::Vector(vector, portable(layout, classifier)), fuse_parts: true })
}

/// Which portable kernel serves `layout` and the classifier's palette.
fn portable(layout: PixelLayout, classifier: &Classifier) -> Portable {
    let canonical = matches!(classifier.palette(), Fcsp::Canonical { .. });
    Portable { layout, canonical, single: classifier.backgrounds().len() == 1 }
}

/// The portable kernel for `layout` and the classifier's palette.
pub(crate) fn portable_row_scan(layout: PixelLayout, classifier: &Classifier) -> RowScan {
    RowScan { choice: Choice::Portable(portable(layout, classifier)), fuse_parts: false }
}

#[inline(always)]
fn pack<const BYTES: usize, const GRAY: bool>(row: &[u8], pixel: usize) -> u32 {
    let at = pixel * BYTES;
    if GRAY {
        u32::from(row[at]) * 0x01_0101
    } else {
        (u32::from(row[at]) << 16) | (u32::from(row[at + 1]) << 8) | u32::from(row[at + 2])
    }
}

/// Adds what a vector kernel found to the per-class counts.
#[inline(always)]
fn add_row_classes(by_class: &mut ClassCounts, tally: RowTally) {
    by_class[PixelClass::Background as usize] += tally.background;
    by_class[PixelClass::Stray as usize] += tally.stray;
    by_class[PixelClass::Texel as usize] += tally.pixels as u64 - tally.background - tally.stray;
}

/// Accumulates the bits of one [`SeenSet`] word at a time (the portable
/// kernel's choice).
///
/// Writing each pixel's bit to memory would chain neighbouring pixels through
/// store-to-load forwarding on the same word; holding the word in a register
/// and flushing it when the word changes keeps the loop free of that chain
/// (measured 1.85 → 1.53 ns per pixel when it was introduced).
struct WordAccumulator {
    index: usize,
    bits: u64,
}

impl WordAccumulator {
    fn new() -> WordAccumulator {
        WordAccumulator { index: 0, bits: 0 }
    }

    /// Adds `bits` (possibly none) at word `index`.
    #[inline(always)]
    fn add(&mut self, seen: &mut SeenSet, index: usize, bits: u64) {
        if index != self.index {
            self.flush(seen);
            self.index = index;
        }
        self.bits |= bits;
    }

    #[inline(always)]
    fn flush(&mut self, seen: &mut SeenSet) {
        if self.bits != 0 {
            seen.or_word(self.index, self.bits);
            self.bits = 0;
        }
    }
}

/// Pixels per block of the portable kernel (a power of two).
const BLOCK: usize = 16;

/// The portable kernel; with an active `runs` it reports each pixel whose
/// colour differs from its left neighbour's (and the slice's first).
#[inline(always)]
fn scan_row<
    const BYTES: usize,
    const GRAY: bool,
    const CANONICAL: bool,
    const SINGLE_BACKGROUND: bool,
    R: ColorRuns,
>(
    row: &[u8],
    classifier: &Classifier,
    seen: &mut SeenSet,
    strays: &AtomicColorSet,
    by_class: &mut ClassCounts,
    mut runs: R,
) {
    let pixels = row.len() / BYTES;
    let texels = classifier.palette().texel_count() as u32;
    let background_0 = classifier.backgrounds()[0];
    let block_bytes = BLOCK * BYTES;
    let mut previous_class = PixelClass::Background as usize;
    // No colour has more than 24 bits: the first pixel starts a run.
    let mut previous_color = u32::MAX;
    let mut word = WordAccumulator::new();
    let mut start = 0;
    while start < pixels {
        // A block equal to the block one pixel earlier repeats the previous
        // pixel throughout (byte equality implies colour equality; differing
        // alpha merely sends the block down the exact path below).
        if start > 0
            && start + BLOCK <= pixels
            && row[start * BYTES..start * BYTES + block_bytes]
                == row[(start - 1) * BYTES..(start - 1) * BYTES + block_bytes]
        {
            by_class[previous_class] += BLOCK as u64;
            start += BLOCK;
            continue;
        }
        let end = (start + BLOCK).min(pixels);
        let (mut background, mut stray) = (0u64, 0u64);
        for pixel in start..end {
            let color = pack::<BYTES, GRAY>(row, pixel);
            let is_background =
                if SINGLE_BACKGROUND { color == background_0 } else { classifier.is_background(color) };
            let member = if CANONICAL { color < texels } else { classifier.palette().contains(color) };
            let is_texel = member & !is_background;
            let is_stray = !member & !is_background;
            let key = color_key(color);
            // Non-texels add no bit.
            word.add(seen, (key >> 6) as usize, u64::from(is_texel) << (key & 63));
            background += u64::from(is_background);
            stray += u64::from(is_stray);
            if is_stray {
                strays.insert(color); // rare: damaged or filtered pixels
            }
            if R::ACTIVE && color != previous_color {
                runs.start(pixel, color, is_texel);
            }
            previous_color = color;
            previous_class = usize::from(is_texel) + 2 * usize::from(is_stray);
        }
        by_class[PixelClass::Background as usize] += background;
        by_class[PixelClass::Stray as usize] += stray;
        by_class[PixelClass::Texel as usize] += (end - start) as u64 - background - stray;
        start = end;
    }
    word.flush(seen);
}

/// The checks that hold the vector kernels to the portable one. `tests/kernels`
/// runs them (`testing::kernel_checks`), and reports one ignored
/// where this CPU lacks its kernel.
#[cfg(any(test, feature = "synthetic"))]
pub(crate) mod kernel_checks {
    use super::*;
    use crate::optics::solid_angle::TileView;

    /// Per-class counts and texel keys of one row; strays go to `strays`.
    pub(crate) fn scan_with(
        scan: RowScan,
        classifier: &Classifier,
        row: &[u8],
        strays: &AtomicColorSet,
    ) -> (ClassCounts, Vec<u32>) {
        // A 2 MiB set per call would make the test slow unoptimised.
        thread_local! {
            static SEEN: std::cell::RefCell<SeenSet> = std::cell::RefCell::new(SeenSet::new());
        }
        SEEN.with_borrow_mut(|seen| {
            let mut by_class = [0; 3];
            scan.scan(row, classifier, seen, strays, &mut by_class);
            let keys = seen.keys();
            seen.clear();
            (by_class, keys)
        })
    }

    /// A xorshift64 generator from `state` (deterministic test data).
    fn xorshift(mut state: u64) -> impl FnMut() -> u64 {
        move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        }
    }

    /// A deterministic pseudo-random row mixing background runs, texel
    /// gradients, repeats, strays and (for RGBA) arbitrary alpha.
    fn random_row(seed: u64, pixels: usize, bytes: usize, backgrounds: &[u32]) -> Vec<u8> {
        let mut next = xorshift(seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1));
        let mut row = Vec::with_capacity(pixels * bytes);
        let mut color = 0u32;
        while row.len() < pixels * bytes {
            let run = (next() % 40) as usize + 1;
            let kind = next() % 10;
            for step in 0..run {
                color = match kind {
                    0..=2 => backgrounds[(next() as usize) % backgrounds.len()],
                    3..=7 => ((next() as u32) & 0xFF_FFFF) / 2 + (step as u32 / 3), // texels, magnified
                    8 => (next() as u32) & 0xFF_FFFF,                               // anything, often stray
                    _ => color,                                                     // repeat
                };
                row.extend_from_slice(
                    &[(color >> 16) as u8, (color >> 8) as u8, color as u8, next() as u8][..bytes],
                );
            }
        }
        row.truncate(pixels * bytes);
        row
    }

    /// The AVX2 row kernel against the portable one, on random rows.
    pub(crate) fn the_avx2_kernel_equals_the_portable_kernel() {
        vector_kernel_equals_the_portable_kernel(Kernel::Avx2);
    }

    /// The AVX-512 row kernel against the portable one, on random rows.
    pub(crate) fn the_avx512_kernel_equals_the_portable_kernel() {
        vector_kernel_equals_the_portable_kernel(Kernel::Avx512);
    }

    fn vector_kernel_equals_the_portable_kernel(kernel: Kernel) {
        // 4096 × 3000 texels: colours from 12,288,000 up are strays.
        let palette = Fcsp::canonical([4096, 3000]).unwrap();
        for backgrounds in [vec![0x000FFF], vec![0x000FFF, 0x000010, 0xFFFFFF]] {
            let classifier = Classifier::new(&palette, &backgrounds).unwrap();
            for (layout, bytes) in [(PixelLayout::Rgb, 3), (PixelLayout::Rgba, 4)] {
                let Some(vector) = vector_row_scan(kernel, layout, &classifier) else {
                    panic!("{kernel:?} has no kernel for {layout:?}");
                };
                let portable = portable_row_scan(layout, &classifier);
                let (vector_strays, portable_strays) = (AtomicColorSet::new(), AtomicColorSet::new());
                for seed in 0..300u64 {
                    let pixels = (seed as usize * 7) % 200 + (seed as usize % 3) * 1284;
                    let row = random_row(seed, pixels, bytes, &backgrounds);
                    assert_eq!(
                        scan_with(vector, &classifier, &row, &vector_strays),
                        scan_with(portable, &classifier, &row, &portable_strays),
                        "{kernel:?}, seed {seed}, {pixels} pixels, {bytes} bytes per pixel"
                    );
                }
                let all = usize::MAX;
                assert!(vector_strays.len() > 1000, "the rows must exercise strays");
                assert_eq!(vector_strays.first(all), portable_strays.first(all));
            }
        }
    }

    /// A lookup with many parts, drawn as charts the way a PIdT marks them:
    /// triangles a few dozen texels across (so 8 × 8 blocks on their edges
    /// hold several slots), lone texels of another part, and unlabelled
    /// texels (no legend colour).
    fn pidt_like_lookup(palette: &Fcsp, backgrounds: &[u32]) -> PartLookup {
        use crate::archive::labels::{Legend, Part, Pidt};
        use crate::color::Color;
        let Fcsp::Canonical { width, height } = *palette else { unreachable!("canonical palettes only") };
        let parts: Vec<Part> = (0..6u32)
            .map(|i| Part { name: format!("part {i}"), color: Color::from_packed(0x10_0000 * (i + 1)) })
            .collect();
        let legend = Legend::new(Path::new("parts.csv"), parts).unwrap();
        let colors: Vec<u32> = (0..width * height)
            .map(|texel| {
                let (x, y) = (texel % width, texel / width);
                let chart = (x / 37 + 3 * (y / 29)) % 7; // 6: unlabelled
                let upper = (x % 37) * 29 > (y % 29) * 37; // the chart's diagonal
                match (texel % 331 == 7, chart) {
                    (true, _) => 0x10_0000 * 4,
                    (false, 6) => 0x12_3456,
                    (false, _) => 0x10_0000 * ((chart + u32::from(upper)) % 6 + 1),
                }
            })
            .collect();
        let pidt = Pidt::from_colors([width, height], &colors, &legend);
        PartLookup::new(palette, Some((&legend, &pidt)), backgrounds)
    }

    /// A deterministic pseudo-random row that walks the palette's grid as a
    /// rendered surface does: texel gradients (magnified, minified, crossing
    /// part boundaries and 8 × 8 block edges, sometimes a texture row down),
    /// background runs, strays, repeats and (RGBA) arbitrary alpha.
    fn random_part_row(
        seed: u64,
        pixels: usize,
        bytes: usize,
        width: u32,
        texels: u32,
        backgrounds: &[u32],
    ) -> Vec<u8> {
        let mut next = xorshift(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15).wrapping_add(7));
        let mut row = Vec::with_capacity(pixels * bytes);
        let mut color = 0u32;
        while row.len() < pixels * bytes {
            let run = (next() % 60) as usize + 1;
            let kind = next() % 12;
            let (start, magnify, step) =
                ((next() as u32) % texels, (next() % 5) as u32 + 1, (next() % 3) as u32);
            for i in 0..run as u32 {
                color = match kind {
                    0..=2 => backgrounds[(next() as usize) % backgrounds.len()],
                    3..=8 => {
                        let down = if next().is_multiple_of(50) { width } else { 0 };
                        (start + i / magnify * step + down).min(texels - 1)
                    }
                    9 => (next() as u32) & 0xFF_FFFF, // anything, mostly stray
                    _ => color,                       // repeat
                };
                row.extend_from_slice(
                    &[(color >> 16) as u8, (color >> 8) as u8, color as u8, next() as u8][..bytes],
                );
            }
        }
        row.truncate(pixels * bytes);
        row
    }

    /// Counts and tallies `row` with `rows` (row `y` of its image); returns
    /// what both gave.
    fn scan_parts(
        rows: &mut PartRows,
        row: &[u8],
        y: u32,
        strays: &AtomicColorSet,
    ) -> (ClassCounts, Vec<u32>) {
        let mut seen = SeenSet::new();
        let mut by_class = [0; 3];
        rows.scan(row, y, &mut seen, strays, &mut by_class);
        (by_class, seen.keys())
    }

    /// The AVX-512 kernel's form that tallies parts against the separate
    /// per-part pass.
    pub(crate) fn the_kernel_that_tallies_parts_gives_the_separate_passs_pixels_and_solid_angles() {
        let projection = crate::optics::solid_angle::EyeProjection::new(107.0, [1284, 1620]).unwrap();
        // Widths of 512 and 4 texels: blocks of the slot table inside and
        // (4 × 4) wider than the grid; 100 is no power of two (separate pass).
        for (width, height) in [(512u32, 256u32), (4, 4), (100, 37)] {
            let palette = Fcsp::canonical([width, height]).unwrap();
            for backgrounds in [vec![0x000FFF], vec![0x000FFF, 0x000010, 5]] {
                let classifier = Classifier::new(&palette, &backgrounds).unwrap();
                let lookups =
                    [pidt_like_lookup(&palette, &backgrounds), PartLookup::new(&palette, None, &backgrounds)];
                for (lookup, (layout, bytes)) in
                    lookups.iter().flat_map(|l| [(l, (PixelLayout::Rgb, 3)), (l, (PixelLayout::Rgba, 4))])
                {
                    let fused_scan = vector_row_scan(Kernel::Avx512, layout, &classifier).unwrap();
                    let plain_scan = portable_row_scan(layout, &classifier);
                    for view in [None, Some(TileView { projection, origin: [300, 700] })] {
                        let (mut fused_tally, mut separate_tally) =
                            (PartPixels::new(lookup), PartPixels::new(lookup));
                        fused_tally.view = view;
                        separate_tally.view = view;
                        let mut fused =
                            PartRows::new(fused_scan, layout, &classifier, lookup, &mut fused_tally);
                        let mut separate =
                            PartRows::new(plain_scan, layout, &classifier, lookup, &mut separate_tally);
                        assert_eq!(fused.fused(), width.is_power_of_two());
                        assert!(!separate.fused());
                        let strays = AtomicColorSet::new();
                        for seed in 0..120u64 {
                            let pixels = match seed % 4 {
                                0 => seed as usize % 16, // shorter than a block
                                1 => 1284,
                                _ => (seed as usize * 37) % 300,
                            };
                            let row =
                                random_part_row(seed, pixels, bytes, width, width * height, &backgrounds);
                            let y = (seed % 300) as u32;
                            let by_fused = scan_parts(&mut fused, &row, y, &strays);
                            let by_separate = scan_parts(&mut separate, &row, y, &strays);
                            assert_eq!(by_fused, by_separate, "{width}×{height}, seed {seed}, {bytes} bytes");
                        }
                        assert_eq!(
                            fused_tally, separate_tally,
                            "{width}×{height}, {layout:?}, view {view:?}"
                        );
                        let texels: u64 = separate_tally.pixels[..lookup.parts()].iter().sum();
                        assert!(texels > 10_000, "the rows must show texels");
                        if lookup.parts() > 1 && width == 512 {
                            let parts_shown = separate_tally.pixels.iter().filter(|&&p| p > 0).count();
                            assert_eq!(parts_shown, lookup.parts() + 1, "every part and the non-texels");
                        }
                    }
                }
            }
        }
    }
    /// The per-texel solid angles of a kernel's runs, in its plain form and
    /// its form with the part tally (AVX-512: fused when the palette's width
    /// is a power of two), against the second pass they replaced
    /// ([`crate::count::texel_area::reference_add_row`]): the same integers
    /// for every texel, on rows that walk the palette as a rendered surface
    /// does, with background runs, strays, repeats and arbitrary alpha.
    pub(crate) fn kernel_texel_areas_equal_the_reference(kernel: Kernel) {
        use crate::count::texel_area::reference_add_row;
        let projection = crate::optics::solid_angle::EyeProjection::new(107.0, [1284, 1620]).unwrap();
        let view = TileView { projection, origin: [0, 600] };
        for (width, height) in [(512u32, 256u32), (100, 37)] {
            let palette = Fcsp::canonical([width, height]).unwrap();
            for backgrounds in [vec![0x000FFF], vec![0x000FFF, 0x000010, 5]] {
                let classifier = Classifier::new(&palette, &backgrounds).unwrap();
                let lookup = pidt_like_lookup(&palette, &backgrounds);
                for (layout, bytes) in [(PixelLayout::Rgb, 3), (PixelLayout::Rgba, 4)] {
                    let scan = match kernel {
                        Kernel::Portable => portable_row_scan(layout, &classifier),
                        vector => vector_row_scan(vector, layout, &classifier).unwrap(),
                    };
                    let sums: [TexelSolidAngles; 3] =
                        std::array::from_fn(|_| TexelSolidAngles::new(&palette, &backgrounds));
                    let table = sums[0].pixel_prefix(&view, [1284, 300]).unwrap();
                    let mut tally = PartPixels::new(&lookup);
                    tally.view = Some(view);
                    let mut parts = PartRows::new(scan, layout, &classifier, &lookup, &mut tally);
                    assert_eq!(parts.fused(), kernel == Kernel::Avx512 && width.is_power_of_two());
                    let (mut seen, strays, mut by_class) = (SeenSet::new(), AtomicColorSet::new(), [0; 3]);
                    let mut pending: [PendingRuns; 3] = Default::default();
                    for seed in 0..160u64 {
                        let pixels = match seed % 4 {
                            0 => seed as usize % 16, // shorter than a block
                            1 => 1284,
                            _ => (seed as usize * 37) % 300,
                        };
                        let row = random_part_row(seed, pixels, bytes, width, width * height, &backgrounds);
                        let y = (seed % 300) as u32;
                        reference_add_row(&sums[0], &row, layout, table.row(y), &mut pending[0]);
                        let [_, plain, with_parts] = &mut pending;
                        let mut runs = sums[1].row_runs(table.row(y), plain);
                        scan.scan_runs(&row, &classifier, &mut seen, &strays, &mut by_class, &mut runs);
                        runs.finish(pixels);
                        seen.clear();
                        let mut runs = sums[2].row_runs(table.row(y), with_parts);
                        parts.scan_runs(&row, y, (&mut seen, &strays, &mut by_class), &mut runs);
                        runs.finish(pixels);
                        seen.clear();
                    }
                    for (sum, pending) in sums.iter().zip(&mut pending) {
                        sum.flush(pending);
                    }
                    let [reference, plain, with_parts] = sums.map(TexelSolidAngles::into_units);
                    let shown = reference.iter().filter(|&&u| u > 0).count();
                    assert!(shown > 1000.min(width as usize * height as usize / 2), "{shown} texels shown");
                    let case = format!(
                        "{kernel:?}, {width}×{height}, {layout:?}, {} backgrounds",
                        backgrounds.len()
                    );
                    assert!(plain == reference, "the kernel's areas differ from the reference: {case}");
                    assert!(
                        with_parts == reference,
                        "the kernel with parts differs from the reference: {case}"
                    );
                }
            }
        }
    }

    /// [`kernel_texel_areas_equal_the_reference`] for the portable kernel.
    pub(crate) fn the_portable_kernels_texel_areas_equal_the_reference_pass() {
        kernel_texel_areas_equal_the_reference(Kernel::Portable);
    }

    /// [`kernel_texel_areas_equal_the_reference`] for the AVX2 kernel.
    pub(crate) fn the_avx2_kernels_texel_areas_equal_the_reference_pass() {
        kernel_texel_areas_equal_the_reference(Kernel::Avx2);
    }

    /// [`kernel_texel_areas_equal_the_reference`] for the AVX-512 kernels.
    pub(crate) fn the_avx512_kernels_texel_areas_equal_the_reference_pass() {
        kernel_texel_areas_equal_the_reference(Kernel::Avx512);
    }
}

#[cfg(test)]
mod tests {
    use super::kernel_checks::scan_with;
    use super::*;

    fn rgb(colors: &[u32]) -> Vec<u8> {
        colors.iter().flat_map(|&c| [(c >> 16) as u8, (c >> 8) as u8, c as u8]).collect()
    }

    #[test]
    fn runs_of_every_length_are_counted_exactly() {
        let palette = Fcsp::canonical([16, 16]).unwrap();
        let classifier = Classifier::new(&palette, &[0x000FFF]).unwrap();
        for scan in
            [portable_row_scan(PixelLayout::Rgb, &classifier), row_scan(PixelLayout::Rgb, &classifier)]
        {
            let strays = AtomicColorSet::new();
            for length in 0..60 {
                let mut colors = vec![0x000FFF; length];
                colors.extend([5, 5, 7, 0xFFFFFF, 5]);
                colors.extend(vec![9; length]);
                colors.push(0x000FFF);
                let (by_class, seen) = scan_with(scan, &classifier, &rgb(&colors), &strays);
                let seen: Vec<u32> = seen.into_iter().map(crate::color::sets::key_color).collect();
                assert_eq!(by_class, [length as u64 + 1, 4 + length as u64, 1], "length {length}");
                let mut expected = vec![5, 7];
                if length > 0 {
                    expected.push(9);
                }
                assert_eq!(seen, expected);
                assert_eq!(strays.first(10), vec![0xFFFFFF]);
            }
        }
    }
}

/// At most this many background colours (checked without branches).
pub(crate) const MAX_BACKGROUNDS: usize = 8;

/// Decides, for each pixel colour, whether it is background, a palette
/// texel or a stray. Built once from validated options; shared read-only.
pub struct Classifier<'a> {
    palette: &'a Fcsp,
    /// Background colours, padded by repeating the first.
    backgrounds: [u32; MAX_BACKGROUNDS],
    /// How many of `backgrounds` were given.
    background_count: usize,
}

/// What a pixel colour is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(usize)]
pub enum PixelClass {
    Background = 0,
    Texel = 1,
    Stray = 2,
}

impl<'a> Classifier<'a> {
    /// A classifier for `palette` ignoring `backgrounds` (1 to
    /// [`MAX_BACKGROUNDS`] packed colours).
    pub fn new(palette: &'a Fcsp, backgrounds: &[u32]) -> Result<Classifier<'a>> {
        let Some(&first) = backgrounds.first() else {
            return Err(Error::BadOptions("at least one background colour is needed".into()));
        };
        if backgrounds.len() > MAX_BACKGROUNDS {
            return Err(Error::BadOptions(format!(
                "at most {MAX_BACKGROUNDS} background colours are supported, {} were given",
                backgrounds.len()
            )));
        }
        let mut padded = [first; MAX_BACKGROUNDS];
        padded[..backgrounds.len()].copy_from_slice(backgrounds);
        Ok(Classifier { palette, backgrounds: padded, background_count: backgrounds.len() })
    }

    /// The palette whose colours are texels.
    pub fn palette(&self) -> &Fcsp {
        self.palette
    }

    /// The background colours, as given.
    pub fn backgrounds(&self) -> &[u32] {
        &self.backgrounds[..self.background_count]
    }

    /// What a vector kernel needs of it.
    #[inline]
    pub(crate) fn classes(&self) -> Classes<'_> {
        Classes { backgrounds: self.backgrounds(), texels: self.palette.texel_count() as u32 }
    }

    /// Compares with all [`MAX_BACKGROUNDS`] slots, so the check has no
    /// branches whatever the number of backgrounds.
    #[inline(always)]
    pub(crate) fn is_background(&self, color: u32) -> bool {
        self.backgrounds.iter().fold(false, |hit, &background| hit | (color == background))
    }

    /// Background wins over palette membership: a background colour is
    /// ignored even when it also names a texel.
    #[inline(always)]
    pub fn classify(&self, color: u32) -> PixelClass {
        if self.is_background(color) {
            PixelClass::Background
        } else if self.palette.contains(color) {
            PixelClass::Texel
        } else {
            PixelClass::Stray
        }
    }
}

/// Pixel statistics of one decoded image.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct ImageTally {
    pub width: u32,
    pub height: u32,
    /// Pixels of palette colours.
    pub texel_pixels: u64,
    pub background_pixels: u64,
    pub stray_pixels: u64,
}

impl ImageTally {
    /// True when every pixel is background.
    pub fn is_pure_background(&self) -> bool {
        self.texel_pixels == 0 && self.stray_pixels == 0
    }
}

/// Decodes one PNG and records its distinct palette colours in `seen`
/// as [`color_key`]s (`seen` must be empty on entry; [`crate::color::sets::key_color`] turns
/// them back into colours). Stray colours go to `strays`.
///
/// On error `seen` is cleared again, so nothing of a failed image is counted.
pub fn scan_image(
    path: &Path,
    bytes: &[u8],
    classifier: &Classifier,
    seen: &mut SeenSet,
    strays: &AtomicColorSet,
) -> Result<ImageTally> {
    scan_image_by_part(path, bytes, classifier, seen, strays, None)
}

/// [`scan_image`], and with `parts` also the image's pixels by part (added
/// to the tally, see [`crate::count::part_lookup::PartLookup::add_row`]; on error the
/// tally holds a part of the image's pixels: the caller discards it). The
/// per-part pass is a separate loop over each row, so [`scan_image`] keeps
/// its kernels untouched.
pub fn scan_image_by_part(
    path: &Path,
    bytes: &[u8],
    classifier: &Classifier,
    seen: &mut SeenSet,
    strays: &AtomicColorSet,
    parts: Option<(&PartLookup, &mut PartPixels)>,
) -> Result<ImageTally> {
    scan_image_with(
        path,
        bytes,
        classifier,
        seen,
        strays,
        RowPasses { parts, neighbours: None, texel_area: None },
    )
}

/// The optional passes over each decoded row beside the counting kernel:
/// pixels by part, the neighbour sample of the colour checks, and the
/// per-texel solid angles (with where the image lies in its eye).
pub(crate) struct RowPasses<'p, 'l> {
    pub parts: Option<(&'l PartLookup, &'p mut PartPixels)>,
    pub neighbours: Option<&'p mut NeighbourSampler>,
    pub texel_area: Option<(&'l TexelSolidAngles, TileView)>,
}

/// [`scan_image_by_part`] with every optional row pass (on error the
/// passes hold part of the image: the caller discards it).
pub(crate) fn scan_image_with(
    path: &Path,
    bytes: &[u8],
    classifier: &Classifier,
    seen: &mut SeenSet,
    strays: &AtomicColorSet,
    passes: RowPasses,
) -> Result<ImageTally> {
    debug_assert!(seen.is_empty());
    let outcome = scan_rows(path, bytes, classifier, seen, strays, passes);
    if outcome.is_err() {
        seen.clear();
    }
    outcome
}

fn scan_rows(
    path: &Path,
    bytes: &[u8],
    classifier: &Classifier,
    seen: &mut SeenSet,
    strays: &AtomicColorSet,
    passes: RowPasses,
) -> Result<ImageTally> {
    let RowPasses { parts, mut neighbours, texel_area } = passes;
    if let Some(sampler) = neighbours.as_mut() {
        sampler.start_image();
    }
    let mut reader = RowReader::new(path, bytes)?;
    let layout = reader.layout();
    let scan = row_scan(layout, classifier);
    let mut parts = parts.map(|(lookup, tally)| PartRows::new(scan, layout, classifier, lookup, tally));
    let size = [reader.width(), reader.height()];
    let texel_area = texel_area.and_then(|(sums, view)| Some((sums, sums.pixel_prefix(&view, size)?)));
    let mut by_class = [0u64; 3];
    let mut pending = PendingRuns::default();
    let mut y = 0;
    while let Some(row) = reader.next_row()? {
        let counts = (&mut *seen, strays, &mut by_class);
        match &texel_area {
            Some((sums, table)) => {
                let mut runs = sums.row_runs(table.row(y), &mut pending);
                scan_row_with(&scan, parts.as_mut(), row, (y, classifier), counts, &mut runs);
                runs.finish(size[0] as usize);
                sums.flush_if_full(&mut pending);
            }
            None => scan_row_with(&scan, parts.as_mut(), row, (y, classifier), counts, ()),
        }
        if let Some(sampler) = neighbours.as_mut() {
            sampler.row(y, row, layout);
        }
        y += 1;
    }
    reader.finish()?;
    if let Some((sums, _)) = &texel_area {
        sums.flush(&mut pending);
    }
    Ok(ImageTally {
        width: reader.width(),
        height: reader.height(),
        background_pixels: by_class[PixelClass::Background as usize],
        texel_pixels: by_class[PixelClass::Texel as usize],
        stray_pixels: by_class[PixelClass::Stray as usize],
    })
}

/// Row `y` through the counting kernel `scan`, or through `parts` when the
/// row is also tallied by part; its runs go to `runs`.
#[inline]
fn scan_row_with<R: ColorRuns>(
    scan: &RowScan,
    parts: Option<&mut PartRows>,
    row: &[u8],
    (y, classifier): (u32, &Classifier),
    (seen, strays, by_class): (&mut SeenSet, &AtomicColorSet, &mut ClassCounts),
    runs: R,
) {
    match parts {
        Some(parts) => parts.scan_runs(row, y, (seen, strays, by_class), runs),
        None => scan.scan_runs(row, classifier, seen, strays, by_class, runs),
    }
}
