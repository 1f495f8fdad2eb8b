//! Dense bit sets over the 2^24 colours.
//!
//! Counting "once per image" needs a set membership test for every distinct
//! pixel colour. A hash set costs ~10 ns per lookup; a 2 MiB bit set costs one
//! load, and clearing it through the list of touched colours keeps the per
//! image reset proportional to what the image showed, not to 2^24.

use std::sync::atomic::{AtomicU64, Ordering};

use crate::color::COLOR_COUNT;

const WORDS: usize = COLOR_COUNT / 64;

/// The position of a colour in the dense per-colour tables ([`SeenSet`]
/// and `Counts`): a bijection of the 24 bits that stores each block of 32×16
/// canonical-palette texels (colour = `y * 4096 + x`) in one 64-byte run of
/// bits. Neighbouring pixels show neighbouring texels in *both* directions,
/// so this keeps a tile's working set in cache: measured 2–4× faster count
/// updates than the row-major order, where one texel step down jumps 512 B.
#[inline(always)]
pub const fn color_key(color: u32) -> u32 {
    // With x = color & 4095 and y = color >> 12 this is
    // ((y >> 4) << 16) | ((x >> 5) << 9) | ((y & 15) << 5) | (x & 31),
    // written as three masked shifts (the vector scanner does the same).
    (color & 0xFF_001F) | ((color << 4) & 0xFE00) | ((color >> 7) & 0x1E0)
}

/// The colour at a table position: the inverse of [`color_key`].
#[inline(always)]
pub(crate) const fn key_color(key: u32) -> u32 {
    let x = (((key >> 9) & 127) << 5) | (key & 31);
    let y = (((key >> 16) & 255) << 4) | ((key >> 5) & 15);
    (y << 12) | x
}

/// A zeroed slice whose pages are already mapped, writable.
///
/// A fresh allocation is the kernel's shared zero page until written. The
/// counting loops read before they write, so their first read maps that page
/// read-only, and the write after it must replace the mapping on every CPU
/// that runs the process: a TLB shootdown, i.e. an inter-processor interrupt
/// (a VM exit under virtualisation). On two threads those made adding an
/// image's counts 3.7× slower (measured 2.5 vs 0.68 ms per tile). Writing one
/// zero per page up front maps each page writable once, with no shootdown.
pub(crate) fn zeroed_writable<T: Copy + Default>(len: usize) -> Box<[T]> {
    let mut slice = vec![T::default(); len].into_boxed_slice();
    let per_page = (4096 / std::mem::size_of::<T>().max(1)).max(1);
    for page in slice.chunks_mut(per_page) {
        // An opaque value, so that the compiler cannot drop the store of
        // the value already there.
        page[0] = std::hint::black_box(T::default());
    }
    slice
}

/// Words of [`SeenSet::dirty`]: one bit per word of the set.
const DIRTY_WORDS: usize = WORDS / 64;

/// A per-thread set of colour keys (the texels one image or eye-frame showed),
/// with a second, 32 KiB bit set marking which of its 64-bit words may hold
/// members.
///
/// The marks make clearing and draining proportional to what the image
/// showed rather than to the 2 MiB set, without a list of inserted members
/// (which an earlier version appended to for every new colour): the scanner
/// marks a word once, when it writes the word back. Aligned to 128 bytes so
/// that the sets of different workers, kept side by side, never share a
/// cache line.
#[repr(align(128))]
pub struct SeenSet {
    pub(crate) words: Box<[u64]>,
    /// Bit `i` set when `words[i]` may be non-zero (never clear while it is).
    pub(crate) dirty: Box<[u64]>,
}

impl Default for SeenSet {
    fn default() -> Self {
        SeenSet::new()
    }
}

impl SeenSet {
    /// An empty set over all 2^24 keys (2 MiB).
    pub fn new() -> SeenSet {
        SeenSet { words: zeroed_writable(WORDS), dirty: zeroed_writable(DIRTY_WORDS) }
    }

    /// Sets `bits` in word `index` and marks the word.
    #[inline(always)]
    pub(crate) fn or_word(&mut self, index: usize, bits: u64) {
        let index = index & (WORDS - 1);
        self.words[index] |= bits;
        self.dirty[index >> 6] |= 1u64 << (index & 63);
    }

    /// Sets `bits` in word `index` and leaves the word unmarked: the caller
    /// marks it with [`SeenSet::mark`] before the set is read, drained or
    /// cleared (a vector kernel collects a row's marks in a register,
    /// `simd::scan`'s `MarkAccumulator`).
    #[inline(always)]
    pub(crate) fn or_word_unmarked(&mut self, index: usize, bits: u64) {
        self.words[index & (WORDS - 1)] |= bits;
    }

    /// Marks words `dirty_index * 64 + i` for each bit `i` of `marks` as
    /// possibly non-zero.
    #[inline(always)]
    pub(crate) fn mark(&mut self, dirty_index: usize, marks: u64) {
        self.dirty[dirty_index & (DIRTY_WORDS - 1)] |= marks;
    }

    /// Inserts `key` (< 2^24); returns true when it was not yet present.
    pub fn insert(&mut self, key: u32) -> bool {
        let fresh = !self.contains(key);
        self.or_word((key >> 6) as usize, 1u64 << (key & 63));
        fresh
    }

    /// True when `key` is in the set.
    pub fn contains(&self, key: u32) -> bool {
        self.words[(key >> 6) as usize & (WORDS - 1)] & (1u64 << (key & 63)) != 0
    }

    /// Calls `visit(index, word)` for every non-zero word, in ascending order
    /// of `index`.
    pub(crate) fn for_each_word(&self, mut visit: impl FnMut(usize, u64)) {
        for dirty_index in 0..DIRTY_WORDS {
            let mut marks = self.dirty[dirty_index];
            while marks != 0 {
                let index = dirty_index * 64 + marks.trailing_zeros() as usize;
                marks &= marks - 1;
                let word = self.words[index];
                if word != 0 {
                    visit(index, word);
                }
            }
        }
    }

    /// Number of keys in the set.
    pub fn len(&self) -> usize {
        let mut members = 0;
        self.for_each_word(|_, word| members += word.count_ones() as usize);
        members
    }

    /// True when the set has no members.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The members in ascending order.
    pub fn keys(&self) -> Vec<u32> {
        let mut keys = Vec::new();
        self.for_each_word(|index, mut word| {
            while word != 0 {
                keys.push(((index as u32) << 6) | word.trailing_zeros());
                word &= word - 1;
            }
        });
        keys
    }

    /// Adds every member of this set to `other`.
    pub fn merge_into(&self, other: &mut SeenSet) {
        self.for_each_word(|index, word| other.or_word(index, word));
    }

    /// Keys per block of [`SeenSet::drain_blocks`] (2^12).
    pub const BLOCK_KEYS: usize = 64 * 64;

    /// True when keys `block * BLOCK_KEYS ..` to `(block + blocks) * BLOCK_KEYS`
    /// may hold members.
    pub fn blocks_marked(&self, block: usize, blocks: usize) -> bool {
        self.dirty[block..block + blocks].iter().any(|&marks| marks != 0)
    }

    /// Calls `add(counts, word)` for every non-zero 64-bit word of shard
    /// `shard` (keys `shard · SIZE ..`, `SIZE` a power of two and a multiple
    /// of [`SeenSet::BLOCK_KEYS`]) with the 64 of `counts` (the shard's
    /// `SIZE` counts) its bits stand for, and removes those keys from the
    /// set. Always inlined, so each caller's `add` is too.
    #[inline(always)]
    pub(crate) fn drain_shard<const SIZE: usize>(
        &mut self,
        shard: usize,
        counts: &mut [u32],
        mut add: impl FnMut(&mut [u32], u64),
    ) {
        let blocks = SIZE / SeenSet::BLOCK_KEYS;
        self.drain_blocks(shard * blocks, blocks, |index, word| {
            let offset = (index * 64) & (SIZE - 1);
            add(&mut counts[offset..offset + 64], word);
        });
    }

    /// Calls `visit(index, word)` with every non-zero 64-bit word (keys
    /// `index * 64 + bit`) of keys `block * BLOCK_KEYS ..` to
    /// `(block + blocks) * BLOCK_KEYS`, in ascending order, and removes those
    /// keys from the set.
    ///
    /// Always inlined, so that a caller compiled with extra CPU features (the
    /// vector count updates) can inline `visit` too.
    #[inline(always)]
    pub fn drain_blocks(&mut self, block: usize, blocks: usize, mut visit: impl FnMut(usize, u64)) {
        for dirty_index in block..block + blocks {
            let mut marks = std::mem::take(&mut self.dirty[dirty_index]);
            while marks != 0 {
                let index = dirty_index * 64 + marks.trailing_zeros() as usize;
                marks &= marks - 1;
                let word = std::mem::take(&mut self.words[index]);
                if word != 0 {
                    visit(index, word);
                }
            }
        }
    }

    /// Empties the set in time proportional to the words it touched.
    pub fn clear(&mut self) {
        self.drain_blocks(0, DIRTY_WORDS, |_, _| {});
    }
}

/// A read-only set of colours, e.g. the colours of a non-canonical palette.
#[derive(Clone)]
pub struct ColorSet {
    words: Box<[u64]>,
}

impl Default for ColorSet {
    fn default() -> Self {
        ColorSet::new()
    }
}

impl ColorSet {
    /// The empty set.
    pub fn new() -> ColorSet {
        ColorSet { words: vec![0u64; WORDS].into_boxed_slice() }
    }

    /// Inserts `color`; returns true when it was not yet present.
    pub fn insert(&mut self, color: u32) -> bool {
        let index = (color >> 6) as usize & (WORDS - 1);
        let bit = 1u64 << (color & 63);
        let fresh = self.words[index] & bit == 0;
        self.words[index] |= bit;
        fresh
    }

    /// True when `color` is in the set.
    #[inline(always)]
    pub fn contains(&self, color: u32) -> bool {
        self.words[(color >> 6) as usize & (WORDS - 1)] & (1u64 << (color & 63)) != 0
    }
}

/// A set of colours shared by all threads (used for the rare stray colours).
pub struct AtomicColorSet {
    words: Box<[AtomicU64]>,
}

impl Default for AtomicColorSet {
    fn default() -> Self {
        AtomicColorSet::new()
    }
}

impl AtomicColorSet {
    /// The empty set.
    pub fn new() -> AtomicColorSet {
        AtomicColorSet { words: (0..WORDS).map(|_| AtomicU64::new(0)).collect() }
    }

    /// Inserts `color`.
    pub fn insert(&self, color: u32) {
        self.words[(color >> 6) as usize & (WORDS - 1)].fetch_or(1u64 << (color & 63), Ordering::Relaxed);
    }

    /// Number of colours in the set.
    pub fn len(&self) -> u64 {
        self.words.iter().map(|word| u64::from(word.load(Ordering::Relaxed).count_ones())).sum()
    }

    /// True when the set is empty.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Up to `limit` members in ascending order (for examples in reports).
    pub fn first(&self, limit: usize) -> Vec<u32> {
        let mut found = Vec::new();
        for (index, word) in self.words.iter().enumerate() {
            let mut bits = word.load(Ordering::Relaxed);
            while bits != 0 && found.len() < limit {
                found.push((index as u32) << 6 | bits.trailing_zeros());
                bits &= bits - 1;
            }
            if found.len() >= limit {
                break;
            }
        }
        found
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn color_key_is_a_bijection() {
        let mut seen = ColorSet::new();
        for color in 0..COLOR_COUNT as u32 {
            let key = color_key(color);
            assert!(key < COLOR_COUNT as u32);
            assert_eq!(key_color(key), color);
            assert!(seen.insert(key));
        }
        // 32×16 texel blocks share one cache line of bits.
        assert_eq!(color_key(4096 * 15 + 31) >> 9, color_key(0) >> 9);
    }

    #[test]
    fn seen_set_inserts_once_merges_and_clears() {
        let mut set = SeenSet::new();
        assert!(set.insert(5));
        assert!(!set.insert(5));
        assert!(set.insert(0xFF_FFFF));
        assert_eq!(set.keys(), vec![5, 0xFF_FFFF]);
        assert_eq!(set.len(), 2);
        let mut other = SeenSet::new();
        other.insert(7);
        set.merge_into(&mut other);
        assert_eq!(other.keys(), vec![5, 7, 0xFF_FFFF]);
        set.clear();
        assert!(set.is_empty());
        assert!(set.words.iter().chain(set.dirty.iter()).all(|&w| w == 0));
        assert!(set.insert(5));
    }

    #[test]
    fn drains_blocks_in_ascending_order() {
        let mut set = SeenSet::new();
        let keys: Vec<u32> = (0..50_000u32).map(|k| k.wrapping_mul(2_654_435_761) >> 8).collect();
        for &key in &keys {
            set.insert(key);
        }
        let mut expected = keys.clone();
        expected.sort_unstable();
        expected.dedup();
        let (upper, blocks) = (DIRTY_WORDS / 2, DIRTY_WORDS / 2);
        assert!(set.blocks_marked(upper, blocks));
        let mut drained = Vec::new();
        for block in [upper, 0] {
            set.drain_blocks(block, blocks, |index, mut word| {
                while word != 0 {
                    drained.push(((index as u32) << 6) | word.trailing_zeros());
                    word &= word - 1;
                }
            });
            assert!(!set.blocks_marked(block, blocks));
        }
        // The upper half first, then the lower half.
        let split = expected.partition_point(|&k| (k as usize) < upper * SeenSet::BLOCK_KEYS);
        let wanted: Vec<u32> = expected[split..].iter().chain(&expected[..split]).copied().collect();
        assert_eq!(drained, wanted);
        assert!(set.is_empty());
        assert!(set.words.iter().chain(set.dirty.iter()).all(|&w| w == 0));
    }

    #[test]
    fn atomic_set_counts_and_lists() {
        let set = AtomicColorSet::new();
        set.insert(70);
        set.insert(3);
        set.insert(70);
        assert_eq!(set.len(), 2);
        assert_eq!(set.first(10), vec![3, 70]);
    }
}
