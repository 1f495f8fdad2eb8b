//! `--shard I/N` and `assemble`: a capture split over jobs writes the same
//! archive, byte for byte, as one process; a missing, doubled or foreign
//! shard is a clear error, and nothing is assembled.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn capture(out: &Path, extra: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_ufcsr-capture"))
        .args(["demo", "--scenario", "B", "--ppd", "3", "--palette-size", "256", "--frames", "0-180/6"])
        .arg("--out")
        .arg(out)
        .args(extra)
        .output()
        .expect("run ufcsr-capture")
}

fn succeed(output: Output) -> String {
    assert!(
        output.status.success(),
        "ufcsr-capture failed (is a Vulkan or GL driver installed?): {}",
        String::from_utf8_lossy(&output.stderr)
    );
    String::from_utf8_lossy(&output.stdout).into_owned()
}

fn assemble(archive: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_ufcsr-capture")).arg("assemble").arg(archive).output().unwrap()
}

/// Every file under `dir` (relative path → bytes).
fn files(dir: &Path) -> BTreeMap<PathBuf, Vec<u8>> {
    fn walk(root: &Path, dir: &Path, found: &mut BTreeMap<PathBuf, Vec<u8>>) {
        for entry in std::fs::read_dir(dir).unwrap().flatten() {
            let path = entry.path();
            if path.is_dir() {
                walk(root, &path, found);
            } else {
                found.insert(path.strip_prefix(root).unwrap().to_path_buf(), std::fs::read(&path).unwrap());
            }
        }
    }
    let mut found = BTreeMap::new();
    walk(dir, dir, &mut found);
    found
}

#[test]
fn shards_assemble_into_the_archive_one_process_writes() {
    let dir = tempfile::tempdir().unwrap();
    let whole = dir.path().join("whole");
    succeed(capture(&whole, &[]));
    let sharded = dir.path().join("sharded");
    // Shards in any order, into one folder; a leftover whole-archive
    // manifest and stale tiles are replaced.
    std::fs::create_dir_all(sharded.join("tiles")).unwrap();
    std::fs::copy(whole.join("manifest.json"), sharded.join("manifest.json")).unwrap();
    std::fs::write(sharded.join("tiles/f0006_left_r0_c0.png"), b"stale").unwrap();
    for index in [2, 0, 3, 1] {
        let said = succeed(capture(&sharded, &["--shard", &format!("{index}/4")]));
        assert!(said.contains("ufcsr assemble"), "the shard says what comes next: {said}");
    }
    assert!(!sharded.join("manifest.json").exists(), "a shard left the old whole-archive manifest");
    let said = succeed(assemble(&sharded));
    assert!(said.contains("4 shards, 31 frames"), "{said}");
    let (whole_files, sharded_files) = (files(&whole), files(&sharded));
    assert_eq!(
        whole_files.keys().collect::<Vec<_>>(),
        sharded_files.keys().collect::<Vec<_>>(),
        "the sharded archive holds other files"
    );
    for (path, bytes) in &whole_files {
        assert!(
            bytes == &sharded_files[path],
            "{} differs between the whole and the sharded capture",
            path.display()
        );
    }
    // And it verifies as any archive.
    let verified =
        Command::new(env!("CARGO_BIN_EXE_ufcsr-capture")).arg("verify").arg(&sharded).output().unwrap();
    assert!(verified.status.success(), "{}", String::from_utf8_lossy(&verified.stderr));
}

#[test]
fn a_missing_or_foreign_shard_is_refused_and_nothing_is_assembled() {
    let dir = tempfile::tempdir().unwrap();
    let archive = dir.path().join("a");
    succeed(capture(&archive, &["--shard", "0/3"]));
    succeed(capture(&archive, &["--shard", "2/3"]));
    let refused = assemble(&archive);
    assert!(!refused.status.success());
    let message = String::from_utf8_lossy(&refused.stderr);
    assert!(message.contains("shard 1/3 is missing"), "{message}");
    assert!(!archive.join("manifest.json").exists());

    // A shard of another setting (another eye height) is named, with the field.
    let other = capture(&archive, &["--shard", "1/3", "--rig", r#"{"eye_height_m": 1.6}"#]);
    succeed(other);
    let refused = assemble(&archive);
    assert!(!refused.status.success());
    let message = String::from_utf8_lossy(&refused.stderr);
    assert!(message.contains("manifest-1-of-3.json") && message.contains("differs"), "{message}");
    assert!(!archive.join("manifest.json").exists());

    // Nothing to assemble.
    let empty = dir.path().join("empty");
    std::fs::create_dir_all(&empty).unwrap();
    let message = String::from_utf8_lossy(&assemble(&empty).stderr).into_owned();
    assert!(message.contains("no shard manifests"), "{message}");
}

#[test]
fn shards_that_cannot_work_are_clear_errors() {
    let dir = tempfile::tempdir().unwrap();
    let archive = dir.path().join("a");
    for (extra, expected) in [
        (&["--shard", "3/3"][..], "shard 3/3"),
        (&["--shard", "40/41"][..], "has no frame"),
        (&["--shard", "0/2", "--count"][..], "--count with --shard"),
        (&["--shard", "auto"][..], "no job array index"),
    ] {
        let output = Command::new(env!("CARGO_BIN_EXE_ufcsr-capture"))
            .args([
                "demo",
                "--scenario",
                "B",
                "--ppd",
                "3",
                "--palette-size",
                "256",
                "--frames",
                "0-180/6",
                "-q",
            ])
            .arg("--out")
            .arg(&archive)
            .args(extra)
            .env_remove("SLURM_ARRAY_TASK_ID")
            .env_remove("JOB_COMPLETION_INDEX")
            .env_remove("AWS_BATCH_JOB_ARRAY_INDEX")
            .output()
            .unwrap();
        assert!(!output.status.success(), "{extra:?} succeeded");
        let message = String::from_utf8_lossy(&output.stderr);
        assert!(message.contains(expected), "{extra:?}: {message}");
    }
}
