//! The analyzer's commands: the analysis (`ufcsr analyze ARCHIVE`, or
//! `ufcsr analyze ARCHIVE`; [`analyze_cmd`], with what ARCHIVE means in
//! [`intent`]), the commands on results (`merge`, `report`, `heatmap`,
//! `palette`: [`run`]), describing external frames ([`manifest`]) and the
//! placement search ([`placement`]); their grammar is in [`args`] and in each
//! command's own file. Each parses into the analyzer library's plain options.

mod analyze_cmd;
mod args;
mod intent;
mod manifest;
pub(crate) mod placement;
mod run;

use clap::Subcommand;

use crate::console::{Completion, Console};

pub(crate) use analyze_cmd::run_analyze;
pub(crate) use args::AnalyzeArgs;

use args::{HeatmapArgs, MergeArgs, PaletteArgs, ReportArgs};
use manifest::ManifestArgs;
use placement::PlacementArgs;

/// The analyzer's commands besides the analysis.
#[derive(Subcommand)]
pub(crate) enum AnalyzerCommand {
    /// Add up the results of every shard (`--shard I/N`) of one archive (their folders or
    /// result.json files): the same files as analysing it whole.
    ///
    /// Example: `ufcsr merge shard-1/results shard-2/results --out whole/`
    Merge(MergeArgs),
    /// Write one report.html comparing several results (result folders or result.json files;
    /// the first is the reference for the ranking differences).
    ///
    /// Example: `ufcsr report capA/results capB/results --label "scenario A" --label
    /// "scenario B" --out compared/`
    Report(ReportArgs),
    /// Re-draw a result's heatmap texture (its folder or result.json; no archive needed): the
    /// palette's UV layout as heatmap.png holds it, per-texel angular area (deg²·s) when the result
    /// has texel-area.f32, else the count. The pictures on the vehicle are the result's views.png.
    ///
    /// Example: `ufcsr heatmap capA/results --out heat.png --scale log --area-max 0.01`
    Heatmap(HeatmapArgs),
    /// Write the canonical Full Color Space Palette as a PNG (to texture a mesh in Unity/Blender).
    ///
    /// Example: `ufcsr palette --size 4096 --out palette.png`
    Palette(PaletteArgs),
    /// Describe a folder of frames rendered elsewhere (Unity, Blender) as an archive: write its
    /// manifest.json with tiles, palette, PIdT, legend and what fps, field of view, rig and frame
    /// times are known, so `ufcsr analyze DIR` needs no options (docs/archive-format.md).
    ///
    /// Example: `ufcsr manifest dataset --pidt dataset/pidt.png --legend dataset/parts.csv
    /// --palette-size 4096`
    Manifest(ManifestArgs),
    /// Where to put an eHMI: legible exposure per candidate placement and the best 1..k placements
    /// from the exact measure's placement-frames.csv (docs/placement.md).
    ///
    /// Example: `ufcsr placement runs/A runs/B runs/C runs/D --k 3 --symmetric --out
    /// placement/`
    Placement(PlacementArgs),
}

impl AnalyzerCommand {
    /// The command's name, as `--json` reports it.
    pub(crate) fn name(&self) -> &'static str {
        match self {
            AnalyzerCommand::Merge(_) => "merge",
            AnalyzerCommand::Report(_) => "report",
            AnalyzerCommand::Heatmap(_) => "heatmap",
            AnalyzerCommand::Palette(_) => "palette",
            AnalyzerCommand::Manifest(_) => "manifest",
            AnalyzerCommand::Placement(_) => "placement",
        }
    }
}

/// Runs one of the analyzer's commands besides the analysis.
pub(crate) fn run(command: AnalyzerCommand, console: &Console) -> anyhow::Result<Completion> {
    match command {
        AnalyzerCommand::Merge(args) => run::run_merge(args, console),
        AnalyzerCommand::Report(args) => run::run_report(args, console),
        AnalyzerCommand::Heatmap(args) => run::run_heatmap(args, console),
        AnalyzerCommand::Palette(args) => run::run_palette(args, console),
        AnalyzerCommand::Manifest(args) => manifest::run_manifest(args, console),
        AnalyzerCommand::Placement(args) => placement::run_placement(args, console),
    }
}
