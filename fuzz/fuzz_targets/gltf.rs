//! Fuzz target: arbitrary bytes as a glTF or GLB vehicle model (see `ufcsr_capture::fuzz_entry::gltf`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| ufcsr_capture::fuzz_entry::gltf(data));
