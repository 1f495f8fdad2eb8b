//! The capture's integration tests in one binary (one link step of wgpu instead of one per
//! file): one module per behaviour area, named as the files were. Tests that need something
//! from outside the repository (reference data in `../shared`, Slurm, the analyzer's binary)
//! are in `tests/external/`, whose harness reports them *ignored* when it is missing; those that
//! run the binaries are in `cli/tests` (the crate that builds them).

// Test code may use std::fs directly; production code goes through the file
// layer (clippy.toml, docs/reliability.md).
#![allow(clippy::disallowed_methods, clippy::disallowed_types)]

mod degenerate;
mod exactness;
mod extremes;
mod family;
mod fuzz_regressions;
mod observers;
mod palette;
pub mod render_check;
mod rgba32_capture;
mod scenes;
mod scissor;
mod silent_numbers;
mod study_accuracy;
mod study_coverage;
mod study_setup;
mod texel_sample;
mod tile_filter;
mod uvless_models;
mod vehicles;
