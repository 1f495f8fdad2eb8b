//! Sums and shares are bit-identical whatever the order of the work (thread
//! count, tile order in the manifest, order of merged shards), and counts
//! that reach the most a `u32` holds saturate and are reported.

use std::path::{Path, PathBuf};

use ufcsr::{AnalyzeOptions, Shard, analyze, merge_results, output::write_results};

fn example() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("fixtures/example")
}

fn result_json(options: &AnalyzeOptions, out: &Path) -> Vec<u8> {
    let mut analysis = analyze(options, None).expect("analysis");
    let written = write_results(&mut analysis, out).expect("write");
    std::fs::read(written.result_json).unwrap()
}

/// result.json without the fields that name where the inputs were.
fn without_paths(bytes: &[u8]) -> serde_json::Value {
    let mut value: serde_json::Value = serde_json::from_slice(bytes).unwrap();
    for field in ["archive", "pidt", "parts"] {
        value["settings"][field] = serde_json::Value::Null;
    }
    // The identity digests the manifest's bytes: a reordered manifest is
    // another file (merge refuses to mix their shards), the counts are not.
    value["settings"]["archive_identity"] = serde_json::Value::Null;
    value
}

#[test]
fn the_result_is_bit_identical_for_any_thread_count() {
    let dir = tempfile::tempdir().unwrap();
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        let options = AnalyzeOptions { archive: example(), ..AnalyzeOptions::default() };
        pool.install(|| result_json(&options, &dir.path().join(format!("t{threads}"))))
    };
    let one = run(1);
    for threads in [2, 3, 8] {
        assert!(run(threads) == one, "{threads} threads give another result.json than 1");
    }
}

#[test]
fn the_result_is_bit_identical_whatever_the_tile_order() {
    let dir = tempfile::tempdir().unwrap();
    let copy = dir.path().join("reversed");
    std::fs::create_dir_all(copy.join("tiles")).unwrap();
    for name in ["pidt.png", "parts.csv", "vehicle.glb"] {
        std::fs::copy(example().join(name), copy.join(name)).unwrap();
    }
    for entry in std::fs::read_dir(example().join("tiles")).unwrap().flatten() {
        std::fs::copy(entry.path(), copy.join("tiles").join(entry.file_name())).unwrap();
    }
    let mut manifest: serde_json::Value =
        serde_json::from_slice(&std::fs::read(example().join("manifest.json")).unwrap()).unwrap();
    manifest["tiles"].as_array_mut().unwrap().reverse();
    manifest["frames"].as_array_mut().unwrap().reverse();
    std::fs::write(copy.join("manifest.json"), serde_json::to_vec_pretty(&manifest).unwrap()).unwrap();

    let original = result_json(
        &AnalyzeOptions { archive: example(), ..AnalyzeOptions::default() },
        &dir.path().join("a"),
    );
    let reversed =
        result_json(&AnalyzeOptions { archive: copy, ..AnalyzeOptions::default() }, &dir.path().join("b"));
    assert_eq!(without_paths(&original), without_paths(&reversed));
}

#[test]
fn shards_merge_to_the_same_bytes_in_any_order() {
    let dir = tempfile::tempdir().unwrap();
    let shards: Vec<PathBuf> = (0..3)
        .map(|index| {
            let options = AnalyzeOptions {
                archive: example(),
                shard: Some(Shard::new(index, 3).unwrap()),
                ..AnalyzeOptions::default()
            };
            let out = dir.path().join(format!("shard{index}"));
            result_json(&options, &out);
            out.join("result.json")
        })
        .collect();
    let merged = |order: &[usize], name: &str| {
        let paths: Vec<PathBuf> = order.iter().map(|&i| shards[i].clone()).collect();
        let mut analysis = merge_results(&paths).expect("merge");
        std::fs::read(write_results(&mut analysis, &dir.path().join(name)).unwrap().result_json).unwrap()
    };
    let forward = merged(&[0, 1, 2], "m012");
    for (order, name) in [([2, 1, 0], "m210"), ([1, 2, 0], "m120")] {
        assert!(merged(&order, name) == forward, "merging in order {order:?} gives other bytes");
    }
}

#[test]
fn counts_saturate_at_the_u32_maximum_and_the_result_says_so() {
    let dir = tempfile::tempdir().unwrap();
    // Two shards whose first seen texel was counted 3·10⁹ times each (as by
    // a 10⁶-frame run merged with others): their sum does not fit a u32.
    let shards: Vec<PathBuf> = (0..2)
        .map(|index| {
            let options = AnalyzeOptions {
                archive: example(),
                shard: Some(Shard::new(index, 2).unwrap()),
                ..AnalyzeOptions::default()
            };
            let out = dir.path().join(format!("shard{index}"));
            result_json(&options, &out);
            let path = out.join("result.json");
            let mut value: serde_json::Value =
                serde_json::from_slice(&std::fs::read(&path).unwrap()).unwrap();
            value["texel_counts"]["count"][0] = serde_json::json!(3_000_000_000u32);
            std::fs::write(&path, serde_json::to_vec(&value).unwrap()).unwrap();
            path
        })
        .collect();
    let first_texel = |path: &Path| {
        let value: serde_json::Value = serde_json::from_slice(&std::fs::read(path).unwrap()).unwrap();
        value["texel_counts"]["texel_delta"][0].as_u64().unwrap()
    };
    assert_eq!(first_texel(&shards[0]), first_texel(&shards[1]), "the shards should share their first texel");
    let merged = merge_results(&shards).expect("merge");
    assert_eq!(merged.result.max_count, u32::MAX);
    assert_eq!(merged.texel_counts[first_texel(&shards[0]) as usize], u32::MAX);
    assert!(
        merged
            .result
            .warnings
            .iter()
            .any(|w| w.contains("1 texels reached 4294967295") && w.contains("lower bounds")),
        "{:?}",
        merged.result.warnings
    );
}

/// Shards keep their integer per-texel sums (`texel-area.units`), and a
/// merge adds them: its per-texel angular area and `texel-area.f32` are the
/// whole analysis' to the bit, in any order (the `f32` values of the shards
/// alone would not add up to it).
#[test]
fn shards_merge_the_per_texel_angular_area_to_the_whole_analysis_bits() {
    let dir = tempfile::tempdir().unwrap();
    let whole_options = AnalyzeOptions { archive: example(), frames: true, ..AnalyzeOptions::default() };
    let mut whole = analyze(&whole_options, None).expect("analysis");
    let whole_written = write_results(&mut whole, &dir.path().join("whole")).unwrap();
    assert!(whole_written.texel_area_units.is_none(), "a whole analysis keeps no sums");
    let whole_area = whole.texel_angular_area.clone().expect("the example has the eyes' projection");
    let shards: Vec<PathBuf> = (0..3)
        .map(|index| {
            let options =
                AnalyzeOptions { shard: Some(Shard::new(index, 3).unwrap()), ..whole_options.clone() };
            let mut analysis = analyze(&options, None).expect("shard");
            let written = write_results(&mut analysis, &dir.path().join(format!("s{index}"))).unwrap();
            assert!(written.texel_area_units.is_some_and(|f| f.is_file()), "a shard keeps its sums");
            written.result_json
        })
        .collect();
    for (order, name) in [([0, 1, 2], "m012"), ([2, 0, 1], "m201")] {
        let paths: Vec<PathBuf> = order.iter().map(|&i| shards[i].clone()).collect();
        let mut merged = merge_results(&paths).expect("merge");
        assert!(
            merged.texel_angular_area.as_ref() == Some(&whole_area),
            "merge {order:?} differs from the whole"
        );
        let written = write_results(&mut merged, &dir.path().join(name)).unwrap();
        let bytes = |path: Option<PathBuf>| std::fs::read(path.unwrap()).unwrap();
        assert!(
            bytes(written.texel_area) == bytes(whole_written.texel_area.clone()),
            "texel-area.f32 differs"
        );
    }
    // A shard without its sums: no area (the count is drawn), not a wrong one.
    std::fs::remove_file(shards[1].parent().unwrap().join(ufcsr::TEXEL_AREA_UNITS_FILE)).unwrap();
    assert!(merge_results(&shards).unwrap().texel_angular_area.is_none());
}
