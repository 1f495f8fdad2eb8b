//! The three programs as one command tree. `ufcsr` is the whole tree
//! (`ufcsr analyze ARCHIVE`, `ufcsr merge …`, `ufcsr capture demo …`,
//! `ufcsr study …`, …); `ufcsr-analyze` and `ufcsr-capture` are the same
//! commands under the grammar they always had (`ufcsr-analyze ARCHIVE`,
//! `ufcsr-analyze merge …`, `ufcsr-capture demo …`). Each parses into one
//! [`Job`], which [`run`] carries out the same way whatever the program:
//! one options model ([`Global`]), one `--json` design ([`Console`]), one
//! exit-code map, one interrupt handler.

// The command enums are parsed once per process: their size does not matter,
// and boxing their variants would cost clap's derive its flattening.
#![allow(clippy::large_enum_variant)]

use std::ffi::OsString;
use std::process::ExitCode;

use clap::{CommandFactory, FromArgMatches, Parser, Subcommand};

use crate::analyze::{AnalyzeArgs, AnalyzerCommand};
#[cfg(feature = "capture")]
use crate::capture::{CaptureCommand, CaptureToolCommand};
use crate::command_docs::DocsCommand;
use crate::console::{Console, EXIT_STATUS_HELP, Style};
use crate::options::Global;

/// Which of the three programs is running.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Program {
    /// `ufcsr`: the whole command tree.
    Ufcsr,
    /// `ufcsr-analyze`: the analysis as the main command, and the analyzer's commands.
    Analyze,
    /// `ufcsr-capture`: the captures and the tools around them.
    #[cfg(feature = "capture")]
    Capture,
}

/// Counts how often each texel of a vehicle is visible to a pedestrian (UFCSR), records the
/// archives of frames that show it, and turns the counts into per-part statistics, heatmaps,
/// placements and reports.
///
/// `ufcsr analyze ARCHIVE` analyses an archive (a folder of PNG tiles rendered with a Full Color
/// Space Palette); `ufcsr capture demo` records one. `ufcsr-analyze` and `ufcsr-capture` are the
/// same commands under their own names.
///
/// Example: `ufcsr capture demo --scenario A --preview --out capA && ufcsr analyze capA`
#[derive(Parser)]
#[command(name = "ufcsr", version, subcommand_required = true, arg_required_else_help = true)]
struct UfcsrLine {
    #[command(subcommand)]
    command: UfcsrCommand,
    #[command(flatten)]
    global: Global,
}

#[derive(Subcommand)]
enum UfcsrCommand {
    /// Count an archive: per-part statistics, heatmap, views, plots and report.html
    /// (`ufcsr-analyze ARCHIVE`).
    ///
    /// Example: `ufcsr analyze capA --out capA/results`
    Analyze(AnalyzeArgs),
    #[command(flatten)]
    Analyzer(AnalyzerCommand),
    /// Record an archive with the headless wgpu renderer: the built-in demo, a scene file or a
    /// Unity export (`ufcsr-capture demo|scene|unity`).
    ///
    /// Example: `ufcsr capture scene fixtures/scenes/milk-truck.json --preview --out truck`
    #[cfg(feature = "capture")]
    Capture {
        #[command(subcommand)]
        command: CaptureCommand,
    },
    #[cfg(feature = "capture")]
    #[command(flatten)]
    CaptureTool(CaptureToolCommand),
    #[command(flatten)]
    Docs(DocsCommand),
}

/// Counts how often each texel of a vehicle is visible in captured frames
/// (UFCSR), and turns the counts into per-part statistics and a heatmap.
///
/// ARCHIVE is a folder of PNG tiles rendered with a Full Color Space Palette.
/// With a manifest.json in it (written by ufcsr-capture), no other option is
/// needed. Writes result.json, parts.csv, heatmap.png, report.html and
/// timings.json to --out (default: ARCHIVE/results). The same as `ufcsr analyze`.
///
/// Example: `ufcsr-analyze capA` (then open capA/results/report.html)
#[derive(Parser)]
#[command(
    name = "ufcsr-analyze",
    version,
    args_conflicts_with_subcommands = true,
    subcommand_negates_reqs = true
)]
struct AnalyzeLine {
    #[command(subcommand)]
    command: Option<AnalyzeLineCommand>,
    #[command(flatten)]
    analyze: AnalyzeArgs,
    #[command(flatten)]
    global: Global,
}

#[derive(Subcommand)]
enum AnalyzeLineCommand {
    #[command(flatten)]
    Analyzer(AnalyzerCommand),
    #[command(flatten)]
    Docs(DocsCommand),
}

/// Record UFCSR archives with a headless, exact wgpu renderer (the same as `ufcsr capture …`,
/// `ufcsr study …` and the other capture commands of `ufcsr`).
///
/// Example: `ufcsr-capture scene my-scene.json --preview --out look && ufcsr-analyze look`
#[cfg(feature = "capture")]
#[derive(Parser)]
#[command(name = "ufcsr-capture", version)]
struct CaptureLine {
    #[command(subcommand)]
    command: CaptureLineCommand,
    #[command(flatten)]
    global: Global,
}

#[cfg(feature = "capture")]
#[derive(Subcommand)]
enum CaptureLineCommand {
    #[command(flatten)]
    Capture(CaptureCommand),
    #[command(flatten)]
    CaptureTool(CaptureToolCommand),
    #[command(flatten)]
    Docs(DocsCommand),
}

/// One command to carry out, whichever program parsed it.
pub enum Job {
    Analyze(Box<AnalyzeArgs>),
    Analyzer(AnalyzerCommand),
    #[cfg(feature = "capture")]
    Capture(CaptureCommand),
    #[cfg(feature = "capture")]
    CaptureTool(CaptureToolCommand),
    Docs(DocsCommand),
}

impl Job {
    /// The command's name, as `--json` reports it.
    fn name(&self) -> &'static str {
        match self {
            Job::Analyze(_) => "analyze",
            Job::Analyzer(command) => command.name(),
            #[cfg(feature = "capture")]
            Job::Capture(command) => command.name(),
            #[cfg(feature = "capture")]
            Job::CaptureTool(command) => command.name(),
            Job::Docs(command) => command.name(),
        }
    }
}

impl Program {
    /// The program's name, as `--help` and the man pages show it.
    pub fn name(self) -> &'static str {
        match self {
            Program::Ufcsr => "ufcsr",
            Program::Analyze => "ufcsr-analyze",
            #[cfg(feature = "capture")]
            Program::Capture => "ufcsr-capture",
        }
    }

    /// The program's command tree, every command with the exit codes under its help.
    pub fn command(self) -> clap::Command {
        let command = match self {
            Program::Ufcsr => UfcsrLine::command(),
            Program::Analyze => AnalyzeLine::command(),
            #[cfg(feature = "capture")]
            Program::Capture => CaptureLine::command(),
        };
        with_exit_status(command)
    }

    /// The job and the global options the parsed command line asks for.
    fn job(self, matches: &clap::ArgMatches) -> Result<(Job, Global), clap::Error> {
        Ok(match self {
            Program::Ufcsr => {
                let line = UfcsrLine::from_arg_matches(matches)?;
                let job = match line.command {
                    UfcsrCommand::Analyze(args) => Job::Analyze(Box::new(args)),
                    UfcsrCommand::Analyzer(command) => Job::Analyzer(command),
                    #[cfg(feature = "capture")]
                    UfcsrCommand::Capture { command } => Job::Capture(command),
                    #[cfg(feature = "capture")]
                    UfcsrCommand::CaptureTool(command) => Job::CaptureTool(command),
                    UfcsrCommand::Docs(command) => Job::Docs(command),
                };
                (job, line.global)
            }
            Program::Analyze => {
                let line = AnalyzeLine::from_arg_matches(matches)?;
                let job = match line.command {
                    None => Job::Analyze(Box::new(line.analyze)),
                    Some(AnalyzeLineCommand::Analyzer(command)) => Job::Analyzer(command),
                    Some(AnalyzeLineCommand::Docs(command)) => Job::Docs(command),
                };
                (job, line.global)
            }
            #[cfg(feature = "capture")]
            Program::Capture => {
                let line = CaptureLine::from_arg_matches(matches)?;
                let job = match line.command {
                    CaptureLineCommand::Capture(command) => Job::Capture(command),
                    CaptureLineCommand::CaptureTool(command) => Job::CaptureTool(command),
                    CaptureLineCommand::Docs(command) => Job::Docs(command),
                };
                (job, line.global)
            }
        })
    }

    /// The command a usage error belongs to, as far as the arguments name
    /// one (the deepest subcommand named; the main command otherwise).
    fn command_named(self, args: &[OsString]) -> String {
        let mut command = self.command();
        let mut names = Vec::new();
        for arg in args.iter().skip(1).filter_map(|arg| arg.to_str()) {
            let Some(sub) = command.find_subcommand(arg).cloned() else { continue };
            names.push(sub.get_name().to_string());
            command = sub;
        }
        if names.len() > 1 && names[0] == "capture" {
            names.remove(0);
        }
        match (names.is_empty(), self) {
            (false, _) => names.join(" "),
            (true, Program::Analyze) => "analyze".into(),
            (true, program) => program.name().into(),
        }
    }
}

/// `command` and every command below it with the exit codes under its help.
fn with_exit_status(command: clap::Command) -> clap::Command {
    command.after_help(EXIT_STATUS_HELP).mut_subcommands(with_exit_status)
}

/// True when the arguments ask for `--json` (before a `--`): how a usage
/// error, which clap reports before the options are known, learns it.
fn asks_for_json(args: &[OsString]) -> bool {
    args.iter().skip(1).take_while(|arg| *arg != "--").any(|arg| arg == "--json")
}

/// Runs `program` on this process's arguments: parse, carry out, end.
pub fn main(program: Program) -> ExitCode {
    let args: Vec<OsString> = std::env::args_os().collect();
    let parsed = program.command().try_get_matches_from(&args).and_then(|matches| program.job(&matches));
    let (job, global) = match parsed {
        Ok(parsed) => parsed,
        Err(error) => return usage_end(program, &args, &error),
    };
    let console = Console::new(job.name(), global.style());
    #[cfg(feature = "capture")]
    // Before any other thread starts (the interrupt handler's, the GPU's).
    let _runtime_dir =
        matches!(job, Job::Capture(_) | Job::CaptureTool(_)).then(crate::capture::PrivateRuntimeDir::create);
    crate::interrupt::remove_temporaries_on_interrupt(&console);
    warn_of_unknown_kernel();
    // A panic is a bug, but under --json it still ends in the one JSON object
    // (exit 101, as Rust's own; the panic's message is on stderr already).
    let ran = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        global.start_threads().and_then(|()| run(job, program, &global, &console))
    }));
    match ran {
        Ok(outcome) => console.end(outcome),
        Err(panic) => console.end_with(PANICKED, Some(&format!("internal error: {}", panic_text(&*panic)))),
    }
}

/// The exit code of a run that panicked (a bug), as Rust gives it.
const PANICKED: u8 = 101;

/// What a panic said, when it said it as text.
fn panic_text(panic: &(dyn std::any::Any + Send)) -> String {
    match (panic.downcast_ref::<&str>(), panic.downcast_ref::<String>()) {
        (Some(text), _) => (*text).to_string(),
        (_, Some(text)) => text.clone(),
        _ => "a panic".to_string(),
    }
}

/// Carries out one job.
fn run(
    job: Job,
    program: Program,
    global: &Global,
    console: &Console,
) -> anyhow::Result<crate::console::Completion> {
    #[cfg(not(feature = "capture"))]
    let _ = global; // only the captures use it (their encoder threads)
    match job {
        Job::Analyze(args) => crate::analyze::run_analyze(*args, console),
        Job::Analyzer(command) => crate::analyze::run(command, console),
        #[cfg(feature = "capture")]
        Job::Capture(command) => crate::capture::run_capture_command(command, global, console),
        #[cfg(feature = "capture")]
        Job::CaptureTool(command) => crate::capture::run_tool(command, console),
        Job::Docs(command) => crate::command_docs::run(command, program.command(), program.name(), console),
    }
}

/// `UFCSR_KERNEL` naming no kernel: said once, and the kernel used instead.
fn warn_of_unknown_kernel() {
    if let Some(value) = ufcsr::Kernel::unknown_request() {
        eprintln!(
            "warning: {}={value:?} names no kernel (portable, avx2, avx512); using {}",
            ufcsr::KERNEL_ENV,
            ufcsr::Kernel::selected().name()
        );
    }
}

/// A usage error, `--help` or `--version`: clap's text as clap prints it,
/// and under `--json` the one JSON object (the text in `help`, `version` or
/// `error`); clap's exit code (0 for help and version, 2 for usage errors).
fn usage_end(program: Program, args: &[OsString], error: &clap::Error) -> ExitCode {
    use clap::error::ErrorKind;
    let code = u8::try_from(error.exit_code()).unwrap_or(crate::console::exit_code::NOTHING_DONE);
    if !asks_for_json(args) {
        // Nothing to say when stderr or stdout is gone.
        let _ = error.print();
        return ExitCode::from(code);
    }
    let text = error.render().to_string();
    let console = Console::new(program.command_named(args), Style::Json);
    match error.kind() {
        ErrorKind::DisplayHelp => console.fact("help", &text),
        ErrorKind::DisplayVersion => console.fact("version", text.trim_end()),
        _ => {
            let _ = error.print();
            return console.end_with(code, Some(text.trim_end()));
        }
    }
    console.end_with(code, None)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every command below `command` (`help` left out), depth first, with
    /// its path of names below the program.
    fn subcommands(command: &clap::Command, path: &str, out: &mut Vec<(String, clap::Command)>) {
        for sub in command.get_subcommands().filter(|sub| sub.get_name() != "help") {
            let name = if path.is_empty() {
                sub.get_name().to_string()
            } else {
                format!("{path} {}", sub.get_name())
            };
            out.push((name.clone(), sub.clone()));
            subcommands(sub, &name, out);
        }
    }

    /// Everything a command's `--help` says besides its options, unwrapped.
    fn texts(command: &clap::Command) -> String {
        [command.get_long_about(), command.get_about(), command.get_before_help(), command.get_after_help()]
            .into_iter()
            .flatten()
            .map(|text| format!("{text}\n"))
            .collect()
    }

    /// The example a command's `--help` gives (`Example: `…``), if any.
    fn example(command: &clap::Command) -> Option<String> {
        let help = texts(command);
        let (_, after) = help.split_once("Example: `")?;
        after.split_once('`').map(|(example, _)| example.to_string())
    }

    /// The words of an example's first command (up to `|`, `&&` or `>`),
    /// quotes removed as a shell would.
    fn first_command(example: &str) -> Vec<String> {
        let (mut words, mut word, mut quote, mut any) = (Vec::new(), String::new(), None, false);
        for c in example.chars() {
            match (quote, c) {
                (Some(q), c) if c == q => quote = None,
                (Some(_), c) => word.push(c),
                (None, '"' | '\'') => (quote, any) = (Some(c), true),
                (None, '|' | '&' | '>') => break,
                (None, c) if c.is_whitespace() => {
                    if any || !word.is_empty() {
                        words.push(std::mem::take(&mut word));
                    }
                    any = false;
                }
                (None, c) => word.push(c),
            }
        }
        if any || !word.is_empty() {
            words.push(word);
        }
        words
    }

    /// Whether `example`'s first command parses (asked for `--help` after
    /// its arguments, so that no file is needed): a typo in an option fails.
    fn parses(example: &str) -> Result<(), String> {
        let words = first_command(example);
        let program = match words.first().map(String::as_str) {
            Some("ufcsr") => Program::Ufcsr,
            Some("ufcsr-analyze") => Program::Analyze,
            #[cfg(feature = "capture")]
            Some("ufcsr-capture") => Program::Capture,
            other => return Err(format!("names no program: {other:?}")),
        };
        let args = words.iter().map(String::as_str).chain(["--help"]);
        match program.command().try_get_matches_from(args) {
            Err(error) if error.kind() == clap::error::ErrorKind::DisplayHelp => Ok(()),
            Err(error) => Err(error.render().to_string()),
            Ok(_) => Err("parsed without showing help".into()),
        }
    }

    #[test]
    fn every_command_has_its_own_help_example() {
        let mut programs = vec![Program::Ufcsr, Program::Analyze];
        #[cfg(feature = "capture")]
        programs.push(Program::Capture);
        for program in programs {
            let mut main = program.command();
            main.build();
            let main_example =
                example(&main).unwrap_or_else(|| panic!("{} --help has no example", program.name()));
            assert_eq!(parses(&main_example), Ok(()), "{main_example}");
            let mut commands = Vec::new();
            subcommands(&main, "", &mut commands);
            assert!(commands.len() >= 8, "{}: {} commands", program.name(), commands.len());
            for (path, command) in &commands {
                let shown = format!("{} {path}", program.name());
                let Some(own) = example(command) else { panic!("`{shown} --help` has no example") };
                // Its own: it names the command (`ufcsr-capture demo` names `capture demo`).
                assert!(own.contains(path.as_str()), "`{shown} --help`'s example does not run it: {own}");
                if let Err(error) = parses(&own) {
                    panic!("`{shown} --help`'s example does not parse: {own}\n{error}");
                }
                assert!(
                    !texts(command).contains(&main_example),
                    "`{shown} --help` repeats the main example: {main_example}"
                );
            }
        }
    }
}
