//! `ufcsr`: one entry point for the toolkit's commands, like `git`.
//!
//! `ufcsr analyze|merge|report|heatmap|palette|manifest|placement ...` runs `ufcsr-analyze`,
//! `ufcsr capture|batch|study|observers|assemble|verify|inspect|views ...` runs `ufcsr-capture` (the program found beside
//! this one, or else on `PATH`), with the rest of the arguments. It holds no
//! logic of its own, so each command behaves and is documented exactly as in
//! the tool it belongs to.

use std::ffi::OsString;
use std::path::PathBuf;
use std::process::{Command, ExitCode};

const USAGE: &str = "usage: ufcsr COMMAND [ARGS...]

  analyze ARCHIVE ...          ufcsr-analyze ARCHIVE ...       count an archive
  merge RESULT... --out DIR    ufcsr-analyze merge ...         add shards' results
  report A B ... --out DIR     ufcsr-analyze report ...        compare several results
  heatmap RESULT.json ...      ufcsr-analyze heatmap ...       re-render the heatmap
  palette --out PNG            ufcsr-analyze palette ...       write the canonical palette
  manifest DIR ...             ufcsr-analyze manifest ...      describe Unity/Blender frames
  placement RESULTS... ...     ufcsr-analyze placement ...     the best eHMI placements
  capture demo|scene|unity ... ufcsr-capture demo|scene|unity  record an archive
  assemble ARCHIVE             ufcsr-capture assemble          join a sharded capture
  batch plan BATCH.json        ufcsr-capture batch plan        one command per task
  study SCENE ...              ufcsr-capture study             error against run time
  observers SCENE ...          ufcsr-capture observers         spread over pedestrians
  verify ARCHIVE               ufcsr-capture verify            check an archive
  inspect MESH                 ufcsr-capture inspect           look at a vehicle
  views RESULTS                ufcsr-capture views             the eight views on the GPU

`ufcsr COMMAND --help` shows the command's options; `ufcsr --version` the version.";

/// The program and the arguments that replace `ufcsr COMMAND`.
fn route(command: &str) -> Option<(&'static str, Option<&'static str>)> {
    Some(match command {
        "analyze" => ("ufcsr-analyze", None),
        "merge" => ("ufcsr-analyze", Some("merge")),
        "report" => ("ufcsr-analyze", Some("report")),
        "heatmap" => ("ufcsr-analyze", Some("heatmap")),
        "palette" => ("ufcsr-analyze", Some("palette")),
        "manifest" => ("ufcsr-analyze", Some("manifest")),
        "placement" => ("ufcsr-analyze", Some("placement")),
        "capture" => ("ufcsr-capture", None),
        "assemble" => ("ufcsr-capture", Some("assemble")),
        "batch" => ("ufcsr-capture", Some("batch")),
        "study" => ("ufcsr-capture", Some("study")),
        "observers" => ("ufcsr-capture", Some("observers")),
        "verify" => ("ufcsr-capture", Some("verify")),
        "inspect" => ("ufcsr-capture", Some("inspect")),
        "views" => ("ufcsr-capture", Some("views")),
        _ => return None,
    })
}

/// `name` beside this executable if it is there, else `name` (found on PATH).
fn program(name: &str) -> PathBuf {
    std::env::current_exe()
        .ok()
        .map(|exe| exe.with_file_name(name))
        .filter(|path| path.is_file())
        .unwrap_or_else(|| PathBuf::from(name))
}

fn main() -> ExitCode {
    let mut args = std::env::args_os().skip(1);
    let Some(command) = args.next() else {
        eprintln!("{USAGE}");
        return ExitCode::from(2);
    };
    let command_text = command.to_string_lossy();
    if matches!(command_text.as_ref(), "-h" | "--help" | "help") {
        println!("{USAGE}");
        return ExitCode::SUCCESS;
    }
    if matches!(command_text.as_ref(), "-V" | "--version" | "version") {
        println!("ufcsr {}", env!("CARGO_PKG_VERSION"));
        return ExitCode::SUCCESS;
    }
    let Some((name, first)) = route(&command_text) else {
        eprintln!("ufcsr: unknown command {command_text:?}\n\n{USAGE}");
        return ExitCode::from(2);
    };
    let rest: Vec<OsString> = first.map(OsString::from).into_iter().chain(args).collect();
    let program = program(name);
    match Command::new(&program).args(&rest).status() {
        Ok(status) => match status.code() {
            Some(code) => ExitCode::from(u8::try_from(code).unwrap_or(1)),
            None => ExitCode::FAILURE, // killed by a signal
        },
        Err(error) => {
            eprintln!(
                "ufcsr: cannot run {}: {error} (install it beside ufcsr or on PATH)",
                program.display()
            );
            ExitCode::FAILURE
        }
    }
}
