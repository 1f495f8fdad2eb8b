//! Fuzz target: arbitrary bytes as an OBJ vehicle model (its mtllib reads the same bytes) (see `ufcsr_capture::fuzz_entry::obj`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| ufcsr_capture::fuzz_entry::obj(data));
