//! Fuzz target: arbitrary bytes as a legend input (see `ufcsr::fuzz_entry::legend`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| ufcsr::fuzz_entry::legend(data));
