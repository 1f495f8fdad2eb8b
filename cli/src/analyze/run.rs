//! The commands on results (`merge`, `report`, `heatmap`, `palette`) and
//! the one way every analyzer command says what it did ([`Done`], told to
//! the console by [`finish`]: a summary for people, or with `--json` the
//! command's facts beside every file written; nothing with `--quiet`).

use std::path::{Path, PathBuf};

use anyhow::Result;
use serde_json::{Value, json};
use ufcsr::{output::format_table, read_texel_counts};

use super::args::{HeatmapArgs, MergeArgs, PaletteArgs, ReportArgs};
use crate::choices::Switch;
use crate::console::{Completion, Console, say, shown};

/// What a command did, for [`finish`].
pub(crate) struct Done {
    pub completion: Completion,
    /// Every file written, in the order written.
    pub written: Vec<PathBuf>,
    /// The summary for people (stdout), without a trailing newline.
    pub text: String,
    /// The command's own facts for `--json`: an object merged into the summary.
    pub facts: Value,
}

/// Tells the console what `done` did; returns how it finished.
pub(crate) fn finish(console: &Console, done: Done) -> Completion {
    for file in &done.written {
        console.wrote(file);
    }
    console.facts(done.facts);
    if !done.text.is_empty() {
        say!(console, "{}", done.text);
    }
    done.completion
}

/// The result.json a result argument names: the file, or the one in a result folder.
pub(crate) fn result_json(path: &Path) -> PathBuf {
    if path.is_dir() { path.join("result.json") } else { path.to_path_buf() }
}

pub(crate) fn run_heatmap(args: HeatmapArgs, console: &Console) -> Result<Completion> {
    let result = result_json(&args.result);
    ufcsr::files::refuse_overwriting_inputs(std::slice::from_ref(&args.out), std::slice::from_ref(&result))?;
    let stored = read_texel_counts(&result)?;
    let options = args.heatmap.options(Some((stored.scale, stored.max)))?;
    let folder = result.parent().unwrap_or(Path::new("."));
    let area = match args.texel_area {
        Switch::On => ufcsr::read_texel_area_in(folder, stored.width, stored.height)?,
        Switch::Off => None,
    };
    let size = [stored.width, stored.height];
    let drawn = match &area {
        Some(values) => {
            let area_max = args.area_max.or(stored.area_max);
            ufcsr::AnalyzeOptions { area_max, ..Default::default() }.check_area_max()?;
            let levels = ufcsr::output::AreaLevels::new(values);
            ufcsr::output::write_area_heatmap(&args.out, &levels, size, options.scale, area_max)?;
            "angular area, deg²·s per texel"
        }
        None => {
            ufcsr::output::write_heatmap(
                &args.out,
                &stored.texel_counts,
                stored.width,
                stored.height,
                options,
            )?;
            "count per texel"
        }
    };
    Ok(finish(
        console,
        Done {
            completion: Completion::Done,
            written: vec![args.out.clone()],
            text: format!(
                "wrote {} (heatmap texture of {}: {drawn}, {:?} scale)",
                args.out.display(),
                result.display(),
                options.scale
            ),
            facts: json!({
                "result": shown(&result),
                "width": stored.width,
                "height": stored.height,
                "measure": if area.is_some() { "angular_area_deg2_s" } else { "count" },
            }),
        },
    ))
}

pub(crate) fn run_palette(args: PaletteArgs, console: &Console) -> Result<Completion> {
    let [width, height] = ufcsr::parse_palette_size(&args.size)?;
    ufcsr::write_canonical_png(&args.out, [width, height])?;
    Ok(finish(
        console,
        Done {
            completion: Completion::Done,
            written: vec![args.out.clone()],
            text: format!("wrote {} ({width}×{height} canonical palette)", args.out.display()),
            facts: json!({ "width": width, "height": height }),
        },
    ))
}

pub(crate) fn run_report(args: ReportArgs, console: &Console) -> Result<Completion> {
    let options =
        ufcsr::output::ComparisonOptions { labels: args.labels.clone(), own_scales: args.own_scales };
    let written = ufcsr::output::write_comparison_with(&args.results, &args.out, &options)?;
    Ok(finish(
        console,
        Done {
            completion: Completion::Done,
            text: format!("wrote {} ({} inputs)", written.page.display(), args.results.len()),
            written: written.files,
            facts: json!({
                "results": shown_all(&args.results),
                "out": shown(&args.out),
                "labels": args.labels,
                "shared_scale": !args.own_scales,
            }),
        },
    ))
}

pub(crate) fn run_merge(args: MergeArgs, console: &Console) -> Result<Completion> {
    let results: Vec<PathBuf> = args.results.iter().map(|path| result_json(path)).collect();
    let mut analysis = ufcsr::merge_results(&results)?;
    let written = ufcsr::output::write_results_with(
        &mut analysis,
        &args.out,
        &ufcsr::output::ResultSetOptions {
            csv_style: args.csv_style.into(),
            views_scale: args.views_scale,
            ..Default::default()
        },
    )?;
    for warning in &analysis.result.warnings {
        eprintln!("warning: {warning}");
    }
    let complete = analysis.is_complete();
    Ok(finish(
        console,
        Done {
            completion: if complete { Completion::Done } else { Completion::WithFailures },
            written: written.all(&args.out),
            text: format!(
                "{}\nmerged {} results; wrote {}",
                format_table(&analysis.result).trim_end(),
                results.len(),
                written.result_json.display()
            ),
            facts: json!({ "results": shown_all(&results), "out": shown(&args.out), "result": analysis.result }),
        },
    ))
}

/// Paths as `--json` shows them.
fn shown_all(paths: &[PathBuf]) -> Vec<String> {
    paths.iter().map(|path| shown(path)).collect()
}
