//! Real Slurm job arrays on a throwaway local cluster: a batch
//! (`scripts/slurm/submit-batch` runs each task of `ufcsr batch plan`
//! as one array task; each result.json must equal running the command
//! directly), and a sharded capture (`scripts/slurm/submit-capture`: a capture
//! array, an afterok assemble, an analysis array and an afterok merge; the
//! archive and the merged result must equal one process's). Ignored with the
//! reason without Slurm or root; a failure when `CI` is set.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Duration;

use libtest_mimic::Completion;

use crate::need::{Outcome, missing};
use crate::slurm_support::{logs, script, slurm_available, start_cluster, wait_for};

const NEED_SLURM: &str = "Slurm and root (apt-get install slurmctld slurmd slurm-client munge)";

pub fn a_batch_runs_as_a_slurm_array_one_task_per_setting() -> Outcome {
    if !slurm_available() {
        return missing(NEED_SLURM);
    }
    let (_one, dir, cluster) = start_cluster(true, NEED_SLURM).expect("Slurm was found just now");
    let runs = dir.path().join("runs");
    let batch = dir.path().join("batch.json");
    std::fs::write(
        &batch,
        format!(
            r#"{{"out": "{}", "scenes": ["demo"], "scenarios": ["B"], "ppd": [3], "frame_step": [10, 20], "palette_size": "256"}}"#,
            runs.display()
        ),
    )
    .unwrap();
    let capture = env!("CARGO_BIN_EXE_ufcsr-capture");
    let submitted = Command::new(script("submit-batch"))
        .arg(&batch)
        .arg(capture)
        .env("SLURM_CONF", cluster.conf())
        .output()
        .unwrap();
    assert!(submitted.status.success(), "{}", String::from_utf8_lossy(&submitted.stderr));
    let results: Vec<PathBuf> = [10, 20]
        .iter()
        .map(|step| runs.join(format!("0-demo/B/ppd3-step{step}/results/result.json")))
        .collect();
    assert!(wait_for(&results, Duration::from_secs(180)), "the array tasks did not finish in 3 minutes");
    // The same command run directly gives the same result.
    let direct = dir.path().join("direct");
    let status = Command::new(capture)
        .args(["demo", "--scenario", "B", "--ppd", "3", "--frames", "all/10", "--palette-size", "256"])
        .args(["--count", "--quiet", "--out"])
        .arg(&direct)
        .stdout(std::process::Stdio::null())
        .status()
        .unwrap();
    assert!(status.success());
    let strip = |path: &Path| {
        let mut value: serde_json::Value = serde_json::from_slice(&std::fs::read(path).unwrap()).unwrap();
        for key in ["archive", "pidt", "parts"] {
            value["settings"][key] = serde_json::Value::Null;
        }
        value
    };
    assert_eq!(strip(&results[0]), strip(&direct.join("results/result.json")));
    drop(cluster);
    Ok(Completion::Completed)
}

/// The analyzer built beside this crate's binary (by `cargo test --workspace`).
fn analyzer() -> Option<PathBuf> {
    let path = Path::new(env!("CARGO_BIN_EXE_ufcsr-capture")).with_file_name("ufcsr-analyze");
    path.is_file().then_some(path)
}

pub fn a_sharded_capture_assembles_and_analyses_through_slurm_equal_to_one_process() -> Outcome {
    if !slurm_available() {
        return missing(NEED_SLURM);
    }
    let Some(analyzer) = analyzer() else {
        return missing("ufcsr-analyze beside ufcsr-capture (cargo test --workspace builds it)");
    };
    let (_one, dir, cluster) = start_cluster(true, NEED_SLURM).expect("Slurm was found just now");
    let capture = env!("CARGO_BIN_EXE_ufcsr-capture");
    let setting = ["demo", "--scenario", "B", "--ppd", "3", "--frames", "0-180/4", "--palette-size", "256"];
    let run = dir.path().join("run");
    let submitted = Command::new(script("submit-capture"))
        .arg(&run)
        .arg("4")
        .arg(capture)
        .arg(&analyzer)
        .args(setting)
        .env("SLURM_CONF", cluster.conf())
        .output()
        .unwrap();
    assert!(submitted.status.success(), "{}", String::from_utf8_lossy(&submitted.stderr));
    let merged = run.join("analysis/merged/result.json");
    if !wait_for(std::slice::from_ref(&merged), Duration::from_secs(240)) {
        panic!(
            "the capture, assemble, analysis and merge jobs did not finish in 4 minutes; logs:\n{}",
            logs(&run)
        );
    }
    // The assembled archive is the one a single process captures...
    let whole = dir.path().join("whole");
    let status = Command::new(capture)
        .args(setting)
        .args(["--quiet", "--out"])
        .arg(&whole)
        .stdout(std::process::Stdio::null())
        .status()
        .unwrap();
    assert!(status.success());
    let archive = run.join("archive");
    assert!(
        std::fs::read(whole.join("manifest.json")).unwrap()
            == std::fs::read(archive.join("manifest.json")).unwrap(),
        "the assembled manifest differs from the single-process capture's"
    );
    for entry in std::fs::read_dir(whole.join("tiles")).unwrap().flatten() {
        let sharded = archive.join("tiles").join(entry.file_name());
        assert!(
            std::fs::read(entry.path()).unwrap() == std::fs::read(&sharded).unwrap(),
            "{}",
            sharded.display()
        );
    }
    // ...and the merged analysis is the single-process analysis of it.
    let single = dir.path().join("single");
    let status =
        Command::new(&analyzer).arg(&archive).arg("--out").arg(&single).arg("--quiet").status().unwrap();
    assert!(status.success());
    assert!(
        std::fs::read(single.join("result.json")).unwrap() == std::fs::read(&merged).unwrap(),
        "the merged result differs from the single-process analysis"
    );
    drop(cluster);
    Ok(Completion::Completed)
}
