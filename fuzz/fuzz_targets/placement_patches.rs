//! Fuzz target: arbitrary bytes as a patches' footprint table `placement-patches.csv` (see `ufcsr::fuzz_entry::placement_patches`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| ufcsr::fuzz_entry::placement_patches(data));
