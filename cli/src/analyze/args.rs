//! The grammar of the analysis and of the commands on results, in one
//! place: the analysis's options ([`AnalyzeArgs`]) and those of `merge`,
//! `report`, `heatmap` and `palette`. The words every command understands
//! (`--quiet`, `--json`, `--threads/-j`) and the options shared with
//! `manifest` are in `crate::options`; the man page and the shell completions
//! are generated from these same definitions.

use std::path::PathBuf;

use clap::Args;

use crate::choices::{CsvStyle, Dedupe, FiguresChoice, Switch};
use crate::options::{HeatmapScaleArgs, LabelArgs};

#[derive(Args)]
pub(crate) struct PaletteArgs {
    /// PNG to write.
    #[arg(long, short, value_name = "PNG")]
    pub out: PathBuf,

    /// Palette size, W or WxH (W alone: square; at most 2^24 texels).
    #[arg(long, visible_alias = "palette-size", default_value = "4096", value_name = "W|WxH")]
    pub size: String,
}

#[derive(Args)]
pub(crate) struct AnalyzeArgs {
    /// Folder of captured PNG tiles (searched recursively without a manifest).
    #[arg(required = true)]
    pub archive: Option<PathBuf>,

    #[command(flatten)]
    pub labels: LabelArgs,

    /// What one count means: `image` (once per PNG, the paper's count and the default here and in
    /// `capture --count`), `frame` (once per eye-frame; `study`'s default, as the exact measure
    /// counts) or `eye-pair` (once per frame over both eyes); the last two need a manifest.
    #[arg(long, value_enum, default_value_t = Dedupe::Image)]
    pub dedupe: Dedupe,

    /// Skip all-background tiles: `auto` (find and verify the empty-file size), a size in bytes, or `off`.
    #[arg(long, default_value = "auto", value_name = "auto|BYTES|off")]
    pub trim: String,

    #[command(flatten)]
    pub heatmap: HeatmapScaleArgs,

    /// Angular area (deg²·s per texel) shown as the top of the colour scale of heatmap.png,
    /// heatmap.glb and the views (share one scale across scenarios; --max is the count heatmap's).
    #[arg(long, value_name = "DEG2_S")]
    pub area_max: Option<f64>,

    /// Output folder (default: ARCHIVE/results; with --each, DIR/NAME for each archive NAME).
    #[arg(long, short, value_name = "DIR")]
    pub out: Option<PathBuf>,

    /// Count only shard I of N (0 ≤ I < N) of the archive's eye-frames; merge the shards'
    /// results with `ufcsr merge`. Default: from SLURM_ARRAY_TASK_ID/COUNT, or
    /// JOB_COMPLETION_INDEX / AWS_BATCH_JOB_ARRAY_INDEX with UFCSR_SHARD_COUNT.
    #[arg(long, value_name = "I/N")]
    pub shard: Option<String>,

    /// The vehicle as unwrapped (glTF/GLB whose UVs address the palette), for heatmap.glb;
    /// default: the archive's vehicle.glb (written by ufcsr capture).
    #[arg(long, value_name = "GLB")]
    pub mesh: Option<PathBuf>,

    /// Per-eye-frame pixels and texels by part (frames.csv) and the resolution-independent
    /// measures (deg²·s, exposure seconds) in result.json and parts.csv: `on` or `off`.
    #[arg(long, value_enum, default_value_t = Switch::On)]
    pub frames_csv: Switch,

    /// Per-texel angular area (deg²·s): heatmap.png, heatmap.glb and the views in deg²·s, with
    /// texel-area.f32 and the count in heatmap-count.png (needs frames.csv and the eyes'
    /// projection): `on` (the default) or `off` (heatmap.png, glb and views show the paper's count).
    #[arg(long, value_enum, default_value_t = Switch::On)]
    pub texel_area: Switch,

    /// Columns of parts.csv: `report` (the report's names, precision and order) or `paper`
    /// (part_name, pixel_count, part_total_value, …: the paper's names, for old scripts).
    #[arg(long, value_enum, default_value_t = CsvStyle::Report)]
    pub csv_style: CsvStyle,

    /// Size of the heatmap views: each is 400×300 pixels times this (1–8).
    #[arg(long, value_name = "N", default_value_t = ufcsr::output::DEFAULT_VIEWS_SCALE,
          value_parser = clap::value_parser!(u32).range(1..=8))]
    pub views_scale: u32,

    /// The figures (plots, views, views.pdf, map, frame strip): `on` (each once), `all` (also
    /// SVGs, one-column plots and each view alone) or `off` (for batch runs; the tables are the same).
    #[arg(long, value_enum, default_value_t = FiguresChoice::On)]
    pub figures: FiguresChoice,

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
}

#[derive(Args)]
pub(crate) struct ReportArgs {
    /// Result folders (or their result.json), at least two; or one and a placement folder (written
    /// by `ufcsr placement`, holding placement.json), whose section the page adds.
    #[arg(required = true, num_args = 2..)]
    pub results: Vec<PathBuf>,

    /// Output folder for report.html and the images it shows.
    #[arg(long, short, value_name = "DIR")]
    pub out: PathBuf,

    /// The label of a result in the page's columns, once per result in order (else the result
    /// folder's name, or its parent's for ARCHIVE/results).
    #[arg(long = "label", value_name = "TEXT")]
    pub labels: Vec<String>,

    /// Show each result's own pictures, each on its own colour scale (by default the heatmaps are
    /// drawn again on one scale, 0 to the largest count of any result, so colours compare).
    #[arg(long)]
    pub own_scales: bool,
}

#[derive(Args)]
pub(crate) struct MergeArgs {
    /// The shards' result folders (or their result.json files).
    #[arg(required = true)]
    pub results: Vec<PathBuf>,

    /// Output folder.
    #[arg(long, short, value_name = "DIR")]
    pub out: PathBuf,

    /// Columns of parts.csv (as for the analysis).
    #[arg(long, value_enum, default_value_t = CsvStyle::Report)]
    pub csv_style: CsvStyle,

    /// Size of the heatmap views: each is 400×300 pixels times this (1–8).
    #[arg(long, value_name = "N", default_value_t = ufcsr::output::DEFAULT_VIEWS_SCALE,
          value_parser = clap::value_parser!(u32).range(1..=8))]
    pub views_scale: u32,
}

#[derive(Args)]
pub(crate) struct HeatmapArgs {
    /// A result folder written by ufcsr analyze, or its result.json.
    pub result: PathBuf,

    /// Heatmap texture PNG to write (the palette's UV layout, as the result's heatmap.png).
    #[arg(long, short, value_name = "PNG")]
    pub out: PathBuf,

    #[command(flatten)]
    pub heatmap: HeatmapScaleArgs,

    /// Angular area (deg²·s per texel) shown as the top of the colour scale (default: the
    /// result's own, else the largest texel's; --max is the count's).
    #[arg(long, value_name = "DEG2_S")]
    pub area_max: Option<f64>,

    /// `on` (the default): the per-texel angular area (deg²·s) when the result has it
    /// (texel-area.f32), as heatmap.png; `off`: the paper's count, as heatmap-count.png.
    #[arg(long, value_enum, default_value_t = Switch::On)]
    pub texel_area: Switch,
}
