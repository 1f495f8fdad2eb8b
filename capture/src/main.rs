//! `ufcsr-capture`: record UFCSR archives of a vehicle approaching a pedestrian.
//!
//! Thin edge: parse the command line, build the scene and options, call the
//! library, print a report, turn errors into an exit code.

use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Context;
use clap::{Args, Parser, Subcommand};
use ufcsr_capture::archive::{self, CaptureOptions, Compression, FrameSelection, Summary};
use ufcsr_capture::render::gpu::{Backend, Gpu};
use ufcsr_capture::inspect::{self, InspectOptions};
use ufcsr_capture::texture::pidt::own::OwnLabels;
use ufcsr_capture::scene::Scene;
use ufcsr_capture::unobstructed::MeasureDevice;
use ufcsr_capture::texture::uv_islands::parse_palette_size;

#[derive(Parser)]
#[command(
    name = "ufcsr-capture",
    version,
    about = "Record UFCSR archives with a headless, exact wgpu renderer"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// The built-in demo: pickup truck, intersection, scenarios A–D.
    Demo {
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
}

/// A resolution study (see `ufcsr_capture::study`).
#[derive(Args)]
struct StudyArgs {
    /// `demo`, or a scene JSON file.
    scene: String,
    /// Scenario name (default: the first, A for the demo).
    #[arg(long)]
    scenario: Option<String>,
    /// Pixels per degree to try; the highest is the reference.
    #[arg(long, value_delimiter = ',', default_value = "60,40,30,20,15,10,6")]
    ppd: Vec<f64>,
    /// Every n-th frame to try; the smallest is the reference.
    #[arg(long, value_delimiter = ',', default_value = "1,2,4,6,10")]
    frame_step: Vec<u32>,
    /// Largest acceptable share L1 error against the reference, percentage points.
    #[arg(long, default_value_t = 1.0)]
    tolerance: f64,
    /// What one count means: image (once per tile), frame (once per eye-frame) or eye-pair
    /// (once per frame over both eyes).
    #[arg(long, value_enum, default_value_t = ufcsr::Dedupe::Image)]
    dedupe: ufcsr::Dedupe,
    /// Canonical palette size, W or WxH.
    #[arg(long, default_value = "4096")]
    palette_size: String,
    /// Study folder: study.csv, study.json, study.svg/.png and one folder per setting.
    #[arg(long, default_value = "study")]
    out: PathBuf,
    /// GPU backend.
    #[arg(long, value_enum, default_value_t = Backend::Auto)]
    backend: Backend,
    /// Also compare every setting with the exact unobstructed measure of this share of the
    /// texels, e.g. 1/64 (see --measure unobstructed).
    #[arg(long, value_name = "FRACTION")]
    unobstructed_sample: Option<String>,
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

#[derive(Args)]
struct Common {
    /// Output folder (one archive; with --scenario all, one sub-folder per scenario).
    #[arg(long, default_value = "archive")]
    out: PathBuf,
    /// Scenario name, or `all` (default: the first, A for the demo).
    #[arg(long)]
    scenario: Option<String>,
    /// Pixels per degree (60 = the paper's 6420×8100 per eye); rounded to whole tiles.
    #[arg(long)]
    ppd: Option<f64>,
    /// Rig overrides as JSON, e.g. '{"eye_height_m": 1.6, "pedestrian": [-6, -6, 0]}' (applied before --ppd).
    #[arg(long, value_name = "JSON")]
    rig: Option<String>,
    /// Canonical palette size, W or WxH (default 4096).
    #[arg(long, default_value = "4096")]
    palette_size: String,
    /// An external palette PNG (unique colours) instead of the canonical palette.
    #[arg(long, value_name = "PNG")]
    palette: Option<PathBuf>,
    /// Keep the mesh's own UVs (checked to be unique and non-overlapping).
    #[arg(long)]
    keep_uvs: bool,
    /// With --keep-uvs: a PIdT painted for the mesh's own UVs (e.g. in Blender), used as is.
    #[arg(long, value_name = "PNG", requires_all = ["keep_uvs", "parts"])]
    pidt: Option<PathBuf>,
    /// The legend (name,color CSV or JSON) of --pidt.
    #[arg(long, value_name = "FILE", requires = "pidt")]
    parts: Option<PathBuf>,
    /// Frames to capture: `all` or a list like 0,30,60-90/10.
    #[arg(long, default_value = "all")]
    frames: String,
    /// Tile PNG compression.
    #[arg(long, value_enum, default_value_t = Compression::Fast)]
    png_compression: Compression,
    /// Skip tiles already on disk (readable PNGs of the tile size; others are rendered again).
    #[arg(long)]
    resume: bool,
    /// Write rendered tiles even when they are pure background.
    #[arg(long)]
    keep_background_tiles: bool,
    /// Render every tile, even those the vehicle's projected bounds do not touch.
    #[arg(long)]
    no_cull: bool,
    /// Render whole tiles: no scissor to the vehicle's projected bounds, no skipping of
    /// tiles occluders hide (same tiles either way; for benchmarks and checks).
    #[arg(long)]
    no_scissor: bool,
    /// GPU backend: auto (Vulkan, then GL; UFCSR_BACKEND overrides auto), vulkan or gl.
    #[arg(long, value_enum, default_value_t = Backend::Auto)]
    backend: Backend,
    /// PNG encoder threads (0: one per core).
    #[arg(long, default_value_t = 0)]
    threads: usize,
    /// Count each rendered tile straight from the GPU readback with the analyzer (no PNGs):
    /// writes the manifest, PIdT, legend and the analyzer's results/ (same result.json as
    /// capturing PNGs and running `ufcsr-analyze --trim off`).
    #[arg(long)]
    count: bool,
    /// With --count: what one count means, image (once per tile), frame (once per eye-frame) or
    /// eye-pair (once per frame over both eyes).
    #[arg(long, value_enum, default_value_t = ufcsr::Dedupe::Image, requires = "count")]
    dedupe: ufcsr::Dedupe,
    /// `unobstructed`: instead of rendering pixels, count per texel the eye-frames in which its
    /// point is in view, faces the eye and is not hidden (exact ray casts; writes results/).
    #[arg(long, value_name = "unobstructed")]
    measure: Option<String>,
    /// With --measure unobstructed: the share of texels to measure, e.g. 1/16 or 0.25 (seeded).
    #[arg(long, default_value = "1", requires = "measure")]
    sample: String,
    /// Seed of the texel sample.
    #[arg(long, default_value_t = 1, requires = "measure")]
    seed: u64,
    /// With --measure unobstructed: K, each texel's footprint is sampled on K×K sub-cells (a texel
    /// counts when any sample is visible; the solid angle sums them). 1: one sample per texel piece.
    #[arg(long, default_value_t = ufcsr_capture::unobstructed::DEFAULT_TEXEL_SAMPLES, requires = "measure")]
    texel_samples: u32,
    /// Where the unobstructed measure runs: cpu (every core; the reference) or gpu (wgpu compute
    /// in f64; needs SHADER_F64, which Mesa's lavapipe and data-centre GPUs have).
    #[arg(long, value_enum, default_value_t = MeasureDevice::Cpu, requires = "measure")]
    measure_on: MeasureDevice,
    /// Render only shard I of N (0 ≤ I < N) of the selected frames into --out, with the other
    /// shards; then `ufcsr-capture assemble OUT`. `auto`: from the job array (SLURM_ARRAY_TASK_ID
    /// and _COUNT, or JOB_COMPLETION_INDEX / AWS_BATCH_JOB_ARRAY_INDEX with UFCSR_SHARD_COUNT).
    #[arg(long, value_name = "I/N|auto")]
    shard: Option<String>,
    /// No progress bar.
    #[arg(long, short)]
    quiet: bool,
}

/// `I/N`, or `auto`: the job array's index (an error outside one). Unlike the
/// analyzer, the capture does not read a job array unasked: batch tasks run as
/// array tasks too, each a whole capture.
fn parse_shard(text: &str) -> anyhow::Result<ufcsr::Shard> {
    if text == "auto" {
        return ufcsr::Shard::from_job_array(|name| std::env::var(name).ok())?.context(
            "--shard auto: no job array index in the environment (SLURM_ARRAY_TASK_ID, JOB_COMPLETION_INDEX \
             or AWS_BATCH_JOB_ARRAY_INDEX)",
        );
    }
    Ok(text.parse()?)
}

/// `1/16`, `0.25` or `1`.
fn parse_fraction(text: &str) -> anyhow::Result<f64> {
    let value = match text.split_once('/') {
        Some((a, b)) => a.trim().parse::<f64>()? / b.trim().parse::<f64>()?,
        None => text.trim().parse::<f64>()?,
    };
    anyhow::ensure!(value > 0.0 && value <= 1.0, "--sample {text}: must be a fraction in (0, 1]");
    Ok(value)
}

fn run(cli: Cli) -> anyhow::Result<()> {
    let (mut scene, common) = match cli.command {
        Command::Demo { common } => (Scene::demo(), common),
        Command::Scene { scene, common } => (Scene::load(&scene)?, common),
        Command::Unity { file, common } => (Scene::unity(&file)?, common),
        Command::Inspect { input, out, pixels_per_metre } => {
            let inspection = inspect::inspect(&InspectOptions { input, out, pixels_per_metre })?;
            print!("{inspection}");
            return Ok(());
        }
        Command::Study(args) => return run_study(args),
        Command::Views { results, model, out, backend } => {
            let gpu = Gpu::create(backend)?;
            let options = ufcsr_capture::inspect::heatmap_views_gpu::ViewsOptions { results, model, out };
            let written =
                ufcsr_capture::inspect::heatmap_views_gpu::views_from_results(&gpu.device, &gpu.queue, &options)?;
            println!("views ({}): {}", gpu.describe(), written.contact_sheet.display());
            for view in &written.views {
                println!("  {}", view.display());
            }
            return Ok(());
        }
        Command::Batch { action: BatchAction::Plan { batch, program } } => {
            let plan = ufcsr_capture::archive::batch::load(&batch)?;
            let program = match program {
                Some(program) => program,
                None => std::env::current_exe()?.display().to_string(),
            };
            let base = batch.parent().unwrap_or(std::path::Path::new("."));
            let mut stdout = std::io::stdout().lock();
            for task in ufcsr_capture::archive::batch::plan(&plan, base, &program)? {
                // The plan is made to be piped (`| head`, `| sed -n 5p`): a
                // reader that stops early is not an error.
                match writeln!(stdout, "{}", task.shell_line()) {
                    Err(error) if error.kind() == std::io::ErrorKind::BrokenPipe => return Ok(()),
                    other => other?,
                }
            }
            return Ok(());
        }
        Command::Assemble { archive } => {
            let assembled = ufcsr_capture::archive::capture_shard::assemble(&archive)?;
            println!(
                "{}: {} shards, {} frames, {} tiles → {}",
                archive.display(),
                assembled.shards,
                assembled.frames,
                assembled.tiles,
                assembled.manifest_path.display()
            );
            return Ok(());
        }
        Command::Verify { archive } => {
            let (vehicle, stray) = archive::verify(&archive)?;
            println!("{}: {vehicle} vehicle pixels, {stray} stray pixels", archive.display());
            anyhow::ensure!(stray == 0, "{stray} pixels are neither background nor labelled palette texels");
            return Ok(());
        }
    };
    for warning in &scene.warnings {
        eprintln!("warning: {warning}");
    }
    if let Some(json) = &common.rig {
        scene.rig = scene.rig.override_with(json)?;
    }
    if let Some(ppd) = common.ppd {
        scene.rig.set_pixels_per_degree(ppd)?;
    }
    let options = CaptureOptions {
        out: common.out.clone(),
        palette: parse_palette_size(&common.palette_size)?,
        palette_file: common.palette.clone(),
        keep_uvs: common.keep_uvs,
        own_labels: match (common.pidt.clone(), common.parts.clone()) {
            (Some(pidt), Some(parts)) => Some(OwnLabels { pidt, parts }),
            _ => None,
        },
        frames: common.frames.parse::<FrameSelection>()?,
        compression: common.png_compression,
        resume: common.resume,
        keep_background_tiles: common.keep_background_tiles,
        no_cull: common.no_cull,
        no_scissor: common.no_scissor,
        progress: !common.quiet,
        encoder_threads: common.threads,
        shard: common.shard.as_deref().map(parse_shard).transpose()?,
    };
    let all = common.scenario.as_deref().is_some_and(|s| s.eq_ignore_ascii_case("all"));
    let names: Vec<String> = match &common.scenario {
        Some(all) if all.eq_ignore_ascii_case("all") => {
            scene.scenarios.iter().map(|s| s.name.clone()).collect()
        }
        Some(name) => vec![scene.scenario(name)?.name.clone()],
        None => scene.scenarios.iter().take(1).map(|s| s.name.clone()).collect(),
    };
    let gpu = Gpu::create(common.backend).context("creating the GPU device")?;
    eprintln!("adapter: {}", gpu.describe());
    let rig = &scene.rig;
    eprintln!(
        "eye {}×{} px in {}×{} tiles of {}×{}, {:.2} px/°, palette {}",
        rig.eye_pixels[0],
        rig.eye_pixels[1],
        rig.tiles[0],
        rig.tiles[1],
        rig.tile_pixels()[0],
        rig.tile_pixels()[1],
        rig.pixels_per_degree(),
        match &options.palette_file {
            Some(file) => file.display().to_string(),
            None => format!("{}×{} (canonical)", options.palette[0], options.palette[1]),
        }
    );
    if let Some(measure) = &common.measure {
        anyhow::ensure!(
            measure == "unobstructed",
            "--measure {measure:?}: the only other measure is unobstructed"
        );
        anyhow::ensure!(
            options.shard.is_none(),
            "--measure unobstructed with --shard is not supported: sample fewer texels (--sample) instead"
        );
        let sample = parse_fraction(&common.sample)?;
        archive::for_each_scenario(&scene, &names, all, &options, |scenario, options| {
            let measured = ufcsr_capture::unobstructed::measure_unobstructed(
                &gpu.device,
                &gpu.queue,
                &scene,
                scenario,
                options,
                &ufcsr_capture::unobstructed::MeasureOptions {
                    sample,
                    seed: common.seed,
                    texel_samples: common.texel_samples,
                    on: common.measure_on,
                },
            )?;
            println!(
                "scenario {}: unobstructed measure of {} of {} texels ({} surface samples) over {} eye-frames in {:.2} s",
                scenario.name,
                measured.sampled_texels,
                measured.labelled_texels,
                measured.surface_samples,
                measured.eye_frames,
                measured.seconds
            );
            println!(
                "  ray casts: {:.2} s, {:.3e} sample-eye-frame tests per second (each up to two segment queries)",
                measured.visibility_seconds,
                (measured.surface_samples * measured.eye_frames) as f64
                    / measured.visibility_seconds.max(1e-9)
            );
            print!("{}", ufcsr::format_table(&measured.analysis.result));
            for warning in &measured.analysis.result.warnings {
                eprintln!("  warning: {warning}");
            }
            println!("  results: {}", measured.written.result_json.display());
            println!("           {} (per-part estimates, standard errors)", measured.estimates_csv.display());
            Ok(())
        })?;
        return Ok(());
    }
    if common.count {
        let dedupe = common.dedupe;
        archive::for_each_scenario(&scene, &names, all, &options, |scenario, options| {
            let counted =
                archive::capture_counted(&gpu.device, &gpu.queue, &scene, scenario, options, dedupe)?;
            report(&counted.summary);
            report_counted(&counted);
            Ok(())
        })?;
        return Ok(());
    }
    let summaries = archive::capture_all(&gpu.device, &gpu.queue, &scene, &names, all, &options)?;
    for summary in &summaries {
        report(summary);
        if let Some(shard) = options.shard {
            println!(
                "  shard {shard}: wrote its part of the manifest; once every shard has finished, run \
                 `ufcsr-capture assemble {}`",
                summary.out.display()
            );
        }
    }
    Ok(())
}

fn report(s: &Summary) {
    println!(
        "scenario {}: {} frames in {:.2} s ({:.2} s setup; {:.2} frames/s, both eyes, encoding included) → {}",
        s.scenario,
        s.frames,
        s.seconds,
        s.setup_seconds,
        s.frames_per_second(),
        s.out.display()
    );
    println!(
        "  tiles: {} total, {} rendered, {} written, {} culled (outside the vehicle's bounds), {} background only, {} resumed",
        s.tiles, s.tally.rendered, s.tally.written, s.tally.culled, s.tally.background, s.tally.resumed
    );
    // On stderr: how the run was done, not what it found.
    eprintln!(
        "  left out: {} of the {} pixels of tiles the vehicle's bounds touch ({:.1}%, scissor), {} tiles hidden by occluders (not rendered)",
        s.tally.pixels_scissored,
        s.pixels,
        if s.pixels > 0 { s.tally.pixels_scissored as f64 * 100.0 / s.pixels as f64 } else { 0.0 },
        s.tally.hidden
    );
    println!(
        "  unwrap: {} triangles, {} parts, {:.1} texels/m² ({:.1} mm texels), {:.1}% of the palette used",
        s.triangles,
        s.parts,
        s.texels_per_m2,
        1000.0 / s.texels_per_m2.sqrt(),
        s.palette_share * 100.0
    );
    for warning in &s.warnings {
        eprintln!("  warning: {warning}");
    }
}

fn run_study(args: StudyArgs) -> anyhow::Result<()> {
    let scene =
        if args.scene == "demo" { Scene::demo() } else { Scene::load(std::path::Path::new(&args.scene))? };
    let scenario = match &args.scenario {
        Some(name) => scene.scenario(name)?.name.clone(),
        None => scene.scenarios.first().map(|s| s.name.clone()).context("the scene has no scenario")?,
    };
    let options = ufcsr_capture::study::StudyOptions {
        scenario,
        ppds: args.ppd,
        frame_steps: args.frame_step,
        tolerance_pp: args.tolerance,
        dedupe: args.dedupe,
        capture: CaptureOptions {
            out: args.out.clone(),
            palette: parse_palette_size(&args.palette_size)?,
            ..CaptureOptions::default()
        },
        unobstructed_sample: args.unobstructed_sample.as_deref().map(parse_fraction).transpose()?,
    };
    let gpu = Gpu::create(args.backend).context("creating the GPU device")?;
    eprintln!("adapter: {}", gpu.describe());
    let study = ufcsr_capture::study::run_study(&gpu.device, &gpu.queue, &scene, &options)?;
    println!("scenario {}: reference {}", study.scenario, study.reference);
    println!(
        "{:>6} {:>5} {:>6} {:>9} {:>9} {:>9} {:>7} {:>5} {:>6} {:>12} {:>9}",
        "ppd",
        "step",
        "frames",
        "seconds",
        "L1 pp",
        "max pp",
        "tau",
        "top5",
        "pareto",
        "L1 vs exact",
        "tau exact"
    );
    for row in &study.rows {
        let e = &row.error;
        let exact = row.error_vs_unobstructed.as_ref();
        println!(
            "{:>6} {:>5} {:>6} {:>9.2} {:>9.3} {:>9.3} {:>7.3} {:>5} {:>6} {:>12} {:>9}",
            row.ppd,
            row.frame_step,
            row.frames,
            row.seconds,
            e.share_l1_pp,
            e.share_max_pp,
            e.kendall_tau_total,
            e.top_k_overlap,
            if row.pareto { "*" } else { "" },
            exact.map_or("-".into(), |u| format!("{:.3}", u.share_l1_pp)),
            exact.map_or("-".into(), |u| format!("{:.3}", u.kendall_tau_total)),
        );
    }
    match study.cheapest_within_tolerance {
        Some(index) => {
            let row = &study.rows[index];
            println!(
                "cheapest within {} pp: {} ({:.2} s, share L1 {:.3} pp)",
                study.tolerance_pp,
                row.label(),
                row.seconds,
                row.error.share_l1_pp
            );
        }
        None => println!("no setting is within {} pp of the reference", study.tolerance_pp),
    }
    for file in ufcsr_capture::study::write_study(&study, &args.out)? {
        println!("wrote {}", file.display());
    }
    Ok(())
}

fn report_counted(counted: &archive::CountedCapture) {
    let result = &counted.analysis.result;
    println!(
        "  counted: {} tiles, {:.1} Mpixels straight from the renderer (no PNGs); {} texels seen, grand total {}",
        result.images.decoded,
        counted.pixels_counted as f64 / 1e6,
        result.texels_seen,
        result.grand_total
    );
    print!("{}", ufcsr::format_table(result));
    let written = &counted.written;
    println!("  results: {}", written.result_json.display());
    if let Some(parts) = &written.parts_csv {
        println!("           {}", parts.display());
    }
    println!("           {}", written.heatmap_png.display());
}

fn main() -> ExitCode {
    ufcsr::remove_temporaries_on_interrupt();
    match run(Cli::parse()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) => {
            // Library errors already name their cause; only add causes that
            // are not in the message yet (anyhow context, wrapped errors).
            let mut message = error.to_string();
            for cause in error.chain().skip(1) {
                let text = cause.to_string();
                if !message.contains(&text) {
                    message = format!("{message}: {text}");
                }
            }
            eprintln!("error: {message}");
            ExitCode::FAILURE
        }
    }
}
