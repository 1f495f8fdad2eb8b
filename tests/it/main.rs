//! The analyzer's integration tests, one binary (one link step instead of
//! one per file): each module is one former `tests/*.rs` file, named as it
//! was, so `cargo test -p ufcsr --test it known_answers::` runs one of them.
//! The tests that need outside tools (Slurm, Chromium, Python, `../shared`)
//! are in `tests/external`, whose harness reports a missing tool as ignored;
//! those that run the binaries are in `cli/tests` (the crate that builds them).
// A test crate has no API: its helpers are `pub` for the sibling modules
// (the workspace's unreachable_pub is about the libraries' surface).
#![allow(unreachable_pub)]
// Test code may use std::fs directly; production code goes through the file
// layer (clippy.toml, docs/reliability.md).
#![allow(clippy::disallowed_methods, clippy::disallowed_types)]

mod common;

mod api_surface;
mod architecture_page;
mod area_first;
mod bad_input;
mod doc_links;
mod figures;
mod file_layer;
mod frames;
mod fuzz_regressions;
mod golden_example;
mod indexed_png;
mod known_answers;
mod loaded_labels;
mod module_graph;
mod order_and_saturation;
mod path_openers;
mod placement;
mod placement_uncertainty;
mod published_locations;
mod reliability;
mod reliability_merge;
mod rgba32_ids;
mod scenario_map;
mod schemas;
mod shards;
mod texture_skipping;
mod trimming;
mod views;
