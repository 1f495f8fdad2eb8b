//! The analyzer's tests that need something from outside the repository —
//! the reference data in `../shared` — in their own binary with its own
//! harness (`libtest-mimic`, `harness = false`): a test whose input is
//! missing is reported *ignored* with the reason, so `cargo test` counts it
//! among the ignored, never among the passed; with `CI` set (`.ci/run` sets
//! `CI=1`) it fails instead. `skips_are_reported` checks the rule itself.
//! The rule (`need.rs`) is shared by path with the capture's and the command
//! line's external tests (`cli/tests/external`: Slurm, Chromium, Python,
//! Blender, the glTF validator), and so is `../slurm_support`.
// A test crate has no API: its helpers are `pub` for the sibling modules
// (the workspace's unreachable_pub is about the libraries' surface).
#![allow(unreachable_pub)]
// Test and benchmark code may use std::fs directly; production code goes
// through the file layer (clippy.toml, docs/reliability.md).
#![allow(clippy::disallowed_methods, clippy::disallowed_types)]

#[allow(dead_code)] // the other binaries use the rest of the rule's helpers
mod need;
mod reference_pidt;
mod skips_are_reported;

use libtest_mimic::{Arguments, Trial};
use need::trial;

fn trials() -> Vec<Trial> {
    vec![
        trial(
            "reference_pidt::f150_part_texel_counts_match_an_independent_count",
            reference_pidt::f150_part_texel_counts_match_an_independent_count,
        ),
        trial(
            "skips_are_reported::a_missing_input_is_counted_ignored_and_fails_under_ci",
            a_missing_input_is_counted_ignored_and_fails_under_ci,
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
