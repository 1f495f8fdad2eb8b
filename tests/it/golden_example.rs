//! The bundled example's result, byte for byte: `result.json`, `parts.csv`
//! and `frames.csv` of `fixtures/example` analysed as the command line does
//! (with frames.csv on) are compared with checked-in copies in
//! `tests/reference/` (the example's absolute path in `result.json` written
//! as `fixtures/example`). A refactor that claims "no behaviour change" is
//! held to it; a change on purpose replaces the copies (the message says how).

use std::path::{Path, PathBuf};

fn workspace_file(relative: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(relative)
}

/// `written` with the example's absolute path (as JSON writes it) replaced by
/// `fixtures/example`, so the copy does not depend on where the checkout is.
fn with_relative_example_path(written: &str, example: &Path) -> String {
    let absolute = serde_json::to_string(&example.display().to_string()).unwrap();
    written.replace(absolute.trim_end_matches('"'), "\"fixtures/example")
}

fn assert_same_as_reference(written: &str, reference: &str) {
    let expected = std::fs::read_to_string(workspace_file(reference)).unwrap();
    if written != expected {
        let differing = written.lines().zip(expected.lines()).enumerate().find(|(_, (a, b))| a != b);
        let line = differing.map_or_else(
            || {
                format!(
                    "one is longer: {} against {} lines",
                    written.lines().count(),
                    expected.lines().count()
                )
            },
            |(number, (now, before))| format!("line {}: now {now:?}, expected {before:?}", number + 1),
        );
        panic!(
            "{reference} differs from what the analyzer writes now ({line}); \
             if the result changed on purpose, replace it with the new output of \
             `ufcsr-analyze fixtures/example --out DIR` (result.json with the example's path \
             written as fixtures/example)"
        );
    }
}

#[test]
fn the_example_analysed_as_the_command_line_does_writes_the_checked_in_result_byte_for_byte() {
    let dir = tempfile::tempdir().unwrap();
    let example = workspace_file("fixtures/example");
    let options = ufcsr::AnalyzeOptions { archive: example.clone(), frames: true, ..Default::default() };
    let mut analysis = ufcsr::analyze(&options, None).unwrap();
    ufcsr::write_results(&mut analysis, dir.path()).unwrap();
    let read = |name: &str| std::fs::read_to_string(dir.path().join(name)).unwrap();
    let result = with_relative_example_path(&read("result.json"), &example);
    assert_same_as_reference(&result, "tests/reference/example-result.json");
    assert_same_as_reference(&read("parts.csv"), "tests/reference/example-parts.csv");
    assert_same_as_reference(&read("frames.csv"), "tests/reference/example-frames.csv");
}
