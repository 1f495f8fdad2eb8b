//! For tests, benches and fuzzers, not for analyses: synthetic archives
//! with known answers ([`synthetic`], behind the `synthetic` feature), the
//! vector kernels' checks ([`kernel_checks`], likewise) and the fuzzers'
//! entry points ([`fuzz_entry`]).

#[doc(hidden)]
pub mod fuzz_entry;
#[cfg(feature = "synthetic")]
pub(crate) mod kernel_checks;
#[cfg(feature = "synthetic")]
pub mod synthetic;
