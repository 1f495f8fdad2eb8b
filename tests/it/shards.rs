//! Shards and merge: analysing an archive in N shards and merging the
//! results gives the same files, byte for byte, as analysing it whole; bad
//! merges (missing, repeated or mismatched shards) are clear errors.

use crate::common;

use std::path::{Path, PathBuf};

use ufcsr::{AnalyzeOptions, Dedupe, Shard, analyze, merge_results, output::write_results};

fn result_of(options: &AnalyzeOptions, out: &Path) -> PathBuf {
    let mut analysis = analyze(options, None).expect("analysis");
    write_results(&mut analysis, out).expect("write").result_json
}

fn shards_merge_to_the_whole(options: AnalyzeOptions, count: u32, dir: &Path) {
    let whole = result_of(&options, &dir.join("whole"));
    let shards: Vec<PathBuf> = (0..count)
        .map(|index| {
            let options =
                AnalyzeOptions { shard: Some(Shard::new(index, count).unwrap()), ..options.clone() };
            result_of(&options, &dir.join(format!("shard{index}")))
        })
        .collect();
    let mut merged = merge_results(&shards).expect("merge");
    let written = write_results(&mut merged, &dir.join("merged")).unwrap();
    for (a, b) in [
        (whole.clone(), written.result_json),
        (dir.join("whole/parts.csv"), dir.join("merged/parts.csv")),
        (dir.join("whole/heatmap.png"), dir.join("merged/heatmap.png")),
        (dir.join("whole/frames.csv"), dir.join("merged/frames.csv")),
    ] {
        if a.exists() {
            assert!(
                std::fs::read(&a).unwrap() == std::fs::read(&b).unwrap(),
                "{} differs from {}",
                b.display(),
                a.display()
            );
        }
    }
    // Missing and repeated shards are refused.
    let error = merge_results(&shards[1..]).err().expect("a shard is missing").to_string();
    assert!(error.contains("missing"), "{error}");
    let twice = [shards.clone(), vec![shards[0].clone()]].concat();
    assert!(merge_results(&twice).err().expect("given twice").to_string().contains("twice"));
}

#[test]
fn shards_of_a_captured_archive_merge_to_the_whole_byte_for_byte() {
    let example = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("fixtures/example");
    for (dedupe, frames) in [(Dedupe::Image, false), (Dedupe::Frame, false), (Dedupe::Image, true)] {
        let dir = tempfile::tempdir().unwrap();
        let options =
            AnalyzeOptions { archive: example.clone(), dedupe, frames, ..AnalyzeOptions::default() };
        shards_merge_to_the_whole(options, 4, dir.path());
        // frames.csv and the measures merge too.
        assert_eq!(dir.path().join("merged/frames.csv").exists(), frames);
    }
}

#[test]
fn shards_of_a_folder_without_manifest_merge_to_the_whole() {
    let dir = tempfile::tempdir().unwrap();
    common::known_archive(dir.path());
    shards_merge_to_the_whole(common::known_options(dir.path()), 3, &dir.path().join("out"));
    let options = AnalyzeOptions { frames: true, ..common::known_options(dir.path()) };
    shards_merge_to_the_whole(options, 3, &dir.path().join("out-frames"));
}

#[test]
fn results_of_different_settings_do_not_merge() {
    let example = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("fixtures/example");
    let dir = tempfile::tempdir().unwrap();
    let image = AnalyzeOptions {
        archive: example.clone(),
        shard: Some(Shard::new(0, 2).unwrap()),
        ..Default::default()
    };
    let frame =
        AnalyzeOptions { dedupe: Dedupe::Frame, shard: Some(Shard::new(1, 2).unwrap()), ..image.clone() };
    let a = result_of(&image, &dir.path().join("a"));
    let b = result_of(&frame, &dir.path().join("b"));
    let error = merge_results(&[a, b.clone()]).err().expect("mismatched settings").to_string();
    assert!(error.contains("dedupe") && error.contains(&b.display().to_string()), "{error}");
}
