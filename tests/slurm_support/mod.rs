//! A throwaway local Slurm cluster for tests (`scripts/slurm/local-cluster`),
//! shared by the root crate's and the capture crate's Slurm tests.

#![allow(dead_code)] // each test crate uses its own part

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::{Mutex, MutexGuard, PoisonError};
use std::time::{Duration, Instant};

/// One local cluster at a time: they listen on Slurm's fixed ports.
static ONE_CLUSTER: Mutex<()> = Mutex::new(());

/// A script of `scripts/slurm/`, from either crate.
pub fn script(name: &str) -> PathBuf {
    let crate_dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let here = crate_dir.join("scripts/slurm");
    let dir = if here.is_dir() { here } else { crate_dir.join("../scripts/slurm") };
    dir.join(name)
}

/// True when Slurm and munge are installed and this is root.
pub fn slurm_available() -> bool {
    let installed = ["sbatch", "slurmctld", "slurmd", "munged"].iter().all(|tool| {
        Command::new("sh")
            .arg("-c")
            .arg(format!("command -v {tool}"))
            .output()
            .is_ok_and(|o| o.status.success())
    });
    installed && Command::new("id").arg("-u").output().is_ok_and(|o| o.stdout.starts_with(b"0"))
}

/// Waits (bounded) until every path is a file.
pub fn wait_for(paths: &[PathBuf], limit: Duration) -> bool {
    let start = Instant::now();
    while start.elapsed() < limit {
        if paths.iter().all(|p| p.is_file()) {
            return true;
        }
        std::thread::sleep(Duration::from_millis(250));
    }
    false
}

/// The cluster's folder; stopping it on drop.
pub struct Cluster(pub PathBuf);

impl Cluster {
    pub fn conf(&self) -> PathBuf {
        self.0.join("slurm.conf")
    }
}

impl Drop for Cluster {
    fn drop(&mut self) {
        let _ = Command::new(script("local-cluster")).arg("stop").arg(&self.0).status();
    }
}

/// A running local cluster in a fresh temporary folder (one at a time); or
/// `None`, skipped with a message (a failure under CI), when Slurm, root or
/// `extra_need` is missing.
pub fn start_cluster(
    extra_need: bool,
    missing: &str,
) -> Option<(MutexGuard<'static, ()>, tempfile::TempDir, Cluster)> {
    if !(slurm_available() && extra_need) {
        assert!(std::env::var_os("CI").is_none(), "CI: {missing} is missing");
        eprintln!("SKIPPED: {missing} is missing");
        return None;
    }
    let one = ONE_CLUSTER.lock().unwrap_or_else(PoisonError::into_inner);
    let dir = tempfile::tempdir().unwrap();
    let cluster = Cluster(dir.path().join("cluster"));
    let started = Command::new(script("local-cluster")).arg("start").arg(&cluster.0).output().unwrap();
    assert!(started.status.success(), "local cluster: {}", String::from_utf8_lossy(&started.stderr));
    Some((one, dir, cluster))
}

/// The job logs in `dir`, for a failure message.
pub fn logs(dir: &Path) -> String {
    std::fs::read_dir(dir)
        .map(|d| d.flatten().filter_map(|e| std::fs::read_to_string(e.path()).ok()).collect())
        .unwrap_or_default()
}
