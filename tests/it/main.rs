//! The analyzer's integration tests, one binary (one link step instead of
//! one per file): each module is one former `tests/*.rs` file, named as it
//! was, so `cargo test -p ufcsr --test it known_answers::` runs one of them.
//! The tests that need outside tools (Slurm, Chromium, Python, `../shared`)
//! are in `tests/external`, whose harness reports a missing tool as ignored.

mod common;

mod atomic_results;
mod bad_input;
mod cli;
mod cli_grammar;
mod colour_damage;
mod comparison_page;
mod doc_links;
mod external_manifest;
mod frames;
mod fuzz_regressions;
mod golden_example;
mod indexed_png;
mod known_answers;
mod loaded_labels;
mod missing_vehicle;
mod module_graph;
mod order_and_saturation;
mod placement;
mod placement_pages;
mod placement_uncertainty;
mod reliability;
mod reliability_inputs;
mod reliability_merge;
mod reliability_outputs;
mod result_validation;
mod scenario_map;
mod schemas;
mod shards;
mod texture_skipping;
mod trimming;
mod views;
