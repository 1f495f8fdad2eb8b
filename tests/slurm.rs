//! A real Slurm job array: a throwaway single-node cluster
//! (`scripts/slurm/local-cluster`) runs a 4-shard analysis of the bundled
//! example through `sbatch --array` and an `afterok` merge job
//! (`scripts/slurm/submit`); the merged result.json must equal the
//! single-process one byte for byte. Skipped with a message where Slurm is
//! not installed or we are not root; a failure when `CI` is set.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

struct Cluster {
    dir: PathBuf,
}

impl Drop for Cluster {
    fn drop(&mut self) {
        let _ = Command::new(script("local-cluster")).arg("stop").arg(&self.dir).status();
    }
}

fn script(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("scripts/slurm").join(name)
}

fn slurm_available() -> bool {
    let installed = ["sbatch", "slurmctld", "slurmd", "munged"].iter().all(|tool| {
        Command::new("sh")
            .arg("-c")
            .arg(format!("command -v {tool}"))
            .output()
            .is_ok_and(|o| o.status.success())
    });
    let root = Command::new("id").arg("-u").output().is_ok_and(|o| o.stdout.starts_with(b"0"));
    installed && root
}

fn wait_for(path: &Path, limit: Duration) -> bool {
    let start = Instant::now();
    while start.elapsed() < limit {
        if path.is_file() {
            return true;
        }
        std::thread::sleep(Duration::from_millis(250));
    }
    false
}

#[test]
fn a_slurm_array_of_shards_and_an_afterok_merge_equal_the_whole_analysis() {
    if !slurm_available() {
        assert!(
            std::env::var_os("CI").is_none(),
            "CI: Slurm (slurmctld, slurmd, slurm-client, munge) or root is missing"
        );
        eprintln!(
            "SKIPPED: Slurm is not installed or this is not root (apt-get install slurmctld slurmd slurm-client munge)"
        );
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let cluster = Cluster { dir: dir.path().join("cluster") };
    let started = Command::new(script("local-cluster")).arg("start").arg(&cluster.dir).output().unwrap();
    assert!(started.status.success(), "local cluster: {}", String::from_utf8_lossy(&started.stderr));
    let conf = cluster.dir.join("slurm.conf");

    let example = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("fixtures/example").canonicalize().unwrap();
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
    if !wait_for(&merged, Duration::from_secs(180)) {
        let logs: String = std::fs::read_dir(&out)
            .map(|d| d.flatten().filter_map(|e| std::fs::read_to_string(e.path()).ok()).collect())
            .unwrap_or_default();
        panic!("the merge job did not finish in 3 minutes; job logs:\n{logs}");
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
}
