//! Fuzz target: arbitrary bytes as a Unity Perception SOLO frame file (see `ufcsr::fuzz_entry::solo_frame`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| ufcsr::fuzz_entry::solo_frame(data));
