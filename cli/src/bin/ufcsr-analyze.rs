//! `ufcsr-analyze`: command-line front end. Parses arguments
//! ([`cli::args`]), runs the library, prints what was done and maps the
//! outcome to the exit code every subcommand shares: 0 done, 1 done with
//! failures, 2 nothing done (docs/guide.md#exit-codes).

#[path = "../analyze/mod.rs"]
mod cli;
#[path = "../command_docs.rs"]
mod command_docs;

use std::process::ExitCode;

use clap::Parser;

use cli::args::{Cli, Command};

fn main() -> ExitCode {
    let cli = Cli::parse();
    ufcsr::remove_temporaries_on_interrupt();
    if let Some(value) = ufcsr::Kernel::unknown_request() {
        eprintln!(
            "warning: {}={value:?} names no kernel (portable, avx2, avx512); using {}",
            ufcsr::KERNEL_ENV,
            ufcsr::Kernel::selected().name()
        );
    }
    let (name, json) = match &cli.command {
        Some(Command::Heatmap(args)) => ("heatmap", args.common.json),
        Some(Command::Merge(args)) => ("merge", args.common.json),
        Some(Command::Report(args)) => ("report", args.common.json),
        Some(Command::Palette(args)) => ("palette", args.common.json),
        Some(Command::Placement(args)) => ("placement", args.common.json),
        Some(Command::Manifest(args)) => ("manifest", args.common.json),
        Some(Command::Completions(_)) => ("completions", false),
        Some(Command::Man(_)) => ("man", false),
        None => ("analyze", cli.analyze.common.json),
    };
    let outcome = match cli.command {
        Some(Command::Heatmap(args)) => cli::run::run_heatmap(args),
        Some(Command::Palette(args)) => cli::run::run_palette(args),
        Some(Command::Merge(args)) => cli::run::run_merge(args),
        Some(Command::Report(args)) => cli::run::run_report(args),
        Some(Command::Placement(args)) => cli::placement::run_placement(args),
        Some(Command::Manifest(args)) => cli::manifest::run_manifest(args),
        Some(Command::Completions(args)) => cli::run::run_completions(args),
        Some(Command::Man(args)) => cli::run::run_man(args),
        None => cli::analyze_cmd::run_analyze(cli.analyze),
    };
    match outcome {
        Ok(code) => code,
        Err(error) => {
            eprintln!("error: {error:#}");
            if json {
                // A script reading stdout learns that nothing was done, and why.
                let summary = serde_json::json!({
                    "command": name, "exit_code": 2, "written": [], "error": format!("{error:#}"),
                });
                println!("{summary}");
            }
            ExitCode::from(2)
        }
    }
}
