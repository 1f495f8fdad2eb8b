//! The command line of `ufcsr-capture`: the subcommands and one `run_*` for
//! each ([`capture`] the captures of `demo`, `scene` and `unity` with their
//! `--count` and `--measure` variants, [`study`] the resolution study, [`observers`] the
//! observer study,
//! [`tools`] inspect, views, batch, assemble and verify), and the progress
//! bar the library reports to ([`progress`]). Only the binary draws on the
//! terminal; the library returns what it did.

mod capture;
mod observers;
mod progress;
mod study;
mod tools;

use std::path::PathBuf;

use anyhow::Context;
use clap::{Parser, Subcommand};
use ufcsr_capture::{Backend, ViewsOptions};

use capture::Common;
use observers::ObserversArgs;
use study::StudyArgs;

#[derive(Parser)]
#[command(
    name = "ufcsr-capture",
    version,
    about = "Record UFCSR archives with a headless, exact wgpu renderer"
)]
pub struct Cli {
    #[command(subcommand)]
    command: Command,
    /// Nothing on stdout and no progress bar; warnings and errors still go to stderr.
    #[arg(long, short, global = true)]
    quiet: bool,
    /// Worker threads: PNG encoders, the exact measure's ray casting and the other parallel
    /// work (default 0: one per core).
    #[arg(long, short = 'j', global = true, default_value_t = 0, value_parser = clap::value_parser!(u16).range(0..=1024))]
    threads: u16,
    /// One JSON object on stdout instead of the text: command, exit_code, written (every file
    /// written) and the command's own facts; on an error, exit_code, an empty written and error.
    #[arg(long, global = true)]
    pub json: bool,
}

impl Cli {
    /// The subcommand's name, as `--json` reports it.
    pub fn command_name(&self) -> &'static str {
        match &self.command {
            Command::Demo { .. } => "demo",
            Command::Scene { .. } => "scene",
            Command::Unity { .. } => "unity",
            Command::Inspect { .. } => "inspect",
            Command::Views { .. } => "views",
            Command::Batch { .. } => "batch plan",
            Command::Study(_) => "study",
            Command::Observers(_) => "observers",
            Command::Assemble { .. } => "assemble",
            Command::Verify { .. } => "verify",
            Command::Completions { .. } => "completions",
            Command::Man { .. } => "man",
        }
    }
}

/// What a command did, for `--json`, recorded by the `run_*` functions as
/// they go: the files it wrote ([`wrote`]) and its facts ([`fact`], or
/// [`fact_item`] for one entry of a list such as one per scenario).
#[derive(Default)]
struct Outcome {
    written: Vec<PathBuf>,
    facts: Vec<(String, serde_json::Value, bool)>,
}

static OUTCOME: std::sync::Mutex<Outcome> =
    std::sync::Mutex::new(Outcome { written: Vec::new(), facts: Vec::new() });

fn outcome() -> std::sync::MutexGuard<'static, Outcome> {
    OUTCOME.lock().unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// Records a file the command wrote.
pub fn wrote(path: &std::path::Path) {
    outcome().written.push(path.to_path_buf());
}

/// Records one of the command's facts.
pub fn fact(key: &str, value: impl serde::Serialize) {
    let value = serde_json::to_value(value).unwrap_or(serde_json::Value::Null);
    outcome().facts.push((key.into(), value, false));
}

/// Records one entry of the list `key` (e.g. one per scenario).
pub fn fact_item(key: &str, value: impl serde::Serialize) {
    let value = serde_json::to_value(value).unwrap_or(serde_json::Value::Null);
    outcome().facts.push((key.into(), value, true));
}

/// The `--json` summary of a finished (or failed) command.
pub fn json_summary(command: &str, exit_code: u8, error: Option<&str>) -> String {
    let Outcome { written, facts } = std::mem::take(&mut *outcome());
    let mut summary = serde_json::Map::new();
    summary.insert("command".into(), command.into());
    summary.insert("exit_code".into(), exit_code.into());
    if let Some(error) = error {
        // Nothing done: nothing written that counts.
        summary.insert("written".into(), serde_json::Value::Array(Vec::new()));
        summary.insert("error".into(), error.into());
        return serde_json::Value::Object(summary).to_string();
    }
    let written: Vec<String> = written.iter().map(|p| p.display().to_string()).collect();
    summary.insert("written".into(), written.into());
    for (key, value, item) in facts {
        if !item {
            summary.insert(key, value);
            continue;
        }
        match summary.entry(key).or_insert_with(|| serde_json::Value::Array(Vec::new())) {
            serde_json::Value::Array(list) => list.push(value),
            other => *other = serde_json::Value::Array(vec![other.take(), value]),
        }
    }
    serde_json::Value::Object(summary).to_string()
}

/// Set once from `--quiet` before a command runs: [`say!`] prints nothing.
static QUIET: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// Set once from `--json` before a command runs.
static JSON: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// True under `--json`: stdout holds only the summary.
pub fn json() -> bool {
    JSON.load(std::sync::atomic::Ordering::Relaxed)
}

/// True under `--quiet` (and `--json`).
pub fn quiet() -> bool {
    QUIET.load(std::sync::atomic::Ordering::Relaxed)
}

/// `println!` unless `--quiet`: what a command did, on stdout.
macro_rules! say {
    ($($arg:tt)*) => {
        if !$crate::cli::quiet() {
            println!($($arg)*);
        }
    };
}
pub(crate) use say;

#[derive(Subcommand)]
enum Command {
    /// The built-in demo: pickup truck, intersection, scenarios A–D.
    Demo {
        /// A second pickup in traffic: alongside the truck in the lane on the pedestrian's side
        /// (adjacent-lane), or ahead of it in its lane (lead-car); see docs/scene-file.md.
        #[arg(long, value_enum)]
        traffic: Option<ufcsr_capture::DemoTraffic>,
        #[command(flatten)]
        common: Common,
    },
    /// A scene file (see capture/README.md).
    Scene {
        /// The scene JSON file.
        scene: PathBuf,
        #[command(flatten)]
        common: Common,
    },
    /// Replay a Unity export (unity-intersection.json) with the demo truck.
    Unity {
        /// The Unity scenario export.
        file: PathBuf,
        #[command(flatten)]
        common: Common,
    },
    /// Look at a vehicle before capturing: size and origin after `axes`,
    /// triangle quality, UVs, parts and their areas, and pictures of it.
    Inspect {
        /// A scene file (.json) or a mesh (.glb, .gltf, .obj; default axes).
        input: PathBuf,
        /// Folder for inspect-side/top/front.png and inspect-parts.csv.
        #[arg(long, default_value = "inspect")]
        out: PathBuf,
        /// Picture scale (default: the longest picture about 1200 pixels).
        #[arg(long)]
        pixels_per_metre: Option<f64>,
    },
    /// Draw a result's eight heatmap views with the GPU renderer (the analyzer draws them on
    /// the CPU): views/*.png and views.png, from RESULTS/result.json and heatmap.glb.
    Views {
        /// A result folder written by ufcsr-analyze (or --count).
        results: PathBuf,
        /// The vehicle model with its palette UVs (default RESULTS/heatmap.glb).
        #[arg(long)]
        model: Option<PathBuf>,
        /// Where views/ and views.png go (default: the result folder).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Size of the views: each is 400×300 pixels times this (1–8), as the analyzer's.
        #[arg(long, value_name = "N", default_value_t = ufcsr::DEFAULT_VIEWS_SCALE,
              value_parser = clap::value_parser!(u32).range(1..=8))]
        views_scale: u32,
        /// GPU backend.
        #[arg(long, value_enum, default_value_t = Backend::Auto)]
        backend: Backend,
    },
    /// Plan a batch (batch.json: scenes × scenarios × ppd × frame steps): prints one
    /// `ufcsr-capture ... --count` command per task, task i on line i (for job arrays, xargs -P).
    Batch {
        #[command(subcommand)]
        action: BatchAction,
    },
    /// Capture and count one scenario at several ppd and frame steps, compare each with the
    /// finest, and plot error against run time (writes study.csv, study.json, study.svg/.png).
    Study(StudyArgs),
    /// Capture one scenario from pedestrians drawn from a declared population (kerb or area,
    /// statures of a named source) and report per part the population mean, its 95 % interval
    /// (each observer's resolution error folded in) and the spread over people
    /// (writes observers.json, observers.csv, observer-parts.csv).
    Observers(ObserversArgs),
    /// Join the parts the shards of a capture (`--shard I/N`) wrote into the archive's
    /// manifest.json, once all have finished (checks that every shard is there, once).
    Assemble {
        /// The archive folder the shards wrote into (their --out).
        archive: PathBuf,
    },
    /// Check an archive without the analyzer: tile pixels are background or
    /// palette colours the PIdT labels.
    Verify {
        /// The archive folder.
        archive: PathBuf,
    },
    /// Print a shell completion script (bash, zsh, fish, elvish, powershell) on stdout.
    Completions {
        /// The shell.
        #[arg(value_enum)]
        shell: ufcsr::Shell,
    },
    /// Print the man page (roff) on stdout, or write one page per subcommand into --out.
    Man {
        /// Write ufcsr-capture.1 and one ufcsr-capture-COMMAND.1 per subcommand into this folder.
        #[arg(long)]
        out: Option<PathBuf>,
    },
}

#[derive(Subcommand)]
enum BatchAction {
    /// Print the tasks' commands, one per line.
    Plan {
        /// The batch file.
        batch: PathBuf,
        /// The ufcsr-capture the commands call (default: this one).
        #[arg(long)]
        program: Option<String>,
    },
}

/// A command that did its work but found failures (exit code 1), as opposed
/// to one that could do nothing (exit code 2).
#[derive(Debug)]
pub struct DoneWithFailures(pub String);

impl std::fmt::Display for DoneWithFailures {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for DoneWithFailures {}

/// Runs one subcommand.
pub fn run(cli: Cli) -> anyhow::Result<()> {
    // --json: the one JSON object is all that goes to stdout.
    QUIET.store(cli.quiet || cli.json, std::sync::atomic::Ordering::Relaxed);
    JSON.store(cli.json, std::sync::atomic::Ordering::Relaxed);
    let threads = usize::from(cli.threads);
    if threads > 0 {
        // The first and only pool of the process; the exact measure and the placement pass use it.
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build_global()
            .context("setting up the worker threads")?;
    }
    match cli.command {
        Command::Demo { traffic: None, common } => {
            capture::run_capture(ufcsr_capture::Scene::demo(), &common, threads)
        }
        Command::Demo { traffic: Some(traffic), common } => {
            capture::run_demo_with_traffic(traffic, &common, threads)
        }
        Command::Scene { scene, common } => {
            capture::run_capture(ufcsr_capture::Scene::load(&scene)?, &common, threads)
        }
        Command::Unity { file, common } => {
            capture::run_capture(ufcsr_capture::Scene::unity(&file)?, &common, threads)
        }
        Command::Inspect { input, out, pixels_per_metre } => tools::run_inspect(input, out, pixels_per_metre),
        Command::Study(args) => study::run_study(args),
        Command::Observers(args) => observers::run_observers(args),
        Command::Views { results, model, out, views_scale, backend } => {
            tools::run_views(ViewsOptions { results, model, out, views_scale }, backend)
        }
        Command::Batch { action: BatchAction::Plan { batch, program } } => {
            tools::run_batch_plan(&batch, program)
        }
        Command::Assemble { archive } => tools::run_assemble(&archive),
        Command::Verify { archive } => tools::run_verify(&archive),
        Command::Completions { shell } => {
            ufcsr::print_completions(shell, <Cli as clap::CommandFactory>::command(), "ufcsr-capture");
            Ok(())
        }
        Command::Man { out } => {
            for path in ufcsr::write_man_pages(
                <Cli as clap::CommandFactory>::command(),
                "ufcsr-capture",
                out.as_deref(),
            )? {
                wrote(&path);
                eprintln!("wrote {}", path.display());
            }
            Ok(())
        }
    }
}
