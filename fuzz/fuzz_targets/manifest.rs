//! Fuzz target: arbitrary bytes as a manifest input (see `ufcsr::fuzz_entry::manifest`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| ufcsr::fuzz_entry::manifest(data));
