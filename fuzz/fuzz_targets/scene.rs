//! Fuzz target: arbitrary bytes as a scene file (see `ufcsr_capture::fuzz_entry::scene`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| ufcsr_capture::fuzz_entry::scene(data));
