//! The subcommands around a capture: `inspect` a vehicle before capturing,
//! redraw a result's heatmap `views`, `batch plan` the commands of a
//! batch, `assemble` the shards of a capture and `verify` an archive.

use std::path::{Path, PathBuf};

use ufcsr_capture::{InspectOptions, ViewsOptions};

use crate::console::{Completion, Console, say};

/// `inspect`: the vehicle's report on stdout, its pictures in `out`.
pub(crate) fn run_inspect(
    input: PathBuf,
    out: PathBuf,
    pixels_per_metre: Option<f64>,
    console: &Console,
) -> anyhow::Result<()> {
    let options = InspectOptions { input, out, pixels_per_metre };
    // A scene that measures several vehicles: each of them, into out/NAME.
    let fleet = ufcsr_capture::inspect_fleet(&options)?;
    for (name, inspection) in &fleet {
        inspection.files.iter().for_each(|file| console.wrote(file));
        console.fact_item("vehicles", serde_json::json!({ "name": name, "triangles": inspection.triangles }));
        say!(console, "== vehicle {name} → {}", options.out.join(name).display());
        console.print(&inspection.to_string());
    }
    if fleet.is_empty() {
        let inspection = ufcsr_capture::inspect(&options)?;
        inspection.files.iter().for_each(|file| console.wrote(file));
        console.fact("triangles", inspection.triangles);
        console.print(&inspection.to_string());
    }
    Ok(())
}

/// `views`: a result's eight heatmap views, redrawn as the analysis draws them.
pub(crate) fn run_views(options: ViewsOptions, console: &Console) -> anyhow::Result<()> {
    let written = ufcsr_capture::views_from_results(&options)?;
    say!(console, "views: {}", written.contact_sheet.display());
    console.wrote(&written.contact_sheet);
    console.wrote(&written.pdf);
    for view in &written.views {
        console.wrote(view);
        say!(console, "  {}", view.display());
    }
    Ok(())
}

/// `batch plan`: one command per task of the batch file, task i on line i.
pub(crate) fn run_batch_plan(batch: &Path, program: Option<String>, console: &Console) -> anyhow::Result<()> {
    let plan = ufcsr_capture::load_batch(batch)?;
    let program = match program {
        Some(program) => program,
        // The tasks are `ufcsr capture …` commands of this very program.
        None => std::env::current_exe()?.display().to_string(),
    };
    let base = batch.parent().unwrap_or(Path::new("."));
    let tasks = ufcsr_capture::plan_batch(&plan, base, &program)?;
    let lines: Vec<String> = tasks.iter().map(|t| t.shell_line()).collect();
    // The plan is its product: printed even with --quiet, made to be piped
    // (`| head`, `| sed -n 5p`: a reader that stops early is not an error);
    // with --json the lines are a list in the one JSON object.
    console.fact("tasks", &lines);
    let mut text = lines.join("\n");
    if !text.is_empty() {
        text.push('\n');
    }
    console.product(text.as_bytes());
    Ok(())
}

/// `assemble`: the shards' partial manifests joined into manifest.json. On
/// the folder of a sharded capture of several vehicles (no shards of its
/// own, each vehicle's archive `OUT/NAME` with its `shards/`) each vehicle's
/// archive in turn, as `ufcsr analyze OUT` analyses each: one that fails is
/// named and the others go on (exit 1).
pub(crate) fn run_assemble(archive: &Path, console: &Console) -> anyhow::Result<Completion> {
    let vehicles = sharded_vehicles(archive);
    if vehicles.is_empty() {
        assemble_one(archive, console)?;
        return Ok(Completion::Done);
    }
    let mut failed = Vec::new();
    for vehicle in &vehicles {
        if let Err(error) = assemble_one(vehicle, console) {
            eprintln!("error: {error:#}");
            failed.push(vehicle.display().to_string());
        }
    }
    say!(
        console,
        "{}: assembled {} of {} vehicle archives{}",
        archive.display(),
        vehicles.len() - failed.len(),
        vehicles.len(),
        if failed.is_empty() { String::new() } else { format!("; not {}", failed.join(", ")) }
    );
    Ok(if failed.is_empty() { Completion::Done } else { Completion::WithFailures })
}

/// The vehicles' archives of a sharded several-vehicle capture in `dir`
/// (sorted): the folders below with shard manifests of their own, when
/// `dir` has neither shards nor a manifest (empty otherwise).
fn sharded_vehicles(dir: &Path) -> Vec<PathBuf> {
    let own = ["shards", ufcsr::MANIFEST_FILE].iter().any(|name| dir.join(name).symlink_metadata().is_ok());
    if own {
        return Vec::new();
    }
    let mut below: Vec<PathBuf> = std::fs::read_dir(dir)
        .into_iter()
        .flatten()
        .flatten()
        .map(|entry| entry.path())
        .filter(|path| path.join("shards").is_dir() && !path.join("shards").is_symlink())
        .collect();
    below.sort();
    below
}

/// `assemble` of one archive.
fn assemble_one(archive: &Path, console: &Console) -> anyhow::Result<()> {
    let assembled = ufcsr_capture::assemble(archive)?;
    console.wrote(&assembled.manifest_path);
    console.fact("shards", assembled.shards);
    console.fact("frames", assembled.frames);
    say!(
        console,
        "{}: {} shards, {} frames, {} tiles → {}",
        archive.display(),
        assembled.shards,
        assembled.frames,
        assembled.tiles,
        assembled.manifest_path.display()
    );
    Ok(())
}

/// `verify`: every tile pixel is background or a labelled palette texel;
/// done with failures when some are not.
pub(crate) fn run_verify(archive: &Path, console: &Console) -> anyhow::Result<Completion> {
    let (vehicle, stray) = ufcsr_capture::verify(archive)?;
    console.fact("vehicle_pixels", vehicle);
    console.fact("stray_pixels", stray);
    say!(console, "{}: {vehicle} vehicle pixels, {stray} stray pixels", archive.display());
    if stray > 0 {
        let failure = format!(
            "{}: {stray} pixels are neither background nor labelled palette texels",
            archive.display()
        );
        eprintln!("error: {failure}");
        console.fact("failures", failure);
        return Ok(Completion::WithFailures);
    }
    Ok(Completion::Done)
}
