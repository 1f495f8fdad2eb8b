//! The capture's integration tests in one binary (one link step of wgpu instead of one per
//! file): one module per behaviour area, named as the files were.

mod archive_models;
mod bad_capture;
mod capture_shards;
mod degenerate;
mod exactness;
mod extremes;
mod fused_count;
mod hardening;
mod module_graph;
mod palette;
mod round_trip;
mod scenes;
mod schemas;
mod scissor;
mod slurm_batch;
mod study_accuracy;
mod tile_filter;
mod umbrella;
mod unobstructed;
mod vehicles;
mod views_gpu;
