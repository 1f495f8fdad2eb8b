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
    let inspection = ufcsr_capture::inspect(&InspectOptions { input, out, pixels_per_metre })?;
    inspection.files.iter().for_each(|file| console.wrote(file));
    console.fact("triangles", inspection.triangles);
    console.print(&inspection.to_string());
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

/// `assemble`: the shards' partial manifests joined into manifest.json.
pub(crate) fn run_assemble(archive: &Path, console: &Console) -> anyhow::Result<()> {
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
