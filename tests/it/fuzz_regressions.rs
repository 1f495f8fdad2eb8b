//! Every saved fuzzing input — the seed corpus and each input that once made
//! a fuzz target fail — goes through the same entry points as the fuzzers
//! (`ufcsr::fuzz_entry`), so CI re-checks them without nightly or libFuzzer.
//! A panic here is a regression.

use std::path::PathBuf;

/// A fuzz target's name and its entry point.
type Target = (&'static str, fn(&[u8]));

#[test]
fn every_saved_fuzz_input_is_handled_without_a_panic() {
    let fuzz = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("fuzz");
    let targets: [Target; 4] = [
        ("tile", ufcsr::fuzz_entry::tile),
        ("manifest", ufcsr::fuzz_entry::manifest),
        ("result_json", ufcsr::fuzz_entry::result_json),
        ("legend", ufcsr::fuzz_entry::legend),
    ];
    let mut inputs = 0;
    for (target, entry) in targets {
        for folder in ["seeds", "regressions"] {
            let Ok(files) = std::fs::read_dir(fuzz.join(folder).join(target)) else { continue };
            for file in files.flatten() {
                let bytes = std::fs::read(file.path()).unwrap();
                let outcome = std::panic::catch_unwind(|| entry(&bytes));
                assert!(outcome.is_ok(), "fuzz target {target} panics on {}", file.path().display());
                inputs += 1;
            }
        }
    }
    assert!(inputs >= 6, "the seed corpus is missing ({inputs} inputs)");
}
