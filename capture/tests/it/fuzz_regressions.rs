//! Every saved fuzzing input of the capture's targets — the seed corpus and
//! each input that once made a target fail — goes through the same entry
//! points as the fuzzers (`ufcsr_capture::fuzz_entry`), so CI re-checks them
//! without nightly or libFuzzer, as `tests/it/fuzz_regressions.rs` does for
//! the analyzer's. A panic here is a regression; so is a seed that no longer
//! loads (a seed that stopped parsing fuzzes nothing past the parser).

use std::path::PathBuf;

const TARGETS: [ufcsr::fuzz_entry::Target; 6] = [
    ("scene", ufcsr_capture::fuzz_entry::scene),
    ("gltf", ufcsr_capture::fuzz_entry::gltf),
    ("obj", ufcsr_capture::fuzz_entry::obj),
    ("unity", ufcsr_capture::fuzz_entry::unity),
    ("design", ufcsr_capture::fuzz_entry::design),
    ("design_task", ufcsr_capture::fuzz_entry::design_task),
];

fn fuzz_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fuzz")
}

#[test]
fn every_saved_capture_fuzz_input_is_handled_without_a_panic() {
    let inputs =
        ufcsr::fuzz_entry::replay_saved_inputs(&fuzz_dir(), &TARGETS).unwrap_or_else(|e| panic!("{e}"));
    assert!(inputs >= 8, "the capture's seed corpus is missing ({inputs} inputs)");
}

#[test]
fn the_capture_s_fuzz_seeds_load_so_the_fuzzers_start_past_the_parsers() {
    let seeds = fuzz_dir().join("seeds");
    let nowhere = std::path::Path::new("/nonexistent-ufcsr-fuzz");
    for file in std::fs::read_dir(seeds.join("scene")).unwrap().flatten() {
        let bytes = std::fs::read(file.path()).unwrap();
        let scene = ufcsr_capture::Scene::parse(&nowhere.join("scene.json"), &bytes);
        assert!(scene.is_ok(), "{}: {}", file.path().display(), scene.unwrap_err());
    }
    for file in std::fs::read_dir(seeds.join("design")).unwrap().flatten() {
        let bytes = std::fs::read(file.path()).unwrap();
        let design: ufcsr::format::Design = serde_json::from_slice(&bytes).unwrap();
        let plan = ufcsr_capture::design::plan_checked(design, &nowhere.join("design.json"));
        assert!(plan.is_ok(), "{}: {}", file.path().display(), plan.err().unwrap());
    }
    for file in std::fs::read_dir(seeds.join("design_task")).unwrap().flatten() {
        let bytes = std::fs::read(file.path()).unwrap();
        let task =
            ufcsr::format::parse_json::<ufcsr::format::DesignTask>(&file.path(), &bytes, "design task");
        let task = task.unwrap_or_else(|e| panic!("{e}"));
        let checked = ufcsr_capture::design::check_design_task(&task, f64::INFINITY);
        assert!(checked.is_ok(), "{}: {}", file.path().display(), checked.unwrap_err());
    }
    for file in std::fs::read_dir(seeds.join("gltf")).unwrap().flatten() {
        let bytes = std::fs::read(file.path()).unwrap();
        let model = ufcsr::files::parse_gltf(&nowhere.join("model.glb"), &bytes, ufcsr::files::MODEL_LIMIT);
        assert!(model.is_ok(), "{}: {}", file.path().display(), model.err().unwrap());
    }
}
