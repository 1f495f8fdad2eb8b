//! The tests that need something from outside the repository — Slurm,
//! Chromium, Python with pip, Node with the glTF validator, Python with
//! Blender's `bpy`, the reference data in `../shared`, the capture
//! binary — in their own binary with its own harness (`libtest-mimic`,
//! `harness = false`): a test whose tool is missing is reported *ignored*
//! with the reason, so `cargo test` counts it among the ignored, never among
//! the passed; with `CI` set (`.ci/run` sets `CI=1`) it fails instead. The
//! names are those the tests had in `tests/it` (`cargo test -p ufcsr --test
//! external slurm` runs one); `skips_are_reported` checks the rule itself.

#[path = "../it/common.rs"]
mod common;
// Shared with capture/tests/slurm_batch.rs, which includes it by this path.
#[path = "../slurm_support/mod.rs"]
mod slurm_support;
// The schema tests' validator (the Blender test checks its archive's manifest).
#[path = "../../docs/schemas/validator.rs"]
mod validator;

mod atomic_results;
mod blender;
mod gltf_validator;
mod manifest_script;
mod need;
mod python_package;
mod reference_pidt;
mod report_browser;
mod skips_are_reported;
mod slurm;

use libtest_mimic::{Arguments, Trial};
use need::trial;

fn trials() -> Vec<Trial> {
    vec![
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
            "reference_pidt::f150_part_texel_counts_match_an_independent_count",
            reference_pidt::f150_part_texel_counts_match_an_independent_count,
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
            "skips_are_reported::a_missing_input_is_counted_ignored_and_fails_under_ci",
            a_missing_input_is_counted_ignored_and_fails_under_ci,
        ),
        trial(
            "slurm::a_slurm_array_of_shards_and_an_afterok_merge_equal_the_whole_analysis",
            slurm::a_slurm_array_of_shards_and_an_afterok_merge_equal_the_whole_analysis,
        ),
    ]
}

/// The skip rule on this binary's reference-data test.
fn a_missing_input_is_counted_ignored_and_fails_under_ci() -> need::Outcome {
    skips_are_reported::a_hidden_reference_is_ignored_and_fails_under_ci(
        "reference_pidt::f150_part_texel_counts_match_an_independent_count",
        "ref/f150",
    )
}

fn main() {
    let arguments = Arguments::from_args();
    libtest_mimic::run(&arguments, trials()).exit();
}
