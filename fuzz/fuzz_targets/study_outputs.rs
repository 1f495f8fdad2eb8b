//! Fuzz target: arbitrary bytes as an `observers.json` or a `study.json` (see `ufcsr::fuzz_entry::study_outputs`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| ufcsr::fuzz_entry::study_outputs(data));
