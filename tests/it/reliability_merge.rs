//! Issue 19, scale-out: `merge` refuses shards of different archives at one
//! path, sums that overflow and impossible shard numbers (errors, never a
//! panic or a wrapped number); the merged result has the whole one's
//! `heatmap.glb` and views; Slurm arrays with a step map to shards or are
//! refused.

use std::path::{Path, PathBuf};

use ufcsr::{AnalyzeOptions, Shard, analyze, merge_results, output::write_results};

fn example() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("fixtures/example")
}

/// A copy of the example archive at `to`.
fn copy_example(to: &Path) {
    for entry in walk(&example()) {
        let target = to.join(entry.strip_prefix(example()).unwrap());
        std::fs::create_dir_all(target.parent().unwrap()).unwrap();
        std::fs::copy(&entry, &target).unwrap();
    }
}

fn walk(dir: &Path) -> Vec<PathBuf> {
    let mut files = Vec::new();
    for entry in std::fs::read_dir(dir).unwrap().flatten() {
        if entry.path().is_dir() {
            files.extend(walk(&entry.path()));
        } else {
            files.push(entry.path());
        }
    }
    files
}

fn shard_result(archive: &Path, index: u32, count: u32, out: &Path) -> PathBuf {
    let options = AnalyzeOptions {
        archive: archive.to_path_buf(),
        shard: Some(Shard::new(index, count).unwrap()),
        ..Default::default()
    };
    let mut analysis = analyze(&options, None).unwrap();
    write_results(&mut analysis, out).unwrap().result_json
}

#[test]
fn shards_of_two_archives_at_one_path_do_not_merge() {
    let dir = tempfile::tempdir().unwrap();
    let archive = dir.path().join("archive");
    copy_example(&archive);
    let a = shard_result(&archive, 0, 2, &dir.path().join("s0"));
    // Another capture analysed later under the same path: one tile fewer.
    let manifest = std::fs::read_to_string(archive.join("manifest.json")).unwrap();
    std::fs::write(archive.join("manifest.json"), manifest.replacen("25.31941", "25.5", 1)).unwrap();
    let b = shard_result(&archive, 1, 2, &dir.path().join("s1"));
    let error = merge_results(&[a, b.clone()]).err().expect("different archives merged").to_string();
    assert!(error.contains("archive identity") && error.contains(&b.display().to_string()), "{error}");
}

/// `result.json` at `path` with `edit` applied to its JSON.
fn edit_result(path: &Path, edit: impl Fn(&mut serde_json::Value)) {
    let mut value: serde_json::Value = serde_json::from_slice(&std::fs::read(path).unwrap()).unwrap();
    edit(&mut value);
    std::fs::write(path, serde_json::to_vec_pretty(&value).unwrap()).unwrap();
}

#[test]
fn impossible_shard_numbers_and_overflowing_sums_are_errors_not_panics() {
    let dir = tempfile::tempdir().unwrap();
    let shards: Vec<PathBuf> =
        (0..2).map(|i| shard_result(&example(), i, 2, &dir.path().join(format!("s{i}")))).collect();
    for (index, count) in [(5, 2), (0, 0), (2, 2)] {
        edit_result(&shards[1], |r| {
            r["settings"]["shard"] = serde_json::json!({"index": index, "count": count})
        });
        let error = merge_results(&shards).err().expect("a bad shard merged").to_string();
        assert!(error.contains(&shards[1].display().to_string()), "{error}");
    }
    edit_result(&shards[1], |r| r["settings"]["shard"] = serde_json::json!({"index": 1, "count": 2}));
    merge_results(&shards).expect("the shards merge again");
    edit_result(&shards[1], |r| r["images"]["found"] = serde_json::json!(u64::MAX));
    let error = merge_results(&shards).err().expect("an overflowing sum merged").to_string();
    assert!(error.contains("images.found") && error.contains("overflows"), "{error}");
}

#[test]
fn the_merged_result_has_the_vehicle_and_views_of_the_whole() {
    let dir = tempfile::tempdir().unwrap();
    let options = AnalyzeOptions { archive: example(), ..Default::default() };
    let mut whole = analyze(&options, None).unwrap();
    write_results(&mut whole, &dir.path().join("whole")).unwrap();
    let shards: Vec<PathBuf> =
        (0..3).map(|i| shard_result(&example(), i, 3, &dir.path().join(format!("s{i}")))).collect();
    let mut merged = merge_results(&shards).unwrap();
    write_results(&mut merged, &dir.path().join("merged")).unwrap();
    for name in ["heatmap.glb", "views.png", "result.json", "heatmap.png"] {
        let (a, b) = (dir.path().join("whole").join(name), dir.path().join("merged").join(name));
        assert!(b.is_file(), "the merged result has no {name}");
        assert!(std::fs::read(&a).unwrap() == std::fs::read(&b).unwrap(), "{name} differs from the whole");
    }
}

fn slurm(pairs: &[(&'static str, &'static str)]) -> ufcsr::Result<Option<Shard>> {
    Shard::from_job_array(|name| pairs.iter().find(|(k, _)| *k == name).map(|(_, v)| v.to_string()))
}

#[test]
fn slurm_arrays_map_min_max_and_step_or_are_refused() {
    // --array=0-6:2: tasks 0, 2, 4, 6 are shards 0..3 of 4.
    for (id, index) in [("0", 0), ("2", 1), ("4", 2), ("6", 3)] {
        let env = [
            ("SLURM_ARRAY_TASK_ID", id),
            ("SLURM_ARRAY_TASK_MIN", "0"),
            ("SLURM_ARRAY_TASK_MAX", "6"),
            ("SLURM_ARRAY_TASK_STEP", "2"),
            ("SLURM_ARRAY_TASK_COUNT", "4"),
        ];
        assert_eq!(slurm(&env).unwrap(), Some(Shard { index, count: 4 }), "task {id}");
    }
    // MIN/MAX without COUNT are enough.
    let env = [("SLURM_ARRAY_TASK_ID", "7"), ("SLURM_ARRAY_TASK_MIN", "5"), ("SLURM_ARRAY_TASK_MAX", "8")];
    assert_eq!(slurm(&env).unwrap(), Some(Shard { index: 2, count: 4 }));
    // The id alone: the number of shards is unknown.
    let error = slurm(&[("SLURM_ARRAY_TASK_ID", "3")]).unwrap_err().to_string();
    assert!(error.contains("SLURM_ARRAY_TASK_COUNT"), "{error}");
    // --array=1,3,8 (a list): COUNT 3 disagrees with 1-8.
    let list = [
        ("SLURM_ARRAY_TASK_ID", "3"),
        ("SLURM_ARRAY_TASK_MIN", "1"),
        ("SLURM_ARRAY_TASK_MAX", "8"),
        ("SLURM_ARRAY_TASK_COUNT", "3"),
    ];
    assert!(slurm(&list).unwrap_err().to_string().contains("list"));
    // An id off the step.
    let off = [
        ("SLURM_ARRAY_TASK_ID", "3"),
        ("SLURM_ARRAY_TASK_MIN", "0"),
        ("SLURM_ARRAY_TASK_MAX", "6"),
        ("SLURM_ARRAY_TASK_STEP", "2"),
    ];
    assert!(slurm(&off).unwrap_err().to_string().contains("STEP"));
}
