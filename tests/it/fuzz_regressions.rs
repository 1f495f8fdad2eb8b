//! Every saved fuzzing input — the seed corpus and each input that once made
//! a fuzz target fail — goes through the same entry points as the fuzzers
//! (`ufcsr::fuzz_entry`), so CI re-checks them without nightly or libFuzzer.
//! A panic here is a regression.

use std::path::PathBuf;

#[test]
fn every_saved_fuzz_input_is_handled_without_a_panic() {
    let fuzz = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("fuzz");
    let targets: [ufcsr::fuzz_entry::Target; 10] = [
        ("tile", ufcsr::fuzz_entry::tile),
        ("manifest", ufcsr::fuzz_entry::manifest),
        ("result_json", ufcsr::fuzz_entry::result_json),
        ("legend", ufcsr::fuzz_entry::legend),
        ("commit_journal", ufcsr::fuzz_entry::commit_journal),
        ("placement_table", ufcsr::fuzz_entry::placement_table),
        ("placement_patches", ufcsr::fuzz_entry::placement_patches),
        ("placement_json", ufcsr::fuzz_entry::placement_json),
        ("study_outputs", ufcsr::fuzz_entry::study_outputs),
        ("solo_frame", ufcsr::fuzz_entry::solo_frame),
    ];
    let inputs = ufcsr::fuzz_entry::replay_saved_inputs(&fuzz, &targets).unwrap_or_else(|e| panic!("{e}"));
    assert!(inputs >= 10, "the seed corpus is missing ({inputs} inputs)");
}
