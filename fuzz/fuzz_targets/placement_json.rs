//! Fuzz target: arbitrary bytes as a `placement.json` (see `ufcsr::fuzz_entry::placement_json`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| ufcsr::fuzz_entry::placement_json(data));
