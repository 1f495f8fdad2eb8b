//! Fuzz target: arbitrary bytes as a design's `task.json` as merge reads it (see `ufcsr_capture::fuzz_entry::design_task`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| ufcsr_capture::fuzz_entry::design_task(data));
