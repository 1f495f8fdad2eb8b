//! The command line's grammar, in one place: every subcommand that does work
//! takes the same `--quiet`, `--json` and `--threads/-j` ([`Common`]), so a
//! script learns one set of words; the man page and the shell completions
//! are generated from these same definitions.

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand};
use ufcsr::{Dedupe, Scale};

/// Counts how often each texel of a vehicle is visible in captured frames
/// (UFCSR), and turns the counts into per-part statistics and a heatmap.
///
/// ARCHIVE is a folder of PNG tiles rendered with a Full Color Space Palette.
/// With a manifest.json in it (written by ufcsr-capture), no other option is
/// needed. Writes result.json, parts.csv, heatmap.png, report.html and
/// timings.json to --out (default: ARCHIVE/results).
#[derive(Parser)]
#[command(
    name = "ufcsr-analyze",
    version,
    args_conflicts_with_subcommands = true,
    subcommand_negates_reqs = true,
    after_help = EXIT_STATUS
)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Option<Command>,
    #[command(flatten)]
    pub analyze: AnalyzeArgs,
}

/// The exit codes, the same for every subcommand (docs/guide.md#exit-codes).
pub const EXIT_STATUS: &str = "Exit status: 0 done; 1 done, but with failures (results written, some \
    images could not be read: named on stderr and in result.json); 2 nothing done (bad options or \
    inputs, named on stderr).\n\
    Example: ufcsr-analyze archive/ --pidt pidt.png --parts parts.csv --out results/";

#[derive(Subcommand)]
pub enum Command {
    /// Re-render the heatmap from a result (its folder or its result.json), without the archive.
    #[command(after_help = EXIT_STATUS)]
    Heatmap(HeatmapArgs),
    /// Add up the results of every shard (`--shard I/N`) of one archive (their folders or
    /// result.json files): the same files as analysing it whole.
    #[command(after_help = EXIT_STATUS)]
    Merge(MergeArgs),
    /// Write one report.html comparing several results (result folders or result.json files;
    /// the first is the reference for the ranking differences).
    #[command(after_help = EXIT_STATUS)]
    Report(ReportArgs),
    /// Write the canonical Full Color Space Palette as a PNG (to texture a mesh in Unity/Blender).
    #[command(after_help = EXIT_STATUS)]
    Palette(PaletteArgs),
    /// Where to put an eHMI: legible exposure per candidate placement and the best 1..k placements
    /// from the exact measure's placement-frames.csv (docs/placement.md).
    #[command(after_help = EXIT_STATUS)]
    Placement(super::placement::PlacementArgs),
    /// Describe a folder of frames rendered elsewhere (Unity, Blender) as an archive: write its
    /// manifest.json with tiles, palette, PIdT, legend and what fps, field of view, rig and frame
    /// times are known, so `ufcsr-analyze DIR` needs no options (docs/archive-format.md).
    #[command(after_help = EXIT_STATUS)]
    Manifest(super::manifest::ManifestArgs),
    /// Print a shell completion script (bash, zsh, fish, elvish, powershell) on stdout.
    Completions(CompletionsArgs),
    /// Print the man page (roff) on stdout, or write one page per subcommand into --out.
    Man(ManArgs),
}

/// The words every subcommand that does work understands.
#[derive(Args, Clone, Copy, Default)]
pub struct Common {
    /// No progress bar and no summary on stdout; errors and warnings still go to stderr.
    #[arg(long, short)]
    pub quiet: bool,

    /// Print a machine-readable summary of what was done and written (JSON) on stdout
    /// instead of the text summary.
    #[arg(long)]
    pub json: bool,

    /// Worker threads (default: all cores).
    #[arg(long, short = 'j', value_name = "N")]
    pub threads: Option<usize>,
}

#[derive(Args)]
pub struct PaletteArgs {
    /// PNG to write.
    #[arg(long, short, value_name = "PNG")]
    pub out: PathBuf,

    /// Palette size, W or WxH (W alone: square; at most 2^24 texels).
    #[arg(long, visible_alias = "palette-size", default_value = "4096", value_name = "W|WxH")]
    pub size: String,

    #[command(flatten)]
    pub common: Common,
}

#[derive(Args)]
pub struct AnalyzeArgs {
    /// Folder of captured PNG tiles (searched recursively without a manifest).
    #[arg(required = true)]
    pub archive: Option<PathBuf>,

    #[command(flatten)]
    pub labels: LabelArgs,

    /// What one count means: `image` (once per PNG), `frame` (once per eye-frame) or `eye-pair`
    /// (once per frame over both eyes); the last two need a manifest.
    #[arg(long, value_enum, default_value_t = Dedupe::Image)]
    pub dedupe: Dedupe,

    /// Skip all-background tiles: `auto` (find and verify the empty-file size), a size in bytes, or `off`.
    #[arg(long, default_value = "auto", value_name = "auto|BYTES|off")]
    pub trim: String,

    #[command(flatten)]
    pub heatmap: HeatmapScaleArgs,

    /// Output folder (default: ARCHIVE/results; with --each, DIR/NAME for each archive NAME).
    #[arg(long, short, value_name = "DIR")]
    pub out: Option<PathBuf>,

    /// Count only shard I of N (0 ≤ I < N) of the archive's eye-frames; merge the shards'
    /// results with `ufcsr-analyze merge`. Default: from SLURM_ARRAY_TASK_ID/COUNT, or
    /// JOB_COMPLETION_INDEX / AWS_BATCH_JOB_ARRAY_INDEX with UFCSR_SHARD_COUNT.
    #[arg(long, value_name = "I/N")]
    pub shard: Option<String>,

    /// The vehicle as unwrapped (glTF/GLB whose UVs address the palette), for heatmap.glb;
    /// default: the archive's vehicle.glb (written by ufcsr-capture).
    #[arg(long, value_name = "GLB")]
    pub mesh: Option<PathBuf>,

    /// Per-eye-frame pixels and texels by part (frames.csv) and the resolution-independent
    /// measures (deg²·s, exposure seconds) in result.json and parts.csv: `on` or `off`.
    #[arg(long, value_enum, default_value_t = Switch::On)]
    pub frames_csv: Switch,

    /// Columns of parts.csv: `report` (the report's names, precision and order) or `paper`
    /// (part_name, pixel_count, part_total_value, …: the paper's names, for old scripts).
    #[arg(long, value_enum, default_value_t = CsvStyleArg::Report)]
    pub csv_style: CsvStyleArg,

    /// Size of the heatmap views: each is 400×300 pixels times this (1–8).
    #[arg(long, value_name = "N", default_value_t = ufcsr::DEFAULT_VIEWS_SCALE,
          value_parser = clap::value_parser!(u32).range(1..=8))]
    pub views_scale: u32,

    /// Stop at the first image that cannot be read (default: report it, go on, exit 1).
    #[arg(long)]
    pub strict: bool,

    /// Fail (exit 2, nothing written) when the capture shows colour-management or filtering
    /// damage: the `colour damage` warnings (docs/guide.md#colour-damage).
    #[arg(long)]
    pub strict_colors: bool,

    /// Ignore ARCHIVE/manifest.json (and count ARCHIVE's PNGs even where a manifest lies above
    /// or below it).
    #[arg(long)]
    pub no_manifest: bool,

    /// ARCHIVE holds several archives (a manifest.json in each, e.g. from `--scenario all`):
    /// analyse each one separately.
    #[arg(long, conflicts_with_all = ["no_manifest", "shard"])]
    pub each: bool,

    #[command(flatten)]
    pub common: Common,
}

/// An on/off option.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Switch {
    On,
    Off,
}

/// `--csv-style`, for [`ufcsr::CsvStyle`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum CsvStyleArg {
    Report,
    Paper,
}

impl From<CsvStyleArg> for ufcsr::CsvStyle {
    fn from(style: CsvStyleArg) -> Self {
        match style {
            CsvStyleArg::Report => ufcsr::CsvStyle::Report,
            CsvStyleArg::Paper => ufcsr::CsvStyle::Paper,
        }
    }
}

#[derive(Args)]
pub struct HeatmapScaleArgs {
    /// Colour scale of the heatmap: `linear` or `log` (default: linear, or the result's own).
    #[arg(long, value_enum)]
    pub scale: Option<Scale>,

    /// Count shown as the top of the colour scale (share one scale across scenarios).
    #[arg(long, value_name = "N")]
    pub max: Option<u32>,
}

#[derive(Args)]
pub struct ReportArgs {
    /// Result folders (or their result.json), at least two; or one and a placement folder (written
    /// by `ufcsr-analyze placement`, holding placement.json), whose section the page adds.
    #[arg(required = true, num_args = 2..)]
    pub results: Vec<PathBuf>,

    /// Output folder for report.html and the images it shows.
    #[arg(long, short, value_name = "DIR")]
    pub out: PathBuf,

    #[command(flatten)]
    pub common: Common,
}

#[derive(Args)]
pub struct MergeArgs {
    /// The shards' result folders (or their result.json files).
    #[arg(required = true)]
    pub results: Vec<PathBuf>,

    /// Output folder.
    #[arg(long, short, value_name = "DIR")]
    pub out: PathBuf,

    /// Columns of parts.csv (as for the analysis).
    #[arg(long, value_enum, default_value_t = CsvStyleArg::Report)]
    pub csv_style: CsvStyleArg,

    /// Size of the heatmap views: each is 400×300 pixels times this (1–8).
    #[arg(long, value_name = "N", default_value_t = ufcsr::DEFAULT_VIEWS_SCALE,
          value_parser = clap::value_parser!(u32).range(1..=8))]
    pub views_scale: u32,

    #[command(flatten)]
    pub common: Common,
}

#[derive(Args)]
pub struct HeatmapArgs {
    /// A result folder written by ufcsr-analyze, or its result.json.
    pub result: PathBuf,

    /// Heatmap PNG to write.
    #[arg(long, short, value_name = "PNG")]
    pub out: PathBuf,

    #[command(flatten)]
    pub heatmap: HeatmapScaleArgs,

    #[command(flatten)]
    pub common: Common,
}

#[derive(Args)]
pub struct CompletionsArgs {
    /// The shell: bash, zsh, fish, elvish or powershell.
    #[arg(value_enum)]
    pub shell: clap_complete::Shell,
}

#[derive(Args)]
pub struct ManArgs {
    /// Write ufcsr-analyze.1 and one ufcsr-analyze-COMMAND.1 per subcommand into this folder
    /// (default: print the main page on stdout).
    #[arg(long, short, value_name = "DIR")]
    pub out: Option<PathBuf>,
}

/// How the frames name texels and parts: the palette they were rendered with,
/// the PIdT and its legend, and the background. One set of options for every
/// command that reads frames (`ufcsr-analyze ARCHIVE` and `manifest`), parsed
/// once by [`LabelArgs::palette`] and [`LabelArgs::background_colors`].
/// Relative paths are from the working directory.
#[derive(Args)]
pub struct LabelArgs {
    /// Part Identification Texture: palette-sized PNG, each texel in its part's colour.
    #[arg(long, value_name = "PNG")]
    pub pidt: Option<PathBuf>,

    /// Legend of the PIdT: CSV `name,color` (#RRGGBB) or JSON [{"name","color"}].
    #[arg(long, visible_alias = "parts", value_name = "CSV|JSON")]
    pub legend: Option<PathBuf>,

    /// Palette image the frames were rendered with: unique colours in any layout (default: the
    /// canonical palette).
    #[arg(long, value_name = "PNG", conflicts_with = "palette_size")]
    pub fcsp: Option<PathBuf>,

    /// Size of the canonical palette the frames were rendered with, W or WxH (default 4096x4096).
    #[arg(long, value_name = "W|WxH")]
    pub palette_size: Option<String>,

    /// Background colour to ignore, #RRGGBB; repeat for several (default #000FFF).
    #[arg(long, value_name = "HEX")]
    pub background: Vec<String>,
}

impl LabelArgs {
    /// `--fcsp` or `--palette-size`, if either is given.
    pub fn palette(&self) -> anyhow::Result<Option<ufcsr::PaletteChoice>> {
        Ok(match (&self.fcsp, &self.palette_size) {
            (Some(png), _) => Some(ufcsr::PaletteChoice::Image(png.clone())),
            (None, Some(size)) => {
                let (width, height) = ufcsr::parse_palette_size(size)?;
                Some(ufcsr::PaletteChoice::Canonical { width, height })
            }
            (None, None) => None,
        })
    }

    /// Every `--background`, parsed (empty when none is given).
    pub fn background_colors(&self) -> anyhow::Result<Vec<ufcsr::Color>> {
        use anyhow::Context;
        self.background
            .iter()
            .map(|text| text.parse::<ufcsr::Color>().with_context(|| format!("--background {text:?}")))
            .collect()
    }
}
