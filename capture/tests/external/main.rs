//! The capture's tests that need something from outside the repository —
//! the reference vehicle in `../shared` (those that also run the binaries
//! are in `cli/tests/external`) — in their own binary with the
//! analyzer's harness (`libtest-mimic`, `harness = false`, and the one rule in
//! `tests/external/need.rs`, included by path): a test whose input is missing
//! is reported *ignored* with the reason, never passed; with `CI` set it fails.
//! `cargo test -p ufcsr-capture --test external milk` runs some of them.
// A test crate has no API: its helpers are `pub` for the sibling modules
// (the workspace's unreachable_pub is about the libraries' surface).
#![allow(unreachable_pub)]
// Test and benchmark code may use std::fs directly; production code goes
// through the file layer (clippy.toml, docs/reliability.md).
#![allow(clippy::disallowed_methods, clippy::disallowed_types)]

#[allow(dead_code)] // the capture uses part of the rule's helpers
#[path = "../../../tests/external/need.rs"]
mod need;
#[path = "../it/render_check.rs"]
mod render_check;
#[path = "../../../tests/external/skips_are_reported.rs"]
mod skips_are_reported;

mod milk_truck;

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
            "milk_truck::milk_truck_inspects_and_labels_into_named_parts",
            milk_truck::milk_truck_inspects_and_labels_into_named_parts,
        ),
        trial(
            "milk_truck::milk_truck_keep_uvs_names_the_primitives_without_uvs_and_a_tiny_capture_verifies",
            milk_truck::milk_truck_keep_uvs_names_the_primitives_without_uvs_and_a_tiny_capture_verifies,
        ),
        trial(
            "milk_truck::milk_truck_parts_from_a_part_map_over_its_own_uvs_are_its_materials",
            milk_truck::milk_truck_parts_from_a_part_map_over_its_own_uvs_are_its_materials,
        ),
        trial(
            "milk_truck::every_pixel_of_the_milk_truck_names_a_labelled_texel",
            milk_truck::every_pixel_of_the_milk_truck_names_a_labelled_texel,
        ),
        trial(
            "skips_are_reported::a_missing_reference_vehicle_is_counted_ignored_and_fails_under_ci",
            a_missing_reference_vehicle_is_counted_ignored_and_fails_under_ci,
        ),
    ]
}

fn main() {
    let arguments = Arguments::from_args();
    libtest_mimic::run(&arguments, trials()).exit();
}
