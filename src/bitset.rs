//! Dense bit sets over the 2^24 colours.
//!
//! Counting "once per image" needs a set membership test for every distinct
//! pixel colour. A hash set costs ~10 ns per lookup; a 2 MiB bit set costs one
//! load, and clearing it through the list of touched colours keeps the per
//! image reset proportional to what the image showed, not to 2^24.

use std::sync::atomic::{AtomicU64, Ordering};

use crate::color::COLOR_COUNT;

const WORDS: usize = COLOR_COUNT / 64;

/// The position of a colour in the dense per-colour tables ([`TouchedSet`]
/// and `Counts`): a bijection of the 24 bits that stores each block of 32×16
/// canonical-palette texels (colour = `y * 4096 + x`) in one 64-byte run of
/// bits. Neighbouring pixels show neighbouring texels in *both* directions,
/// so this keeps a tile's working set in cache: measured 2–4× faster count
/// updates than the row-major order, where one texel step down jumps 512 B.
#[inline(always)]
pub const fn color_key(color: u32) -> u32 {
    let x = color & 4095;
    let y = (color >> 12) & 4095;
    ((y >> 4) << 16) | ((x >> 5) << 9) | ((y & 15) << 5) | (x & 31)
}

/// The colour at a table position: the inverse of [`color_key`].
#[inline(always)]
pub const fn key_color(key: u32) -> u32 {
    let x = (((key >> 9) & 127) << 5) | (key & 31);
    let y = (((key >> 16) & 255) << 4) | ((key >> 5) & 15);
    (y << 12) | x
}

/// A per-thread set of colours with the list of colours inserted since the
/// last clear. Aligned to 128 bytes so that the sets of different workers,
/// kept side by side, never share a cache line (the scan updates the list's
/// length every 16 pixels).
#[repr(align(128))]
pub struct TouchedSet {
    pub(crate) words: Box<[u64]>,
    pub(crate) touched: Vec<u32>,
}

impl Default for TouchedSet {
    fn default() -> Self {
        TouchedSet::new()
    }
}

impl TouchedSet {
    /// An empty set over all 2^24 colours (2 MiB, zeroed lazily by the OS).
    pub fn new() -> TouchedSet {
        TouchedSet { words: vec![0u64; WORDS].into_boxed_slice(), touched: Vec::with_capacity(1 << 16) }
    }

    /// Inserts `color` (< 2^24); returns true when it was not yet present.
    #[inline(always)]
    pub fn insert(&mut self, color: u32) -> bool {
        let index = (color >> 6) as usize & (WORDS - 1);
        let bit = 1u64 << (color & 63);
        // `index` is masked into range, so this never panics and the bounds
        // check folds away.
        let word = &mut self.words[index];
        if *word & bit == 0 {
            *word |= bit;
            self.touched.push(color);
            true
        } else {
            false
        }
    }

    /// The colours inserted since the last clear, in insertion order.
    pub fn touched(&self) -> &[u32] {
        &self.touched
    }

    /// Number of colours in the set.
    pub fn len(&self) -> usize {
        self.touched.len()
    }

    /// True when nothing was inserted since the last clear.
    pub fn is_empty(&self) -> bool {
        self.touched.is_empty()
    }

    /// Calls `visit` with every member in ascending order, starting at
    /// `start` and wrapping around, and empties the set.
    ///
    /// Ascending order turns the caller's count updates into a sequential
    /// sweep; distinct starts keep threads that sweep at the same time out of
    /// each other's way. Large sets are read straight from the bit words
    /// (2 MiB, faster than sorting hundreds of thousands of colours); small
    /// ones are sorted.
    pub fn drain_sorted_from(&mut self, start: u32, mut visit: impl FnMut(u32)) {
        let start = start as usize & (COLOR_COUNT - 1);
        if self.touched.len() > WORDS / 16 {
            let first_word = start / 64;
            let (tail, head) = self.words.split_at_mut(first_word);
            for (index, word) in head
                .iter_mut()
                .enumerate()
                .map(|(i, w)| (i + first_word, w))
                .chain(tail.iter_mut().enumerate())
            {
                // Write only words that hold members: untouched pages of a
                // fresh set are the kernel's shared zero page, and writing
                // them would fault them in (with TLB shootdowns) for nothing.
                if *word == 0 {
                    continue;
                }
                let mut bits = std::mem::take(word);
                while bits != 0 {
                    visit(((index as u32) << 6) | bits.trailing_zeros());
                    bits &= bits - 1;
                }
            }
            self.touched.clear();
        } else {
            self.touched.sort_unstable();
            let split = self.touched.partition_point(|&color| (color as usize) < start);
            for &color in self.touched[split..].iter().chain(&self.touched[..split]) {
                visit(color);
            }
            self.clear();
        }
    }

    /// Empties the set in time proportional to its size.
    pub fn clear(&mut self) {
        for &color in &self.touched {
            self.words[(color >> 6) as usize & (WORDS - 1)] = 0;
        }
        self.touched.clear();
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
    fn touched_set_inserts_once_and_clears() {
        let mut set = TouchedSet::new();
        assert!(set.insert(5));
        assert!(!set.insert(5));
        assert!(set.insert(0xFF_FFFF));
        assert_eq!(set.touched(), &[5, 0xFF_FFFF]);
        set.clear();
        assert!(set.is_empty());
        assert!(set.insert(5));
    }

    #[test]
    fn drains_in_ascending_order_small_and_large() {
        for size in [3usize, WORDS / 16 + 10] {
            let mut set = TouchedSet::new();
            let colors: Vec<u32> = (0..size as u32).map(|k| k.wrapping_mul(2_654_435_761) >> 8).collect();
            for &c in &colors {
                set.insert(c);
            }
            let mut expected: Vec<u32> = colors.clone();
            expected.sort_unstable();
            expected.dedup();
            let mut drained = Vec::new();
            set.drain_sorted_from(0, |c| drained.push(c));
            assert_eq!(drained, expected);
            assert!(set.is_empty());
            assert!(set.words.iter().all(|&w| w == 0));
            // From the middle: the upper part first, then the wrapped lower part.
            for &c in &colors {
                set.insert(c);
            }
            let start = 1 << 23;
            let mut rotated = Vec::new();
            set.drain_sorted_from(start, |c| rotated.push(c));
            let split = expected.partition_point(|&c| c < start);
            let wanted: Vec<u32> = expected[split..].iter().chain(&expected[..split]).copied().collect();
            assert_eq!(rotated, wanted);
            assert!(set.words.iter().all(|&w| w == 0));
        }
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
