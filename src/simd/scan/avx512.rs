//! The AVX-512 row kernel (x86-64 only, chosen at run time): skips blocks
//! that repeat the pixel before them, unpacks, classifies and keys 16 RGB or
//! RGBA pixels per instruction, and hands only the texels whose colour
//! differs from their left neighbour's to scalar code.
//!
//! Its second form, [`scan_row_by_part`], also tallies the row by part in
//! the same pass: the separate per-part pass re-read every row to find its
//! runs and cost twice the kernel (`perf`: 19 % of a default analysis
//! against 8.7 %). Here each block that is not a repeat looks its 16 slots
//! up with a gather from the slot table's block entries (a second gather
//! only for lanes in blocks on a chart's edge), and only the rare lanes
//! whose slot differs from their left neighbour's reach scalar code, which
//! closes a span there ([`SlotSpans`]). A repeated block changes no slot.
//!
//! Both forms also report the row's runs of equal colour when asked
//! ([`ColorRuns`], the per-texel solid angles): the lanes whose colour differs
//! from their left neighbour's, found by the comparison the new texels are
//! found by; a repeated block continues the open run.

use std::arch::x86_64::*;

use super::{
    BACKGROUND, BlockSlots, Classes, ColorRuns, MarkAccumulator, RowTally, STRAY, SlotSpans, unpack_table,
};
use crate::color::{AtomicColorSet, SeenSet};

/// The vector form of [`crate::color::color_key`].
#[target_feature(enable = "avx512f")]
#[inline]
fn color_keys(colors: __m512i) -> __m512i {
    let low = _mm512_and_si512(colors, _mm512_set1_epi32(0xFF_001F));
    let x_blocks = _mm512_and_si512(_mm512_slli_epi32::<4>(colors), _mm512_set1_epi32(0xFE00));
    let y_rows = _mm512_and_si512(_mm512_srli_epi32::<7>(colors), _mm512_set1_epi32(0x1E0));
    _mm512_or_si512(low, _mm512_or_si512(x_blocks, y_rows))
}

/// What a block adds by part: nothing (`()`, the plain kernel) or its part
/// spans ([`FusedParts`]).
trait BlockParts {
    /// Records the block of `colors` whose lane 0 is pixel `first`; `member`
    /// marks the lanes in `lanes` with a palette colour (texels, and
    /// background colours that name a texel).
    ///
    /// # Safety
    /// As [`RowScanner::block`].
    unsafe fn block(&mut self, first: usize, colors: __m512i, member: __mmask16, lanes: __mmask16);
}

impl BlockParts for () {
    #[inline(always)]
    unsafe fn block(&mut self, _: usize, _: __m512i, _: __mmask16, _: __mmask16) {}
}

/// The part spans of one row, found 16 slots at a time.
struct FusedParts<S> {
    /// `BlockSlots::blocks` and `BlockSlots::detail`.
    blocks: *const u8,
    detail: *const u8,
    width_shift: __m512i,
    blocks_per_row: __m512i,
    /// The slot of colours outside the table's grid (no palette colour).
    outside: __m512i,
    /// The slots of the last block scanned (an impossible slot before the
    /// first, so the first pixel always opens a span).
    previous: __m512i,
    spans: S,
}

impl<S: SlotSpans> FusedParts<S> {
    /// Before a row's first pixel.
    #[target_feature(enable = "avx512f")]
    #[inline]
    fn new(slots: &BlockSlots, spans: S) -> FusedParts<S> {
        FusedParts {
            blocks: slots.blocks.as_ptr().cast(),
            detail: slots.detail.as_ptr().cast(),
            width_shift: _mm512_set1_epi32(slots.width_shift as i32),
            blocks_per_row: _mm512_set1_epi32(slots.blocks_per_row as i32),
            outside: _mm512_set1_epi32(i32::from(slots.outside)),
            previous: _mm512_set1_epi32(-1),
            spans,
        }
    }

    /// The slot of each lane of `member` ([`BlockSlots`]' arithmetic), the
    /// outside slot elsewhere.
    ///
    /// # Safety
    /// As [`RowScanner::block`]; the colours of `member` lanes are below the
    /// table's `len`.
    #[inline(always)]
    unsafe fn slots(&self, colors: __m512i, member: __mmask16) -> __m512i {
        // SAFETY: the caller guarantees the CPU features (as for every
        // intrinsic of this function).
        let y = unsafe { _mm512_srlv_epi32(colors, self.width_shift) };
        // SAFETY: CPU features as above.
        let row_start = unsafe { _mm512_sllv_epi32(y, self.width_shift) };
        // SAFETY: CPU features as above.
        let x = unsafe { _mm512_sub_epi32(colors, row_start) };
        // SAFETY: CPU features as above.
        let block_row = unsafe { _mm512_srli_epi32::<3>(y) };
        // SAFETY: CPU features as above.
        let block_row = unsafe { _mm512_mullo_epi32(block_row, self.blocks_per_row) };
        // SAFETY: CPU features as above.
        let block_column = unsafe { _mm512_srli_epi32::<3>(x) };
        // SAFETY: CPU features as above.
        let block = unsafe { _mm512_add_epi32(block_row, block_column) };
        // SAFETY: CPU features as above; the gathered lanes (`member`, a
        // colour below `len`) index an entry of `blocks`, which
        // `BlockSlots::new` checked has one for every block of the grid.
        let entries =
            unsafe { _mm512_mask_i32gather_epi32::<4>(self.outside, member, block, self.blocks.cast()) };
        // SAFETY: CPU features as above.
        let detailed_bit = unsafe { _mm512_set1_epi32(BlockSlots::DETAILED as i32) };
        // SAFETY: CPU features as above.
        let detailed = unsafe { _mm512_mask_test_epi32_mask(member, entries, detailed_bit) };
        if detailed == 0 {
            return entries;
        }
        // SAFETY: the rest of this function is `slots_in_detail`'s
        // contract: CPU features as above, `detailed` lanes hold detailed
        // entries of `blocks`.
        unsafe { self.slots_in_detail(y, x, entries, detailed) }
    }

    /// [`FusedParts::slots`] for a block on a chart's edge (rare): the
    /// `detailed` lanes' slots, each from its entry's 64 in `detail`.
    ///
    /// # Safety
    /// As [`FusedParts::slots`]; `detailed` lanes of `entries` hold detailed
    /// entries of `blocks`.
    #[inline(always)]
    unsafe fn slots_in_detail(
        &self,
        y: __m512i,
        x: __m512i,
        entries: __m512i,
        detailed: __mmask16,
    ) -> __m512i {
        // SAFETY: the caller guarantees the CPU features (as for every
        // intrinsic of this function).
        let seven = unsafe { _mm512_set1_epi32(7) };
        // SAFETY: CPU features as above.
        let row_in_block = unsafe { _mm512_and_si512(y, seven) };
        // SAFETY: CPU features as above.
        let row_in_block = unsafe { _mm512_slli_epi32::<3>(row_in_block) };
        // SAFETY: CPU features as above.
        let column_in_block = unsafe { _mm512_and_si512(x, seven) };
        // SAFETY: CPU features as above.
        let within = unsafe { _mm512_or_si512(row_in_block, column_in_block) };
        // Shifting the entry left by 6 drops the DETAILED bit.
        // SAFETY: CPU features as above.
        let first = unsafe { _mm512_slli_epi32::<6>(entries) };
        // SAFETY: CPU features as above.
        let at = unsafe { _mm512_or_si512(first, within) };
        // SAFETY: CPU features as above; each gathered lane reads 4 bytes
        // at one of a detailed entry's 64 slots, which `SlotBlocks::new`
        // checked lie in `detail` with a slot after them.
        let pairs = unsafe { _mm512_mask_i32gather_epi32::<2>(entries, detailed, at, self.detail.cast()) };
        // SAFETY: CPU features as above.
        let low_half = unsafe { _mm512_set1_epi32(0xFFFF) };
        // SAFETY: CPU features as above.
        unsafe { _mm512_mask_and_epi32(entries, detailed, pairs, low_half) }
    }
}

impl<S: SlotSpans> BlockParts for FusedParts<S> {
    #[inline(always)]
    unsafe fn block(&mut self, first: usize, colors: __m512i, member: __mmask16, lanes: __mmask16) {
        // SAFETY: as `RowScanner::block`; `scan_row_by_part`'s caller
        // vouches that palette colours are below the table's `len`.
        let slots = unsafe { self.slots(colors, member) };
        // SAFETY: CPU features as `RowScanner::block`'s caller guarantees.
        let left = unsafe { _mm512_alignr_epi32::<15>(slots, self.previous) };
        // SAFETY: CPU features as above.
        let changes = unsafe { _mm512_mask_cmpneq_epi32_mask(lanes, slots, left) };
        if changes != 0 {
            let mut lane_slots = [0u32; 16];
            // SAFETY: CPU features as above; the store writes the 64 bytes
            // of `lane_slots`.
            unsafe { _mm512_storeu_si512(lane_slots.as_mut_ptr().cast(), slots) };
            let mut remaining = changes;
            while remaining != 0 {
                let lane = remaining.trailing_zeros() as usize;
                self.spans.change(first + lane, lane_slots[lane] as usize);
                remaining &= remaining - 1;
            }
        }
        self.previous = slots;
    }
}

/// One row in progress: what its blocks need and what they add up to.
struct RowScanner<'a, const SINGLE_BACKGROUND: bool, P: BlockParts, R: ColorRuns> {
    backgrounds: &'a [u32],
    texel_limit: __m512i,
    seen: &'a mut SeenSet,
    strays: &'a AtomicColorSet,
    marks: MarkAccumulator,
    /// The colours of the last block scanned (an impossible colour, above
    /// 2^24, before the first, so the first pixel always differs).
    previous: __m512i,
    /// The class of the last pixel scanned ([`BACKGROUND`], texel or
    /// [`STRAY`]).
    last_class: usize,
    background: u64,
    stray: u64,
    parts: P,
    runs: R,
}

impl<const SINGLE_BACKGROUND: bool, P: BlockParts, R: ColorRuns> RowScanner<'_, SINGLE_BACKGROUND, P, R> {
    /// Adds a block of `pixels` that all repeat the last pixel scanned: its
    /// class, and nothing new.
    #[inline(always)]
    fn repeat(&mut self, pixels: u64) {
        self.background += pixels * u64::from(self.last_class == BACKGROUND);
        self.stray += pixels * u64::from(self.last_class == STRAY);
    }

    /// Classifies the 16 colours of `colors` (pixels `first` on; lanes
    /// outside `lanes` are ignored), records the texels whose colour differs
    /// from their left neighbour's, and hands the block to `parts`.
    ///
    /// # Safety
    /// The CPU must have the features `scan_row` enables. (A plain
    /// `#[target_feature]` function is not inlined into its caller, and the
    /// call per 16 pixels cost 15 % of the kernel; so each intrinsic below
    /// is called in an `unsafe` block of its own.)
    #[inline(always)]
    unsafe fn block(&mut self, first: usize, colors: __m512i, lanes: __mmask16) {
        // SAFETY: the caller guarantees the CPU features (see above).
        let is_background = unsafe { self.backgrounds_of(colors) } & lanes;
        // SAFETY: CPU features as above.
        let member = unsafe { _mm512_cmplt_epu32_mask(colors, self.texel_limit) };
        let is_texel = member & !is_background & lanes;
        let is_stray = !member & !is_background & lanes;
        // SAFETY: the caller's guarantees are `parts.block`'s.
        unsafe { self.parts.block(first, colors, member & lanes, lanes) };
        if is_stray != 0 {
            // Rare: damaged or filtered pixels.
            let mut lane_colors = [0u32; 16];
            // SAFETY: CPU features as above; the store writes the 64 bytes
            // of `lane_colors`.
            unsafe { _mm512_storeu_si512(lane_colors.as_mut_ptr().cast(), colors) };
            let mut remaining = is_stray;
            while remaining != 0 {
                self.strays.insert(lane_colors[remaining.trailing_zeros() as usize]);
                remaining &= remaining - 1;
            }
        }
        // A pixel with its left neighbour's colour adds nothing new.
        // SAFETY: CPU features as above.
        let left = unsafe { _mm512_alignr_epi32::<15>(colors, self.previous) };
        if R::ACTIVE {
            // SAFETY: as above.
            unsafe { self.report_runs(first, colors, left, lanes, is_texel) };
        }
        // SAFETY: CPU features as above.
        let fresh = unsafe { _mm512_mask_cmpneq_epi32_mask(is_texel, colors, left) };
        if fresh != 0 {
            let mut keys = [0u32; 16];
            // SAFETY: CPU features as above.
            let all_keys = unsafe { color_keys(colors) };
            // SAFETY: CPU features as above.
            let fresh_keys = unsafe { _mm512_maskz_compress_epi32(fresh, all_keys) };
            // SAFETY: CPU features as above; the store writes the 64 bytes
            // of `keys`.
            unsafe { _mm512_storeu_si512(keys.as_mut_ptr().cast(), fresh_keys) };
            for &key in &keys[..fresh.count_ones() as usize] {
                self.marks.add(self.seen, key);
            }
        }
        self.background += u64::from(is_background.count_ones());
        self.stray += u64::from(is_stray.count_ones());
        // Lane 15 (only a row's last, partial block has fewer lanes, and
        // nothing follows it): background 0, texel 1, stray 2.
        let (last_background, last_stray) = (usize::from(is_background >> 15), usize::from(is_stray >> 15));
        self.last_class = (1 - last_background) * (1 + last_stray);
        self.previous = colors;
    }

    /// Reports the lanes of `lanes` whose colour differs from `left` (their
    /// left neighbour's) as starts of runs ([`ColorRuns`]).
    ///
    /// # Safety
    /// As [`RowScanner::block`].
    #[inline(always)]
    unsafe fn report_runs(
        &mut self,
        first: usize,
        colors: __m512i,
        left: __m512i,
        lanes: __mmask16,
        is_texel: __mmask16,
    ) {
        // SAFETY: the caller guarantees the CPU features.
        let starts = unsafe { _mm512_mask_cmpneq_epi32_mask(lanes, colors, left) };
        if starts != 0 {
            let mut lane_colors = [0u32; 16];
            // SAFETY: CPU features as above; the store writes the 64 bytes
            // of `lane_colors`.
            unsafe { _mm512_storeu_si512(lane_colors.as_mut_ptr().cast(), colors) };
            let mut remaining = starts;
            while remaining != 0 {
                let lane = remaining.trailing_zeros() as usize;
                self.runs.start(first + lane, lane_colors[lane], is_texel >> lane & 1 != 0);
                remaining &= remaining - 1;
            }
        }
    }

    /// The lanes of `colors` that are a background colour.
    ///
    /// # Safety
    /// As [`RowScanner::block`].
    #[inline(always)]
    unsafe fn backgrounds_of(&self, colors: __m512i) -> __mmask16 {
        // SAFETY: the caller guarantees the CPU features (as for every
        // intrinsic of this function).
        let first = unsafe { _mm512_set1_epi32(self.backgrounds[0] as i32) };
        // SAFETY: CPU features as above.
        let mut is_background = unsafe { _mm512_cmpeq_epi32_mask(colors, first) };
        if !SINGLE_BACKGROUND {
            for &color in &self.backgrounds[1..] {
                // SAFETY: CPU features as above.
                let color = unsafe { _mm512_set1_epi32(color as i32) };
                // SAFETY: CPU features as above.
                is_background |= unsafe { _mm512_cmpeq_epi32_mask(colors, color) };
            }
        }
        is_background
    }
}

/// The AVX-512 kernel for rows of `BYTES`-byte pixels (3: RGB, 4: RGBA)
/// against a canonical palette with one background colour or (when
/// `SINGLE_BACKGROUND` is false) several, over the whole row; for CPUs
/// where [`crate::simd::Kernel::supported`] is AVX-512.
#[target_feature(enable = "avx512f,avx512bw,avx512vbmi,popcnt,bmi1,bmi2")]
pub(super) fn scan_row<const BYTES: usize, const SINGLE_BACKGROUND: bool, R: ColorRuns>(
    row: &[u8],
    classes: Classes,
    seen: &mut SeenSet,
    strays: &AtomicColorSet,
    runs: R,
) -> RowTally {
    let scanner = RowScanner::<SINGLE_BACKGROUND, (), R>::new(classes, seen, strays, ((), runs));
    scan_blocks::<BYTES, SINGLE_BACKGROUND, (), R>(row, scanner).0
}

/// [`scan_row`], which also reports the row's part spans to `spans`, as
/// `count::PartLookup::add_row_at` finds them, looking slots up in `slots`.
///
/// # Safety
/// As [`scan_row`]; besides, `classes.texels` must be at most `slots.len`
/// (so every palette colour is in the table's grid).
#[target_feature(enable = "avx512f,avx512bw,avx512vbmi,popcnt,bmi1,bmi2")]
pub(super) unsafe fn scan_row_by_part<
    const BYTES: usize,
    const SINGLE_BACKGROUND: bool,
    S: SlotSpans,
    R: ColorRuns,
>(
    row: &[u8],
    classes: Classes,
    seen: &mut SeenSet,
    strays: &AtomicColorSet,
    slots: &BlockSlots,
    (spans, runs): (S, R),
) -> RowTally {
    let parts = FusedParts::new(slots, spans);
    let scanner = RowScanner::<SINGLE_BACKGROUND, _, R>::new(classes, seen, strays, (parts, runs));
    let (tally, parts) = scan_blocks::<BYTES, SINGLE_BACKGROUND, _, R>(row, scanner);
    parts.spans.finish(row.len() / BYTES);
    tally
}

impl<'a, const SINGLE_BACKGROUND: bool, P: BlockParts, R: ColorRuns> RowScanner<'a, SINGLE_BACKGROUND, P, R> {
    /// A scanner before a row's first pixel.
    #[target_feature(enable = "avx512f")]
    #[inline]
    fn new(
        classes: Classes<'a>,
        seen: &'a mut SeenSet,
        strays: &'a AtomicColorSet,
        (parts, runs): (P, R),
    ) -> RowScanner<'a, SINGLE_BACKGROUND, P, R> {
        RowScanner {
            backgrounds: classes.backgrounds,
            texel_limit: _mm512_set1_epi32(classes.texels as i32),
            seen,
            strays,
            marks: MarkAccumulator::new(),
            previous: _mm512_set1_epi32(-1),
            last_class: BACKGROUND,
            background: 0,
            stray: 0,
            parts,
            runs,
        }
    }
}

/// The body of both kernels: the row's blocks through `scanner`; returns
/// what they add up to and the scanner's `parts` (which hold what they
/// gathered).
#[target_feature(enable = "avx512f,avx512bw,avx512vbmi,popcnt,bmi1,bmi2")]
#[inline]
fn scan_blocks<const BYTES: usize, const SINGLE_BACKGROUND: bool, P: BlockParts, R: ColorRuns>(
    row: &[u8],
    mut scanner: RowScanner<'_, SINGLE_BACKGROUND, P, R>,
) -> (RowTally, P) {
    let pixels = row.len() / BYTES;
    // SAFETY: the load reads the 64 bytes of the table.
    let index = unsafe { _mm512_loadu_si512(unpack_table::<BYTES, 64>(16).as_ptr().cast()) };
    // The bytes of `count` pixels (16 of RGB: 48, of RGBA: 64) from pixel
    // `start`, zero beyond; masked-out bytes are neither read nor faulted on.
    let load = |start: usize, count: usize| {
        let bytes = count * BYTES;
        let mask = if bytes >= 64 { !0 } else { (1u64 << bytes) - 1 };
        // SAFETY: callers keep `start + count` pixels inside `row`, and the
        // masked load reads only those bytes.
        unsafe { _mm512_maskz_loadu_epi8(mask, row.as_ptr().wrapping_add(start * BYTES).cast()) }
    };
    let unpack = |raw: __m512i| _mm512_maskz_permutexvar_epi8(0x7777_7777_7777_7777, index, raw);
    let full_blocks = pixels / 16;
    for block in 0..full_blocks {
        let raw = load(block * 16, 16);
        // A block whose bytes equal the bytes one pixel earlier repeats the
        // last pixel scanned (a run of background or of one magnified texel).
        // As in the portable kernel, equal bytes imply equal colours; RGBA
        // pixels that differ only in alpha take the exact path.
        if block > 0 && _mm512_cmpneq_epi8_mask(raw, load(block * 16 - 1, 16)) == 0 {
            scanner.repeat(16);
            continue;
        }
        // SAFETY: this function has the features `block` needs.
        unsafe { scanner.block(block * 16, unpack(raw), !0) };
    }
    let rest = pixels - full_blocks * 16;
    if rest > 0 {
        let lanes = ((1u32 << rest) - 1) as __mmask16;
        // SAFETY: as above.
        unsafe { scanner.block(full_blocks * 16, unpack(load(full_blocks * 16, rest)), lanes) };
    }
    scanner.marks.flush(scanner.seen);
    (RowTally { pixels, background: scanner.background, stray: scanner.stray }, scanner.parts)
}
