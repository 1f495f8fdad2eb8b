//! The Khronos glTF validator (npm `gltf-validator`, run by
//! `tests/external/validate-gltf.js` under Node) finds no error and no
//! warning in the glTF files ufcsr writes: a capture's `vehicle.glb` and
//! `scene.glb`, and the analyzer's `heatmap.glb` (made here from the bundled
//! example's old z-up `vehicle.glb`, so the rewrite of an old file is
//! checked too). Nor the infos that mean a mistake of ours: a `TEXCOORD_0`
//! no material uses (UNUSED_OBJECT). The validator is looked for in
//! `$UFCSR_GLTF_VALIDATOR/node_modules`, else `target/gltf-validator/`
//! (where `.ci/run` installs it); a missing Node, validator or capture
//! binary makes the test ignored (failed under CI).

use std::path::{Path, PathBuf};
use std::process::Command;

use crate::need::{Outcome, missing, runs};
use libtest_mimic::Completion;

/// The folder holding `node_modules/gltf-validator`, if installed.
fn validator_dir() -> Option<PathBuf> {
    let dir = std::env::var_os("UFCSR_GLTF_VALIDATOR")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../target/gltf-validator"));
    dir.join("node_modules/gltf-validator/package.json").is_file().then_some(dir)
}

/// One file's report from validate-gltf.js.
struct Report {
    errors: u64,
    warnings: u64,
    messages: Vec<String>,
}

fn validate(dir: &Path, files: &[PathBuf]) -> Vec<Report> {
    let script = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/external/validate-gltf.js");
    let output = Command::new("node")
        .arg(script)
        .args(files)
        .env("NODE_PATH", dir.join("node_modules"))
        .output()
        .unwrap();
    assert!(output.status.success(), "validate-gltf.js: {}", String::from_utf8_lossy(&output.stderr));
    let text = String::from_utf8(output.stdout).unwrap();
    text.lines()
        .map(|line| {
            let report: serde_json::Value = serde_json::from_str(line).unwrap();
            Report {
                errors: report["errors"].as_u64().unwrap(),
                warnings: report["warnings"].as_u64().unwrap(),
                messages: report["messages"]
                    .as_array()
                    .unwrap()
                    .iter()
                    .map(|m| m.as_str().unwrap().to_string())
                    .collect(),
            }
        })
        .collect()
}

fn run_ok(command: &mut Command) {
    let output = command.output().unwrap();
    assert!(output.status.success(), "{command:?}: {}", String::from_utf8_lossy(&output.stderr));
}

pub fn vehicle_heatmap_and_scene_glb_validate_with_no_error_or_warning() -> Outcome {
    if !runs("node") {
        return missing("Node.js (node) for the Khronos glTF validator");
    }
    let Some(validator) = validator_dir() else {
        return missing(
            "npm gltf-validator in $UFCSR_GLTF_VALIDATOR or target/gltf-validator (.ci/run installs it)",
        );
    };
    let analyzer = Path::new(env!("CARGO_BIN_EXE_ufcsr-analyze"));
    let capture = analyzer.with_file_name("ufcsr-capture");
    if !capture.is_file() {
        return missing("ufcsr-capture built beside ufcsr-analyze (cargo test --workspace builds it)");
    }
    let dir = tempfile::tempdir().unwrap();
    let archive = dir.path().join("archive");
    // The demo scene: boxes and the ground as occluders; --count writes no tiles.
    run_ok(
        Command::new(&capture)
            .args(["demo", "--scenario", "A", "--ppd", "3", "--palette-size", "256", "--frames", "0-180/90"])
            .args(["--count", "-q", "--out"])
            .arg(&archive),
    );
    let results = dir.path().join("results");
    let example = concat!(env!("CARGO_MANIFEST_DIR"), "/../fixtures/example");
    run_ok(Command::new(analyzer).arg(example).arg("--out").arg(&results).arg("-q"));
    let files = [archive.join("vehicle.glb"), archive.join("scene.glb"), results.join("heatmap.glb")];
    for (file, report) in files.iter().zip(validate(&validator, &files)) {
        let ours: Vec<&String> = report.messages.iter().filter(|m| m.contains("UNUSED_OBJECT")).collect();
        assert!(
            report.errors == 0 && report.warnings == 0 && ours.is_empty(),
            "{}: {} errors, {} warnings:\n{}",
            file.display(),
            report.errors,
            report.warnings,
            report.messages.join("\n")
        );
    }
    Ok(Completion::Completed)
}
