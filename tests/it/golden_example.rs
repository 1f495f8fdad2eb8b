//! The bundled example's result, byte for byte: `result.json`, `parts.csv`
//! and `frames.csv` of `fixtures/example` analysed as the command line does
//! (with frames.csv on) are compared with checked-in copies in
//! `tests/reference/` (the example's absolute path in `result.json` written
//! as `fixtures/example`). A refactor that claims "no behaviour change" is
//! held to it; a change on purpose replaces the copies (the message says how).

use std::path::{Path, PathBuf};

fn workspace_file(relative: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(relative)
}

/// `written` with the example's absolute path (as JSON writes it) replaced by
/// `fixtures/example`, so the copy does not depend on where the checkout is.
fn with_relative_example_path(written: &str, example: &Path) -> String {
    let absolute = serde_json::to_string(&example.display().to_string()).unwrap();
    written.replace(absolute.trim_end_matches('"'), "\"fixtures/example")
}

fn assert_same_as_reference(written: &str, reference: &str) {
    let expected = std::fs::read_to_string(workspace_file(reference)).unwrap();
    if written != expected {
        let differing = written.lines().zip(expected.lines()).enumerate().find(|(_, (a, b))| a != b);
        let line = differing.map_or_else(
            || {
                format!(
                    "one is longer: {} against {} lines",
                    written.lines().count(),
                    expected.lines().count()
                )
            },
            |(number, (now, before))| format!("line {}: now {now:?}, expected {before:?}", number + 1),
        );
        panic!(
            "{reference} differs from what the analyzer writes now ({line}); \
             if the result changed on purpose, replace it with the new output of \
             `ufcsr analyze fixtures/example --out DIR` (result.json with the example's path \
             written as fixtures/example)"
        );
    }
}

#[test]
fn the_example_analysed_as_the_command_line_does_writes_the_checked_in_result_byte_for_byte() {
    let dir = tempfile::tempdir().unwrap();
    let example = workspace_file("fixtures/example");
    let options = ufcsr::AnalyzeOptions { archive: example.clone(), frames: true, ..Default::default() };
    let mut analysis = ufcsr::analyze(&options, None).unwrap();
    ufcsr::output::write_results(&mut analysis, dir.path()).unwrap();
    let read = |name: &str| std::fs::read_to_string(dir.path().join(name)).unwrap();
    let result = with_relative_example_path(&read("result.json"), &example);
    assert_same_as_reference(&result, "tests/reference/example-result.json");
    assert_same_as_reference(&read("parts.csv"), "tests/reference/example-parts.csv");
    assert_same_as_reference(&read("frames.csv"), "tests/reference/example-frames.csv");
}

/// The lowest point and the extents `[x, y, z]` of every mesh a glTF file
/// places, as its accessors' bounds say, with the node's translation; a
/// rotated or scaled node is refused (the positions themselves must hold
/// the axes, as docs/archive-format.md says ufcsr writes them).
fn placed_bounds(path: &Path) -> ([f64; 3], [f64; 3]) {
    let gltf = gltf::Gltf::open(path).unwrap();
    let (mut low, mut high) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for node in gltf.nodes() {
        let Some(mesh) = node.mesh() else { continue };
        let (translation, rotation, scale) = node.transform().decomposed();
        assert!(
            rotation == [0.0, 0.0, 0.0, 1.0] && scale == [1.0; 3],
            "{}: node {:?} is turned",
            path.display(),
            node.name()
        );
        for primitive in mesh.primitives() {
            let bounds = primitive.bounding_box();
            for axis in 0..3 {
                low[axis] = low[axis].min(f64::from(bounds.min[axis] + translation[axis]));
                high[axis] = high[axis].max(f64::from(bounds.max[axis] + translation[axis]));
            }
        }
    }
    (low, high)
}

#[test]
fn every_gltf_file_of_the_bundled_example_stands_upright() {
    let example = workspace_file("fixtures/example");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&example)
        .unwrap()
        .map(|entry| entry.unwrap().path())
        .filter(|path| path.extension().is_some_and(|e| e == "glb" || e == "gltf"))
        .collect();
    files.sort();
    assert!(files.iter().any(|f| f.ends_with("vehicle.glb")), "no vehicle.glb in {files:?}");
    for file in &files {
        let bytes = std::fs::read(file).unwrap();
        let json: serde_json::Value = match gltf::Glb::from_slice(&bytes) {
            Ok(glb) => serde_json::from_slice(&glb.json).unwrap(),
            Err(_) => serde_json::from_slice(&bytes).unwrap(),
        };
        let marked = json["asset"]["extras"]["ufcsr_axes"].is_string();
        assert!(
            marked,
            "{}: no asset.extras.ufcsr_axes, so it is read as the old z-up frame",
            file.display()
        );
        let (low, high) = placed_bounds(file);
        let extent = [0, 1, 2].map(|axis| high[axis] - low[axis]);
        // glTF: +Y up, front +Z, left +X. On the ground (y from 0) and longest front to back.
        assert!(
            low[1].abs() < 0.01,
            "{}: lowest point at y = {} m, not on the ground",
            file.display(),
            low[1]
        );
        assert!(
            extent[2] > extent[0] && extent[2] > extent[1],
            "{}: extents {extent:?} are not longest along z",
            file.display()
        );
    }
}
