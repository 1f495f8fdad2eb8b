//! The capture's tests that need something from outside the repository —
//! the reference vehicle and the Unity export in `../shared`, Slurm, the
//! analyzer's binary beside the capture's — in their own binary with the
//! analyzer's harness (`libtest-mimic`, `harness = false`, and the one rule in
//! `tests/external/need.rs`, included by path): a test whose input is missing
//! is reported *ignored* with the reason, never passed; with `CI` set it fails.
//! `cargo test -p ufcsr-capture --test external milk` runs some of them.

#[allow(dead_code)] // the capture uses part of the rule's helpers
#[path = "../../../tests/external/need.rs"]
mod need;
#[path = "../it/render_check.rs"]
mod render_check;
#[path = "../../../tests/external/skips_are_reported.rs"]
mod skips_are_reported;
#[path = "../../../tests/slurm_support/mod.rs"]
mod slurm_support;

mod analyzer_umbrella;
mod milk_truck;
mod slurm_batch;
mod unity_reference;

use libtest_mimic::{Arguments, Trial};
use need::trial;

/// The skip rule on this binary's reference-data test.
fn a_missing_reference_vehicle_is_counted_ignored_and_fails_under_ci() -> need::Outcome {
    skips_are_reported::a_hidden_reference_is_ignored_and_fails_under_ci(
        "milk_truck::every_pixel_of_the_milk_truck_names_a_labelled_texel",
        "ref/vehicles/cesium-milk-truck.glb",
    )
}

fn trials() -> Vec<Trial> {
    vec![
        trial(
            "analyzer_umbrella::ufcsr_analyze_runs_the_analyzer_and_passes_its_exit_code",
            analyzer_umbrella::ufcsr_analyze_runs_the_analyzer_and_passes_its_exit_code,
        ),
        trial(
            "milk_truck::milk_truck_inspects_and_labels_into_named_parts",
            milk_truck::milk_truck_inspects_and_labels_into_named_parts,
        ),
        trial(
            "milk_truck::milk_truck_keep_uvs_names_the_primitives_without_uvs_and_a_tiny_capture_verifies",
            milk_truck::milk_truck_keep_uvs_names_the_primitives_without_uvs_and_a_tiny_capture_verifies,
        ),
        trial(
            "milk_truck::every_pixel_of_the_milk_truck_names_a_labelled_texel",
            milk_truck::every_pixel_of_the_milk_truck_names_a_labelled_texel,
        ),
        trial(
            "skips_are_reported::a_missing_reference_vehicle_is_counted_ignored_and_fails_under_ci",
            a_missing_reference_vehicle_is_counted_ignored_and_fails_under_ci,
        ),
        trial(
            "slurm_batch::a_batch_runs_as_a_slurm_array_one_task_per_setting",
            slurm_batch::a_batch_runs_as_a_slurm_array_one_task_per_setting,
        ),
        trial(
            "slurm_batch::a_sharded_capture_assembles_and_analyses_through_slurm_equal_to_one_process",
            slurm_batch::a_sharded_capture_assembles_and_analyses_through_slurm_equal_to_one_process,
        ),
        trial(
            "unity_reference::unity_scenarios_replay_with_the_demo_truck",
            unity_reference::unity_scenarios_replay_with_the_demo_truck,
        ),
        trial(
            "unity_reference::unity_scenarios_put_the_vehicle_where_unity_would",
            unity_reference::unity_scenarios_put_the_vehicle_where_unity_would,
        ),
        trial(
            "unity_reference::the_replay_equals_unitys_curve_evaluation_and_the_jumps_are_in_the_keys",
            unity_reference::the_replay_equals_unitys_curve_evaluation_and_the_jumps_are_in_the_keys,
        ),
    ]
}

fn main() {
    let arguments = Arguments::from_args();
    libtest_mimic::run(&arguments, trials()).exit();
}
