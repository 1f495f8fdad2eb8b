//! The capture's commands: the captures (`ufcsr capture demo|scene|unity`;
//! [`captures`], with their `--count` and `--measure` variants; what they
//! measure is a [`Source`], named the same way by `where`, `study` and
//! `observers`), the one route to the placement answer ([`answer`]: `ufcsr
//! where`), the resolution study ([`study`]), the observer
//! study ([`observers`]), the factorial study ([`design`]) and the tools around a capture ([`tools`]: inspect,
//! views, batch plan, assemble, verify), and the private runtime folder Mesa
//! wants ([`runtime_dir`]). Each parses into the capture library's plain
//! options; only the command line draws on the terminal.

mod answer;
mod captures;
mod design;
mod observers;
mod runtime_dir;
mod source;
mod study;
mod tools;

use std::path::PathBuf;

use clap::Subcommand;
use ufcsr_capture::ViewsOptions;

use crate::choices::{BodyType, DemoTraffic};
use crate::console::{Completion, Console};
use crate::options::Global;

pub(crate) use runtime_dir::PrivateRuntimeDir;

use answer::WhereArgs;
use captures::CaptureArgs;
use design::DesignAction;
use observers::ObserversArgs;
use source::Source;
use study::StudyArgs;

/// The captures: a scene recorded into an archive.
#[derive(Subcommand)]
pub(crate) enum CaptureCommand {
    /// The built-in demo: pickup truck, intersection, scenarios A–D.
    ///
    /// Example: `ufcsr capture demo --scenario A --preview --out capA` (a quick look; drop
    /// --preview for the paper's 60 px/° and every frame)
    Demo {
        /// A second pickup in traffic: alongside the truck in the lane on the pedestrian's side
        /// (adjacent-lane), or ahead of it in its lane (lead-car); see docs/scene-file.md.
        #[arg(long, value_enum)]
        traffic: Option<DemoTraffic>,
        /// A body of the parametric family, with its typical dimensions, in place of the truck
        /// (docs/vehicles.md); a scene file can give other dimensions.
        #[arg(long, value_enum, conflicts_with = "traffic")]
        body: Option<BodyType>,
        #[command(flatten)]
        capture: CaptureArgs,
    },
    /// A scene file (see capture/README.md).
    ///
    /// Example: `ufcsr capture scene fixtures/scenes/milk-truck.json --palette-size 1024 --ppd 10 --out
    /// truck`
    Scene {
        /// The scene JSON file.
        scene: PathBuf,
        #[command(flatten)]
        capture: CaptureArgs,
    },
    /// Replay a Unity export (unity-intersection.json) with the demo truck.
    ///
    /// Example: `ufcsr capture unity unity-intersection.json --scenario all --ppd 10 --out unity/`
    Unity {
        /// The Unity scenario export.
        file: PathBuf,
        #[command(flatten)]
        capture: CaptureArgs,
    },
}

/// The commands around a capture.
#[derive(Subcommand)]
pub(crate) enum CaptureToolCommand {
    /// Where should the eHMI go? Measures the scene exactly with display-sized candidates on
    /// every part (as `capture … --measure unobstructed --placement --display`), then ranks them
    /// (as `placement`), and prints the best one, two and three displays with their intervals,
    /// the rules used (display size, surfaces left out, observer) and where the files are.
    ///
    /// The scene is named as after `ufcsr capture`: `demo`, `scene FILE` or `unity FILE`. Every
    /// scenario is measured (unless --scenario names one) so that the answer has an interval
    /// over them; each goes to OUT/runs/SCENARIO, the answer to OUT/answer. Under half a minute
    /// per demo scenario on 2 cores (release build, 1/16 of the texels, every frame).
    ///
    /// Example: `ufcsr where demo --display 0.40x0.15 --symmetric --out where-demo`
    #[command(name = "where")]
    Where(WhereArgs),
    /// Join the parts the shards of a capture (`--shard I/N`) wrote into the archive's
    /// manifest.json, once all have finished (checks that every shard is there, once).
    ///
    /// Example: `ufcsr assemble capA` (after `ufcsr capture demo --shard 0/2 --out capA` and
    /// `--shard 1/2`)
    Assemble {
        /// The archive folder the shards wrote into (their --out).
        archive: PathBuf,
    },
    /// Plan a batch (batch.json: scenes × scenarios × ppd × frame steps): prints one
    /// `ufcsr capture ... --count` command per task, task i on line i (for job arrays, xargs -P).
    ///
    /// Example: `ufcsr batch plan batch.json | xargs -d '\n' -P 4 -I{} sh -c '{}'` (-d keeps the quotes)
    Batch {
        #[command(subcommand)]
        action: BatchAction,
    },
    /// Capture and count one scenario at several ppd and frame steps, compare each with the
    /// finest, and plot error against run time (writes study.csv, study.json, study.svg/.png).
    ///
    /// Example: `ufcsr study demo --scenario A --ppd 40,20,10 --frame-step 1,2,4 --out
    /// study-A`
    Study(StudyArgs),
    /// Capture one scenario from pedestrians drawn from a declared population (kerb or area,
    /// statures of a named source) and report per part the population mean, its 95 % interval
    /// (each observer's resolution error folded in) and the spread over people
    /// (writes observers.json, observers.csv, observer-parts.csv); with --display WxH, the same
    /// per candidate display (and part) for its legible seconds (observer-displays.csv).
    ///
    /// Example: `ufcsr observers demo --scenario A --kerb=-6.5,-4.5:-4.5,-6.5 --observers 16
    /// --seed 1 --out observers-A`
    Observers(ObserversArgs),
    /// The factorial study: plan a design file (vehicles × scenarios × traffic × pedestrians)
    /// into independent tasks, run them (one, or all, resumable) and merge them into one
    /// placement answer per body type (design.json, design.csv, design.html; docs/design.md).
    ///
    /// Example: `ufcsr design run fixtures/designs/tiny-2x2.json --out runs/tiny && ufcsr design merge
    /// fixtures/designs/tiny-2x2.json --out runs/tiny`
    Design {
        #[command(subcommand)]
        action: DesignAction,
    },
    /// Check an archive without the analyzer: tile pixels are background or
    /// palette colours the PIdT labels.
    ///
    /// Example: `ufcsr verify capA`
    Verify {
        /// The archive folder.
        archive: PathBuf,
    },
    /// Look at a vehicle before capturing: size and origin after `axes`,
    /// triangle quality, UVs, parts and their areas, and pictures of it.
    ///
    /// Example: `ufcsr inspect fixtures/scenes/milk-truck.json --out truck-inspect`
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
    /// Redraw a result's eight heatmap views (another scale, the count, another model):
    /// views/*.png, views.png and views.pdf, from RESULTS/result.json and heatmap.glb, drawn as
    /// the analysis draws them.
    ///
    /// Example: `ufcsr views capA/results --views-scale 2`
    Views {
        /// A result folder written by `ufcsr analyze` (or --count).
        results: PathBuf,
        /// The vehicle model with its palette UVs (default RESULTS/heatmap.glb).
        #[arg(long)]
        model: Option<PathBuf>,
        /// Where views/ and views.png go (default: the result folder).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Size of the views: each is 400×300 pixels times this (1–8), as the analyzer's.
        #[arg(long, value_name = "N", default_value_t = ufcsr::output::DEFAULT_VIEWS_SCALE,
              value_parser = clap::value_parser!(u32).range(1..=8))]
        views_scale: u32,
        /// Draw the paper's per-texel count instead of the angular area (deg²·s per texel, the
        /// default where the result kept texel-area.f32; the count otherwise).
        #[arg(long)]
        count: bool,
    },
}

#[derive(Subcommand)]
pub(crate) enum BatchAction {
    /// Print the tasks' commands, one per line.
    ///
    /// Example: `ufcsr batch plan batch.json --program /opt/ufcsr/bin/ufcsr`
    Plan {
        /// The batch file.
        batch: PathBuf,
        /// The ufcsr capture the commands call (default: the ufcsr capture beside this program).
        #[arg(long)]
        program: Option<String>,
    },
}

impl CaptureCommand {
    /// The command's name, as `--json` reports it.
    pub(crate) fn name(&self) -> &'static str {
        match self {
            CaptureCommand::Demo { .. } => "demo",
            CaptureCommand::Scene { .. } => "scene",
            CaptureCommand::Unity { .. } => "unity",
        }
    }
}

impl CaptureToolCommand {
    /// The command's name, as `--json` reports it.
    pub(crate) fn name(&self) -> &'static str {
        match self {
            CaptureToolCommand::Where(_) => "where",
            CaptureToolCommand::Assemble { .. } => "assemble",
            CaptureToolCommand::Batch { .. } => "batch plan",
            CaptureToolCommand::Study(_) => "study",
            CaptureToolCommand::Observers(_) => "observers",
            CaptureToolCommand::Design { action } => action.name(),
            CaptureToolCommand::Verify { .. } => "verify",
            CaptureToolCommand::Inspect { .. } => "inspect",
            CaptureToolCommand::Views { .. } => "views",
        }
    }
}

/// Runs one capture.
pub(crate) fn run_capture_command(
    command: CaptureCommand,
    global: &Global,
    console: &Console,
) -> anyhow::Result<Completion> {
    let (source, capture) = match command {
        CaptureCommand::Demo { traffic, body, capture } => (Source::Demo { traffic, body }, capture),
        CaptureCommand::Scene { scene, capture } => (Source::Scene(scene), capture),
        CaptureCommand::Unity { file, capture } => (Source::Unity(file), capture),
    };
    capture_source(&source, &capture, usize::from(global.threads), console)?;
    Ok(Completion::Done)
}

/// Captures `source` as `capture` says (`threads`: PNG encoders, 0: one per core).
fn capture_source(
    source: &Source,
    capture: &CaptureArgs,
    threads: usize,
    console: &Console,
) -> anyhow::Result<()> {
    match source {
        Source::Demo { traffic: Some(traffic), .. } => {
            captures::run_demo_with_traffic((*traffic).into(), capture, threads, console)
        }
        _ => captures::run_capture(source.scene()?, capture, threads, console),
    }
}

/// Runs one of the commands around a capture.
pub(crate) fn run_tool(command: CaptureToolCommand, console: &Console) -> anyhow::Result<Completion> {
    match command {
        CaptureToolCommand::Where(args) => return answer::run_where(args, console),
        CaptureToolCommand::Assemble { archive } => return tools::run_assemble(&archive, console),
        CaptureToolCommand::Batch { action: BatchAction::Plan { batch, program } } => {
            tools::run_batch_plan(&batch, program, console)
        }
        CaptureToolCommand::Study(args) => study::run_study(args, console),
        CaptureToolCommand::Observers(args) => observers::run_observers(args, console),
        CaptureToolCommand::Design { action } => design::run_design_action(action, console),
        CaptureToolCommand::Verify { archive } => return tools::run_verify(&archive, console),
        CaptureToolCommand::Inspect { input, out, pixels_per_metre } => {
            tools::run_inspect(input, out, pixels_per_metre, console)
        }
        CaptureToolCommand::Views { results, model, out, views_scale, count } => {
            tools::run_views(ViewsOptions { results, model, out, views_scale, count }, console)
        }
    }?;
    Ok(Completion::Done)
}
