//! The vehicle model only feeds the pictures: when the one a manifest names
//! is missing, the analysis still writes its results and says why there is
//! no heatmap.glb; a `--mesh` that is not there is an error before counting.

use crate::common;

use std::path::PathBuf;

fn example_without_vehicle(dir: &std::path::Path) -> PathBuf {
    let example = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fixtures/example");
    let copy = dir.join("archive");
    std::fs::create_dir_all(copy.join("tiles")).unwrap();
    for name in ["manifest.json", "pidt.png", "parts.csv"] {
        std::fs::copy(example.join(name), copy.join(name)).unwrap();
    }
    for entry in std::fs::read_dir(example.join("tiles")).unwrap().flatten() {
        std::fs::copy(entry.path(), copy.join("tiles").join(entry.file_name())).unwrap();
    }
    copy
}

#[test]
fn a_missing_vehicle_model_is_a_warning_and_the_results_are_written() {
    let dir = tempfile::tempdir().unwrap();
    let archive = example_without_vehicle(dir.path());
    let out = dir.path().join("out");
    let output = common::analyzer().arg(&archive).arg("--out").arg(&out).arg("-q").output().unwrap();
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    let result = std::fs::read_to_string(out.join("result.json")).unwrap();
    assert!(result.contains("the vehicle the manifest names is missing"), "no warning in result.json");
    assert!(!out.join("heatmap.glb").exists());

    let missing_mesh = dir.path().join("no-such.glb");
    let output = common::analyzer()
        .arg(&archive)
        .arg("--out")
        .arg(dir.path().join("out2"))
        .arg("--mesh")
        .arg(&missing_mesh)
        .output()
        .unwrap();
    assert!(!output.status.success());
    assert!(String::from_utf8_lossy(&output.stderr).contains("no-such.glb"));
    assert!(!dir.path().join("out2/result.json").exists(), "counted before checking --mesh");
}
