//! Fuzz target: arbitrary bytes as a placement table `placement-frames.csv` (see `ufcsr::fuzz_entry::placement_table`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| ufcsr::fuzz_entry::placement_table(data));
