//! `scripts/manifest-from-tiles.py` (deprecated: a wrapper of `ufcsr-analyze
//! manifest`): a Unity-style folder of tiles gets a manifest the analyzer
//! accepts, with eye-frame grouping from the names; its old options still work.
//! Ignored (with the reason) when `python3` is not installed.

use crate::common;
use crate::need::{Outcome, missing, runs};
use libtest_mimic::Completion;

use std::process::Command;

use common::*;
use ufcsr::{AnalyzeOptions, Dedupe, analyze};

pub fn unity_named_tiles_get_a_working_manifest() -> Outcome {
    if !runs("python3") {
        return missing("python3");
    }
    let dir = tempfile::tempdir().unwrap();
    let archive = dir.path();
    rgb_png(&archive.join("Left_0001_0_0.png"), 2, 1, &[1, 2]);
    rgb_png(&archive.join("Left_0001_0_1.png"), 2, 1, &[1, BG]);
    rgb_png(&archive.join("Right_0001_0_0.png"), 2, 1, &[1, BG]);
    rgb_png(&archive.join("pidt.png"), 4, 4, &[0xFF0000; 16]);
    std::fs::write(archive.join("parts.csv"), "name,color\nBody,#FF0000\n").unwrap();
    let script = concat!(env!("CARGO_MANIFEST_DIR"), "/../scripts/manifest-from-tiles.py");
    let run = |pattern: &str| {
        Command::new("python3")
            .env("UFCSR_ANALYZE", env!("CARGO_BIN_EXE_ufcsr-analyze"))
            .current_dir(archive)
            .arg(script)
            .arg(".")
            .args(["--pattern", pattern, "--palette", "4x4", "--pidt", "pidt.png", "--parts", "parts.csv"])
            .arg("--missing-tiles-empty")
            // A tile is missing: the grid must be given (the tiles present cannot tell it).
            .args(["--grid", "2x1"])
            .output()
            .unwrap()
    };
    let wrong = run(r"f(?P<frame>\d+)_(?P<eye>\w+)_r(?P<row>\d+)_c(?P<col>\d+)\.png$");
    assert_eq!(wrong.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&wrong.stderr).contains("do not match"));
    assert!(!archive.join("manifest.json").exists(), "nothing written on error");

    let ok = run(r"(?P<eye>Left|Right)_(?P<frame>\d+)_(?P<row>\d+)_(?P<col>\d+)\.png$");
    assert!(ok.status.success(), "{}", String::from_utf8_lossy(&ok.stderr));
    let per_frame = analyze(
        &AnalyzeOptions { archive: archive.to_path_buf(), dedupe: Dedupe::Frame, ..Default::default() },
        None,
    )
    .unwrap();
    // Right_0001_0_1 was never written: --missing-tiles-empty lists it as empty (counted as trimmed).
    assert_eq!(per_frame.result.images.found, 4, "three files and one listed empty; the PIdT is not a tile");
    assert_eq!(per_frame.result.images.listed_empty, 1);
    assert_eq!(per_frame.texel_counts[1..3], [2, 1], "texel 1: once per eye-frame, two eye-frames");
    assert_eq!(per_frame.result.parts[0].total, 3);
    Ok(Completion::Completed)
}
