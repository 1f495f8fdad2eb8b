//! A batch through a real Slurm job array: `scripts/slurm/submit-batch` runs
//! each task of a two-task batch (`ufcsr-capture batch plan`) as one array
//! task on a throwaway local cluster; both must leave a result.json equal to
//! running the same command directly. Skipped without Slurm or root; a
//! failure when `CI` is set.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

fn script(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../scripts/slurm").join(name)
}

struct Cluster(PathBuf);

impl Drop for Cluster {
    fn drop(&mut self) {
        let _ = Command::new(script("local-cluster")).arg("stop").arg(&self.0).status();
    }
}

fn slurm_available() -> bool {
    let installed = ["sbatch", "slurmctld", "slurmd", "munged"].iter().all(|tool| {
        Command::new("sh")
            .arg("-c")
            .arg(format!("command -v {tool}"))
            .output()
            .is_ok_and(|o| o.status.success())
    });
    installed && Command::new("id").arg("-u").output().is_ok_and(|o| o.stdout.starts_with(b"0"))
}

fn wait_for(paths: &[PathBuf], limit: Duration) -> bool {
    let start = Instant::now();
    while start.elapsed() < limit {
        if paths.iter().all(|p| p.is_file()) {
            return true;
        }
        std::thread::sleep(Duration::from_millis(250));
    }
    false
}

#[test]
fn a_batch_runs_as_a_slurm_array_one_task_per_setting() {
    if !slurm_available() {
        assert!(
            std::env::var_os("CI").is_none(),
            "CI: Slurm (slurmctld, slurmd, slurm-client, munge) or root is missing"
        );
        eprintln!("SKIPPED: Slurm is not installed or this is not root");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let cluster = Cluster(dir.path().join("cluster"));
    let started = Command::new(script("local-cluster")).arg("start").arg(&cluster.0).output().unwrap();
    assert!(started.status.success(), "{}", String::from_utf8_lossy(&started.stderr));
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
        .env("SLURM_CONF", cluster.0.join("slurm.conf"))
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
        .args(["demo", "--scenario", "B", "--ppd", "3", "--frames", "0-180/10", "--palette-size", "256"])
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
}
