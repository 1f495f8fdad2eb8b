//! The analyzer's integration tests, one binary (one link step instead of
//! one per file): each module is one former `tests/*.rs` file, named as it
//! was, so `cargo test -p ufcsr --test it known_answers::` runs one of them.

mod common;
// Shared with capture/tests/slurm_batch.rs, which includes it by this path.
#[path = "../slurm_support/mod.rs"]
mod slurm_support;

mod atomic_results;
mod bad_input;
mod cli;
mod doc_links;
mod frames;
mod fuzz_regressions;
mod indexed_png;
mod known_answers;
mod manifest_script;
mod missing_vehicle;
mod module_graph;
mod order_and_saturation;
mod placement;
mod python_package;
mod reference_pidt;
mod reliability;
mod report_browser;
mod result_validation;
mod schemas;
mod shards;
mod slurm;
mod texture_skipping;
mod trimming;
mod views;
