//! What the capture writes holds to the published JSON Schemas
//! (`docs/schemas/`): the manifest of a PNG capture, of a shard, of a
//! `--count` capture and of a `--measure unobstructed` capture, and the
//! `result.json` each of the last two writes and the analyzer writes for the
//! first. The capture's own manifest objects (frames, rig, unwrap, capture)
//! are closed in the schema, so a new field there fails here until the schema
//! and `docs/archive-format.md` describe it.

use std::path::{Path, PathBuf};
use std::process::Command;

use serde_json::Value;

#[path = "../../../docs/schemas/validator.rs"]
pub mod validator;

use validator::{Schema, read_json};

/// A schema of the workspace's `docs/schemas/`.
pub(crate) fn schema(name: &str) -> Schema {
    Schema::load(&PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../docs/schemas").join(name))
}

/// Panics unless the JSON file matches `schema`.
pub(crate) fn assert_file_valid(schema: &Schema, file: &Path) {
    schema.assert_valid(&read_json(file), &file.display().to_string());
}

/// A small, quick capture of demo scenario A with `extra` options.
fn capture(out: &Path, extra: &[&str]) {
    let status = Command::new(env!("CARGO_BIN_EXE_ufcsr-capture"))
        .args(["demo", "--scenario", "A", "--out"])
        .arg(out)
        .args(["--ppd", "3", "--palette-size", "256", "--frames", "0-180/60", "-q"])
        .args(extra)
        .stdout(std::process::Stdio::null())
        .status()
        .expect("run ufcsr-capture");
    assert!(status.success(), "ufcsr-capture {extra:?} failed (is a Vulkan or GL driver installed?)");
}

#[test]
fn captured_manifests_and_results_match_the_schemas() {
    let manifest_schema = schema("manifest.schema.json");
    let result_schema = schema("result.schema.json");
    let dir = tempfile::tempdir().unwrap();

    // PNG tiles, then the analyzer as the CLI runs it (frames.csv on).
    let png = dir.path().join("png");
    capture(&png, &[]);
    assert_file_valid(&manifest_schema, &png.join("manifest.json"));
    let options = ufcsr::AnalyzeOptions { archive: png.clone(), frames: true, ..Default::default() };
    let mut analysis = ufcsr::analyze(&options, None).expect("analyse the capture");
    let written = ufcsr::output::write_results(&mut analysis, &png.join("results")).expect("write results");
    assert_file_valid(&result_schema, &written.result_json);

    // One shard of a split capture: its manifest carries `capture.shard`.
    let shard = dir.path().join("shard");
    capture(&shard, &["--shard", "0/2"]);
    assert_file_valid(&manifest_schema, &shard.join("shards/manifest-0-of-2.json"));

    // Counted while rendering, and the exact measure: no tiles written.
    for (name, extra) in [
        ("count", &["--count", "--dedupe", "frame"][..]),
        ("measure", &["--measure", "unobstructed", "--sample", "1/16"][..]),
    ] {
        let archive = dir.path().join(name);
        capture(&archive, extra);
        let manifest = read_json(&archive.join("manifest.json"));
        assert_eq!(manifest["capture"]["tiles_written"], Value::Bool(false), "{name}");
        assert_file_valid(&manifest_schema, &archive.join("manifest.json"));
        assert_file_valid(&result_schema, &archive.join("results/result.json"));
    }
}
