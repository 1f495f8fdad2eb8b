//! Fuzz target: arbitrary bytes as a result.json input (see `ufcsr::fuzz_entry::result_json`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| ufcsr::fuzz_entry::result_json(data));
