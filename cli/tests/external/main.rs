//! The command line's tests that need something from outside the repository
//! — Slurm, Chromium, Python with pip, Node with the glTF validator, Python
//! with Blender's `bpy`, the Unity export in `../shared` — in their own
//! binary with the analyzer's harness (`libtest-mimic`, `harness = false`,
//! and the one rule in `tests/external/need.rs`, included by path): a test
//! whose tool is missing is reported *ignored* with the reason, never passed;
//! with `CI` set (`.ci/run` sets `CI=1`) it fails instead. The files moved
//! here from `tests/external` and `capture/tests/external` because they run
//! the binaries, which only this crate builds; the names are those they had
//! (`cargo test -p ufcsr-cli --test external slurm` runs some of them).
// A test crate has no API: its helpers are `pub` for the sibling modules
// (the workspace's unreachable_pub is about the libraries' surface).
#![allow(unreachable_pub)]
// Test and benchmark code may use std::fs directly; production code goes
// through the file layer (clippy.toml, docs/reliability.md).
#![allow(clippy::disallowed_methods, clippy::disallowed_types)]

#[path = "../../../tests/it/common.rs"]
mod common;
#[allow(dead_code)] // the other binaries use the rest of the rule's helpers
#[path = "../../../tests/external/need.rs"]
mod need;
#[path = "../../../tests/slurm_support/mod.rs"]
mod slurm_support;
// The schema tests' validator (the Blender test checks its archive's manifest).
#[path = "../../../docs/schemas/validator.rs"]
mod validator;

mod analyzer_umbrella;
mod atomic_results;
mod blender;
mod fbx_conversion;
mod gltf_validator;
mod manifest_script;
mod python_package;
mod report_browser;
mod slurm;
mod slurm_batch;
mod slurm_design;
mod unity_reference;

use libtest_mimic::{Arguments, Trial};
use need::trial;

fn trials() -> Vec<Trial> {
    vec![
        trial(
            "analyzer_umbrella::ufcsr_analyze_runs_the_analyzer_and_passes_its_exit_code",
            analyzer_umbrella::ufcsr_analyze_runs_the_analyzer_and_passes_its_exit_code,
        ),
        trial(
            "atomic_results::an_interrupted_capture_leaves_no_temporary_files",
            atomic_results::an_interrupted_capture_leaves_no_temporary_files,
        ),
        trial(
            "blender::blender_rerenders_a_capture_with_its_silhouettes_pixels_and_part_totals",
            blender::blender_rerenders_a_capture_with_its_silhouettes_pixels_and_part_totals,
        ),
        trial(
            "blender::the_blender_script_refuses_an_archive_without_cameras_naming_its_manifest",
            blender::the_blender_script_refuses_an_archive_without_cameras_naming_its_manifest,
        ),
        trial(
            "blender::the_blender_scripts_file_rules_hold_without_blender",
            blender::the_blender_scripts_file_rules_hold_without_blender,
        ),
        trial(
            "fbx_conversion::fbx_to_glb_keeps_units_axes_node_transforms_and_material_names",
            fbx_conversion::fbx_to_glb_keeps_units_axes_node_transforms_and_material_names,
        ),
        trial(
            "gltf_validator::vehicle_heatmap_and_scene_glb_validate_with_no_error_or_warning",
            gltf_validator::vehicle_heatmap_and_scene_glb_validate_with_no_error_or_warning,
        ),
        trial(
            "manifest_script::unity_named_tiles_get_a_working_manifest",
            manifest_script::unity_named_tiles_get_a_working_manifest,
        ),
        trial(
            "python_package::python_package_builds_installs_and_passes_its_pytest_suite",
            python_package::python_package_builds_installs_and_passes_its_pytest_suite,
        ),
        trial(
            "report_browser::the_report_of_the_bundled_example_renders_in_chromium",
            report_browser::the_report_of_the_bundled_example_renders_in_chromium,
        ),
        trial(
            "report_browser::the_comparison_page_of_two_results_renders_in_chromium",
            report_browser::the_comparison_page_of_two_results_renders_in_chromium,
        ),
        trial(
            "report_browser::the_placement_section_renders_in_chromium",
            report_browser::the_placement_section_renders_in_chromium,
        ),
        trial(
            "slurm::a_slurm_array_of_shards_and_an_afterok_merge_equal_the_whole_analysis",
            slurm::a_slurm_array_of_shards_and_an_afterok_merge_equal_the_whole_analysis,
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
            "slurm_design::a_design_runs_as_a_slurm_array_and_its_afterok_merge_equals_one_process",
            slurm_design::a_design_runs_as_a_slurm_array_and_its_afterok_merge_equals_one_process,
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
