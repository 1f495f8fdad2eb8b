//! The paper's Unity scenarios (`../shared/ref/scenarios/unity-intersection.json`,
//! exported from the original project) replayed with the demo truck: every
//! scenario's archive verifies with no stray pixel and shows the truck.
//! Ignored with the reason when the export is absent; a failure under `CI`.

use std::process::Command;

use libtest_mimic::Completion;
use ufcsr_capture::verify;

use crate::need::{Outcome, missing, shared_dir};

pub fn unity_scenarios_replay_with_the_demo_truck() -> Outcome {
    let reference = shared_dir().join("ref/scenarios/unity-intersection.json");
    if !reference.is_file() {
        return missing(&format!("{} (see shared/ref/scenarios/SOURCE.md)", reference.display()));
    }
    let dir = tempfile::tempdir().unwrap();
    let status = Command::new(env!("CARGO_BIN_EXE_ufcsr-capture"))
        .arg("unity")
        .arg(&reference)
        .arg("--out")
        .arg(dir.path())
        .args(["--scenario", "all", "--ppd", "3", "--palette-size", "256", "--frames", "0,90,180", "-q"])
        .status()
        .unwrap();
    assert!(status.success());
    for scenario in ["A", "B", "C", "D"] {
        let (vehicle, stray) = verify(&dir.path().join(scenario)).unwrap();
        assert_eq!(stray, 0);
        // The head turns to the truck, and no building stands in between.
        assert!(vehicle > 100, "scenario {scenario}: {vehicle}");
    }
    Ok(Completion::Completed)
}
