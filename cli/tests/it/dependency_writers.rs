//! Issue 41: the holes the last hostile campaign found, through the command
//! line. Dependencies wrote outputs through paths of their own: `csv`'s
//! `Writer::from_path` wrote `results/unobstructed-parts.csv` (a re-capture
//! wrote through a link planted there, into a file outside `--out`, and
//! blocked forever on a FIFO there), plotters' `SVGBackend::new` wrote
//! `study.svg` through a link planted at `--out/study.svg`. They now write
//! into bytes that the file layer writes, so a link there is refused (the
//! file it names unchanged) and a FIFO neither hangs nor is replaced. And a
//! capture interrupted in place said "earlier outputs are untouched" while
//! its earlier manifest and tiles were gone, and the folder then analysed
//! (exit 0) as the partial new capture.

use std::ffi::OsStr;
use std::os::unix::fs::FileTypeExt;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

fn capture(dir: &Path) -> Command {
    let mut command = Command::new(env!("CARGO_BIN_EXE_ufcsr-capture"));
    command.env("XDG_RUNTIME_DIR", dir).stdin(Stdio::null()).stdout(Stdio::piped()).stderr(Stdio::piped());
    command
}

/// Waits at most `limit` for `child`; a run still going then is killed and
/// the test fails (a FIFO used to block the writer forever).
pub(crate) fn finish_within(mut child: Child, limit: Duration, what: &str) -> Output {
    let start = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed() > limit {
            let _ = child.kill();
            let output = child.wait_with_output().unwrap();
            panic!("{what}: still running after {limit:?} (blocked?): {}", text(&output.stderr));
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    child.wait_with_output().unwrap()
}

fn fifo(path: &Path) {
    let _ = std::fs::remove_file(path);
    assert!(Command::new("mkfifo").arg(path).status().expect("mkfifo").success());
}

fn is_fifo(path: &Path) -> bool {
    std::fs::symlink_metadata(path).is_ok_and(|m| m.file_type().is_fifo())
}

/// Replaces `path` by a link to `target`.
fn link(target: &Path, path: &Path) {
    let _ = std::fs::remove_file(path);
    std::os::unix::fs::symlink(target, path).unwrap();
}

/// A link at `OUT/study.svg` (to a file outside `--out`) and a FIFO at
/// `OUT/study.csv`: each refused by name, the file outside unchanged, the
/// FIFO still a FIFO, and no run blocks.
#[test]
fn the_study_never_writes_through_a_link_nor_blocks_on_a_fifo_at_its_own_files() {
    let dir = tempfile::tempdir().unwrap();
    let scene = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fixtures/scenes/demo.json");
    let outside = dir.path().join("outside.svg");
    std::fs::write(&outside, "mine").unwrap();
    let out = dir.path().join("study");
    std::fs::create_dir(&out).unwrap();
    let study = |out: &Path| {
        let child = capture(dir.path())
            .arg("study")
            .arg(&scene)
            .args(["--scenario", "A", "--ppd", "2", "--palette-size", "256", "--frame-step", "90", "-q"])
            .arg("--out")
            .arg(out)
            .spawn()
            .unwrap();
        finish_within(child, Duration::from_secs(300), "study")
    };
    for (hostile, plant) in [("study.svg", "a link"), ("study.csv", "a FIFO")] {
        let path = out.join(hostile);
        if plant == "a link" {
            link(&outside, &path);
        } else {
            fifo(&path);
        }
        let output = study(&out);
        let stderr = text(&output.stderr);
        assert!(!output.status.success(), "{plant} at {hostile} was accepted: {stderr}");
        assert!(stderr.contains(hostile), "{plant} at {hostile}: the message names no file: {stderr}");
        assert_eq!(
            std::fs::read_to_string(&outside).unwrap(),
            "mine",
            "written through {plant} at {hostile}"
        );
        let kept = std::fs::symlink_metadata(&path).unwrap().file_type();
        assert!(if plant == "a link" { kept.is_symlink() } else { kept.is_fifo() }, "{plant} replaced");
        std::fs::remove_file(&path).unwrap();
    }
    // Nothing planted: the files are written, study.svg an SVG.
    let output = study(&out);
    assert!(output.status.success(), "{}", text(&output.stderr));
    let svg = std::fs::read_to_string(out.join("study.svg")).unwrap();
    assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"), "{svg:.200}");
    assert!(std::fs::read_to_string(out.join("study.csv")).unwrap().starts_with("measure,ppd,"));
}

/// A re-capture with `--measure unobstructed` writes
/// `results/unobstructed-parts.csv` last: a link planted there (to a file
/// outside `--out`) is refused and the file it names unchanged; a FIFO there
/// is refused without blocking.
#[test]
fn a_re_capture_never_writes_through_a_link_nor_blocks_on_a_fifo_at_unobstructed_parts_csv() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("archive");
    let measure = |out: &Path| {
        let child = capture(dir.path())
            .args(["demo", "--scenario", "A", "--palette-size", "256", "--frames", "120"])
            .args(["--measure", "unobstructed", "--sample", "1/4", "-q", "--out"])
            .arg(out)
            .spawn()
            .unwrap();
        finish_within(child, Duration::from_secs(300), "the capture")
    };
    let first = measure(&out);
    assert!(first.status.success(), "{}", text(&first.stderr));
    let estimates = out.join("results/unobstructed-parts.csv");
    assert!(std::fs::read_to_string(&estimates).unwrap().contains("part"));
    let outside = dir.path().join("outside.csv");
    std::fs::write(&outside, "mine").unwrap();
    link(&outside, &estimates);
    let output = measure(&out);
    let stderr = text(&output.stderr);
    assert!(
        !output.status.success() && stderr.contains("unobstructed-parts.csv") && stderr.contains("link"),
        "{stderr}"
    );
    assert_eq!(std::fs::read_to_string(&outside).unwrap(), "mine", "written through the link");
    assert!(std::fs::symlink_metadata(&estimates).unwrap().file_type().is_symlink());
    fifo(&estimates);
    let output = measure(&out);
    let stderr = text(&output.stderr);
    assert!(
        !output.status.success() && stderr.contains("unobstructed-parts.csv") && stderr.contains("FIFO"),
        "{stderr}"
    );
    assert!(is_fifo(&estimates), "the FIFO was replaced");
}

fn analyze<S: AsRef<OsStr>>(args: &[S]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_ufcsr-analyze")).args(args).output().unwrap()
}

/// Ctrl-C during a re-capture: the earlier manifest is gone (removed before
/// the first new tile), so the message says the folder is unfinished, not
/// "untouched", and the analyzer refuses the folder (it used to count the
/// partial capture, exit 0) until a capture there finishes.
#[test]
fn an_interrupted_re_capture_says_its_folder_is_unfinished_and_the_analyzer_refuses_it() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("archive");
    let small = ["--palette-size", "256", "-q", "--out"];
    let first = capture(dir.path())
        .args(["demo", "--scenario", "A", "--frames", "150,180", "--ppd", "2"])
        .args(small)
        .arg(&out)
        .output();
    let first = first.unwrap();
    assert!(first.status.success(), "{}", text(&first.stderr));
    let marker = out.join(ufcsr::files::UNFINISHED_FILE);
    assert!(!marker.exists(), "a finished capture leaves no marker");
    assert_eq!(analyze(&[out.as_os_str(), "-q".as_ref()]).status.code(), Some(0));

    // A long re-capture, interrupted once it has begun rewriting the folder.
    let child = capture(dir.path())
        .args(["demo", "--scenario", "A", "--frames", "0-180", "--ppd", "6"])
        .args(small)
        .arg(&out)
        .spawn()
        .unwrap();
    let start = Instant::now();
    while !marker.exists() {
        assert!(start.elapsed() < Duration::from_secs(120), "the re-capture never marked its folder");
        std::thread::sleep(Duration::from_millis(20));
    }
    let signalled = Command::new("kill").args(["-INT", &child.id().to_string()]).status().unwrap();
    assert!(signalled.success());
    let output = finish_within(child, Duration::from_secs(120), "the interrupted capture");
    let stderr = text(&output.stderr);
    assert_eq!(output.status.code(), Some(130), "{stderr}");
    assert!(!stderr.contains("untouched"), "{stderr}");
    assert!(stderr.contains("did not finish") && stderr.contains(ufcsr::files::UNFINISHED_FILE), "{stderr}");
    assert!(marker.exists());
    let refused = analyze(&[out.as_os_str(), "-q".as_ref()]);
    let refusal = text(&refused.stderr);
    assert_eq!(refused.status.code(), Some(2), "the partial capture was analysed: {refusal}");
    assert!(
        refusal.contains(ufcsr::files::UNFINISHED_FILE) && refusal.contains("has not finished"),
        "{refusal}"
    );

    // Captured again to its end: the marker goes, the folder analyses.
    let again = capture(dir.path())
        .args(["demo", "--scenario", "A", "--frames", "150,180", "--ppd", "2"])
        .args(small)
        .arg(&out)
        .output();
    let again = again.unwrap();
    assert!(again.status.success(), "{}", text(&again.stderr));
    assert!(!marker.exists());
    assert_eq!(analyze(&[out.as_os_str(), "-q".as_ref()]).status.code(), Some(0));
}
