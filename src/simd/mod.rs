//! The only code of the analyzer that may be `unsafe`: the x86-64 vector
//! kernels (AVX2 and AVX-512) of the hot loops, and the choice of kernel
//! ([`Kernel`]) whose feature detection makes calling them sound.
//!
//! Both crate roots `deny(unsafe_code)`; this module alone allows it, and
//! the crates' clippy lints `undocumented_unsafe_blocks` and
//! `multiple_unsafe_ops_per_block` hold every block here to one unsafe
//! operation under a `// SAFETY:` comment that says why it holds. A kernel's
//! functions are compiled for its CPU features (`#[target_feature]`); what
//! they read and write is checked before the first byte (slice sizes
//! asserted, tables validated where they are built), and each is reached
//! only through a safe door that checks the CPU first:
//!
//! * [`VectorScan`] and [`FusedScan`] — the counting row kernels
//!   ([`scan`]); their portable reference is `count::scan`'s;
//! * [`SideBySide`] — the tile decoder's unfilter, several rows at once
//!   ([`unfilter`]); its reference is `png::unfilter`'s row by row;
//! * [`add_shard`] — the count table's updates ([`counts`]); its reference
//!   is `count::counts`'.
//!
//! The unit tests that hold each kernel to its reference run in
//! `tests/kernels` and are reported *ignored*, not passed, on a CPU that
//! lacks the kernel's features.
#![allow(unsafe_code)]

mod counts;
mod kernel;
pub(crate) mod scan;
mod unfilter;

pub(crate) use counts::add_shard;
pub use kernel::{KERNEL_ENV, Kernel};
pub(crate) use scan::{
    BlockSlots, Classes, ColorRuns, FusedScan, RowTally, SlotBlocks, SlotSpans, VectorScan,
};
pub(crate) use unfilter::SideBySide;
