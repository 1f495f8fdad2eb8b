//! Fuzz target: arbitrary bytes as the commit journal `.ufcsr-commit.json` (see `ufcsr::fuzz_entry::commit_journal`).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| ufcsr::fuzz_entry::commit_journal(data));
