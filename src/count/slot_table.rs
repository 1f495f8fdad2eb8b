//! Colour → part slot in two levels, small enough to stay in cache.
//!
//! The per-part pass looks up one slot per run of equal pixels. A flat table
//! of one `u16` per colour is 32 MiB for a 4096² palette, and `perf` put 72 %
//! of the pass's time on the one instruction after that load: neighbouring
//! pixels show texels in neighbouring texture rows, 8 KiB apart, so nearly
//! every run missed the caches. Parts are unwrapped as charts, so most
//! 8 × 8-texel blocks of the palette name one part: those are one entry of
//! a 1 MiB table, and only blocks on a chart's edge keep their 64 slots
//! (`detail`), side by side. Square blocks, not runs of 64 texels of one
//! texture row: every edge of the unwrap is a seam, so a chart is a
//! triangle a few hundred texels across, and most of a row's runs of 64
//! would cross its edge.

use rayon::prelude::*;

use crate::simd::{BlockSlots, SlotBlocks};

/// Side of a block, texels (a block is `SIDE × SIDE` texels).
const SIDE: u32 = 8;
/// Texels per block.
const BLOCK_TEXELS: usize = (SIDE * SIDE) as usize;
/// Set in a block's entry when its slots are in `detail`.
const DETAILED: u32 = BlockSlots::DETAILED;
/// Rows of blocks built per unit of parallel work.
const BLOCK_ROWS_PER_UNIT: u32 = 4;

/// Slot per colour of a `width × height` grid of colours, colour
/// `y · width + x` at `(x, y)` (a canonical palette's texels, or all 2²⁴
/// colours as 4096 × 4096); every other colour gets `outside`.
pub(crate) struct SlotTable {
    width: u32,
    /// `log2(width)` when the width is a power of two (every canonical
    /// palette the capture writes): a shift instead of a division per look-up.
    width_shift: Option<u32>,
    len: u32,
    blocks_per_row: u32,
    /// Per block (row-major): its one slot, or `DETAILED | index` of its
    /// slots in `detail`; and the slots of the blocks that hold more than
    /// one, `BLOCK_TEXELS` each, row-major, and one padding slot after the
    /// last: the vector kernel gathers a slot as the low half of 4 bytes
    /// ([`BlockSlots`]), so these are checked where they are built.
    slots: SlotBlocks,
    /// Slot of colours past the grid.
    outside: u16,
}

impl SlotTable {
    /// The table of `slot_of(colour)` over a `width × height` grid, built in parallel.
    pub(crate) fn new(
        [width, height]: [u32; 2],
        outside: u16,
        slot_of: impl Fn(u32) -> u16 + Sync,
    ) -> SlotTable {
        let (blocks_per_row, block_rows) = (width.div_ceil(SIDE), height.div_ceil(SIDE));
        let block_slots = |bx: u32, by: u32| -> [u16; BLOCK_TEXELS] {
            std::array::from_fn(|k| {
                let (x, y) = (bx * SIDE + k as u32 % SIDE, by * SIDE + k as u32 / SIDE);
                if x < width && y < height { slot_of(y * width + x) } else { outside }
            })
        };
        let units: Vec<(Vec<u32>, Vec<u16>)> = (0..block_rows.div_ceil(BLOCK_ROWS_PER_UNIT))
            .into_par_iter()
            .map(|unit| {
                let rows = unit * BLOCK_ROWS_PER_UNIT..((unit + 1) * BLOCK_ROWS_PER_UNIT).min(block_rows);
                let (mut entries, mut detail) = (Vec::new(), Vec::new());
                for by in rows {
                    for bx in 0..blocks_per_row {
                        let slots = block_slots(bx, by);
                        if slots.iter().all(|&s| s == slots[0]) {
                            entries.push(u32::from(slots[0]));
                        } else {
                            entries.push(DETAILED | (detail.len() / BLOCK_TEXELS) as u32);
                            detail.extend_from_slice(&slots);
                        }
                    }
                }
                (entries, detail)
            })
            .collect();
        let len = width * height;
        let width_shift = width.is_power_of_two().then(|| width.trailing_zeros());
        let (mut blocks, mut all_detail) = (Vec::new(), Vec::new());
        for (entries, detail) in units {
            let offset = (all_detail.len() / BLOCK_TEXELS) as u32;
            blocks.extend(entries.into_iter().map(|e| if e & DETAILED != 0 { e + offset } else { e }));
            all_detail.extend(detail);
        }
        all_detail.push(outside);
        let slots = SlotBlocks::new(blocks, all_detail);
        SlotTable { width, width_shift, len, blocks_per_row, slots, outside }
    }

    /// The table as a vector kernel reads it, where the grid's width is a
    /// power of two (every canonical palette the capture writes).
    pub(crate) fn block_slots(&self) -> Option<BlockSlots<'_>> {
        BlockSlots::new(&self.slots, self.width_shift?, self.blocks_per_row, self.len, self.outside)
    }

    /// Adds one to `tally[slot]` for each colour `first + j` whose bit `j` of
    /// `members` is set. Where the 32 colours lie in one texture row (a
    /// width that is a multiple of 32, `first` a multiple of 32), a block of
    /// one slot adds its members with one population count.
    pub(crate) fn add_32(&self, first: u32, members: u32, tally: &mut [u64]) {
        let aligned = first.is_multiple_of(32) && self.width.is_multiple_of(32) && first + 32 <= self.len;
        if !aligned {
            let mut bits = members;
            while bits != 0 {
                tally[usize::from(self.get(first + bits.trailing_zeros()))] += 1;
                bits &= bits - 1;
            }
            return;
        }
        let y = first / self.width;
        let x = first - y * self.width;
        let base = ((y / SIDE) * self.blocks_per_row + x / SIDE) as usize;
        for block in 0..4u32 {
            let mut bits = (members >> (SIDE * block)) & 0xFF;
            if bits == 0 {
                continue;
            }
            let entry = self.slots.blocks()[base + block as usize];
            if entry & DETAILED == 0 {
                tally[entry as usize] += u64::from(bits.count_ones());
                continue;
            }
            let row = (entry & !DETAILED) as usize * BLOCK_TEXELS + ((y % SIDE) * SIDE) as usize;
            while bits != 0 {
                tally[usize::from(self.slots.detail()[row + bits.trailing_zeros() as usize])] += 1;
                bits &= bits - 1;
            }
        }
    }

    /// The slot of `color`.
    #[inline(always)]
    pub(crate) fn get(&self, color: u32) -> u16 {
        if color >= self.len {
            return self.outside;
        }
        let y = match self.width_shift {
            Some(shift) => color >> shift,
            None => color / self.width,
        };
        let x = color - y * self.width;
        let entry = self.slots.blocks()[((y / SIDE) * self.blocks_per_row + x / SIDE) as usize];
        if entry & DETAILED == 0 {
            entry as u16
        } else {
            let first = (entry & !DETAILED) as usize * BLOCK_TEXELS;
            self.slots.detail()[first + ((y % SIDE) * SIDE + x % SIDE) as usize]
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_color_gets_the_slot_a_flat_table_gives() {
        // Grids whose sides end inside a block, charts of one slot with
        // ragged edges, a few lone colours, and colours far past the grid.
        for [width, height] in [[100u32, 37], [64, 64], [4096, 3]] {
            let len = width * height;
            let flat: Vec<u16> = (0..len)
                .map(|c| {
                    let (x, y) = (c % width, c / width);
                    if c % 977 == 5 { 9 } else { ((x / 30 + y / 20 + (x * y) % 3 / 2) % 4) as u16 }
                })
                .collect();
            let table = SlotTable::new([width, height], 7, |c| flat[c as usize]);
            for color in 0..len + 200 {
                let expected = flat.get(color as usize).copied().unwrap_or(7);
                assert_eq!(table.get(color), expected, "colour {color} of {width}×{height}");
            }
            assert_eq!(table.get(u32::MAX), 7);
            assert_eq!(table.get(0xFF_FFFF), 7);
        }
    }

    #[test]
    fn runs_of_32_colors_add_what_color_by_color_look_ups_add() {
        let mut state = 0x2545_F491_4F6C_DD1D_u64;
        let mut random = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        for [width, height] in [[64u32, 40], [4096, 9], [100, 37], [96, 17]] {
            let slot_of = |c: u32| {
                let (x, y) = (c % width, c / width);
                if c % 211 == 3 { 5 } else { ((x / 11 + y / 6) % 4) as u16 }
            };
            let table = SlotTable::new([width, height], 7, slot_of);
            // Runs starting anywhere (aligned or not), some past the grid.
            for first in (0..width * height + 64).step_by(13).chain((0..width * height).step_by(32)) {
                let members = random() as u32;
                let mut expected = [0u64; 8];
                for j in 0..32 {
                    if members >> j & 1 == 1 {
                        expected[usize::from(table.get(first + j))] += 1;
                    }
                }
                let mut found = [0u64; 8];
                table.add_32(first, members, &mut found);
                assert_eq!(found, expected, "{width}×{height}, first {first}");
            }
        }
    }

    #[test]
    fn block_slots_arithmetic_gives_the_slot_get_gives() {
        // The vector kernel's recipe, lane by lane, on power-of-two widths
        // below, at and above a block's side; the last slot of `detail` is
        // read as the low half of 4 bytes, so a padding slot follows it.
        for [width, height] in [[4u32, 4], [8, 3], [64, 40], [512, 9]] {
            let table =
                SlotTable::new([width, height], 9, |c| ((c % width) / 5 + (c / width) / 3) as u16 % 6);
            let slots = table.block_slots().expect("a power-of-two width");
            assert_eq!(table.slots.detail().len() % BLOCK_TEXELS, 1, "{width}×{height}");
            for color in 0..slots.len() {
                assert_eq!(slots.slot(color), table.get(color), "colour {color} of {width}×{height}");
            }
        }
        assert!(SlotTable::new([100, 37], 9, |_| 0).block_slots().is_none());
    }

    #[test]
    fn uniform_blocks_keep_no_detail() {
        // Two parts split at x = 32 (a block edge) and one lone texel.
        let table =
            SlotTable::new([64, 64], 5, |c| if c == 64 * 9 + 40 { 3 } else { u16::from(c % 64 >= 32) });
        assert_eq!(table.slots.blocks().len(), 64);
        assert_eq!(table.slots.detail().len(), BLOCK_TEXELS + 1, "one detailed block and the padding");
        assert_eq!((table.get(0), table.get(63), table.get(64 * 9 + 40)), (0, 1, 3));
    }

    #[test]
    fn an_empty_table_gives_the_outside_slot() {
        let table = SlotTable::new([0, 0], 3, |_| unreachable!());
        assert_eq!(table.get(0), 3);
    }
}
