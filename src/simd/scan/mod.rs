//! The vector row kernels of the count: AVX-512 ([`avx512`], 16 pixels per
//! instruction, with a second form that also tallies the row by part) and
//! AVX2 ([`avx2`], 8), for RGB and RGBA rows against a canonical palette.
//! `count::scan` holds the method, the portable kernel they are
//! held to, and the choice between them.
//!
//! Here are what they share and their safe doors: a [`VectorScan`] exists
//! only for a kernel whose every CPU feature was detected, and a
//! [`FusedScan`] only over a slot table ([`BlockSlots`]) whose grid holds
//! every colour it is asked about, checked where it is built
//! ([`SlotBlocks::new`]).

use crate::color::{AtomicColorSet, SeenSet};
use crate::simd::Kernel;

#[cfg(target_arch = "x86_64")]
mod avx2;
#[cfg(target_arch = "x86_64")]
mod avx512;

/// What a vector kernel needs of the classifier: the background colours
/// (at least one; more than one when `single_background` was false) and the
/// palette's texel count (a canonical palette: colours below it are
/// texels, unless background).
#[derive(Clone, Copy)]
pub(crate) struct Classes<'a> {
    pub backgrounds: &'a [u32],
    pub texels: u32,
}

/// What a vector kernel found in the start of a row it scanned: `pixels`
/// pixels, `background` and `stray` of them, the rest texels.
#[derive(Clone, Copy)]
pub(crate) struct RowTally {
    pub pixels: usize,
    pub background: u64,
    pub stray: u64,
}

/// The class of the last pixel scanned, for a block that repeats it:
/// background, texel or stray (as the counts index them).
const BACKGROUND: usize = 0;
const STRAY: usize = 2;

/// Where a row kernel reports the runs of equal colour it finds, for the
/// per-texel solid angles (`count::texel_area::RowRuns`): at the first pixel
/// of each run, in pixel order. A kernel may also report a run's continuation
/// as a new run (where it hands the row over to another kernel): the solid
/// angles are integer differences of one row's prefix sums, so a run split in
/// two adds the same to its texel. `()` reports nothing, and a kernel given it
/// does no work for runs at all ([`ColorRuns::ACTIVE`]).
pub(crate) trait ColorRuns {
    /// False only for `()`.
    const ACTIVE: bool;
    /// Pixel `at` of the row (of the slice the kernel was given) starts a run
    /// of `color`; `texel`: a palette texel that is no background colour.
    fn start(&mut self, at: usize, color: u32, texel: bool);
}

impl ColorRuns for () {
    const ACTIVE: bool = false;
    #[inline(always)]
    fn start(&mut self, _: usize, _: u32, _: bool) {}
}

impl<R: ColorRuns> ColorRuns for &mut R {
    const ACTIVE: bool = R::ACTIVE;
    #[inline(always)]
    fn start(&mut self, at: usize, color: u32, texel: bool) {
        (**self).start(at, color, texel);
    }
}

/// A vector row kernel this CPU runs, for one pixel layout and palette.
#[derive(Clone, Copy)]
pub(crate) struct VectorScan {
    kernel: Kernel,
    bytes: usize,
    single_background: bool,
}

impl VectorScan {
    /// The vector kernel of `kernel` for pixels of `bytes` bytes (3: RGB,
    /// 4: RGBA) against one background colour (`single_background`) or
    /// several, if it has one and this CPU has every feature it needs.
    pub(crate) fn new(kernel: Kernel, bytes: usize, single_background: bool) -> Option<VectorScan> {
        if kernel > Kernel::supported() {
            return None;
        }
        let known = matches!(kernel, Kernel::Avx512 | Kernel::Avx2) && matches!(bytes, 3 | 4);
        (cfg!(target_arch = "x86_64") && known).then_some(VectorScan { kernel, bytes, single_background })
    }

    /// Bytes per pixel of the rows it takes.
    pub(crate) fn bytes(self) -> usize {
        self.bytes
    }

    /// Classifies the longest start of `row` it can (all of it with
    /// AVX-512; with AVX2 the pixels of whole 32-byte loads, leaving the
    /// last few to the portable kernel), adds its palette texels (as
    /// [`crate::color::color_key`]s) to `seen` and its stray colours to
    /// `strays`, and says how many pixels of which class it scanned.
    /// With an active `runs`, it also reports the runs of equal colour of
    /// the pixels it scanned ([`ColorRuns`]).
    #[inline]
    pub(crate) fn scan<R: ColorRuns>(
        self,
        row: &[u8],
        classes: Classes,
        seen: &mut SeenSet,
        strays: &AtomicColorSet,
        runs: R,
    ) -> RowTally {
        #[cfg(target_arch = "x86_64")]
        {
            type Row<R> = unsafe fn(&[u8], Classes, &mut SeenSet, &AtomicColorSet, R) -> RowTally;
            let kernel: Row<R> = match (self.kernel, self.bytes, self.single_background) {
                (Kernel::Avx512, 3, true) => avx512::scan_row::<3, true, R>,
                (Kernel::Avx512, 3, false) => avx512::scan_row::<3, false, R>,
                (Kernel::Avx512, _, true) => avx512::scan_row::<4, true, R>,
                (Kernel::Avx512, _, false) => avx512::scan_row::<4, false, R>,
                (_, 3, true) => avx2::scan_row::<3, true, R>,
                (_, 3, false) => avx2::scan_row::<3, false, R>,
                (_, _, true) => avx2::scan_row::<4, true, R>,
                (_, _, false) => avx2::scan_row::<4, false, R>,
            };
            // SAFETY: `new` built this only for a kernel whose every CPU feature
            // `Kernel::supported` detected; the kernel reads only inside `row`.
            unsafe { kernel(row, classes, seen, strays, runs) }
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            let _ = (row, classes, seen, strays, runs);
            unreachable!("no vector kernel is built on this architecture")
        }
    }

    /// This kernel's form that also tallies each row by part in `slots`,
    /// where it has one (AVX-512) and the table's grid holds every palette
    /// colour (`slots.len() ≥ texels`).
    pub(crate) fn fused<'t>(self, slots: BlockSlots<'t>, texels: u32) -> Option<FusedScan<'t>> {
        (self.kernel == Kernel::Avx512 && slots.len >= texels).then_some(FusedScan { scan: self, slots })
    }
}

/// Where the fused kernel reports a row's part spans, in pixel order
/// (`count::part_lookup::RowSpans`).
pub(crate) trait SlotSpans {
    /// Pixel `at` has slot `slot`, unlike the pixel before it (or it is the
    /// row's first pixel).
    fn change(&mut self, at: usize, slot: usize);
    /// The row ends at pixel `end`.
    fn finish(self, end: usize);
}

/// The AVX-512 kernel's form that also tallies each row by part (see
/// [`avx512`]), over a slot table whose grid holds every palette colour.
#[derive(Clone, Copy)]
pub(crate) struct FusedScan<'t> {
    scan: VectorScan,
    slots: BlockSlots<'t>,
}

impl FusedScan<'_> {
    /// [`VectorScan::scan`] of all of `row`, which also reports the row's
    /// part spans (each pixel's slot in the table) to `spans` (and its runs
    /// of equal colour to `runs`).
    ///
    /// # Panics
    /// When `classes.texels` exceeds the table's grid.
    #[inline]
    pub(crate) fn scan<S: SlotSpans, R: ColorRuns>(
        &self,
        row: &[u8],
        classes: Classes,
        seen: &mut SeenSet,
        strays: &AtomicColorSet,
        (spans, runs): (S, R),
    ) -> RowTally {
        assert!(classes.texels <= self.slots.len, "palette colours outside the slot table's grid");
        #[cfg(target_arch = "x86_64")]
        {
            type Fused<S, R> =
                unsafe fn(&[u8], Classes, &mut SeenSet, &AtomicColorSet, &BlockSlots, (S, R)) -> RowTally;
            let fused: Fused<S, R> = match (self.scan.bytes, self.scan.single_background) {
                (3, true) => avx512::scan_row_by_part::<3, true, S, R>,
                (3, false) => avx512::scan_row_by_part::<3, false, S, R>,
                (_, true) => avx512::scan_row_by_part::<4, true, S, R>,
                (_, false) => avx512::scan_row_by_part::<4, false, S, R>,
            };
            // SAFETY: `VectorScan::fused` built this only for the AVX-512
            // kernel, whose every feature `Kernel::supported` detected; the
            // texels it looks up are below the grid's `len` (asserted above),
            // inside the table `SlotBlocks::new` checked.
            unsafe { fused(row, classes, seen, strays, &self.slots, (spans, runs)) }
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            let _ = (row, seen, strays, spans, runs);
            unreachable!("no vector kernel is built on this architecture")
        }
    }
}

/// The two levels of a slot table (`count::slot_table::SlotTable`), checked
/// once so that a vector kernel may gather from them unchecked: `blocks`
/// holds one entry per 8 × 8 block of colours, its slot or, with
/// [`BlockSlots::DETAILED`], the index of its 64 slots in `detail`, which
/// ends in one padding slot.
pub(crate) struct SlotBlocks {
    blocks: Vec<u32>,
    detail: Vec<u16>,
}

impl SlotBlocks {
    /// The table's `blocks` and `detail`.
    ///
    /// # Panics
    /// When a detailed entry's 64 slots and the padding slot after them are
    /// not all inside `detail`, or the tables are too long for the 32-bit
    /// offsets of a gather.
    pub(crate) fn new(blocks: Vec<u32>, detail: Vec<u16>) -> SlotBlocks {
        let limit = i32::MAX as usize / 4;
        assert!(blocks.len() <= limit && detail.len() <= limit, "slot table too large");
        let detailed = blocks.iter().filter(|&&entry| entry & BlockSlots::DETAILED != 0);
        let last = detailed.map(|&entry| (entry & !BlockSlots::DETAILED) as usize).max();
        assert!(last.is_none_or(|last| (last + 1) * 64 < detail.len()), "a detailed block outside `detail`");
        SlotBlocks { blocks, detail }
    }

    /// One entry per block.
    #[inline(always)]
    pub(crate) fn blocks(&self) -> &[u32] {
        &self.blocks
    }

    /// The slots of detailed blocks, 64 each, and a padding slot.
    #[inline(always)]
    pub(crate) fn detail(&self) -> &[u16] {
        &self.detail
    }
}

/// A [`SlotBlocks`] over a grid whose width is a power of two, laid bare for
/// the fused kernel, which computes for colour `c < len` (`y = c >>
/// width_shift`, `x = c - (y << width_shift)`) the slot the table gives: the
/// entry `blocks[(y >> 3) · blocks_per_row + (x >> 3)]` is the slot unless
/// [`BlockSlots::DETAILED`] is set, and then the slot is
/// `detail[((entry & !DETAILED) << 6) | (y & 7) << 3 | (x & 7)]`.
#[derive(Clone, Copy)]
pub(crate) struct BlockSlots<'t> {
    blocks: &'t [u32],
    detail: &'t [u16],
    width_shift: u32,
    blocks_per_row: u32,
    len: u32,
    outside: u16,
}

impl<'t> BlockSlots<'t> {
    /// Set in an entry of `blocks` whose slots are in `detail`.
    pub(crate) const DETAILED: u32 = 1 << 31;

    /// The table of `len` colours, `1 << width_shift` per row of the grid
    /// (`blocks_per_row` blocks) and `outside` the slot of every other
    /// colour; `None` unless `slots` has an entry for every block of it.
    pub(crate) fn new(
        slots: &'t SlotBlocks,
        width_shift: u32,
        blocks_per_row: u32,
        len: u32,
        outside: u16,
    ) -> Option<BlockSlots<'t>> {
        let width = 1u64.checked_shl(width_shift)?;
        let rows = u64::from(len).div_ceil(width);
        let fits = u64::from(blocks_per_row) * 8 >= width
            && rows.div_ceil(8) * u64::from(blocks_per_row) <= slots.blocks.len() as u64;
        let (blocks, detail) = (slots.blocks(), slots.detail());
        fits.then_some(BlockSlots { blocks, detail, width_shift, blocks_per_row, len, outside })
    }

    /// Colours in the grid.
    pub(crate) fn len(&self) -> u32 {
        self.len
    }

    /// The slot of `color` (below [`BlockSlots::len`]) by the fused
    /// kernel's arithmetic, one colour at a time (for tests).
    #[cfg(test)]
    pub(crate) fn slot(&self, color: u32) -> u16 {
        let y = color >> self.width_shift;
        let x = color - (y << self.width_shift);
        let entry = self.blocks[((y >> 3) * self.blocks_per_row + (x >> 3)) as usize];
        if entry & BlockSlots::DETAILED == 0 {
            entry as u16
        } else {
            self.detail[((entry << 6) | (y & 7) << 3 | (x & 7)) as usize]
        }
    }
}

/// A byte shuffle for the vector kernels that turns pixels of `BYTES`
/// samples into `N / 4` lanes of `0x00RRGGBB` (lane byte 0 = B, 1 = G,
/// 2 = R): lane i takes pixel `i % group` of its group of `group` lanes (a
/// 128-bit half for AVX2's in-lane shuffle, the whole register for
/// AVX-512's). Byte 3 is 0x80, which zeroes it (AVX2) or is masked off
/// (AVX-512).
#[cfg(target_arch = "x86_64")]
const fn unpack_table<const BYTES: usize, const N: usize>(group: usize) -> [u8; N] {
    let mut table = [0x80u8; N];
    let mut lane = 0;
    while lane < N / 4 {
        let pixel = lane % group;
        table[lane * 4] = (pixel * BYTES + 2) as u8;
        table[lane * 4 + 1] = (pixel * BYTES + 1) as u8;
        table[lane * 4 + 2] = (pixel * BYTES) as u8;
        lane += 1;
    }
    table
}

/// Sets texel bits in a [`SeenSet`] at once and accumulates the marks of
/// the words it wrote, one 64-bit word of [`SeenSet::dirty`] marks at a
/// time; the vector kernels' choice.
///
/// They hand over only texels whose colour differs from their left
/// neighbour's, and with texels smaller than a pixel (scenario A: 98 % of
/// its texel pixels) about every second one needs another word, a branch
/// the portable kernel's `WordAccumulator` mispredicts. Setting the bit in
/// memory costs no branch (two texels in one word, about half the time,
/// chain through store forwarding, which the loop hides), and a 64-bit word
/// of marks covers 64 words, 4,096 keys, so its branch is nearly always
/// taken the same way. Measured on scenario A's decoded rows, one thread,
/// three alternated runs of `cargo bench --bench throughput -- --archive A
/// --kernels`: the AVX-512 kernel went from 0.87–0.89 to 0.82–0.85 ns per
/// pixel, the AVX2 one from 0.97–0.98 to 0.89–0.92; the generated
/// archive's are unchanged.
#[cfg(target_arch = "x86_64")]
struct MarkAccumulator {
    dirty_index: usize,
    marks: u64,
}

#[cfg(target_arch = "x86_64")]
impl MarkAccumulator {
    fn new() -> MarkAccumulator {
        MarkAccumulator { dirty_index: 0, marks: 0 }
    }

    /// Sets `key`'s bit and collects its word's mark.
    #[inline(always)]
    fn add(&mut self, seen: &mut SeenSet, key: u32) {
        let index = (key >> 6) as usize;
        seen.or_word_unmarked(index, 1u64 << (key & 63));
        if index >> 6 != self.dirty_index {
            self.flush(seen);
            self.dirty_index = index >> 6;
        }
        self.marks |= 1u64 << (index & 63);
    }

    /// Marks the words written since the last flush (before the set is
    /// read: at the end of every row).
    #[inline(always)]
    fn flush(&mut self, seen: &mut SeenSet) {
        if self.marks != 0 {
            seen.mark(self.dirty_index, self.marks);
            self.marks = 0;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    #[should_panic(expected = "a detailed block outside `detail`")]
    fn a_detailed_entry_past_the_detail_table_is_refused() {
        // One detailed block needs 64 slots and the padding slot: 64 are short.
        SlotBlocks::new(vec![BlockSlots::DETAILED], vec![0; 64]);
    }

    #[test]
    fn a_grid_with_more_blocks_than_entries_gets_no_vector_view() {
        let slots = SlotBlocks::new(vec![BlockSlots::DETAILED, 3], vec![0; 65]);
        // 16 colours wide (two blocks per row): 8 rows fit, 9 need a second row of blocks.
        assert!(BlockSlots::new(&slots, 4, 2, 16 * 8, 0).is_some());
        assert!(BlockSlots::new(&slots, 4, 2, 16 * 9, 0).is_none());
        // One block per row cannot cover 16 colours.
        assert!(BlockSlots::new(&slots, 4, 1, 16, 0).is_none());
        let view = BlockSlots::new(&slots, 4, 2, 16 * 8, 7).unwrap();
        assert_eq!((view.slot(8), view.len()), (3, 128));
    }

    #[test]
    fn no_vector_kernel_beyond_what_this_cpu_runs() {
        for kernel in [Kernel::Avx2, Kernel::Avx512] {
            let built = VectorScan::new(kernel, 3, true).is_some();
            assert_eq!(built, kernel <= Kernel::supported() && cfg!(target_arch = "x86_64"), "{kernel:?}");
        }
        assert!(VectorScan::new(Kernel::Portable, 3, true).is_none());
        assert!(VectorScan::new(Kernel::supported(), 2, true).is_none());
    }
}
