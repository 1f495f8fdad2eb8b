//! Fuzz target: arbitrary bytes as a Unity scenario export (see `ufcsr_capture::fuzz_entry::unity`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| ufcsr_capture::fuzz_entry::unity(data));
