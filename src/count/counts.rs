//! The count table: how many images show each colour, once per image.
//!
//! Scanning ([`crate::count::scan`]: the classifier, the row kernels and
//! [`crate::scan_image`]) records an image's palette colours in a
//! per-thread [`SeenSet`]; when the image is complete its colours are added
//! to the shared [`Counts`] in ascending order, a 64-bit word of the set at
//! a time. A failed image is forgotten whole, so a truncated file never
//! leaves half its counts behind.

use std::sync::{Mutex, PoisonError, TryLockError};

use rayon::prelude::*;

use crate::color::COLOR_COUNT;
use crate::color::{SeenSet, color_key, zeroed_writable};
use crate::count::scan::Kernel;

/// Colours per shard of [`Counts`] (2^16 counts = 256 KiB).
const SHARD_BITS: u32 = 16;
const SHARD_SIZE: usize = 1 << SHARD_BITS;
const SHARDS: usize = COLOR_COUNT / SHARD_SIZE;

/// For each of the 2^24 colours, the number of images (or eye-frames) that
/// showed it. Shared by all workers. Indexed by [`color_key`], like the
/// [`SeenSet`]s that feed it.
///
/// Images add their colours in ascending order, so the array is split into
/// shards, each behind a lock: a worker takes a shard once and then adds
/// plainly to a few thousand neighbouring counts, a 64-bit word of its set
/// at a time. That was ~2× faster than one atomic add per colour when it
/// was introduced (2.3 vs 5.4 ms per 1284×1620 tile with 244 k distinct
/// texels; word-at-a-time vector adds now take 0.34 ms), and exact.
pub struct Counts {
    shards: Box<[Mutex<Box<[u32]>>]>,
}

impl Default for Counts {
    fn default() -> Self {
        Counts::new()
    }
}

impl Counts {
    /// All counts zero (64 MiB).
    pub fn new() -> Counts {
        Counts {
            shards: (0..SHARDS).into_par_iter().map(|_| Mutex::new(zeroed_writable(SHARD_SIZE))).collect(),
        }
    }

    /// Adds one to every key of `seen` (keys from [`color_key`]) and empties it.
    ///
    /// Shards are visited in ascending order from a start chosen by the
    /// calling rayon thread, and a shard another worker holds is left for
    /// later instead of waited for, so two workers that commit at the same
    /// moment leapfrog each other rather than queue behind one lock. (On two
    /// threads this made no measurable difference: the commit's two-thread
    /// slowdown turned out to be page faults, see [`zeroed_writable`]. It
    /// costs nothing and matters more the more threads there are.)
    pub fn add_set(&self, seen: &mut SeenSet) {
        let threads = rayon::current_num_threads().max(1);
        let slot = rayon::current_thread_index().unwrap_or(0) % threads;
        let first = slot * SHARDS / threads;
        let kernel = Kernel::selected();
        let mut busy = Vec::new();
        for shard in (first..SHARDS).chain(0..first) {
            if !seen.blocks_marked(shard * BLOCKS_PER_SHARD, BLOCKS_PER_SHARD) {
                continue;
            }
            match self.shards[shard].try_lock() {
                Ok(mut counts) => add_blocks(kernel, seen, shard, &mut counts),
                Err(TryLockError::Poisoned(poisoned)) => {
                    add_blocks(kernel, seen, shard, &mut poisoned.into_inner())
                }
                Err(TryLockError::WouldBlock) => busy.push(shard),
            }
        }
        for shard in busy {
            let mut counts = self.shards[shard].lock().unwrap_or_else(PoisonError::into_inner);
            add_blocks(kernel, seen, shard, &mut counts);
        }
    }

    /// The counts as plain integers, indexed by colour (`0xRRGGBB`).
    pub fn into_vec(self) -> Vec<u32> {
        let mut by_key = Vec::with_capacity(COLOR_COUNT);
        for shard in self.shards.into_vec() {
            by_key.extend_from_slice(&shard.into_inner().unwrap_or_else(PoisonError::into_inner));
        }
        (0..COLOR_COUNT as u32).into_par_iter().map(|color| by_key[color_key(color) as usize]).collect()
    }
}

/// [`SeenSet`] blocks per shard of [`Counts`].
const BLOCKS_PER_SHARD: usize = SHARD_SIZE / SeenSet::BLOCK_KEYS;

/// Moves the keys of `seen` that fall in `shard` into its `counts`, with
/// the vector instructions of `kernel` where this CPU has them
/// ([`crate::simd::add_shard`]).
fn add_blocks(kernel: Kernel, seen: &mut SeenSet, shard: usize, counts: &mut [u32]) {
    if !crate::simd::add_shard::<SHARD_SIZE>(kernel, seen, shard, counts) {
        add_blocks_portable(seen, shard, counts);
    }
}

/// [`add_blocks`] one count at a time (the reference of the vector forms).
fn add_blocks_portable(seen: &mut SeenSet, shard: usize, counts: &mut [u32]) {
    seen.drain_shard::<SHARD_SIZE>(shard, counts, |slots, mut word| {
        while word != 0 {
            let slot = &mut slots[word.trailing_zeros() as usize];
            *slot = slot.saturating_add(1);
            word &= word - 1;
        }
    });
}

/// The checks that hold the vector count updates to the portable one.
/// `tests/kernels` runs them (`testing::kernel_checks`), and
/// reports one ignored where this CPU lacks its kernel.
#[cfg(any(test, feature = "synthetic"))]
pub(crate) mod kernel_checks {
    use super::*;

    /// The AVX2 update against the portable one's answer.
    pub(crate) fn the_avx2_update_adds_words_and_saturates() {
        adds_words_and_saturates(Kernel::Avx2);
    }

    /// The AVX-512 update against the portable one's answer.
    pub(crate) fn the_avx512_update_adds_words_and_saturates() {
        adds_words_and_saturates(Kernel::Avx512);
    }

    /// `kernel`'s update adds one per key of its shard, saturating, and
    /// leaves the keys of other shards.
    pub(crate) fn adds_words_and_saturates(kernel: Kernel) {
        let mut counts = vec![0u32; SHARD_SIZE];
        counts[64 + 5] = u32::MAX;
        counts[64 + 6] = u32::MAX - 1;
        let mut seen = SeenSet::new();
        let keys = [0u32, 7, 8, 63, 64 + 5, 64 + 6, 64 + 40, 2 * SHARD_SIZE as u32 + 3];
        for &key in &keys {
            seen.insert(key);
        }
        if kernel == Kernel::Portable {
            add_blocks_portable(&mut seen, 0, &mut counts);
        } else {
            let ran = crate::simd::add_shard::<SHARD_SIZE>(kernel, &mut seen, 0, &mut counts);
            assert!(ran, "this CPU lacks a feature of {kernel:?}");
        }
        let mut expected = vec![0u32; SHARD_SIZE];
        for key in [0, 7, 8, 63, 64 + 40] {
            expected[key] = 1;
        }
        expected[64 + 5] = u32::MAX;
        expected[64 + 6] = u32::MAX;
        assert_eq!(counts, expected, "{kernel:?}");
        // Keys of other shards stay in the set.
        assert_eq!(seen.keys(), vec![2 * SHARD_SIZE as u32 + 3], "{kernel:?}");
    }
}

#[cfg(test)]
mod counts_tests {
    use super::*;

    #[test]
    fn sharded_counts_add_and_flatten() {
        let counts = Counts::new();
        let mut seen = SeenSet::new();
        for color in [70_000, 3, 0xFF_FFFF] {
            seen.insert(color_key(color));
        }
        counts.add_set(&mut seen);
        seen.insert(color_key(3));
        seen.insert(color_key(65_536));
        counts.add_set(&mut seen);
        assert!(seen.is_empty());
        let flat = counts.into_vec();
        assert_eq!(flat.len(), COLOR_COUNT);
        assert_eq!((flat[3], flat[70_000], flat[65_536], flat[0xFF_FFFF], flat[4]), (2, 1, 1, 1, 0));
    }

    #[test]
    fn the_portable_update_adds_words_and_saturates() {
        super::kernel_checks::adds_words_and_saturates(Kernel::Portable);
    }
}
