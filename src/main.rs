//! `ufcsr-analyze`: command-line front end. Parses arguments into
//! [`ufcsr::AnalyzeOptions`], runs the library, prints the report and maps
//! the outcome to an exit code (0 complete, 1 some images failed, 2 error).

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{Context, Result};
use clap::{Args, Parser, Subcommand};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
mod placement_cli;

use ufcsr::{
    AnalyzeOptions, Color, Dedupe, HeatmapOptions, PaletteChoice, Progress, Scale, Shard, TrimMode, analyze,
    default_output_dir, format_table, read_texel_counts, write_results,
};

/// Counts how often each texel of a vehicle is visible in captured frames
/// (UFCSR), and turns the counts into per-part statistics and a heatmap.
///
/// ARCHIVE is a folder of PNG tiles rendered with a Full Color Space Palette.
/// With a manifest.json in it (written by ufcsr-capture), no other option is
/// needed. Writes result.json, parts.csv, heatmap.png and timings.json to
/// --out (default: ARCHIVE/results).
#[derive(Parser)]
#[command(
    name = "ufcsr-analyze",
    version,
    args_conflicts_with_subcommands = true,
    subcommand_negates_reqs = true,
    after_help = "Exit status: 0 every image was read; 1 results written but some images could not be \
                  read (named on stderr and in result.json); 2 nothing written (bad options or inputs).\n\
                  Example: ufcsr-analyze archive/ --pidt pidt.png --parts parts.csv --out results/"
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
    #[command(flatten)]
    analyze: AnalyzeArgs,
}

#[derive(Subcommand)]
enum Command {
    /// Re-render the heatmap from a result.json, without the archive.
    Heatmap(HeatmapArgs),
    /// Add up the result.json of every shard (`--shard I/N`) of one archive: the same files as
    /// analysing it whole.
    Merge(MergeArgs),
    /// Write one report.html comparing several results (result folders or result.json files;
    /// the first is the reference for the ranking differences).
    Report(ReportArgs),
    /// Write the canonical Full Color Space Palette as a PNG (to texture a mesh in Unity/Blender).
    Palette(PaletteArgs),
    /// Where to put an eHMI: legible exposure per candidate placement and the best 1..k placements
    /// from the exact measure's placement-frames.csv (docs/placement.md).
    Placement(placement_cli::PlacementArgs),
}

#[derive(Args)]
struct PaletteArgs {
    /// PNG to write.
    #[arg(long, short, value_name = "PNG")]
    out: PathBuf,

    /// Palette size, WxH (at most 2^24 texels).
    #[arg(long, default_value = "4096x4096", value_name = "WxH")]
    size: String,
}

#[derive(Args)]
struct AnalyzeArgs {
    /// Folder of captured PNG tiles (searched recursively without a manifest).
    #[arg(required = true)]
    archive: Option<PathBuf>,

    /// Part Identification Texture: palette-sized PNG, each texel in its part's colour.
    #[arg(long, value_name = "PNG")]
    pidt: Option<PathBuf>,

    /// Legend of the PIdT: CSV `name,color` (#RRGGBB) or JSON [{"name","color"}].
    #[arg(long, value_name = "CSV|JSON")]
    parts: Option<PathBuf>,

    /// Palette image with unique colours, in any layout (default: the canonical palette).
    #[arg(long, value_name = "PNG", conflicts_with = "palette_size")]
    fcsp: Option<PathBuf>,

    /// Size of the canonical palette, WxH (default 4096x4096).
    #[arg(long, value_name = "WxH")]
    palette_size: Option<String>,

    /// Background colour to ignore, #RRGGBB; repeat for several (default #000FFF).
    #[arg(long, value_name = "HEX")]
    background: Vec<String>,

    /// What one count means: `image` (once per PNG), `frame` (once per eye-frame) or `eye-pair`
    /// (once per frame over both eyes); the last two need a manifest.
    #[arg(long, value_enum, default_value_t = Dedupe::Image)]
    dedupe: Dedupe,

    /// Skip all-background tiles: `auto` (find and verify the empty-file size), a size in bytes, or `off`.
    #[arg(long, default_value = "auto", value_name = "auto|BYTES|off")]
    trim: String,

    #[command(flatten)]
    heatmap: HeatmapScaleArgs,

    /// Output folder (default: ARCHIVE/results).
    #[arg(long, short, value_name = "DIR")]
    out: Option<PathBuf>,

    /// Count only shard I of N (0 ≤ I < N) of the archive's eye-frames; merge the shards'
    /// results with `ufcsr-analyze merge`. Default: from SLURM_ARRAY_TASK_ID/COUNT, or
    /// JOB_COMPLETION_INDEX / AWS_BATCH_JOB_ARRAY_INDEX with UFCSR_SHARD_COUNT.
    #[arg(long, value_name = "I/N")]
    shard: Option<String>,

    /// The vehicle as unwrapped (glTF/GLB whose UVs address the palette), for heatmap.glb;
    /// default: the archive's vehicle.glb (written by ufcsr-capture).
    #[arg(long, value_name = "GLB")]
    mesh: Option<PathBuf>,

    /// Per-eye-frame pixels and texels by part (frames.csv) and the resolution-independent
    /// measures (deg²·s, exposure seconds) in result.json and parts.csv: `on` or `off`.
    #[arg(long, value_enum, default_value_t = Switch::On)]
    frames_csv: Switch,

    /// Worker threads (default: all cores).
    #[arg(long, short = 'j', value_name = "N")]
    threads: Option<usize>,

    /// Stop at the first image that cannot be read (default: report it, go on, exit 1).
    #[arg(long)]
    strict: bool,

    /// Ignore ARCHIVE/manifest.json.
    #[arg(long)]
    no_manifest: bool,

    /// No progress bar and no table; errors still go to stderr.
    #[arg(long, short)]
    quiet: bool,

    /// Print the result summary as JSON on stdout instead of the table.
    #[arg(long)]
    json: bool,
}

/// An on/off option.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum Switch {
    On,
    Off,
}

#[derive(Args)]
struct HeatmapScaleArgs {
    /// Colour scale of the heatmap: `linear` or `log` (default: linear, or the result's own).
    #[arg(long, value_enum)]
    scale: Option<Scale>,

    /// Count shown as the top of the colour scale (share one scale across scenarios).
    #[arg(long, value_name = "N")]
    max: Option<u32>,
}

#[derive(Args)]
struct ReportArgs {
    /// Result folders (or their result.json), at least two.
    #[arg(required = true, num_args = 2..)]
    results: Vec<PathBuf>,

    /// Output folder for report.html and the images it shows.
    #[arg(long, short, value_name = "DIR")]
    out: PathBuf,
}

#[derive(Args)]
struct MergeArgs {
    /// The shards' result.json files.
    #[arg(required = true)]
    results: Vec<PathBuf>,

    /// Output folder.
    #[arg(long, short, value_name = "DIR")]
    out: PathBuf,
}

#[derive(Args)]
struct HeatmapArgs {
    /// A result.json written by ufcsr-analyze.
    result: PathBuf,

    /// Heatmap PNG to write.
    #[arg(long, short, value_name = "PNG")]
    out: PathBuf,

    #[command(flatten)]
    heatmap: HeatmapScaleArgs,
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    ufcsr::remove_temporaries_on_interrupt();
    if let Some(value) = ufcsr::Kernel::unknown_request() {
        eprintln!(
            "warning: {}={value:?} names no kernel (portable, avx2, avx512); using {}",
            ufcsr::KERNEL_ENV,
            ufcsr::Kernel::selected().name()
        );
    }
    let outcome = match cli.command {
        Some(Command::Heatmap(args)) => run_heatmap(args),
        Some(Command::Palette(args)) => run_palette(args),
        Some(Command::Merge(args)) => run_merge(args),
        Some(Command::Report(args)) => run_report(args),
        Some(Command::Placement(args)) => placement_cli::run_placement(args),
        None => run_analyze(cli.analyze),
    };
    match outcome {
        Ok(code) => code,
        Err(error) => {
            eprintln!("error: {error:#}");
            ExitCode::from(2)
        }
    }
}

fn heatmap_options(args: &HeatmapScaleArgs, stored: Option<(Scale, Option<u32>)>) -> Result<HeatmapOptions> {
    let scale = match args.scale {
        Some(scale) => scale,
        None => stored.map(|s| s.0).unwrap_or_default(),
    };
    let max = args.max.or(stored.and_then(|s| s.1));
    if max == Some(0) {
        anyhow::bail!("--max must be at least 1");
    }
    Ok(HeatmapOptions { scale, max })
}

fn run_heatmap(args: HeatmapArgs) -> Result<ExitCode> {
    let stored = read_texel_counts(&args.result)?;
    let options = heatmap_options(&args.heatmap, Some((stored.scale, stored.max)))?;
    ufcsr::write_heatmap(&args.out, &stored.texel_counts, stored.width, stored.height, options)?;
    eprintln!("wrote {}", args.out.display());
    Ok(ExitCode::SUCCESS)
}

fn run_palette(args: PaletteArgs) -> Result<ExitCode> {
    let (width, height) = ufcsr::parse_palette_size(&args.size)?;
    ufcsr::write_canonical_png(&args.out, width, height)?;
    eprintln!("wrote {} ({width}×{height} canonical palette)", args.out.display());
    Ok(ExitCode::SUCCESS)
}

/// A progress bar on stderr (drawn only on a terminal).
struct Bar(ProgressBar);

impl Progress for Bar {
    fn start(&self, total: u64) {
        self.0.set_length(total);
    }
    fn advance(&self, done: u64) {
        self.0.inc(done);
    }
    fn finish(&self) {
        self.0.finish_and_clear();
    }
}

/// More worker threads than this is a typo, not a machine.
const MAX_THREADS: usize = 1024;

fn run_report(args: ReportArgs) -> Result<ExitCode> {
    let page = ufcsr::write_comparison(&args.results, &args.out)?;
    println!("compared {} results; wrote {}", args.results.len(), page.display());
    Ok(ExitCode::SUCCESS)
}

fn run_merge(args: MergeArgs) -> Result<ExitCode> {
    let mut analysis = ufcsr::merge_results(&args.results)?;
    let written = write_results(&mut analysis, &args.out)?;
    print!("{}", format_table(&analysis.result));
    println!("\nmerged {} results; wrote {}", args.results.len(), written.result_json.display());
    for warning in &analysis.result.warnings {
        eprintln!("warning: {warning}");
    }
    Ok(if analysis.is_complete() { ExitCode::SUCCESS } else { ExitCode::from(1) })
}

/// The analysis options from the command line (validated once, here), and the output folder.
fn analyze_options(args: &AnalyzeArgs) -> Result<(AnalyzeOptions, PathBuf)> {
    let archive = args.archive.clone().context("ARCHIVE is required")?;
    if let Some(threads) = args.threads {
        anyhow::ensure!(threads <= MAX_THREADS, "--threads {threads}: at most {MAX_THREADS}");
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads.max(1))
            .build_global()
            .context("could not start the worker threads")?;
    }
    let palette = match (&args.fcsp, &args.palette_size) {
        (Some(path), _) => Some(PaletteChoice::Image(path.clone())),
        (None, Some(size)) => {
            let (width, height) = ufcsr::parse_palette_size(size)?;
            Some(PaletteChoice::Canonical { width, height })
        }
        (None, None) => None,
    };
    let background = if args.background.is_empty() {
        None
    } else {
        Some(
            args.background
                .iter()
                .map(|text| text.parse::<Color>().with_context(|| "invalid --background".to_string()))
                .collect::<Result<Vec<_>>>()?,
        )
    };
    let out_dir = args.out.clone().unwrap_or_else(|| default_output_dir(&archive));
    let heatmap = heatmap_options(&args.heatmap, None)?;
    let options = AnalyzeOptions {
        archive,
        palette,
        pidt: args.pidt.clone(),
        legend: args.parts.clone(),
        background,
        dedupe: args.dedupe,
        trim: args.trim.parse::<TrimMode>()?,
        heatmap,
        strict: args.strict,
        exclude: vec![out_dir.clone()],
        ignore_manifest: args.no_manifest,
        mesh: args.mesh.clone(),
        frames: args.frames_csv == Switch::On,
        shard: match &args.shard {
            Some(text) => Some(text.parse::<Shard>()?),
            None => Shard::from_job_array(|name| std::env::var(name).ok())?,
        },
    };
    Ok((options, out_dir))
}

/// The table (or JSON) and where every output went, on stdout.
fn print_summary(
    args: &AnalyzeArgs,
    analysis: &ufcsr::Analysis,
    written: &ufcsr::WrittenFiles,
    out_dir: &Path,
) -> Result<()> {
    let result = &analysis.result;
    if args.json {
        let summary = serde_json::json!({
            "result": result,
            "timings": analysis.timings,
            "files": {
                "result_json": written.result_json,
                "parts_csv": written.parts_csv,
                "heatmap_png": written.heatmap_png,
                "timings_json": written.timings_json,
                "frames_csv": written.frames_csv,
            },
        });
        println!("{}", serde_json::to_string_pretty(&summary)?);
    } else if !args.quiet {
        print!("{}", format_table(result));
        println!(
            "\n{:.2} s ({:.0} Mpixel/s decoded); wrote {}",
            analysis.timings.total_seconds,
            analysis.timings.decoded_megapixels_per_second,
            out_dir.display()
        );
        println!("  report:  {}", written.report_html.display());
        if let Some(glb) = &written.heatmap_glb {
            println!("  vehicle: {} (the heatmap on the vehicle, glTF)", glb.display());
        }
        println!("  data:    {}, {}", written.result_json.display(), written.heatmap_png.display());
        if let Some(frames) = &written.frames_csv {
            println!("  frames:  {} (pixels and texels per eye-frame and part)", frames.display());
        }
        if !written.plots.is_empty() {
            let plots: Vec<&str> = written.plots.iter().map(|plot| plot.shown.as_str()).collect();
            println!("  plots:   {} (in {})", plots.join(", "), out_dir.display());
        }
    }
    Ok(())
}

fn run_analyze(args: AnalyzeArgs) -> Result<ExitCode> {
    let (options, out_dir) = analyze_options(&args)?;
    let bar = ProgressBar::with_draw_target(
        Some(0),
        if args.quiet { ProgressDrawTarget::hidden() } else { ProgressDrawTarget::stderr() },
    );
    bar.set_style(
        ProgressStyle::with_template("{spinner} counting {pos}/{len} images [{bar:40}] {per_sec} eta {eta}")
            .unwrap_or_else(|_| ProgressStyle::default_bar())
            .progress_chars("=> "),
    );
    let mut analysis = analyze(&options, Some(&Bar(bar)))?;
    let written = write_results(&mut analysis, &out_dir)?;

    print_summary(&args, &analysis, &written, &out_dir)?;
    let result = &analysis.result;
    for warning in &result.warnings {
        eprintln!("warning: {warning}");
    }
    for stray in result.images_with_stray_pixels.iter().take(10) {
        eprintln!(
            "warning: {}: {} stray pixels (neither background nor palette)",
            stray.file, stray.stray_pixels
        );
    }
    if result.images_with_stray_pixels.len() > 10 {
        eprintln!(
            "warning: {} more images have stray pixels (see result.json)",
            result.images_with_stray_pixels.len() - 10
        );
    }
    for failure in &result.failures {
        eprintln!("error: {}", failure.error);
    }
    if analysis.is_complete() {
        Ok(ExitCode::SUCCESS)
    } else {
        eprintln!(
            "{} of {} images failed and were not counted; results cover the rest",
            result.images.failed, result.images.found
        );
        Ok(ExitCode::from(1))
    }
}
