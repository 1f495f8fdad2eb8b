//! Fuzz target: arbitrary bytes as a design file, planned (see `ufcsr_capture::fuzz_entry::design`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| ufcsr_capture::fuzz_entry::design(data));
