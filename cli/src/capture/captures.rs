//! The captures (`demo`, `scene`, `unity`): their arguments ([`CaptureArgs`]) and
//! [`run_capture`] (and [`run_demo_with_traffic`] for `demo --traffic`), which builds the options, creates the device and runs the
//! capture to PNG tiles, the fused count (`--count`) or the exact measure
//! (`--measure unobstructed`), then prints what each scenario gave.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use anyhow::Context;
use clap::{Args, ValueEnum};
use ufcsr_capture::{
    CaptureOptions, CaptureProgress, CountedCapture, FrameSelection, Gpu, OwnLabelFiles, Scene, Summary,
    parse_capture_palette_size, scene::DemoTraffic,
};

use crate::choices::{Backend, Compression, Dedupe, TileFilter};
use crate::console::{Console, say};
use crate::progress::Bar;

/// What `--measure` counts instead of rendered pixels.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(crate) enum Measure {
    /// Per texel, the eye-frames in which its point is in view, faces the eye and is not hidden
    /// (exact ray casts).
    Unobstructed,
}

/// `--preview`'s pixels per degree (the paper's 60 / 6).
pub(crate) const PREVIEW_PPD: f64 = 10.0;
/// `--preview`'s frame step: every 10th frame (6 a second at 60 fps).
pub(crate) const PREVIEW_FRAME_STEP: u32 = 10;

/// What a capture records, and how: the options of `demo`, `scene` and `unity`.
#[derive(Args, Clone)]
pub(crate) struct CaptureArgs {
    /// Output folder (one archive; with --scenario all, one sub-folder per scenario).
    #[arg(long, default_value = "archive")]
    out: PathBuf,
    /// Scenario name, or `all` (default: the first, A for the demo).
    #[arg(long)]
    scenario: Option<String>,
    /// Pixels per degree (60 = the paper's 6420×8100 per eye); rounded to whole tiles.
    #[arg(long)]
    ppd: Option<f64>,
    /// A quick look: 10 px/° and every 10th frame (`--ppd 10 --frames all/10`; either option,
    /// given too, wins). About 1/360 of the full capture's pixels: texels smaller than a pixel
    /// are undercounted and glimpses shorter than 10 frames missed, so quote no number from it
    /// (docs/guide.md#a-quick-look-first).
    #[arg(long)]
    preview: bool,
    /// Rig overrides as JSON, e.g. '{"eye_height_m": 1.6, "pedestrian": [-6, -6, 0]}' (applied before --ppd),
    /// or an observer: `paper` (the seed paper's eyes, 1.75 m high and 0.1103594 m apart) or `median` (a
    /// median US adult's, 1.571 m and 62.85 mm). --placement answers take `median` unless the scene set its
    /// own eyes.
    #[arg(long, value_name = "JSON|paper|median")]
    rig: Option<String>,
    /// Canonical palette size, W or WxH (default 4096); above 2^24 texels
    /// (up to 8192x8192) the tiles carry 32-bit texel ids (RGBA).
    #[arg(long, value_name = "W|WxH", default_value = "4096")]
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
    /// Frames to capture: `all` (default), every Nth (`all/N`, the middle of each N frames) or a list
    /// like 0,30,60-90/10.
    #[arg(long)]
    frames: Option<String>,
    /// Tile PNG compression.
    #[arg(long, value_enum, default_value_t = Compression::Fast)]
    png_compression: Compression,
    /// Tile PNG row filter: `up` decodes about twice as fast as `adaptive` (mostly Paeth).
    #[arg(long, value_enum, default_value_t = TileFilter::Up)]
    tile_filter: TileFilter,
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
    /// Count each rendered tile straight from the GPU readback with the analyzer (no PNGs):
    /// writes the manifest, PIdT, legend and the analyzer's results/ (same result.json as
    /// capturing PNGs and running `ufcsr analyze --trim off`).
    #[arg(long)]
    count: bool,
    /// With --count: what one count means, image (once per tile, the paper's count and the
    /// default here and in `analyze`), frame (once per eye-frame; `study`'s default, as the exact
    /// measure counts) or eye-pair (once per frame over both eyes).
    #[arg(long, value_enum, default_value_t = Dedupe::Image, requires = "count")]
    dedupe: Dedupe,
    /// With --count: size of the heatmap views in results/, each 400×300 pixels times this (1–8).
    #[arg(long, value_name = "N", default_value_t = ufcsr::output::DEFAULT_VIEWS_SCALE, requires = "count",
          value_parser = clap::value_parser!(u32).range(1..=8))]
    views_scale: u32,
    /// `unobstructed`: instead of rendering pixels, count per texel the eye-frames in which its
    /// point is in view, faces the eye and is not hidden (exact ray casts; writes results/).
    #[arg(long, value_enum)]
    measure: Option<Measure>,
    /// With --measure unobstructed: the share of texels to measure, e.g. 1/16 or 0.25 (seeded).
    #[arg(long, default_value = "1", requires = "measure")]
    sample: String,
    /// Seed of the texel sample.
    #[arg(long, default_value_t = 1, requires = "measure")]
    seed: u64,
    /// With --measure unobstructed: K, each texel's footprint is sampled on K×K sub-cells (a texel
    /// counts when any sample is visible; the solid angle sums them). 1: one sample per texel piece.
    #[arg(long, default_value_t = ufcsr_capture::DEFAULT_TEXEL_SAMPLES, requires = "measure")]
    texel_samples: u32,
    /// With --measure unobstructed: also measure every part as a candidate eHMI placement (and,
    /// with --display, display patches): writes results/placement-frames.csv for
    /// `ufcsr placement` (docs/placement.md). Runs on the CPU; about doubles the ray casts.
    #[arg(long, requires = "measure")]
    placement: bool,
    /// With --placement: candidate display patches of this size, width x height in metres (e.g.
    /// 0.40x0.15), centred every --patch-spacing over the outward-facing surface.
    #[arg(long, value_name = "WxH", requires = "placement")]
    display: Option<String>,
    /// With --display: how far apart candidate patch centres are, metres.
    #[arg(long, value_name = "M", default_value_t = ufcsr_capture::DEFAULT_PATCH_SPACING_M, requires = "display")]
    patch_spacing: f64,
    /// Render only shard I of N (0 ≤ I < N) of the selected frames into --out, with the other
    /// shards; then `ufcsr assemble OUT`. `auto`: from the job array (SLURM_ARRAY_TASK_ID
    /// and _COUNT, or JOB_COMPLETION_INDEX / AWS_BATCH_JOB_ARRAY_INDEX with UFCSR_SHARD_COUNT).
    #[arg(long, value_name = "I/N|auto")]
    shard: Option<String>,
}

/// The words after `ufcsr capture demo` (or `scene FILE`) as one parse.
#[derive(clap::Parser)]
#[command(name = "ufcsr capture")]
struct CaptureWords {
    #[command(flatten)]
    capture: CaptureArgs,
}

impl CaptureArgs {
    /// The capture's options that `words` (as after `ufcsr capture demo`)
    /// give, parsed and checked by the capture's own definition: a command
    /// that runs a capture (`where`) validates its options the capture's way
    /// and gets the capture's defaults.
    pub(crate) fn from_words(words: &[std::ffi::OsString]) -> Result<CaptureArgs, clap::Error> {
        use clap::Parser;
        let line = std::iter::once(std::ffi::OsString::from("capture")).chain(words.iter().cloned());
        Ok(CaptureWords::try_parse_from(line)?.capture)
    }
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
pub(crate) fn parse_fraction(text: &str) -> anyhow::Result<f64> {
    let value = match text.split_once('/') {
        Some((a, b)) => a.trim().parse::<f64>()? / b.trim().parse::<f64>()?,
        None => text.trim().parse::<f64>()?,
    };
    anyhow::ensure!(value > 0.0 && value <= 1.0, "--sample {text}: must be a fraction in (0, 1]");
    Ok(value)
}

/// The rig `args` ask for on `scene`: `--rig` (a preset or JSON overrides;
/// without it a `--placement` answer takes a median adult's eyes), then
/// `--ppd` or `--preview`'s.
pub(crate) fn apply_rig(scene: &mut Scene, args: &CaptureArgs) -> anyhow::Result<()> {
    match args.rig.as_deref() {
        Some(text) => match ufcsr_capture::study::ObserverPreset::parse(text) {
            Some(preset) => preset.apply(&mut scene.rig),
            None => scene.rig = scene.rig.override_with(text)?,
        },
        // Answers are about people: a median adult's eyes, not the paper's camera (issue 42 §6).
        None if args.placement => {
            ufcsr_capture::study::people_by_default(&mut scene.rig);
        }
        None => {}
    }
    if let Some(ppd) = args.ppd.or(args.preview.then_some(PREVIEW_PPD)) {
        scene.rig.set_pixels_per_degree(ppd)?;
    }
    Ok(())
}

/// A capture of `scene` as `args` say: to PNG tiles, counted (`--count`)
/// or measured (`--measure`), one scenario or all.
pub(crate) fn run_capture(
    mut scene: Scene,
    args: &CaptureArgs,
    threads: usize,
    console: &Console,
) -> anyhow::Result<()> {
    if !scene.fleet.is_empty() {
        return run_fleet(&scene, args, threads, console);
    }
    for warning in &scene.warnings {
        eprintln!("warning: {warning}");
    }
    apply_rig(&mut scene, args)?;
    let options = capture_options(args, threads, console)?;
    let all = args.scenario.as_deref().is_some_and(|s| s.eq_ignore_ascii_case("all"));
    let names = scenario_names(&scene, args.scenario.as_deref())?;
    let gpu = Gpu::create(args.backend.into()).context("creating the GPU device")?;
    // How the run is set up: on stderr, and not under --quiet or --json (issue 44 §6).
    if !console.quiet() {
        eprintln!("adapter: {}", gpu.describe());
        describe_rig(&scene, &options);
    }
    if let Some(Measure::Unobstructed) = args.measure {
        return run_unobstructed(&gpu, &scene, &names, all, &options, args, console);
    }
    if args.count {
        let dedupe = args.dedupe.into();
        ufcsr_capture::for_each_scenario(&scene, &names, all, &options, |scenario, options| {
            let counted =
                ufcsr_capture::capture_counted(&gpu.device, &gpu.queue, &scene, scenario, options, dedupe)?;
            report(&counted.summary, Sink::Counted, &counted.summary.out.join(ufcsr::MANIFEST_FILE), console);
            report_counted(&counted, console);
            Ok(())
        })?;
        return Ok(());
    }
    // --resume keeps the tiles already there: `written` names only those this run wrote.
    let kept = if args.resume { files_below(&args.out) } else { BTreeSet::new() };
    let summaries = ufcsr_capture::capture_all(&gpu.device, &gpu.queue, &scene, &names, all, &options)?;
    for summary in &summaries {
        let manifest = match options.shard {
            Some(shard) => ufcsr_capture::partial_manifest_path(&summary.out, shard),
            None => summary.out.join(ufcsr::MANIFEST_FILE),
        };
        report(summary, Sink::Png, &manifest, console);
        record_tiles(&summary.out, &manifest, &kept, console)?;
        if let Some(shard) = options.shard {
            say!(
                console,
                "  shard {shard}: wrote its part of the manifest; once every shard has finished, run \
                 `ufcsr assemble {}`",
                summary.out.display()
            );
        }
    }
    Ok(())
}

/// A scene that measures several vehicles: one pass per vehicle
/// ([`Scene::measuring`]), each an ordinary capture as `args` say into
/// `--out/NAME` (k vehicles, k times the render of one).
fn run_fleet(scene: &Scene, args: &CaptureArgs, threads: usize, console: &Console) -> anyhow::Result<()> {
    let names: Vec<&str> = scene.fleet.iter().map(|vehicle| vehicle.name.as_str()).collect();
    // A one-vehicle archive left at the top would be what `ufcsr analyze OUT` reads.
    anyhow::ensure!(
        !args.out.join(ufcsr::MANIFEST_FILE).exists(),
        "{} holds an archive ({}), but scene {} measures {} vehicles and writes one archive per vehicle below \
         it ({}/NAME): give another --out or remove that archive",
        args.out.display(),
        args.out.join(ufcsr::MANIFEST_FILE).display(),
        scene.name,
        names.len(),
        args.out.display()
    );
    for warning in scene.warnings.iter().chain(&others_below(&args.out, &names)) {
        eprintln!("warning: {warning}");
    }
    say!(
        console,
        "scene {} measures {} vehicles ({}): {} passes, one per vehicle (it carries the palette, the others \
         are occluders), into {}/NAME",
        scene.name,
        names.len(),
        names.join(", "),
        names.len(),
        args.out.display()
    );
    ufcsr::files::create_output_dir(&args.out)?;
    for (which, vehicle) in scene.fleet.iter().enumerate() {
        let mut pass = scene.measuring(which)?;
        pass.warnings.clear();
        let out = ufcsr::files::output_sub_dir(&args.out, Path::new(&vehicle.name))?;
        say!(console, "vehicle {} ({}) → {}", vehicle.name, vehicle.source, out.display());
        run_capture(pass, &CaptureArgs { out, ..args.clone() }, threads, console)?;
        console.fact_item("vehicles", serde_json::json!({ "name": vehicle.name, "source": vehicle.source }));
    }
    let next = match args.shard {
        _ if args.count => {
            format!("each vehicle's results are in {}/NAME/results (counted)", args.out.display())
        }
        Some(_) => format!(
            "once every shard has finished, assemble every vehicle with `ufcsr assemble {0}`, then analyse \
             every vehicle with `ufcsr analyze {0}`",
            args.out.display()
        ),
        None => format!("analyse every vehicle with `ufcsr analyze {}`", args.out.display()),
    };
    say!(
        console,
        "rendered {} passes, one per measured vehicle ({} times the render of one); {next}",
        names.len(),
        names.len(),
    );
    Ok(())
}

/// Archives in folders of `out` that are none of `names` (a capture
/// before, of other vehicles): `ufcsr analyze OUT` would analyse them too.
fn others_below(out: &Path, names: &[&str]) -> Vec<String> {
    let mut others: Vec<String> = std::fs::read_dir(out)
        .into_iter()
        .flatten()
        .flatten()
        .filter(|entry| entry.path().join(ufcsr::MANIFEST_FILE).is_file())
        .filter(|entry| !names.iter().any(|name| entry.file_name() == *name))
        .map(|entry| {
            format!(
                "{} holds an archive that is none of this scene's vehicles: `ufcsr analyze {}` will analyse it \
                 too; remove it, or capture into another --out",
                entry.path().display(),
                out.display()
            )
        })
        .collect();
    others.sort();
    others
}

/// `demo --traffic`: each selected scenario with the truck's twin in
/// traffic (its side depends on the scenario), one capture each, into
/// `--out` or, with `--scenario all`, `--out/NAME`.
pub(crate) fn run_demo_with_traffic(
    traffic: DemoTraffic,
    args: &CaptureArgs,
    threads: usize,
    console: &Console,
) -> anyhow::Result<()> {
    let all = args.scenario.as_deref().is_some_and(|s| s.eq_ignore_ascii_case("all"));
    for name in scenario_names(&Scene::demo(), args.scenario.as_deref())? {
        let scene = Scene::demo_with_traffic(traffic, &name)?;
        // --out/NAME a real folder: a link planted there is replaced, never written through.
        let out = if all {
            ufcsr::files::create_output_dir(&args.out)?;
            ufcsr::files::output_sub_dir(&args.out, std::path::Path::new(&name))?
        } else {
            args.out.clone()
        };
        run_capture(scene, &CaptureArgs { out, scenario: Some(name), ..args.clone() }, threads, console)?;
    }
    Ok(())
}

/// The library's options from the command line's.
/// `threads`: PNG encoders (0: one per core).
fn capture_options(args: &CaptureArgs, threads: usize, console: &Console) -> anyhow::Result<CaptureOptions> {
    Ok(CaptureOptions {
        out: args.out.clone(),
        palette: parse_capture_palette_size(&args.palette_size)?,
        palette_file: args.palette.clone(),
        keep_uvs: args.keep_uvs,
        own_labels: match (args.pidt.clone(), args.parts.clone()) {
            (Some(pidt), Some(parts)) => Some(OwnLabelFiles { pidt, parts }),
            _ => None,
        },
        frames: match (&args.frames, args.preview) {
            (Some(frames), _) => frames.parse::<FrameSelection>()?,
            (None, true) => FrameSelection::every(PREVIEW_FRAME_STEP),
            (None, false) => FrameSelection::all(),
        },
        compression: args.png_compression.into(),
        tile_filter: args.tile_filter.into(),
        resume: args.resume,
        keep_background_tiles: args.keep_background_tiles,
        no_cull: args.no_cull,
        no_scissor: args.no_scissor,
        progress: if console.quiet() {
            CaptureProgress::default()
        } else {
            CaptureProgress::to(Arc::new(Bar::capturing(console)))
        },
        encoder_threads: threads,
        shard: args.shard.as_deref().map(parse_shard).transpose()?,
        views_scale: args.views_scale,
    })
}

/// The scenarios `--scenario` names: one, `all`, or (without it) the first.
pub(crate) fn scenario_names(scene: &Scene, scenario: Option<&str>) -> anyhow::Result<Vec<String>> {
    Ok(match scenario {
        Some(all) if all.eq_ignore_ascii_case("all") => {
            scene.scenarios.iter().map(|s| s.name.clone()).collect()
        }
        Some(name) => vec![scene.scenario(name)?.name.clone()],
        None => scene.scenarios.iter().take(1).map(|s| s.name.clone()).collect(),
    })
}

/// On stderr: the eye's pixels and tiles, the resolution and the palette.
fn describe_rig(scene: &Scene, options: &CaptureOptions) {
    let rig = &scene.rig;
    eprintln!("observer: {}", ufcsr_capture::study::describe_observer(rig));
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
}

/// `--measure unobstructed`: the exact measure of each scenario, printed.
fn run_unobstructed(
    gpu: &Gpu,
    scene: &Scene,
    names: &[String],
    all: bool,
    options: &CaptureOptions,
    args: &CaptureArgs,
    console: &Console,
) -> anyhow::Result<()> {
    anyhow::ensure!(
        options.shard.is_none(),
        "--measure unobstructed with --shard is not supported: sample fewer texels (--sample) instead"
    );
    let sample = parse_fraction(&args.sample)?;
    let placement = placement_options(args)?;
    ufcsr_capture::for_each_scenario(scene, names, all, options, |scenario, options| {
        let measured = ufcsr_capture::measure_unobstructed(
            &gpu.device,
            &gpu.queue,
            scene,
            scenario,
            options,
            &ufcsr_capture::MeasureOptions {
                sample,
                seed: args.seed,
                texel_samples: args.texel_samples,
                placement,
            },
        )
        .map_err(|error| record_written_before(error, &options.out, console))?;
        say!(
            console,
            "scenario {}: unobstructed measure of {} of {} texels ({} surface samples) over {} eye-frames in {:.2} s",
            scenario.name,
            measured.sampled_texels,
            measured.labelled_texels,
            measured.surface_samples,
            measured.eye_frames,
            measured.seconds
        );
        say!(
            console,
            "  ray casts: {:.2} s, {:.3e} sample-eye-frame tests per second (each up to two segment queries)",
            measured.visibility_seconds,
            (measured.surface_samples * measured.eye_frames) as f64 / measured.visibility_seconds.max(1e-9)
        );
        console.print(&ufcsr::output::format_table(&measured.analysis.result));
        record_archive_files(&options.out, &options.out.join(ufcsr::MANIFEST_FILE), console);
        let out = measured.written.result_json.parent().unwrap_or(std::path::Path::new("."));
        measured.written.all(out).iter().for_each(|file| console.wrote(file));
        console.wrote(&measured.estimates_csv);
        console.fact_item("grand_totals", measured.analysis.result.grand_total);
        console.fact_item("observer", ufcsr_capture::study::describe_observer(&scene.rig));
        for warning in &measured.analysis.result.warnings {
            eprintln!("  warning: {warning}");
        }
        say!(console, "  results: {}", measured.written.result_json.display());
        say!(
            console,
            "           {} (per-part estimates, standard errors)",
            measured.estimates_csv.display()
        );
        if let Some(placed) = &measured.placement {
            console.wrote(&placed.csv);
            say!(
                console,
                "           {} (placement: {} parts and {} display patches, {} rows, {:.2} s)",
                placed.csv.display(),
                placed.parts,
                placed.patches,
                placed.rows,
                placed.seconds
            );
            if let Some(patches) = &placed.patches_csv {
                console.wrote(patches);
                say!(console, "           {} (the display patches' footprints)", patches.display());
            }
        }
        Ok(())
    })?;
    Ok(())
}

/// `--placement`, `--display`, `--patch-spacing` as the measure's options.
fn placement_options(args: &CaptureArgs) -> anyhow::Result<Option<ufcsr_capture::PlacementCandidates>> {
    if !args.placement {
        return Ok(None);
    }
    let display_m = args.display.as_deref().map(ufcsr_capture::parse_display).transpose()?;
    Ok(Some(ufcsr_capture::PlacementCandidates { display_m, spacing_m: args.patch_spacing }))
}

/// Every file below `dir` (links not followed), for `--resume`: the tiles
/// already there are kept, not written.
fn files_below(dir: &Path) -> BTreeSet<PathBuf> {
    let mut found = BTreeSet::new();
    let mut folders = vec![dir.to_path_buf()];
    while let Some(folder) = folders.pop() {
        for entry in std::fs::read_dir(&folder).into_iter().flatten().flatten() {
            match entry.file_type() {
                Ok(kind) if kind.is_dir() => folders.push(entry.path()),
                Ok(_) => {
                    found.insert(entry.path());
                }
                Err(_) => {}
            }
        }
    }
    found
}

/// A failure after files were written ([`ufcsr_capture::CaptureError::AfterWriting`]):
/// the archive's files in `out` and the files it names are recorded, so the
/// run ends with exit 1 and `written` lists them; any other error as it is.
fn record_written_before(
    error: ufcsr_capture::CaptureError,
    out: &Path,
    console: &Console,
) -> ufcsr_capture::CaptureError {
    if let ufcsr_capture::CaptureError::AfterWriting { written, .. } = &error {
        record_archive_files(out, &out.join(ufcsr::MANIFEST_FILE), console);
        written.iter().for_each(|file| console.wrote(file));
    }
    error
}

/// For `--json`: every file below `folder`, written whole by this run.
pub(crate) fn record_folder(folder: &Path, console: &Console) {
    files_below(folder).iter().for_each(|file| console.wrote(file));
}

/// For `--json`: every file of the archives whose results are `results`
/// (`ARCHIVE/results/result.json`), each written whole by this run (a
/// study's settings, the observers' folders).
pub(crate) fn record_archives_of<'a>(results: impl Iterator<Item = &'a PathBuf>, console: &Console) {
    let archives: BTreeSet<&Path> = results.filter_map(|json| json.parent()?.parent()).collect();
    for file in archives.into_iter().flat_map(files_below) {
        console.wrote(&file);
    }
}

/// For `--json`: the tiles `manifest` lists that this run wrote (not among
/// `kept`, the files there before a `--resume`).
fn record_tiles(
    archive: &Path,
    manifest: &Path,
    kept: &BTreeSet<PathBuf>,
    console: &Console,
) -> anyhow::Result<()> {
    let bytes = ufcsr::files::read_limited(manifest, ufcsr::files::SMALL_INPUT_LIMIT)?;
    let manifest = ufcsr::Manifest::parse(manifest, &bytes)?;
    for file in manifest.tiles.iter().filter_map(|tile| tile.file.as_ref()) {
        let path = archive.join(file);
        if !kept.contains(&path) {
            console.wrote(&path);
        }
    }
    Ok(())
}

/// For `--json`: the files of the archive in `out` besides its tiles and
/// results (`manifest`: its manifest, or a shard's part of it).
fn record_archive_files(out: &Path, manifest: &Path, console: &Console) {
    if manifest.is_file() {
        console.wrote(manifest);
    }
    for name in ["pidt.png", "parts.csv", "palette.png", "vehicle.glb", "scene.glb"] {
        let path = out.join(name);
        if path.is_file() {
            console.wrote(&path);
        }
    }
}

/// For `--json`: the archive's files and the scenario's facts.
fn record_archive(s: &Summary, manifest: &Path, console: &Console) {
    record_archive_files(&s.out, manifest, console);
    console.fact_item(
        "scenarios",
        serde_json::json!({
            "scenario": s.scenario,
            "out": crate::console::shown(&s.out),
            "frames": s.frames,
            "seconds": s.seconds,
            "tiles": s.tiles,
            // tiles = rendered + culled + hidden + resumed; background_only and
            // written count among the rendered.
            "tiles_rendered": s.tally.rendered,
            "tiles_written": s.tally.written,
            "tiles_background_only": s.tally.background,
            "tiles_culled": s.tally.culled,
            "tiles_hidden": s.tally.hidden,
            "tiles_resumed": s.tally.resumed,
        }),
    );
}

/// Where a capture's tiles went: PNG files, or counted from the readback.
#[derive(Clone, Copy, PartialEq)]
enum Sink {
    Png,
    Counted,
}

fn report(s: &Summary, sink: Sink, manifest: &Path, console: &Console) {
    record_archive(s, manifest, console);
    let work = if sink == Sink::Counted { "counting included, no PNGs" } else { "encoding included" };
    say!(
        console,
        "scenario {}: {} frames in {:.2} s ({:.2} s setup; {:.2} frames/s, both eyes, {work}) → {}",
        s.scenario,
        s.frames,
        s.seconds,
        s.setup_seconds,
        s.frames_per_second(),
        s.out.display()
    );
    let kept = match sink {
        Sink::Png => format!("{} written", s.tally.written),
        Sink::Counted => "counted from the readback, none written".to_string(),
    };
    // The four kinds partition the tiles (TileTally::accounted).
    say!(
        console,
        "  tiles: {} total = {} rendered ({} of them background only; {kept}) + {} culled (outside the vehicle's bounds) + {} hidden by occluders + {} resumed",
        s.tiles,
        s.tally.rendered,
        s.tally.background,
        s.tally.culled,
        s.tally.hidden,
        s.tally.resumed
    );
    // On stderr: how the run was done, not what it found (not under --quiet or --json).
    if !console.quiet() {
        eprintln!(
            "  left out: {} of the {} pixels of tiles the vehicle's bounds touch ({:.1}%, scissor)",
            s.tally.pixels_scissored,
            s.pixels,
            if s.pixels > 0 { s.tally.pixels_scissored as f64 * 100.0 / s.pixels as f64 } else { 0.0 },
        );
    }
    say!(
        console,
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
    if let Some(warning) = saw_nothing(s) {
        eprintln!("warning: {warning}");
    }
}

/// A warning when no tile shows any of the vehicle (every one culled, hidden
/// by occluders or background only, none resumed): such an archive counts
/// nothing, and a capture that exits 0 without a word hides a wrong rig,
/// track, `--frames` or occluder.
fn saw_nothing(s: &Summary) -> Option<String> {
    let t = &s.tally;
    // `background` holds the tiles hidden by occluders (not rendered) and
    // the rendered ones that came out pure background.
    let showing = t.rendered.saturating_sub(t.background.saturating_sub(t.hidden));
    (s.tiles > 0 && showing == 0 && t.resumed == 0).then(|| {
        format!(
            "scenario {}: no tile of the {} shows any of the vehicle ({} culled, {} hidden by occluders, {} \
             background only): the archive counts nothing; check the rig, the tracks, --frames and the occluders",
            s.scenario, s.tiles, t.culled, t.hidden, t.background
        )
    })
}

fn report_counted(counted: &CountedCapture, console: &Console) {
    let result = &counted.analysis.result;
    say!(
        console,
        "  counted: {} tiles, {:.1} Mpixels straight from the renderer (no PNGs); {} texels seen, grand total {}",
        result.images.decoded,
        counted.pixels_counted as f64 / 1e6,
        result.texels_seen,
        result.grand_total
    );
    console.print(&ufcsr::output::format_counted_table(result));
    let out = counted.written.result_json.parent().unwrap_or(std::path::Path::new("."));
    for (n, file) in counted.written.all(out).iter().enumerate() {
        console.wrote(file);
        say!(console, "  {}{}", if n == 0 { "results: " } else { "         " }, file.display());
    }
    console.fact_item("grand_totals", result.grand_total);
}
