//! Issue 34, output streams: `--json`'s `written` names every file the
//! command wrote, and nothing else. Each command runs with `--json`; what
//! it lists is compared with what is in its output folder afterwards (a
//! fresh folder: every file there), or, for a command that writes into a
//! folder already holding files (`views`, `demo --resume`), with the files
//! that are new or replaced (another inode or modification time). It used
//! to leave out the eight `views/*.png` of every result set, the pictures
//! `report` writes beside its page, every tile of a capture, the archive
//! files of `--measure unobstructed` and the folders of `study` and
//! `observers`.

use std::collections::{BTreeMap, BTreeSet};
use std::os::unix::fs::MetadataExt;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use crate::common;

fn example() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fixtures/example")
}

/// Every file below `dir` (links not followed), with its inode and modification time.
fn files(dir: &Path) -> BTreeMap<PathBuf, (u64, i64, i64)> {
    let mut found = BTreeMap::new();
    let mut folders = vec![dir.to_path_buf()];
    while let Some(folder) = folders.pop() {
        for entry in std::fs::read_dir(&folder).into_iter().flatten().flatten() {
            let meta = std::fs::symlink_metadata(entry.path()).unwrap();
            if meta.is_dir() {
                folders.push(entry.path());
            } else {
                found.insert(entry.path(), (meta.ino(), meta.mtime(), meta.mtime_nsec()));
            }
        }
    }
    found
}

/// The files `after` holds that `before` did not, or held as another file.
fn changed(before: &BTreeMap<PathBuf, (u64, i64, i64)>, dir: &Path) -> BTreeSet<PathBuf> {
    files(dir).into_iter().filter(|(path, stamp)| before.get(path) != Some(stamp)).map(|(p, _)| p).collect()
}

/// The one JSON object's `written`, each path made absolute from `cwd`.
fn written(output: &Output, cwd: &Path, what: &str) -> BTreeSet<PathBuf> {
    let text = String::from_utf8_lossy(&output.stdout);
    let summary: serde_json::Value = serde_json::from_str(text.trim())
        .unwrap_or_else(|e| panic!("{what}: not one JSON object ({e}): {text}"));
    assert_eq!(summary["exit_code"], 0, "{what}: {summary}\n{}", String::from_utf8_lossy(&output.stderr));
    summary["written"].as_array().unwrap().iter().map(|p| cwd.join(p.as_str().unwrap())).collect()
}

/// Runs `command --json` in `cwd`; asserts `written` is exactly `expected()`,
/// evaluated after the run.
fn assert_written_is(
    what: &str,
    mut command: Command,
    cwd: &Path,
    expected: impl FnOnce() -> BTreeSet<PathBuf>,
) {
    let output = command.arg("--json").current_dir(cwd).env("XDG_RUNTIME_DIR", cwd).output().unwrap();
    let listed = written(&output, cwd, what);
    let there = expected();
    assert!(!there.is_empty(), "{what}: wrote nothing");
    let unlisted: Vec<_> = there.difference(&listed).collect();
    let not_there: Vec<_> = listed.difference(&there).collect();
    assert!(
        unlisted.is_empty() && not_there.is_empty(),
        "{what}: not in written {unlisted:?}; listed but not written {not_there:?}"
    );
}

fn capture() -> Command {
    Command::new(env!("CARGO_BIN_EXE_ufcsr-capture"))
}

const SMALL: [&str; 6] = ["--ppd", "2", "--palette-size", "256", "--frames", "150,180"];

#[test]
fn written_names_every_file_the_analysis_heatmap_report_and_palette_wrote() {
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path();
    let mut analysis = common::analyzer();
    analysis.arg(example()).args(["--out", "A"]);
    assert_written_is("analysis", analysis, cwd, || files(&cwd.join("A")).into_keys().collect());
    std::fs::create_dir_all(cwd.join("H")).unwrap();
    let mut heatmap = common::analyzer();
    heatmap.args(["heatmap", "A", "--scale", "log", "--out", "H/h.png"]);
    assert_written_is("heatmap", heatmap, cwd, || files(&cwd.join("H")).into_keys().collect());
    let mut palette = common::analyzer();
    palette.args(["palette", "--size", "8", "--out", "H/p.png"]);
    let before = files(&cwd.join("H"));
    assert_written_is("palette", palette, cwd, || changed(&before, &cwd.join("H")));
    // Two results of an archive with a vehicle: the page, and each redrawn on one scale.
    let mut again = common::analyzer();
    again.arg(example()).args(["--out", "B", "--json"]);
    assert!(again.current_dir(cwd).output().unwrap().status.success());
    let mut report = common::analyzer();
    report.args(["report", "A", "B", "--out", "R"]);
    assert_written_is("report", report, cwd, || files(&cwd.join("R")).into_keys().collect());
    let mut own = common::analyzer();
    own.args(["report", "A", "B", "--own-scales", "--out", "R2"]);
    assert_written_is("report --own-scales", own, cwd, || files(&cwd.join("R2")).into_keys().collect());
}

#[test]
fn written_names_every_file_a_capture_and_placement_wrote() {
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path();
    let mut demo = capture();
    demo.arg("demo").args(SMALL).args(["--out", "D"]);
    assert_written_is("demo", demo, cwd, || files(&cwd.join("D")).into_keys().collect());
    // --resume writes only the tile that is missing.
    let tile = files(&cwd.join("D/tiles")).into_keys().next().unwrap();
    std::fs::remove_file(&tile).unwrap();
    let before = files(&cwd.join("D"));
    let mut resumed = capture();
    resumed.arg("demo").args(SMALL).args(["--resume", "--out", "D"]);
    assert_written_is("demo --resume", resumed, cwd, || {
        let changed = changed(&before, &cwd.join("D"));
        assert!(changed.contains(&tile), "the missing tile was not written again");
        changed
    });
    let mut counted = capture();
    counted.arg("demo").args(SMALL).args(["--count", "--out", "C"]);
    assert_written_is("demo --count", counted, cwd, || files(&cwd.join("C")).into_keys().collect());
    let mut measured = capture();
    measured.arg("demo").args(SMALL).args(["--measure", "unobstructed", "--sample", "0.05"]);
    measured.args(["--placement", "--display", "0.5x0.3", "--out", "M"]);
    assert_written_is("demo --measure unobstructed --placement", measured, cwd, || {
        files(&cwd.join("M")).into_keys().collect()
    });
    let mut placement = common::analyzer();
    placement.args(["placement", "M", "--min-dwell-s", "0", "--out", "P"]);
    assert_written_is("placement", placement, cwd, || files(&cwd.join("P")).into_keys().collect());
    let before = files(&cwd.join("C/results"));
    let mut views = capture();
    views.args(["views", "C/results"]);
    assert_written_is("views", views, cwd, || changed(&before, &cwd.join("C/results")));
}

#[test]
fn written_names_every_file_of_a_study_and_an_observer_study() {
    let dir = tempfile::tempdir().unwrap();
    let cwd = dir.path();
    let scene = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fixtures/scenes/demo.json");
    let mut study = capture();
    study.arg("study").arg(&scene).args(["--scenario", "A", "--ppd", "2", "--palette-size", "256"]);
    study.args(["--frame-step", "90", "--exact-sample", "0.05", "--out", "S"]);
    assert_written_is("study", study, cwd, || files(&cwd.join("S")).into_keys().collect());
    let mut observers = capture();
    observers.arg("observers").arg(&scene).args(["--scenario", "A", "--ppd", "2", "--palette-size", "256"]);
    observers.args(["--frame-step", "90", "--kerb=-6.5,-4.5:-4.5,-6.5", "--observers", "1", "--seed", "7"]);
    observers.args(["--out", "O"]);
    assert_written_is("observers", observers, cwd, || files(&cwd.join("O")).into_keys().collect());
}
