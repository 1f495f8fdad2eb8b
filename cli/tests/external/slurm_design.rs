//! A design as a real Slurm job array on a throwaway local cluster:
//! `scripts/slurm/submit-design` runs each task of the 2 × 2 design (one
//! replicate) as one array task and merges them in an `afterok` job; the
//! merged `design.json` must equal a one-process `design run` + `merge`
//! byte for byte. Ignored with the reason without Slurm or root; a failure
//! when `CI` is set.

use std::path::Path;
use std::process::Command;
use std::time::Duration;

use libtest_mimic::Completion;

use crate::need::{Outcome, missing};
use crate::slurm_support::{logs, script, slurm_available, start_cluster, wait_for};

const NEED_SLURM: &str = "Slurm and root (apt-get install slurmctld slurmd slurm-client munge)";

pub fn a_design_runs_as_a_slurm_array_and_its_afterok_merge_equals_one_process() -> Outcome {
    if !slurm_available() {
        return missing(NEED_SLURM);
    }
    let (_one, dir, cluster) = start_cluster(true, NEED_SLURM).expect("Slurm was found just now");
    let fixture = Path::new(env!("CARGO_MANIFEST_DIR")).join("../fixtures/designs/tiny-2x2.json");
    let mut design: serde_json::Value = serde_json::from_slice(&std::fs::read(fixture).unwrap()).unwrap();
    design["replicates"] = 1.into();
    let file = dir.path().join("design.json");
    std::fs::write(&file, serde_json::to_vec(&design).unwrap()).unwrap();
    let ufcsr = env!("CARGO_BIN_EXE_ufcsr");
    let out = dir.path().join("array");
    let submitted = Command::new(script("submit-design"))
        .arg(&file)
        .arg(&out)
        .arg(ufcsr)
        .env("SLURM_CONF", cluster.conf())
        .output()
        .unwrap();
    assert!(submitted.status.success(), "{}", String::from_utf8_lossy(&submitted.stderr));
    let merged = out.join("design.json");
    if !wait_for(std::slice::from_ref(&merged), Duration::from_secs(600)) {
        panic!("the design's merge job did not finish in 10 minutes; job logs:\n{}", logs(&out));
    }
    for index in 0..4 {
        assert!(out.join(format!("tasks/task-{index:04}/task.json")).is_file(), "task {index} missing");
    }
    let whole = dir.path().join("whole");
    let whole_text = whole.to_str().unwrap();
    let file_text = file.to_str().unwrap();
    for action in ["run", "merge"] {
        let status = Command::new(ufcsr)
            .args(["design", action, file_text, "--out", whole_text, "--quiet"])
            .env("XDG_RUNTIME_DIR", dir.path())
            .status()
            .unwrap();
        assert!(status.success(), "design {action}");
    }
    assert!(
        std::fs::read(whole.join("design.json")).unwrap() == std::fs::read(&merged).unwrap(),
        "the merged design differs from the one-process run"
    );
    drop(cluster);
    Ok(Completion::Completed)
}
