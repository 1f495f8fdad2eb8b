//! Fuzz target: arbitrary bytes as a tile input (see `ufcsr::fuzz_entry::tile`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| ufcsr::fuzz_entry::tile(data));
