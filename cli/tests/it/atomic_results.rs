//! A result set is written whole or not at all: a failure while writing it
//! (here a vehicle model that turns out to be corrupt) leaves the previous
//! result set byte for byte and no staging folder or temporary file; runs
//! killed (SIGKILL) or interrupted (SIGINT) at random moments leave the old
//! set or the new one (or, killed mid-move, a set readers refuse), and the
//! next run cleans up and writes its set whole.

use crate::common;

use std::path::{Path, PathBuf};

/// Every file under `dir` whose name marks it temporary.
fn leftovers(dir: &Path) -> Vec<PathBuf> {
    let mut found = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(folder) = stack.pop() {
        for entry in std::fs::read_dir(&folder).unwrap().flatten() {
            let name = entry.file_name().to_string_lossy().into_owned();
            if name.contains(".tmp-") || name.starts_with(".ufcsr-staging-") {
                found.push(entry.path());
            }
            if entry.path().is_dir() {
                stack.push(entry.path());
            }
        }
    }
    found
}

#[test]
fn a_failure_while_writing_leaves_the_previous_result_set_whole() {
    let dir = tempfile::tempdir().unwrap();
    let example = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fixtures/example");
    let out = dir.path().join("out");
    let status = common::analyzer().arg(&example).arg("--out").arg(&out).arg("-q").status().unwrap();
    assert!(status.success());
    let before: Vec<(PathBuf, Vec<u8>)> =
        ["result.json", "parts.csv", "heatmap.png", "heatmap.glb", "report.html"]
            .iter()
            .map(|name| (out.join(name), std::fs::read(out.join(name)).unwrap()))
            .collect();

    // A second run, with a --scale that changes every output, whose
    // vehicle model is garbage: it fails only after counting, while writing.
    let bad_mesh = dir.path().join("bad.glb");
    std::fs::write(&bad_mesh, b"glTF but not really").unwrap();
    let output = common::analyzer()
        .arg(&example)
        .arg("--out")
        .arg(&out)
        .args(["-q", "--scale", "log", "--mesh"])
        .arg(&bad_mesh)
        .output()
        .unwrap();
    assert!(!output.status.success());
    assert!(String::from_utf8_lossy(&output.stderr).contains("bad.glb"));
    for (path, bytes) in &before {
        assert!(&std::fs::read(path).unwrap() == bytes, "{} changed although the run failed", path.display());
    }
    assert!(leftovers(&out).is_empty(), "left behind: {:?}", leftovers(&out));
}

#[test]
fn a_smaller_result_set_takes_away_stale_files_and_keeps_the_users_own() {
    let dir = tempfile::tempdir().unwrap();
    let example = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fixtures/example");
    let out = dir.path().join("out");
    let run = |extra: &[&str]| {
        let status = common::analyzer().arg(&example).arg("--out").arg(&out).arg("-q").args(extra).status();
        assert!(status.unwrap().success());
    };
    run(&["--figures", "all"]);
    assert!(out.join("frames.csv").is_file());
    // A note of the user's inside views/, and a file of theirs beside the results.
    std::fs::write(out.join("views/my-notes.txt"), b"mine").unwrap();
    std::fs::write(out.join("paper-draft.txt"), b"mine too").unwrap();
    run(&["--frames-csv", "off", "--figures", "all"]);
    assert!(!out.join("frames.csv").exists(), "a stale frames.csv of the earlier run is left");
    assert_eq!(std::fs::read(out.join("views/my-notes.txt")).unwrap(), b"mine");
    assert_eq!(std::fs::read(out.join("paper-draft.txt")).unwrap(), b"mine too");
    assert!(out.join("views/front.png").is_file() && out.join("result.json").is_file());
    assert!(leftovers(&out).is_empty(), "left behind: {:?}", leftovers(&out));
}

/// The files of a result set that come out the same in every run.
const DETERMINISTIC: [&str; 4] = ["result.json", "parts.csv", "frames.csv", "heatmap.png"];

fn copy_tree(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for entry in std::fs::read_dir(from).unwrap().flatten() {
        let target = to.join(entry.file_name());
        if entry.path().is_dir() {
            copy_tree(&entry.path(), &target);
        } else {
            std::fs::copy(entry.path(), target).unwrap();
        }
    }
}

#[cfg(unix)]
#[test]
fn random_interruptions_never_leave_a_mixed_set_and_the_next_run_cleans_up() {
    use std::process::Command;
    use std::time::Instant;
    let dir = tempfile::tempdir().unwrap();
    let example = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fixtures/example");
    let analyze = |out: &Path, dedupe: &str| {
        Command::new(env!("CARGO_BIN_EXE_ufcsr-analyze"))
            .arg(&example)
            .args(["--dedupe", dedupe, "--quiet", "--out"])
            .arg(out)
            .stderr(std::process::Stdio::null())
            .spawn()
            .unwrap()
    };
    // Two different sets: the one in place (A) and the one a run replaces it with (B).
    let (set_a, set_b) = (dir.path().join("a"), dir.path().join("b"));
    assert!(analyze(&set_a, "image").wait().unwrap().success());
    let start = Instant::now();
    assert!(analyze(&set_b, "frame").wait().unwrap().success());
    let duration = start.elapsed();
    let read = |set: &Path, name: &str| std::fs::read(set.join(name)).ok();
    assert_ne!(read(&set_a, "result.json"), read(&set_b, "result.json"));
    let matches =
        |out: &Path, set: &Path| DETERMINISTIC.iter().all(|name| read(out, name) == read(set, name));

    // The delays (from this seed: 0.07, 0.89, 0.58, 0.38, 0.25, 0.09, 1.0 and
    // 0.35 of a whole run) stop most runs midway; a run that ends first is
    // still checked, but each signal must have stopped at least one run.
    let mut interrupted = [0u32; 2];
    let mut state = 0x5EED_u64;
    for round in 0..8 {
        state = state.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
        let delay = duration.mul_f64(((state >> 33) % 1100) as f64 / 1000.0);
        let signal = if round % 2 == 0 { "-KILL" } else { "-INT" };
        let out = dir.path().join(format!("out{round}"));
        copy_tree(&set_a, &out);
        let mut child = analyze(&out, "frame");
        std::thread::sleep(delay);
        // Not yet waited for, the child exists (if only as a zombie), so the
        // signal is delivered or, after its end, ignored: `kill` succeeds.
        let killed = Command::new("kill").args([signal, &child.id().to_string()]).status().unwrap();
        let status = child.wait().unwrap();
        let context = format!("round {round}: {signal} after {delay:?} ({status})");
        assert!(killed.success(), "{context}: kill failed");
        interrupted[round % 2] += u32::from(!status.success());
        if out.join(".ufcsr-commit.json").exists() {
            // Killed while moving the new set in: readers refuse the half-old, half-new set.
            let refused = Command::new(env!("CARGO_BIN_EXE_ufcsr-analyze"))
                .args(["heatmap"])
                .arg(out.join("result.json"))
                .arg("--out")
                .arg(dir.path().join("h.png"))
                .output()
                .unwrap();
            assert!(!refused.status.success(), "{context}");
            assert!(String::from_utf8_lossy(&refused.stderr).contains("killed"), "{context}");
        } else {
            assert!(matches(&out, &set_a) || matches(&out, &set_b), "{context}: a mixed result set");
        }
        if signal == "-INT" {
            assert!(leftovers(&out).is_empty(), "{context}: an interrupt left {:?}", leftovers(&out));
        }
        // The next run finishes or cleans whatever was left and writes B whole.
        assert!(analyze(&out, "frame").wait().unwrap().success(), "{context}");
        assert!(matches(&out, &set_b), "{context}: not the new set after the next run");
        assert!(leftovers(&out).is_empty(), "{context}: left {:?}", leftovers(&out));
        assert!(!out.join(".ufcsr-commit.json").exists(), "{context}");
    }
    assert!(interrupted.iter().all(|&rounds| rounds > 0), "rounds interrupted by KILL, INT: {interrupted:?}");
}
