//! Issue 19, outputs: nothing is written outside `--out` or over an input.
//! A link inside `--out` (`views/`, `plots/`, `result.json`) is replaced,
//! never written through; `heatmap` and `report` refuse to replace their own
//! inputs; staging folders of killed runs are removed by the next run, and a
//! smaller re-run takes away the earlier run's plots.

use crate::common;

use std::path::{Path, PathBuf};

fn example() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fixtures/example")
}

/// Runs the analyzer on the example archive into `out`; returns its stderr.
fn analyze_example(out: &Path, extra: &[&str]) -> String {
    let output =
        common::analyzer().arg(example()).arg("--out").arg(out).arg("-q").args(extra).output().unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr).into_owned();
    assert!(output.status.success(), "{stderr}");
    stderr
}

/// Every file below `dir` with its bytes, sorted.
fn snapshot(dir: &Path) -> Vec<(PathBuf, Vec<u8>)> {
    let mut files = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(folder) = stack.pop() {
        for entry in std::fs::read_dir(&folder).unwrap().flatten() {
            let path = entry.path();
            if path.is_dir() {
                stack.push(path);
            } else {
                files.push((path.clone(), std::fs::read(&path).unwrap()));
            }
        }
    }
    files.sort();
    files
}

#[cfg(unix)]
#[test]
fn links_inside_out_are_replaced_and_never_written_through() {
    let dir = tempfile::tempdir().unwrap();
    let elsewhere = dir.path().join("elsewhere");
    std::fs::create_dir_all(elsewhere.join("views")).unwrap();
    std::fs::create_dir_all(elsewhere.join("plots")).unwrap();
    std::fs::write(elsewhere.join("views/front.png"), b"someone else's picture").unwrap();
    std::fs::write(elsewhere.join("plots/parts.svg"), b"someone else's plot").unwrap();
    std::fs::write(elsewhere.join("result.json"), b"someone else's result").unwrap();
    let before = snapshot(&elsewhere);

    let out = dir.path().join("out");
    std::fs::create_dir_all(&out).unwrap();
    std::os::unix::fs::symlink(elsewhere.join("views"), out.join("views")).unwrap();
    std::os::unix::fs::symlink(elsewhere.join("plots"), out.join("plots")).unwrap();
    std::os::unix::fs::symlink(elsewhere.join("result.json"), out.join("result.json")).unwrap();
    analyze_example(&out, &["--figures", "all"]);
    assert_eq!(snapshot(&elsewhere), before, "a file outside --out was changed");
    for name in ["views", "plots", "result.json"] {
        let metadata = std::fs::symlink_metadata(out.join(name)).unwrap();
        assert!(!metadata.file_type().is_symlink(), "{name} is still a link");
    }
    assert!(out.join("views/front.png").is_file() && out.join("plots/parts.svg").is_file());
}

#[test]
fn heatmap_refuses_to_replace_its_own_result() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("R");
    analyze_example(&out, &[]);
    let result = out.join("result.json");
    let before = std::fs::read(&result).unwrap();
    for target in [result.clone(), out.join(".").join("result.json"), dir.path().join("R/../R/result.json")] {
        let output =
            common::analyzer().arg("heatmap").arg(&result).arg("--out").arg(&target).output().unwrap();
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(2), "{stderr}");
        assert!(stderr.contains("would overwrite the input"), "{stderr}");
        assert_eq!(std::fs::read(&result).unwrap(), before, "heatmap replaced its own input");
    }
}

#[test]
fn report_refuses_to_write_into_a_compared_results_folder() {
    let dir = tempfile::tempdir().unwrap();
    let (a, b) = (dir.path().join("A"), dir.path().join("B"));
    analyze_example(&a, &[]);
    analyze_example(&b, &["--scale", "log"]);
    let before = snapshot(&a);
    for out in [a.clone(), a.join(".")] {
        let output =
            common::analyzer().arg("report").arg(&a).arg(&b).arg("--out").arg(&out).output().unwrap();
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(2), "{stderr}");
        assert!(stderr.contains("folder of the compared result"), "{stderr}");
    }
    assert_eq!(snapshot(&a), before, "report changed a compared result set");
    // Elsewhere is fine.
    let output = common::analyzer()
        .arg("report")
        .arg(&a)
        .arg(&b)
        .arg("--out")
        .arg(dir.path().join("cmp"))
        .output()
        .unwrap();
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
}

#[test]
fn the_next_run_removes_staging_folders_that_killed_runs_left() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    std::fs::create_dir_all(&out).unwrap();
    // A run killed with SIGKILL (pid gone), and one of an older version's naming.
    for stale in [".ufcsr-staging-4000000000-0", ".ufcsr-staging-Ab3xYz"] {
        std::fs::create_dir_all(out.join(stale).join("views")).unwrap();
        std::fs::write(out.join(stale).join("heatmap.png"), vec![0u8; 1 << 16]).unwrap();
    }
    // A live process's (pid 1 runs): not ours to remove.
    std::fs::create_dir_all(out.join(".ufcsr-staging-1-0")).unwrap();
    analyze_example(&out, &[]);
    assert!(!out.join(".ufcsr-staging-4000000000-0").exists(), "a dead run's staging folder is left");
    assert!(!out.join(".ufcsr-staging-Ab3xYz").exists(), "an old-style staging folder is left");
    if cfg!(target_os = "linux") {
        assert!(out.join(".ufcsr-staging-1-0").is_dir(), "a live process's staging folder was removed");
    }
}

#[test]
fn a_rerun_without_frames_takes_away_the_earlier_runs_plots() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    analyze_example(&out, &["--figures", "all"]);
    assert!(out.join("plots/visibility-time.svg").is_file(), "the first run drew no time plot");
    std::fs::write(out.join("plots/my-plot.svg"), b"mine").unwrap();
    analyze_example(&out, &["--frames-csv", "off", "--figures", "all"]);
    let plots: Vec<String> = std::fs::read_dir(out.join("plots"))
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    assert!(plots.iter().all(|name| !name.starts_with("visibility-")), "stale plots left: {plots:?}");
    assert!(out.join("plots/parts.svg").is_file());
    assert_eq!(std::fs::read(out.join("plots/my-plot.svg")).unwrap(), b"mine");
}
