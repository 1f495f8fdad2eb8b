//! The analysis, `ufcsr analyze ARCHIVE` (`ufcsr analyze ARCHIVE`): options
//! validated once, the archive checked for what the user meant
//! ([`super::intent`]), the analysis with a progress bar, the result set
//! written, and the summary (table or JSON) with every file written; `--each`
//! does it per archive.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use serde_json::json;
use ufcsr::{
    AnalyzeOptions, Shard, TrimMode, analyze, output::WrittenFiles, output::default_output_dir,
    output::format_table,
};

use super::args::AnalyzeArgs;
use super::intent::{archives_below, fleet_below, misread_archive};
use super::run::{Done, finish};
use crate::choices::Switch;
use crate::console::{Completion, Console, shown};
use crate::progress::Bar;

/// The analysis options from the command line for `archive` (validated
/// once, here), and the output folder.
fn analyze_options(args: &AnalyzeArgs, archive: PathBuf, out_dir: PathBuf) -> Result<AnalyzeOptions> {
    let palette = args.labels.palette()?;
    let background = args.labels.background_colors()?;
    let background = (!background.is_empty()).then_some(background);
    Ok(AnalyzeOptions {
        archive,
        palette,
        pidt: args.labels.pidt.clone(),
        legend: args.labels.legend.clone(),
        background,
        dedupe: args.dedupe.into(),
        trim: args.trim.parse::<TrimMode>()?,
        heatmap: args.heatmap.options(None)?,
        area_max: args.area_max,
        strict: args.strict,
        exclude: vec![out_dir],
        ignore_manifest: args.no_manifest,
        mesh: args.mesh.clone(),
        frames: args.frames_csv == Switch::On,
        texel_area: args.texel_area == Switch::On,
        shard: match &args.shard {
            Some(text) => Some(text.parse::<Shard>()?),
            None => Shard::from_job_array(|name| std::env::var(name).ok())?,
        },
        loaded_labels: None,
    })
}

/// The table and where every output went, for people.
fn summary_text(analysis: &ufcsr::Analysis, written: &WrittenFiles, out_dir: &Path) -> String {
    let mut text = format_table(&analysis.result);
    text.push_str(&format!(
        "\n{:.2} s ({:.0} Mpixel/s decoded); wrote {}\n",
        analysis.timings.total_seconds,
        analysis.timings.decoded_megapixels_per_second,
        out_dir.display()
    ));
    text.push_str(&format!("  report:  {}\n", written.report_html.display()));
    let shown_measure =
        if written.area_first() { "angular area per texel, deg²·s" } else { "count per texel" };
    text.push_str(&format!(
        "  heatmap: {} (texture in the palette's UV layout: {shown_measure})\n",
        written.heatmap_png.display()
    ));
    if let Some(glb) = &written.heatmap_glb {
        text.push_str(&format!("  vehicle: {} (the heatmap on the vehicle, glTF)\n", glb.display()));
    }
    let mut data = vec![written.result_json.display().to_string()];
    data.extend(written.parts_csv.iter().map(|p| p.display().to_string()));
    data.extend(
        written.heatmap_count_png.iter().map(|p| format!("{} (paper-compatible count)", p.display())),
    );
    data.push(written.timings_json.display().to_string());
    text.push_str(&format!("  data:    {}\n", data.join(", ")));
    if let Some(frames) = &written.frames_csv {
        text.push_str(&format!(
            "  frames:  {} (pixels and texels per eye-frame and part)\n",
            frames.display()
        ));
    }
    if let Some(views) = &written.views_png {
        text.push_str(&format!(
            "  views:   {} (the heatmap on the vehicle from eight sides)\n",
            views.display()
        ));
    }
    if !written.plots.is_empty() {
        let plots: Vec<&str> = written.plots.iter().map(|plot| plot.shown.as_str()).collect();
        text.push_str(&format!("  plots:   {} (in {})\n", plots.join(", "), out_dir.display()));
    }
    text.trim_end().to_string()
}

/// Warnings, stray pixels and failures of a finished analysis, on stderr.
fn report_problems(result: &ufcsr::AnalysisResult) {
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
    if result.images.failed > 0 {
        eprintln!(
            "{} of {} images failed and were not counted; results cover the rest",
            result.images.failed, result.images.found
        );
    }
}

/// `--strict-colors`: the colour-damage warnings as the error, before
/// anything is written.
fn refuse_color_damage(archive: &Path, result: &ufcsr::AnalysisResult) -> Result<()> {
    let damage: Vec<String> =
        result.color_checks.iter().flat_map(|c| c.warnings.iter().map(|w| w.line())).collect();
    anyhow::ensure!(
        damage.is_empty(),
        "{}: the capture shows colour damage (--strict-colors; nothing written):\n  {}",
        archive.display(),
        damage.join("\n  ")
    );
    Ok(())
}

/// One archive analysed and written: what was done.
fn analyse_one(args: &AnalyzeArgs, archive: PathBuf, out_dir: PathBuf, console: &Console) -> Result<Done> {
    let options = analyze_options(args, archive, out_dir.clone())?;
    let mut analysis = analyze(&options, Some(&Bar::counting(console)))?;
    if args.strict_colors {
        refuse_color_damage(&options.archive, &analysis.result)?;
    }
    let written = ufcsr::output::write_results_with(
        &mut analysis,
        &out_dir,
        &ufcsr::output::ResultSetOptions {
            csv_style: args.csv_style.into(),
            views_scale: args.views_scale,
            figures: args.figures.into(),
        },
    )?;
    report_problems(&analysis.result);
    Ok(Done {
        completion: if analysis.is_complete() { Completion::Done } else { Completion::WithFailures },
        written: written.all(&out_dir),
        text: summary_text(&analysis, &written, &out_dir),
        facts: json!({
            "archive": shown(&options.archive),
            "out": shown(&out_dir),
            "result": analysis.result,
            "timings": analysis.timings,
            "files": {
                "result_json": shown(&written.result_json),
                "parts_csv": written.parts_csv.as_deref().map(shown),
                "heatmap_png": shown(&written.heatmap_png),
                "heatmap_count_png": written.heatmap_count_png.as_deref().map(shown),
                "timings_json": shown(&written.timings_json),
                "frames_csv": written.frames_csv.as_deref().map(shown),
                "heatmap_glb": written.heatmap_glb.as_deref().map(shown),
                "views_png": written.views_png.as_deref().map(shown),
                "report_html": shown(&written.report_html),
            },
        }),
    })
}

/// Runs the analysis of ARCHIVE (or, with `--each` or for the folder of a
/// several-vehicle capture, of every archive below it).
pub(crate) fn run_analyze(args: AnalyzeArgs, console: &Console) -> Result<Completion> {
    let archive = args.archive.clone().context("ARCHIVE is required")?;
    if args.each || (!args.no_manifest && fleet_below(&archive)) {
        return run_each(&args, &archive, console);
    }
    if !args.no_manifest
        && let Some(problem) = misread_archive(&archive)
    {
        anyhow::bail!(problem);
    }
    let out_dir = args.out.clone().unwrap_or_else(|| default_output_dir(&archive));
    let done = analyse_one(&args, archive, out_dir, console)?;
    Ok(finish(console, done))
}

/// `--each`: every archive below ARCHIVE analysed into its own results
/// folder; exit 1 when any had failures or could not be analysed, 2 when
/// none could.
fn run_each(args: &AnalyzeArgs, parent: &Path, console: &Console) -> Result<Completion> {
    let archives = archives_below(parent);
    anyhow::ensure!(
        !archives.is_empty(),
        "--each: no archive (a folder with a manifest.json) below {}",
        parent.display()
    );
    let mut done =
        Done { completion: Completion::Done, written: Vec::new(), text: String::new(), facts: json!({}) };
    let mut each = Vec::new();
    let mut analysed = 0;
    // One line per archive at the end: analysed into where, or why not.
    let mut lines = Vec::new();
    for archive in archives {
        let out_dir = match &args.out {
            // DIR/A a real folder: a link planted at DIR/A (or on the way) is
            // replaced, never written through into the folder it names.
            Some(out) => {
                let relative = archive.strip_prefix(parent).unwrap_or(&archive);
                ufcsr::files::create_output_dir(out)
                    .and_then(|()| ufcsr::files::output_sub_dir(out, relative))
            }
            None => Ok(default_output_dir(&archive)),
        };
        let out_dir = match out_dir {
            Ok(out_dir) => out_dir,
            Err(error) => {
                let error = anyhow::Error::from(error);
                eprintln!("error: {}: {error:#}", archive.display());
                lines.push(format!(
                    "{}: not analysed ({})",
                    archive.display(),
                    crate::console::message(&error)
                ));
                done.completion = Completion::WithFailures;
                each.push(json!({ "archive": shown(&archive), "error": crate::console::message(&error) }));
                continue;
            }
        };
        match analyse_one(args, archive.clone(), out_dir.clone(), console) {
            Ok(one) => {
                analysed += 1;
                lines.push(format!("{}: analysed → {}", archive.display(), out_dir.display()));
                if one.completion == Completion::WithFailures {
                    done.completion = Completion::WithFailures;
                }
                done.written.extend(one.written.iter().cloned());
                done.text.push_str(&format!("== {}\n{}\n\n", archive.display(), one.text));
                each.push(one.facts);
            }
            Err(error) => {
                eprintln!("error: {}: {error:#}", archive.display());
                lines.push(format!(
                    "{}: not analysed ({})",
                    archive.display(),
                    crate::console::message(&error)
                ));
                done.completion = Completion::WithFailures;
                each.push(json!({ "archive": shown(&archive), "error": crate::console::message(&error) }));
            }
        }
    }
    done.text.push_str(&lines.join("\n"));
    if analysed == 0 {
        anyhow::bail!("--each: none of the archives below {} could be analysed", parent.display());
    }
    done.text = done.text.trim_end().to_string();
    done.facts = json!({ "archives": each });
    Ok(finish(console, done))
}
