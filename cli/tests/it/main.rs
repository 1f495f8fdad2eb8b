//! The tests that run the command line's binaries (`ufcsr`, `ufcsr-analyze`,
//! `ufcsr-capture`, which only this crate builds: `CARGO_BIN_EXE_*` reaches a
//! package's own binaries), in one binary: each module is one file moved
//! here from `tests/it` (the analyzer's) or `capture/tests/it` (the
//! capture's), named as it was, so `cargo test -p ufcsr-cli --test it
//! cli_grammar::` runs one of them. The libraries' own tests stay beside
//! them; tests that need outside tools are in `tests/external`.
// A test crate has no API: its helpers are `pub` for the sibling modules
// (the workspace's unreachable_pub is about the libraries' surface).
#![allow(unreachable_pub)]
// Test code may use std::fs directly; production code goes through the file
// layer (clippy.toml, docs/reliability.md).
#![allow(clippy::disallowed_methods, clippy::disallowed_types)]

#[path = "../../../tests/it/common.rs"]
mod analyzer_helpers;

/// The analyzer's test helpers, and the analyzer's binary.
mod common {
    pub use super::analyzer_helpers::*;

    /// The built `ufcsr-analyze` binary.
    pub fn analyzer() -> std::process::Command {
        std::process::Command::new(env!("CARGO_BIN_EXE_ufcsr-analyze"))
    }

    /// An archive `dir/name` whose placement table has `hood` legible in frames 0–6 and
    /// `grill` in 7–9 (10 frames at 10 per second, one eye), with the example's vehicle.glb
    /// when `vehicle`: the placement tests' shared fixture.
    pub fn placement_archive(dir: &std::path::Path, name: &str, vehicle: bool) -> std::path::PathBuf {
        let archive = dir.join(name);
        std::fs::create_dir_all(archive.join("results")).unwrap();
        if vehicle {
            let example = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fixtures/example");
            std::fs::copy(example.join("vehicle.glb"), archive.join("vehicle.glb")).unwrap();
        }
        let mut table = String::from(
            "frame,time_s,eye,distance_m,candidate,kind,solid_angle_sr,visible_fraction,view_angle_deg,\
             angular_height_deg,frame_s\n",
        );
        for frame in 0..10 {
            for (part, legible) in [("hood", frame < 7), ("grill", frame >= 7)] {
                let fraction = if legible { 1.0 } else { 0.0 };
                table += &format!(
                    "{frame},{},left,{},{part},part,1e-3,{fraction},10,1,0.1\n",
                    f64::from(frame) / 10.0,
                    30 - frame
                );
            }
        }
        std::fs::write(archive.join("results/placement-frames.csv"), table).unwrap();
        archive
    }
}

// The one front door (ufcsr and its two aliases).
mod front_door;

// The analyzer's command line (and the library tests beside them in their files).
mod atomic_results;
mod cli;
mod cli_grammar;
mod color_damage;
mod commit_journal;
mod comparison_page;
mod default_files;
mod external_manifest;
mod manifest_grid;
mod manifest_links;
mod missing_vehicle;
mod output_paths;
mod placement_pages;
mod placement_refusals;
mod placement_tables;
mod published_places;
mod reliability_inputs;
mod reliability_outputs;
mod result_validation;
mod solo_manifest;
mod stdout_failures;

// The capture's command line (and the library tests that share their helpers).
mod archive_models;
mod bad_capture;
mod bus_sized;
mod capture_inputs_kept;
mod capture_replaces_whole;
mod capture_sees_nothing;
mod capture_shards;
mod dependency_writers;
mod design_command;
mod design_pipeline;
mod exit_codes;
mod family_bodies;
mod fleet;
mod fused_count;
mod hardening;
mod heatmap_command;
mod html_escaping;
mod json_written;
mod observer_default;
mod observers_command;
mod own_models;
mod reliability;
mod round_trip;
mod schemas;
mod stale_outputs;
mod traffic;
mod umbrella;
mod unobstructed;
mod views;
mod where_answer;
