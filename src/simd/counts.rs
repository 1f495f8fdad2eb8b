//! The count table's vector updates (`count::Counts`): a set word's
//! 64 bits become one count each, 16 (AVX-512) or 8 (AVX2) per instruction.
//! The portable form, the reference they are held to, is
//! `count::counts::add_blocks_portable`.

use crate::color::SeenSet;
use crate::simd::Kernel;

/// Moves the keys of `seen` that fall in shard `shard` (of `SIZE` keys) into
/// its `counts` with the vector instructions of `kernel`, if this CPU has
/// them; returns whether it did (else nothing changed).
pub(crate) fn add_shard<const SIZE: usize>(
    kernel: Kernel,
    seen: &mut SeenSet,
    shard: usize,
    counts: &mut [u32],
) -> bool {
    match kernel.min(Kernel::supported()) {
        #[cfg(target_arch = "x86_64")]
        Kernel::Avx512 => {
            // SAFETY: the CPU has every feature of the kernel (clamped just above).
            unsafe { add_shard_avx512::<SIZE>(seen, shard, counts) }
        }
        #[cfg(target_arch = "x86_64")]
        Kernel::Avx2 => {
            // SAFETY: as above.
            unsafe { add_shard_avx2::<SIZE>(seen, shard, counts) }
        }
        _ => return false,
    }
    true
}

/// [`add_shard`] 16 counts per instruction: a set word's bits become the
/// lane mask of a masked add.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
fn add_shard_avx512<const SIZE: usize>(seen: &mut SeenSet, shard: usize, counts: &mut [u32]) {
    use std::arch::x86_64::*;
    let (one, full) = (_mm512_set1_epi32(1), _mm512_set1_epi32(-1));
    seen.drain_shard::<SIZE>(shard, counts, |slots, word| {
        for (quarter, lanes) in slots.chunks_exact_mut(16).enumerate() {
            let mask = (word >> (16 * quarter)) as u16;
            if mask != 0 {
                // SAFETY: `lanes` is 16 valid u32s (64 bytes); unaligned
                // access is allowed.
                let counts = unsafe { _mm512_loadu_si512(lanes.as_ptr().cast()) };
                // Saturate like the scalar path: a full count stays full.
                let room = _mm512_cmpneq_epi32_mask(counts, full);
                let counts = _mm512_mask_add_epi32(counts, mask & room, counts, one);
                // SAFETY: as the load.
                unsafe { _mm512_storeu_si512(lanes.as_mut_ptr().cast(), counts) };
            }
        }
    });
}

/// [`add_shard`] 8 counts per instruction: each byte of a set word becomes
/// a lane mask (lane i set when bit i is), and subtracting the all-ones
/// lanes adds one.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn add_shard_avx2<const SIZE: usize>(seen: &mut SeenSet, shard: usize, counts: &mut [u32]) {
    use std::arch::x86_64::*;
    let lane_bits = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
    let full = _mm256_set1_epi32(-1);
    seen.drain_shard::<SIZE>(shard, counts, |slots, word| {
        for (eighth, lanes) in slots.chunks_exact_mut(8).enumerate() {
            let byte = (word >> (8 * eighth)) as u8;
            if byte != 0 {
                let bits = _mm256_and_si256(_mm256_set1_epi32(i32::from(byte)), lane_bits);
                let add = _mm256_cmpeq_epi32(bits, lane_bits);
                // SAFETY: `lanes` is 8 valid u32s (32 bytes); unaligned
                // access is allowed.
                let counts = unsafe { _mm256_loadu_si256(lanes.as_ptr().cast()) };
                // Saturate like the scalar path: a full count stays full.
                let add = _mm256_andnot_si256(_mm256_cmpeq_epi32(counts, full), add);
                let counts = _mm256_sub_epi32(counts, add);
                // SAFETY: as the load.
                unsafe { _mm256_storeu_si256(lanes.as_mut_ptr().cast(), counts) };
            }
        }
    });
}
