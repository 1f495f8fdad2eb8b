//! A real Slurm job array: a throwaway single-node cluster
//! (`scripts/slurm/local-cluster`) runs a 4-shard analysis of the bundled
//! example through `sbatch --array` and an `afterok` merge job
//! (`scripts/slurm/submit`); the merged result.json must equal the
//! single-process one byte for byte. Ignored (with the reason) where Slurm
//! is not installed or we are not root; a failure when `CI` is set.

use crate::need::{Outcome, missing};
use crate::slurm_support;
use libtest_mimic::Completion;

use std::path::PathBuf;
use std::process::Command;
use std::time::Duration;

use slurm_support::{logs, script, slurm_available, start_cluster, wait_for};

pub fn a_slurm_array_of_shards_and_an_afterok_merge_equal_the_whole_analysis() -> Outcome {
    const NEED: &str = "Slurm and root (apt-get install slurmctld slurmd slurm-client munge)";
    if !slurm_available() {
        return missing(NEED);
    }
    let (_one, dir, cluster) = start_cluster(true, NEED).expect("Slurm was found just now");
    let conf = cluster.conf();

    let example =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fixtures/example").canonicalize().unwrap();
    let out = dir.path().join("out");
    let analyzer = env!("CARGO_BIN_EXE_ufcsr-analyze");
    let submitted = Command::new(script("submit"))
        .arg(&example)
        .arg(&out)
        .args(["4", analyzer])
        .env("SLURM_CONF", &conf)
        .output()
        .unwrap();
    assert!(submitted.status.success(), "sbatch: {}", String::from_utf8_lossy(&submitted.stderr));

    let merged = out.join("merged/result.json");
    if !wait_for(std::slice::from_ref(&merged), Duration::from_secs(180)) {
        panic!("the merge job did not finish in 3 minutes; job logs:\n{}", logs(&out));
    }
    // Every shard ran as an array task.
    for index in 0..4 {
        assert!(out.join(format!("shard-{index}/result.json")).is_file(), "shard {index} missing");
    }
    let whole = dir.path().join("whole");
    let status = Command::new(analyzer).arg(&example).arg("--out").arg(&whole).arg("-q").status().unwrap();
    assert!(status.success());
    assert!(
        std::fs::read(whole.join("result.json")).unwrap() == std::fs::read(&merged).unwrap(),
        "the merged result differs from the single-process one"
    );
    drop(cluster);
    Ok(Completion::Completed)
}
