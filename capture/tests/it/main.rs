//! The capture's integration tests in one binary (one link step of wgpu instead of one per
//! file): one module per behaviour area, named as the files were. Tests that need something
//! from outside the repository (reference data in `../shared`, Slurm, the analyzer's binary)
//! are in `tests/external/`, whose harness reports them *ignored* when it is missing.

mod archive_models;
mod bad_capture;
mod capture_shards;
mod degenerate;
mod exactness;
mod exit_codes;
mod extremes;
mod fused_count;
mod fuzz_regressions;
mod hardening;
mod module_graph;
mod observers;
mod palette;
mod reliability;
pub mod render_check;
mod round_trip;
mod scenes;
mod schemas;
mod scissor;
mod study_accuracy;
mod study_coverage;
mod study_setup;
mod tile_filter;
mod traffic;
mod umbrella;
mod unobstructed;
mod vehicles;
mod views_gpu;
