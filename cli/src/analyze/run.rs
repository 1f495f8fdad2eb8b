//! The small subcommands (`heatmap`, `merge`, `report`, `palette`,
//! `completions`, `man`) and what they all share: worker threads, and one
//! way to say what was done — a line for people, or with `--json` one object
//! for programs (`command`, `exit_code`, `written`, and the command's own
//! facts), nothing with `--quiet`.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{Context, Result};
use clap::CommandFactory;
use serde_json::{Value, json};
use ufcsr::{format_table, read_texel_counts};

use crate::cli::args::{
    Cli, Common, CompletionsArgs, HeatmapArgs, HeatmapScaleArgs, ManArgs, MergeArgs, PaletteArgs, ReportArgs,
};

/// More worker threads than this is a typo, not a machine.
const MAX_THREADS: usize = 1024;

/// What a subcommand did, for [`finish`].
pub struct Done {
    pub command: &'static str,
    /// 0 done, 1 done with failures.
    pub exit_code: u8,
    /// Every file written, in the order written.
    pub written: Vec<PathBuf>,
    /// The summary for people (stdout), without a trailing newline.
    pub text: String,
    /// The command's own facts for `--json`: an object merged into the summary.
    pub facts: Value,
}

/// Prints `done` as `common` asks and turns it into the exit code.
pub fn finish(common: &Common, done: Done) -> Result<ExitCode> {
    if common.json {
        let mut summary = json!({
            "command": done.command,
            "exit_code": done.exit_code,
            "written": done.written,
        });
        if let (Some(summary), Value::Object(facts)) = (summary.as_object_mut(), done.facts) {
            summary.extend(facts);
        }
        println!("{}", serde_json::to_string_pretty(&summary)?);
    } else if !common.quiet && !done.text.is_empty() {
        println!("{}", done.text);
    }
    Ok(ExitCode::from(done.exit_code))
}

/// Starts the worker threads `--threads` asks for (default: all cores).
pub fn start_threads(common: &Common) -> Result<()> {
    if let Some(threads) = common.threads {
        anyhow::ensure!(threads <= MAX_THREADS, "--threads {threads}: at most {MAX_THREADS}");
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads.max(1))
            .build_global()
            .context("could not start the worker threads")?;
    }
    Ok(())
}

/// The result.json a result argument names: the file, or the one in a result folder.
pub fn result_json(path: &Path) -> PathBuf {
    if path.is_dir() { path.join("result.json") } else { path.to_path_buf() }
}

pub fn heatmap_options(
    args: &HeatmapScaleArgs,
    stored: Option<(ufcsr::Scale, Option<u32>)>,
) -> Result<ufcsr::HeatmapOptions> {
    let scale = match args.scale {
        Some(scale) => scale,
        None => stored.map(|s| s.0).unwrap_or_default(),
    };
    let max = args.max.or(stored.and_then(|s| s.1));
    if max == Some(0) {
        anyhow::bail!("--max must be at least 1");
    }
    Ok(ufcsr::HeatmapOptions { scale, max })
}

pub fn run_heatmap(args: HeatmapArgs) -> Result<ExitCode> {
    start_threads(&args.common)?;
    let result = result_json(&args.result);
    ufcsr::refuse_overwriting_inputs(std::slice::from_ref(&args.out), std::slice::from_ref(&result))?;
    let stored = read_texel_counts(&result)?;
    let options = heatmap_options(&args.heatmap, Some((stored.scale, stored.max)))?;
    ufcsr::write_heatmap(&args.out, &stored.texel_counts, stored.width, stored.height, options)?;
    finish(
        &args.common,
        Done {
            command: "heatmap",
            exit_code: 0,
            written: vec![args.out.clone()],
            text: format!(
                "wrote {} (heatmap of {}, {:?} scale)",
                args.out.display(),
                result.display(),
                options.scale
            ),
            facts: json!({ "result": result, "width": stored.width, "height": stored.height }),
        },
    )
}

pub fn run_palette(args: PaletteArgs) -> Result<ExitCode> {
    start_threads(&args.common)?;
    let (width, height) = ufcsr::parse_palette_size(&args.size)?;
    ufcsr::write_canonical_png(&args.out, width, height)?;
    finish(
        &args.common,
        Done {
            command: "palette",
            exit_code: 0,
            written: vec![args.out.clone()],
            text: format!("wrote {} ({width}×{height} canonical palette)", args.out.display()),
            facts: json!({ "width": width, "height": height }),
        },
    )
}

pub fn run_report(args: ReportArgs) -> Result<ExitCode> {
    start_threads(&args.common)?;
    let page = ufcsr::write_comparison(&args.results, &args.out)?;
    finish(
        &args.common,
        Done {
            command: "report",
            exit_code: 0,
            written: vec![page.clone()],
            text: format!("wrote {} ({} inputs)", page.display(), args.results.len()),
            facts: json!({ "results": args.results, "out": args.out }),
        },
    )
}

pub fn run_merge(args: MergeArgs) -> Result<ExitCode> {
    start_threads(&args.common)?;
    let results: Vec<PathBuf> = args.results.iter().map(|path| result_json(path)).collect();
    let mut analysis = ufcsr::merge_results(&results)?;
    let written = ufcsr::write_results_with(
        &mut analysis,
        &args.out,
        &ufcsr::ResultSetOptions { csv_style: args.csv_style.into(), views_scale: args.views_scale },
    )?;
    for warning in &analysis.result.warnings {
        eprintln!("warning: {warning}");
    }
    let complete = analysis.is_complete();
    finish(
        &args.common,
        Done {
            command: "merge",
            exit_code: if complete { 0 } else { 1 },
            written: written.all(&args.out),
            text: format!(
                "{}\nmerged {} results; wrote {}",
                format_table(&analysis.result).trim_end(),
                results.len(),
                written.result_json.display()
            ),
            facts: json!({ "results": results, "out": args.out, "result": analysis.result }),
        },
    )
}

pub fn run_completions(args: CompletionsArgs) -> Result<ExitCode> {
    crate::command_docs::print_completions(args.shell, Cli::command(), "ufcsr-analyze");
    Ok(ExitCode::SUCCESS)
}

pub fn run_man(args: ManArgs) -> Result<ExitCode> {
    for path in crate::command_docs::write_man_pages(Cli::command(), "ufcsr-analyze", args.out.as_deref())? {
        eprintln!("wrote {}", path.display());
    }
    Ok(ExitCode::SUCCESS)
}
