//! `heatmap` and `merge` read per-texel counts back from result.json: an
//! edited or damaged file (a texel listed twice, a `texels` field that
//! disagrees, a zero count, an unknown palette kind) is a clear error naming
//! the file, not a silently different heatmap.

use crate::common;

use std::path::{Path, PathBuf};

/// The bundled example's result.json, analysed afresh (results are not in the repository).
fn example_result(dir: &Path) -> serde_json::Value {
    let example = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fixtures/example");
    let out = dir.join("example-results");
    let status = common::analyzer().arg(&example).arg("--out").arg(&out).arg("-q").status().unwrap();
    assert!(status.success());
    serde_json::from_slice(&std::fs::read(out.join("result.json")).unwrap()).unwrap()
}

fn heatmap_error(dir: &Path, name: &str, result: &serde_json::Value) -> String {
    let path = dir.join(name);
    std::fs::write(&path, serde_json::to_vec(result).unwrap()).unwrap();
    let output = common::analyzer()
        .arg("heatmap")
        .arg(&path)
        .arg("--out")
        .arg(dir.join(format!("{name}.png")))
        .output()
        .unwrap();
    assert!(!output.status.success(), "{name}: accepted");
    let message = String::from_utf8_lossy(&output.stderr).into_owned();
    assert!(message.contains(name), "{name}: the message does not name the file: {message}");
    message
}

#[test]
fn damaged_per_texel_counts_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let original = example_result(dir.path());
    // The untouched file is accepted.
    let path = dir.path().join("ok.json");
    std::fs::write(&path, serde_json::to_vec(&original).unwrap()).unwrap();
    let status =
        common::analyzer().arg("heatmap").arg(&path).arg("--out").arg(dir.path().join("ok.png")).status();
    assert!(status.unwrap().success());

    let mut twice = original.clone();
    twice["texel_counts"]["texel_delta"][3] = serde_json::json!(0);
    assert!(heatmap_error(dir.path(), "twice.json", &twice).contains("listed twice"));

    let mut texels = original.clone();
    texels["texel_counts"]["texels"] = serde_json::json!(7);
    assert!(heatmap_error(dir.path(), "texels.json", &texels).contains("\"texels\" says 7"));

    let mut zero = original.clone();
    zero["texel_counts"]["count"][2] = serde_json::json!(0);
    assert!(heatmap_error(dir.path(), "zero.json", &zero).contains("count 0"));

    let mut kind = original.clone();
    kind["settings"]["palette"]["kind"] = serde_json::json!("hexagonal");
    assert!(heatmap_error(dir.path(), "kind.json", &kind).contains("\"hexagonal\""));
}
