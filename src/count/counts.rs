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
/// the vector instructions of `kernel` where this CPU has them.
fn add_blocks(kernel: Kernel, seen: &mut SeenSet, shard: usize, counts: &mut [u32]) {
    match kernel.min(Kernel::supported()) {
        // SAFETY (both): the CPU supports the kernel, clamped just above.
        #[cfg(target_arch = "x86_64")]
        Kernel::Avx512 => unsafe { add_blocks_avx512(seen, shard, counts) },
        #[cfg(target_arch = "x86_64")]
        Kernel::Avx2 => unsafe { add_blocks_avx2(seen, shard, counts) },
        _ => add_blocks_portable(seen, shard, counts),
    }
}

/// Calls `add(slots, word)` for every non-zero 64-bit word of `seen` that
/// falls in `shard`, with the 64 counts its bits stand for, and removes those
/// keys from `seen`. Always inlined, so each caller's `add` is too.
#[inline(always)]
fn drain_shard(seen: &mut SeenSet, shard: usize, counts: &mut [u32], mut add: impl FnMut(&mut [u32], u64)) {
    seen.drain_blocks(shard * BLOCKS_PER_SHARD, BLOCKS_PER_SHARD, |index, word| {
        let offset = (index * 64) & (SHARD_SIZE - 1);
        add(&mut counts[offset..offset + 64], word);
    });
}

/// [`add_blocks`] one count at a time.
fn add_blocks_portable(seen: &mut SeenSet, shard: usize, counts: &mut [u32]) {
    drain_shard(seen, shard, counts, |slots, mut word| {
        while word != 0 {
            let slot = &mut slots[word.trailing_zeros() as usize];
            *slot = slot.saturating_add(1);
            word &= word - 1;
        }
    });
}

/// [`add_blocks`] 16 counts per instruction: a set word's bits become the
/// lane mask of a masked add.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
fn add_blocks_avx512(seen: &mut SeenSet, shard: usize, counts: &mut [u32]) {
    use std::arch::x86_64::*;
    let (one, full) = (_mm512_set1_epi32(1), _mm512_set1_epi32(-1));
    drain_shard(seen, shard, counts, |slots, word| {
        for (quarter, lanes) in slots.chunks_exact_mut(16).enumerate() {
            let mask = (word >> (16 * quarter)) as u16;
            if mask != 0 {
                // SAFETY: `lanes` is 16 valid u32s (64 bytes); unaligned
                // access is allowed.
                unsafe {
                    let counts = _mm512_loadu_si512(lanes.as_ptr().cast());
                    // Saturate like the scalar path: a full count stays full.
                    let room = _mm512_cmpneq_epi32_mask(counts, full);
                    let counts = _mm512_mask_add_epi32(counts, mask & room, counts, one);
                    _mm512_storeu_si512(lanes.as_mut_ptr().cast(), counts);
                }
            }
        }
    });
}

/// [`add_blocks`] 8 counts per instruction: each byte of a set word becomes
/// a lane mask (lane i set when bit i is), and subtracting the all-ones
/// lanes adds one.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn add_blocks_avx2(seen: &mut SeenSet, shard: usize, counts: &mut [u32]) {
    use std::arch::x86_64::*;
    let lane_bits = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
    let full = _mm256_set1_epi32(-1);
    drain_shard(seen, shard, counts, |slots, word| {
        for (eighth, lanes) in slots.chunks_exact_mut(8).enumerate() {
            let byte = (word >> (8 * eighth)) as u8;
            if byte != 0 {
                let bits = _mm256_and_si256(_mm256_set1_epi32(i32::from(byte)), lane_bits);
                let add = _mm256_cmpeq_epi32(bits, lane_bits);
                // SAFETY: `lanes` is 8 valid u32s (32 bytes); unaligned
                // access is allowed.
                unsafe {
                    let counts = _mm256_loadu_si256(lanes.as_ptr().cast());
                    // Saturate like the scalar path: a full count stays full.
                    let add = _mm256_andnot_si256(_mm256_cmpeq_epi32(counts, full), add);
                    _mm256_storeu_si256(lanes.as_mut_ptr().cast(), _mm256_sub_epi32(counts, add));
                }
            }
        }
    });
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
    fn every_kernel_adds_words_and_saturates() {
        let kernels = [Kernel::Portable, Kernel::Avx2, Kernel::Avx512];
        for kernel in kernels.into_iter().filter(|&k| k <= Kernel::supported()) {
            let mut counts = vec![0u32; SHARD_SIZE];
            counts[64 + 5] = u32::MAX;
            counts[64 + 6] = u32::MAX - 1;
            let mut seen = SeenSet::new();
            let keys = [0u32, 7, 8, 63, 64 + 5, 64 + 6, 64 + 40, 2 * SHARD_SIZE as u32 + 3];
            for &key in &keys {
                seen.insert(key);
            }
            add_blocks(kernel, &mut seen, 0, &mut counts);
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
}
