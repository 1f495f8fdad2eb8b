//! The subcommands around a capture: `inspect` a vehicle before capturing,
//! draw a result's heatmap `views` on the GPU, `batch plan` the commands of a
//! batch, `assemble` the shards of a capture and `verify` an archive.

use std::io::Write;
use std::path::{Path, PathBuf};

use ufcsr_capture::{Backend, Gpu, InspectOptions, ViewsOptions};

use super::say;

/// `inspect`: the vehicle's report on stdout, its pictures in `out`.
pub fn run_inspect(input: PathBuf, out: PathBuf, pixels_per_metre: Option<f64>) -> anyhow::Result<()> {
    let inspection = ufcsr_capture::inspect(&InspectOptions { input, out, pixels_per_metre })?;
    inspection.files.iter().for_each(|file| super::wrote(file));
    super::fact("triangles", inspection.triangles);
    if !super::quiet() {
        print!("{inspection}");
    }
    Ok(())
}

/// `views`: a result's eight heatmap views, drawn by the GPU renderer.
pub fn run_views(options: ViewsOptions, backend: Backend) -> anyhow::Result<()> {
    let gpu = Gpu::create(backend)?;
    let written = ufcsr_capture::views_from_results(&gpu.device, &gpu.queue, &options)?;
    say!("views ({}): {}", gpu.describe(), written.contact_sheet.display());
    super::wrote(&written.contact_sheet);
    for view in &written.views {
        super::wrote(view);
        say!("  {}", view.display());
    }
    Ok(())
}

/// `batch plan`: one command per task of the batch file, task i on line i.
pub fn run_batch_plan(batch: &Path, program: Option<String>) -> anyhow::Result<()> {
    let plan = ufcsr_capture::load_batch(batch)?;
    let program = match program {
        Some(program) => program,
        None => std::env::current_exe()?.display().to_string(),
    };
    let base = batch.parent().unwrap_or(Path::new("."));
    let tasks = ufcsr_capture::plan_batch(&plan, base, &program)?;
    if super::json() {
        // The plan's lines as a list: stdout holds the one JSON object.
        super::fact("tasks", tasks.iter().map(|t| t.shell_line()).collect::<Vec<_>>());
        return Ok(());
    }
    let mut stdout = std::io::stdout().lock();
    for task in tasks {
        // The plan is made to be piped (`| head`, `| sed -n 5p`): a
        // reader that stops early is not an error.
        match writeln!(stdout, "{}", task.shell_line()) {
            Err(error) if error.kind() == std::io::ErrorKind::BrokenPipe => return Ok(()),
            other => other?,
        }
    }
    Ok(())
}

/// `assemble`: the shards' partial manifests joined into manifest.json.
pub fn run_assemble(archive: &Path) -> anyhow::Result<()> {
    let assembled = ufcsr_capture::assemble(archive)?;
    super::wrote(&assembled.manifest_path);
    super::fact("shards", assembled.shards);
    super::fact("frames", assembled.frames);
    say!(
        "{}: {} shards, {} frames, {} tiles → {}",
        archive.display(),
        assembled.shards,
        assembled.frames,
        assembled.tiles,
        assembled.manifest_path.display()
    );
    Ok(())
}

/// `verify`: every tile pixel is background or a labelled palette texel.
pub fn run_verify(archive: &Path) -> anyhow::Result<()> {
    let (vehicle, stray) = ufcsr_capture::verify(archive)?;
    super::fact("vehicle_pixels", vehicle);
    super::fact("stray_pixels", stray);
    say!("{}: {vehicle} vehicle pixels, {stray} stray pixels", archive.display());
    if stray > 0 {
        return Err(super::DoneWithFailures(format!(
            "{}: {stray} pixels are neither background nor labelled palette texels",
            archive.display()
        ))
        .into());
    }
    Ok(())
}
