//! For tests, benches and fuzzers, not for analyses: synthetic archives
//! with known answers ([`synthetic`], behind the `synthetic` feature) and the
//! fuzzers' entry points ([`fuzz_entry`]).

#[doc(hidden)]
pub mod fuzz_entry;
#[cfg(feature = "synthetic")]
pub mod synthetic;
