//! Issue 34, the commit journal `.ufcsr-commit.json` is read like any input:
//! through the file layer (a regular file, a size cap), typed and checked. A
//! truncated journal is an error naming it (it used to be ignored), a FIFO
//! is refused at once (it used to hang `heatmap`), and a journal whose
//! `stale` list names a file the result set does not own removes nothing
//! (it used to delete any file in `--out`).

use crate::common;

use std::path::{Path, PathBuf};

fn example() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fixtures/example")
}

/// Exit code and stderr of the analyzer with `args`.
fn analyze(args: &[&std::ffi::OsStr]) -> (Option<i32>, String) {
    let output = common::analyzer().args(args).output().unwrap();
    (output.status.code(), String::from_utf8_lossy(&output.stderr).into_owned())
}

fn refused_naming_the_journal((code, stderr): (Option<i32>, String), what: &str) {
    assert_eq!(code, Some(2), "{what}: {stderr}");
    assert!(stderr.contains(".ufcsr-commit.json"), "{what}: the error does not name the journal: {stderr}");
}

#[cfg(unix)]
#[test]
fn a_truncated_fifo_or_hostile_journal_is_refused_by_name_and_removes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let results = dir.path().join("R");
    let (code, stderr) =
        analyze(&[example().as_os_str(), "-q".as_ref(), "--out".as_ref(), results.as_os_str()]);
    assert_eq!(code, Some(0), "{stderr}");
    let journal = results.join(".ufcsr-commit.json");
    let heatmap = |out: &Path| {
        analyze(&[
            "heatmap".as_ref(),
            results.join("result.json").as_os_str(),
            "--out".as_ref(),
            out.as_os_str(),
        ])
    };

    std::fs::write(&journal, r#"{"staging": ".ufcsr-staging-999999999-0", "files": [], "st"#).unwrap();
    refused_naming_the_journal(heatmap(&dir.path().join("a.png")), "a truncated journal");

    std::fs::remove_file(&journal).unwrap();
    assert!(std::process::Command::new("mkfifo").arg(&journal).status().unwrap().success());
    refused_naming_the_journal(heatmap(&dir.path().join("b.png")), "a FIFO journal");

    std::fs::remove_file(&journal).unwrap();
    std::fs::write(results.join("precious.txt"), "mine").unwrap();
    let hostile = r#"{"staging": ".ufcsr-staging-999999999-0", "files": [], "stale": ["precious.txt"]}"#;
    std::fs::write(&journal, hostile).unwrap();
    let again = analyze(&[example().as_os_str(), "-q".as_ref(), "--out".as_ref(), results.as_os_str()]);
    refused_naming_the_journal(again, "a journal naming a file the set does not own");
    assert_eq!(std::fs::read_to_string(results.join("precious.txt")).unwrap(), "mine");
}
