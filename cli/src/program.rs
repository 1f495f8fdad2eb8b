//! One command tree, `ufcsr` (`ufcsr analyze ARCHIVE`, `ufcsr merge …`,
//! `ufcsr capture demo …`, `ufcsr study …`, …). `ufcsr-analyze` and
//! `ufcsr-capture` are aliases kept for old scripts, never shown: their
//! command lines are rewritten into `ufcsr`'s (`ufcsr-analyze ARCHIVE` is
//! `ufcsr analyze ARCHIVE`, `ufcsr-capture demo` is `ufcsr capture demo`,
//! `ufcsr-capture study` is `ufcsr study`), so every help, usage line and
//! error names `ufcsr <command>`. Each command line parses into one [`Job`],
//! which [`run`] carries out: one options model ([`Global`]), one `--json`
//! design ([`Console`]), one exit-code map, one interrupt handler. Without
//! the `capture` feature the capture commands are not built in, and naming
//! one says how to get them ([`not_built_in`]).

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

/// Which binary is running: `ufcsr`, or one of its two old names.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Program {
    /// `ufcsr`: the whole command tree.
    Ufcsr,
    /// `ufcsr-analyze`: an alias; `ufcsr-analyze ARCHIVE` is `ufcsr analyze ARCHIVE`.
    Analyze,
    /// `ufcsr-capture`: an alias; `ufcsr-capture demo` is `ufcsr capture demo`.
    Capture,
}

/// What `capture` records: the words after `ufcsr capture`.
const CAPTURE_SOURCES: [&str; 3] = ["demo", "scene", "unity"];

/// The commands the `capture` feature builds in (`ufcsr capture demo|scene|unity`
/// and the tools around a capture), known even where it is off so that
/// naming one says how to get it.
const CAPTURE_COMMANDS: [&str; 10] =
    ["capture", "where", "study", "observers", "design", "inspect", "views", "batch", "assemble", "verify"];

/// How to get the capture commands, for a binary built without them.
const HOW_TO_GET_CAPTURE: &str = "the capture commands (capture, where, study, observers, design, inspect, \
     views, batch, assemble, verify) are not built into this binary; build them in with `cargo install \
     --path cli --features capture`, or run them from the repository with `cargo run --release \
     --features capture -- capture demo …` (they add the wgpu stack to the build)";

/// Counts how often each texel of a vehicle is visible to a pedestrian (UFCSR), records the
/// archives of frames that show it, and turns the counts into per-part statistics, heatmaps,
/// placements and reports.
///
/// `ufcsr analyze ARCHIVE` analyses an archive (a folder of PNG tiles rendered with a Full Color
/// Space Palette); `ufcsr capture demo` records one.
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
    /// Count an archive: per-part statistics, heatmap, views, plots and report.html.
    ///
    /// ARCHIVE is a folder of PNG tiles rendered with a Full Color Space Palette. With a
    /// manifest.json in it (written by `ufcsr capture`), no other option is needed. Writes
    /// result.json, parts.csv, heatmap.png, report.html and timings.json to --out (default:
    /// ARCHIVE/results).
    ///
    /// Example: `ufcsr analyze capA --out capA/results`
    #[command(alias = "analyse")]
    Analyze(AnalyzeArgs),
    #[command(flatten)]
    Analyzer(AnalyzerCommand),
    /// Record an archive with the headless wgpu renderer: the built-in demo, a scene file or a
    /// Unity export.
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

/// One command to carry out.
pub(crate) enum Job {
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
    /// The name every help, usage line, completion and man page shows.
    pub fn name(self) -> &'static str {
        "ufcsr"
    }

    /// The command tree, every command with the exit codes under its help
    /// (and, without the `capture` feature, how to get the capture commands).
    pub fn command(self) -> clap::Command {
        crate::advanced::hide_advanced(self.command_all())
    }

    /// The command tree with every option shown: what `--help-all` lists.
    pub fn command_all(self) -> clap::Command {
        let command = with_exit_status(UfcsrLine::command());
        if cfg!(feature = "capture") {
            command
        } else {
            command.before_help(format!("Note: {HOW_TO_GET_CAPTURE}."))
        }
    }

    /// This binary's command line as `ufcsr`'s: an old name's grammar
    /// rewritten (see the module documentation), the program named `ufcsr`.
    pub fn as_ufcsr(self, mut args: Vec<OsString>) -> Vec<OsString> {
        if args.is_empty() {
            args.push(OsString::new());
        }
        args[0] = OsString::from("ufcsr");
        let root = UfcsrLine::command();
        let word = first_word(&args, &root);
        let named = |index: usize| args[index].to_str().unwrap_or("").to_string();
        match (self, word) {
            (Program::Analyze, Some(index)) if !names_a_command(&root, &named(index)) => {
                args.insert(1, OsString::from("analyze"));
            }
            (Program::Capture, Some(index)) if CAPTURE_SOURCES.contains(&named(index).as_str()) => {
                args.insert(index, OsString::from("capture"));
            }
            _ => {}
        }
        args
    }

    /// The job and the global options the parsed command line asks for.
    fn job(matches: &clap::ArgMatches) -> Result<(Job, Global), clap::Error> {
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
        Ok((job, line.global))
    }

    /// The command a usage error belongs to, as far as the arguments name
    /// one (the deepest subcommand named; `ufcsr` otherwise).
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
        if names.is_empty() { self.name().into() } else { names.join(" ") }
    }
}

/// The index of the first word of `args` that is neither an option nor
/// the value of one of `root`'s options (`--threads 2`): the command, or
/// for the old `ufcsr analyze ARCHIVE` grammar the archive.
fn first_word(args: &[OsString], root: &clap::Command) -> Option<usize> {
    let takes_value = |arg: &str| {
        root.get_arguments().any(|option| {
            let named = arg.strip_prefix("--").map_or_else(
                || {
                    arg.strip_prefix('-')
                        .and_then(|short| short.chars().next())
                        .is_some_and(|c| option.get_short() == Some(c) && arg.len() == 2)
                },
                |long| option.get_long() == Some(long),
            );
            named && option.get_action().takes_values()
        })
    };
    let mut index = 1;
    while index < args.len() {
        let arg = args[index].to_str().unwrap_or("");
        if arg == "--" {
            return None;
        }
        if !arg.starts_with('-') || arg == "-" {
            return Some(index);
        }
        index += if takes_value(arg) { 2 } else { 1 };
    }
    None
}

/// Whether `word` names one of `root`'s commands (or an alias of one), or
/// one of the capture commands where they are not built in.
fn names_a_command(root: &clap::Command, word: &str) -> bool {
    word == "help" || root.find_subcommand(word).is_some() || CAPTURE_COMMANDS.contains(&word)
}

/// The error for a capture command this binary was built without, or for
/// `capture` followed by no source: `None` when `args` name neither.
fn not_built_in(program: Program, args: &[OsString]) -> Option<clap::Error> {
    usage_problem(program, args, cfg!(feature = "capture"))
}

/// [`not_built_in`] for a binary built with the capture commands or not.
fn usage_problem(program: Program, args: &[OsString], capture_built: bool) -> Option<clap::Error> {
    let root = UfcsrLine::command();
    let index = first_word(args, &root)?;
    let word = args[index].to_str()?;
    let mut command = program.command();
    command.build();
    if !capture_built && CAPTURE_COMMANDS.contains(&word) {
        return Some(command.error(
            clap::error::ErrorKind::InvalidSubcommand,
            format!("`ufcsr {word}`: {HOW_TO_GET_CAPTURE}"),
        ));
    }
    let next = args[index + 1..].iter().filter_map(|arg| arg.to_str()).find(|arg| !arg.starts_with('-'));
    let asks_for_help = args[index + 1..].iter().any(|arg| arg == "--help" || arg == "-h");
    let source_named = next.is_some_and(|next| CAPTURE_SOURCES.contains(&next) || next == "help");
    if word != "capture" || source_named || asks_for_help {
        return None;
    }
    let capture = command.find_subcommand_mut("capture")?;
    Some(capture.error(
        clap::error::ErrorKind::MissingSubcommand,
        "`ufcsr capture` needs what to capture: `demo`, `scene FILE` or `unity FILE` \
         (for example `ufcsr capture demo --scenario A`)",
    ))
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
    let mut args = program.as_ufcsr(std::env::args_os().collect());
    if let Some(error) = not_built_in(program, &args) {
        return usage_end(program, &args, &error);
    }
    let command =
        if crate::advanced::take_help_all(&mut args) { program.command_all() } else { program.command() };
    let parsed = command.try_get_matches_from(&args).and_then(|matches| Program::job(&matches));
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
        if words.first().map(String::as_str) != Some("ufcsr") {
            return Err(format!("does not start with `ufcsr`: {example}"));
        }
        let args = words.iter().map(String::as_str).chain(["--help"]);
        match Program::Ufcsr.command().try_get_matches_from(args) {
            Err(error) if error.kind() == clap::error::ErrorKind::DisplayHelp => Ok(()),
            Err(error) => Err(error.render().to_string()),
            Ok(_) => Err("parsed without showing help".into()),
        }
    }

    #[test]
    fn every_command_has_its_own_help_example() {
        let mut main = Program::Ufcsr.command();
        main.build();
        let main_example = example(&main).expect("ufcsr --help has no example");
        assert_eq!(parses(&main_example), Ok(()), "{main_example}");
        let mut commands = Vec::new();
        subcommands(&main, "", &mut commands);
        assert!(commands.len() >= 8, "{} commands", commands.len());
        for (path, command) in &commands {
            let shown = format!("ufcsr {path}");
            let Some(own) = example(command) else { panic!("`{shown} --help` has no example") };
            // Its own: it names the command.
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

    /// The old names' command lines, rewritten as `ufcsr`'s.
    fn rewritten(program: Program, line: &str) -> String {
        let args = std::iter::once("old").chain(line.split_whitespace()).map(OsString::from).collect();
        let args = program.as_ufcsr(args);
        args.iter().map(|arg| arg.to_string_lossy().into_owned()).collect::<Vec<_>>().join(" ")
    }

    #[test]
    fn the_old_names_run_the_same_commands_under_ufcsr() {
        let cases = [
            (Program::Analyze, "capA --out r", "ufcsr analyze capA --out r"),
            (Program::Analyze, "--threads 2 capA", "ufcsr analyze --threads 2 capA"),
            (Program::Analyze, "--json merge a b --out m", "ufcsr --json merge a b --out m"),
            (Program::Analyze, "--help", "ufcsr --help"),
            (Program::Capture, "demo --scenario A", "ufcsr capture demo --scenario A"),
            (Program::Capture, "-j 2 scene s.json", "ufcsr -j 2 capture scene s.json"),
            (Program::Capture, "study s.json", "ufcsr study s.json"),
            (Program::Ufcsr, "analyse capA", "ufcsr analyse capA"),
        ];
        for (program, line, expected) in cases {
            assert_eq!(rewritten(program, line), expected, "{program:?} {line}");
        }
    }

    /// Every help text of every command, as `--help` prints it.
    fn every_help() -> Vec<(String, String)> {
        let mut main = Program::Ufcsr.command();
        main.build();
        let mut commands = vec![(String::new(), main.clone())];
        subcommands(&main, "", &mut commands);
        commands
            .into_iter()
            .map(|(path, mut command)| (path, command.render_long_help().to_string()))
            .collect()
    }

    #[test]
    fn no_help_names_the_old_programs() {
        for (path, help) in every_help() {
            for old in ["ufcsr-analyze", "ufcsr-capture"] {
                assert!(!help.contains(old), "`ufcsr {path} --help` names {old}:\n{help}");
            }
        }
    }

    #[test]
    fn capture_without_a_source_says_what_it_needs() {
        let args: Vec<OsString> = ["ufcsr", "capture", "--scenario", "A"].map(OsString::from).to_vec();
        let error = not_built_in(Program::Ufcsr, &args).expect("an error").render().to_string();
        assert!(error.contains("`demo`, `scene FILE` or `unity FILE`"), "{error}");
        assert!(error.contains("Usage: ufcsr capture"), "{error}");
        let fine: Vec<OsString> =
            ["ufcsr", "capture", "demo", "--scenario", "A"].map(OsString::from).to_vec();
        assert!(usage_problem(Program::Ufcsr, &fine, true).is_none());
    }

    #[test]
    fn a_capture_command_not_built_in_says_how_to_get_it() {
        for word in CAPTURE_COMMANDS {
            let args: Vec<OsString> = ["ufcsr", "--json", word, "x"].map(OsString::from).to_vec();
            let error = usage_problem(Program::Ufcsr, &args, false).expect("an error").render().to_string();
            assert!(error.contains(&format!("`ufcsr {word}`")), "{error}");
            assert!(error.contains("cargo install --path cli --features capture"), "{error}");
            assert!(usage_problem(Program::Ufcsr, &args, true).is_none() || word == "capture", "{word}");
        }
        let analysis: Vec<OsString> = ["ufcsr", "analyze", "capA"].map(OsString::from).to_vec();
        assert!(usage_problem(Program::Ufcsr, &analysis, false).is_none());
    }

    #[cfg(feature = "capture")]
    #[test]
    fn the_capture_commands_are_the_ones_named_where_they_are_not_built_in() {
        let main = Program::Ufcsr.command();
        let others =
            DocsCommand::augment_subcommands(AnalyzerCommand::augment_subcommands(clap::Command::new("x")));
        let other =
            |name: &str| name == "analyze" || name == "help" || others.find_subcommand(name).is_some();
        let mut built: Vec<&str> =
            main.get_subcommands().map(clap::Command::get_name).filter(|name| !other(name)).collect();
        built.sort_unstable();
        let mut named = CAPTURE_COMMANDS.to_vec();
        named.sort_unstable();
        assert_eq!(built, named);
    }

    /// Every `.rs` file under `dir`.
    fn rust_files(dir: &std::path::Path, out: &mut Vec<std::path::PathBuf>) {
        for entry in std::fs::read_dir(dir).unwrap().flatten() {
            let path = entry.path();
            if path.is_dir() {
                rust_files(&path, out);
            } else if path.extension().is_some_and(|e| e == "rs") {
                out.push(path);
            }
        }
    }

    #[test]
    fn no_message_of_the_three_crates_names_the_old_programs() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
        let mut files = Vec::new();
        for dir in ["src", "capture/src", "cli/src"] {
            rust_files(&root.join(dir), &mut files);
        }
        // Not messages: the recorded tool name, a GPU debug label, the binaries'
        // own names; unit tests (after `#[cfg(test)]`) are not scanned.
        let allowed = ["concat!(\"ufcsr-capture \"", "label: Some(\"ufcsr-capture\")", "CARGO_BIN_EXE_"];
        let mut found = Vec::new();
        for file in &files {
            let text = std::fs::read_to_string(file).unwrap();
            for (number, line) in
                text.lines().enumerate().take_while(|(_, line)| line.trim() != "#[cfg(test)]")
            {
                let code = line.trim_start();
                let names_old = code.contains("ufcsr-analyze") || code.contains("ufcsr-capture");
                if names_old && !code.starts_with("//") && !allowed.iter().any(|a| code.contains(a)) {
                    found.push(format!("{}:{}: {code}", file.display(), number + 1));
                }
            }
        }
        assert!(found.is_empty(), "messages naming the old programs:\n{}", found.join("\n"));
    }
}
