//! What a command says and what it did, in one place for every command of
//! the three programs: lines for people on stdout (none with `--quiet`), or
//! with `--json` exactly one JSON object for programs, whatever the ending —
//! done, done with failures, an error, a usage error, Ctrl-C, a panic. The object
//! holds `command`, `exit_code`, `written` (every file written, as recorded
//! by [`Console::wrote`]) and the command's own facts ([`Console::fact`]);
//! on an error also `error`. A [`Console`] is a handle: the interrupt handler
//! holds a clone, so an interrupted run still prints its one object.
//!
//! stdout is written through here only: a reader that has gone (`| head`)
//! ends the printing quietly; a stdout that fails otherwise (a full device)
//! is named on stderr and turns the exit code into 1 (files were written) or
//! 2 (none were) — never a panic.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::{Arc, Mutex, MutexGuard, PoisonError};

use serde::Serialize;
use serde_json::{Map, Value};

/// The exit codes, the same for every command of `ufcsr`, `ufcsr analyze`
/// and `ufcsr capture` (docs/guide.md#exit-codes).
pub mod exit_code {
    /// Done: everything read, every file written.
    pub const DONE: u8 = 0;
    /// Done, but with failures named on stderr: some images could not be
    /// read, `verify` found stray pixels, a later part of the run failed after
    /// files were written, or stdout could not take the summary.
    pub const WITH_FAILURES: u8 = 1;
    /// Nothing done: a usage error, bad options or inputs, a failed run that
    /// wrote no file.
    pub const NOTHING_DONE: u8 = 2;
    /// Interrupted (SIGINT/SIGTERM): temporary files removed; earlier outputs untouched, or a capture
    /// folder left unfinished and marked so ([`interruption_message`]).
    pub const INTERRUPTED: u8 = 130;
}

/// The exit codes in one line, shown under every command's `--help`.
pub const EXIT_STATUS_HELP: &str = "Exit status: 0 done; 1 done, but with failures (results written, \
    what failed is named on stderr); 2 nothing done (bad options or inputs, named on stderr); 130 \
    interrupted (temporary files removed). With --json, stdout holds exactly one JSON object whatever \
    the ending (docs/guide.md#exit-codes).";

/// How a command that ran to its end finished.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Completion {
    /// Everything done (exit 0).
    Done,
    /// Done, with failures already named on stderr (exit 1).
    WithFailures,
}

/// What goes to stdout.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Style {
    /// Lines for people.
    Text,
    /// Nothing but a command's product (a completion script, a batch plan).
    Quiet,
    /// One JSON object at the end.
    Json,
}

/// The state of stdout.
#[derive(Debug, Clone, PartialEq, Eq)]
enum Stdout {
    Open,
    /// The reader closed the pipe: nothing more is printed; not an error.
    ReaderGone,
    /// Writing failed otherwise (named on stderr once).
    Failed,
}

/// What the command did so far.
struct Record {
    command: String,
    written: Vec<PathBuf>,
    facts: Map<String, Value>,
    stdout: Stdout,
    /// The JSON object (or the final word) has been printed: nothing more.
    ended: bool,
    /// The interrupt handler ended the command ([`Console::interrupted`]) and
    /// is exiting the process with 130: the command's own thread must not exit.
    interrupted: bool,
}

/// A command's stdout and record; clones share them.
#[derive(Clone)]
pub(crate) struct Console {
    record: Arc<Mutex<Record>>,
    style: Style,
    /// No lines for people from this handle ([`Console::muted`]).
    muted: bool,
}

/// The `--json` object: the fields every command has, then its facts.
#[derive(Serialize)]
struct Summary<'a> {
    command: &'a str,
    exit_code: u8,
    written: Vec<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    error: Option<&'a str>,
    #[serde(flatten)]
    facts: &'a Map<String, Value>,
}

/// A path as JSON and messages show it (lossy where it is not UTF-8).
pub(crate) fn shown(path: &Path) -> String {
    path.display().to_string()
}

/// `text` safe to print on a terminal: control characters (an escape sequence, a newline that
/// would forge a line, a carriage return) and the bidirectional overrides that reorder what is
/// shown are written as `\u{1b}`, so a name read from a file cannot drive the terminal.
#[cfg_attr(not(feature = "capture"), allow(dead_code))] // the design commands' names
pub(crate) fn printable(text: &str) -> std::borrow::Cow<'_, str> {
    let hostile = |c: char| {
        c.is_control()
            || matches!(c, '\u{200e}' | '\u{200f}' | '\u{202a}'..='\u{202e}' | '\u{2066}'..='\u{2069}')
    };
    if !text.chars().any(hostile) {
        return std::borrow::Cow::Borrowed(text);
    }
    let escaped: String = text
        .chars()
        .map(|c| if hostile(c) { c.escape_unicode().to_string() } else { c.to_string() })
        .collect();
    std::borrow::Cow::Owned(escaped)
}

/// An error and the causes its message does not already hold, in one line.
pub(crate) fn message(error: &anyhow::Error) -> String {
    let mut text = error.to_string();
    for cause in error.chain().skip(1) {
        let cause = cause.to_string();
        if !text.contains(&cause) {
            text = format!("{text}: {cause}");
        }
    }
    text
}

impl Console {
    pub(crate) fn new(command: impl Into<String>, style: Style) -> Console {
        let record = Record {
            command: command.into(),
            written: Vec::new(),
            facts: Map::new(),
            stdout: Stdout::Open,
            ended: false,
            interrupted: false,
        };
        Console { record: Arc::new(Mutex::new(record)), style, muted: false }
    }

    /// A handle on the same record that prints no lines for people but
    /// keeps the progress bar and records files and facts as before: for a
    /// step of a command whose own lines say what matters (`where`'s
    /// captures, before its answer).
    #[cfg_attr(not(feature = "capture"), allow(dead_code))] // `where`
    pub(crate) fn muted(&self) -> Console {
        Console { muted: true, ..self.clone() }
    }

    fn record(&self) -> MutexGuard<'_, Record> {
        self.record.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// True under `--quiet` and `--json`: no progress bar, no lines.
    pub(crate) fn quiet(&self) -> bool {
        self.style != Style::Text
    }

    /// A line for people (not under `--quiet` or `--json`).
    pub(crate) fn say(&self, line: std::fmt::Arguments) {
        if self.style == Style::Text && !self.muted {
            self.write(format!("{line}\n").as_bytes());
        }
    }

    /// Text for people as it is, e.g. a table that ends in its own newline.
    #[cfg_attr(not(feature = "capture"), allow(dead_code))] // the captures' tables
    pub(crate) fn print(&self, text: &str) {
        if self.style == Style::Text && !self.muted {
            self.write(text.as_bytes());
        }
    }

    /// The command's product, printed also under `--quiet` (a completion
    /// script, a man page, a batch plan); under `--json` the caller records
    /// it as a fact instead.
    pub(crate) fn product(&self, bytes: &[u8]) {
        if self.style != Style::Json {
            self.write(bytes);
        }
    }

    /// Records a file the command wrote.
    pub(crate) fn wrote(&self, path: &Path) {
        self.record().written.push(path.to_path_buf());
    }

    /// Records one of the command's facts for `--json`.
    pub(crate) fn fact(&self, key: &str, value: impl Serialize) {
        let value = to_value(value);
        self.record().facts.insert(key.into(), value);
    }

    /// Records one entry of the list `key` (e.g. one per scenario).
    #[cfg_attr(not(feature = "capture"), allow(dead_code))] // the captures' scenarios
    pub(crate) fn fact_item(&self, key: &str, value: impl Serialize) {
        let value = to_value(value);
        match self.record().facts.entry(key).or_insert_with(|| Value::Array(Vec::new())) {
            Value::Array(list) => list.push(value),
            other => *other = Value::Array(vec![other.take(), value]),
        }
    }

    /// Records every field of `facts` (an object) as a fact.
    pub(crate) fn facts(&self, facts: impl Serialize) {
        if let Value::Object(map) = to_value(facts) {
            self.record().facts.extend(map);
        }
    }

    /// Writes on stdout unless the reader has gone or writing failed before.
    fn write(&self, bytes: &[u8]) {
        let mut record = self.record();
        if record.stdout != Stdout::Open || record.ended {
            return;
        }
        record.stdout = write_stdout(bytes);
    }

    /// Ends the command: says why on stderr if it failed, prints the JSON
    /// object under `--json`, and gives the exit code.
    pub(crate) fn end(&self, outcome: anyhow::Result<Completion>) -> ExitCode {
        if self.record().interrupted {
            // The interrupt handler has said what happened; its error is no news.
            wait_for_the_interrupt_exit();
        }
        let code = match &outcome {
            Ok(Completion::Done) => exit_code::DONE,
            Ok(Completion::WithFailures) => exit_code::WITH_FAILURES,
            // Files written before the failure are complete (every write is atomic).
            Err(_) if self.record().written.is_empty() => exit_code::NOTHING_DONE,
            Err(_) => exit_code::WITH_FAILURES,
        };
        let error = outcome.err().map(|error| message(&error));
        if let Some(error) = &error {
            eprintln!("error: {error}");
        }
        self.end_with(code, error.as_deref())
    }

    /// Ends the command with `code`: the JSON object under `--json` (with
    /// `error`, if given); the code is raised when stdout failed.
    pub(crate) fn end_with(&self, code: u8, error: Option<&str>) -> ExitCode {
        let mut record = self.record();
        if record.interrupted {
            drop(record);
            wait_for_the_interrupt_exit();
        }
        let mut code = code;
        if self.style == Style::Json {
            print_summary(&mut record, code, error);
        }
        if record.stdout == Stdout::Failed {
            code = code.max(stdout_failure_code(&record));
        }
        record.ended = true;
        ExitCode::from(code)
    }

    /// For the interrupt handler: prints the JSON object of an interrupted
    /// run (under `--json`) unless the command has already ended; true when
    /// the process should exit now.
    pub(crate) fn interrupted(&self, removed: usize, unfinished: &[std::path::PathBuf]) -> bool {
        let mut record = self.record();
        if record.ended {
            return false;
        }
        let why = interruption_message(removed, unfinished);
        eprintln!("{why}");
        if self.style == Style::Json {
            print_summary(&mut record, exit_code::INTERRUPTED, Some(&why));
        }
        record.ended = true;
        record.interrupted = true;
        true
    }

    /// Whether the interrupt handler ended the command and so owns the exit.
    #[cfg(test)]
    fn interrupt_owns_the_exit(&self) -> bool {
        self.record().interrupted
    }
}

/// Parks the command's thread for good once the interrupt handler has ended
/// the command: the handler exits the process with 130, and a second thread
/// calling `exit` at the same time is undefined (a run killed this way died
/// of a signal instead of exiting 130, once in 18 runs of the test
/// `an_interrupted_re_capture_says_its_folder_is_unfinished_and_the_analyzer_refuses_it`).
/// The decision is taken under the record's lock, so exactly one of the two
/// threads ends the command ([`Console::end_with`], [`Console::interrupted`]).
fn wait_for_the_interrupt_exit() -> ! {
    loop {
        std::thread::park();
    }
}

/// What an interruption left: temporaries removed, and either every earlier
/// output untouched or the capture folders left unfinished (issue 41: a
/// capture rewrites its folder in place, so "untouched" was untrue there).
pub(crate) fn interruption_message(removed: usize, unfinished: &[std::path::PathBuf]) -> String {
    if unfinished.is_empty() {
        return format!("interrupted: {removed} temporary files removed; earlier outputs are untouched");
    }
    let folders: Vec<String> = unfinished.iter().map(|dir| shown(dir)).collect();
    format!(
        "interrupted: {removed} temporary files removed; the capture in {} did not finish: the folder holds \
         part of it and no earlier capture's manifest.json, so it is marked unfinished ({}) and the analyzer \
         refuses it; capture again (or add --resume)",
        folders.join(", "),
        ufcsr::files::UNFINISHED_FILE
    )
}

/// A fact as JSON; a value that cannot be one (never for the facts recorded
/// here: paths go in as [`shown`] text) becomes its error message.
fn to_value(value: impl Serialize) -> Value {
    serde_json::to_value(value).unwrap_or_else(|error| Value::String(format!("(not JSON: {error})")))
}

/// The exit code when stdout failed: 1 when files were written, else 2.
fn stdout_failure_code(record: &Record) -> u8 {
    if record.written.is_empty() { exit_code::NOTHING_DONE } else { exit_code::WITH_FAILURES }
}

/// Prints the one JSON object (unless stdout has gone or failed before).
fn print_summary(record: &mut Record, code: u8, error: Option<&str>) {
    let summary = Summary {
        command: &record.command,
        exit_code: code,
        written: record.written.iter().map(|path| shown(path)).collect(),
        error,
        facts: &record.facts,
    };
    // A map of strings and JSON values always serializes.
    let mut text = serde_json::to_string(&summary).unwrap_or_default();
    text.push('\n');
    if record.stdout == Stdout::Open {
        record.stdout = write_stdout(text.as_bytes());
    }
}

/// Writes `bytes` on stdout and flushes: the reader gone is not an error; a
/// failure is named on stderr.
fn write_stdout(bytes: &[u8]) -> Stdout {
    let mut stdout = std::io::stdout().lock();
    match stdout.write_all(bytes).and_then(|()| stdout.flush()) {
        Ok(()) => Stdout::Open,
        Err(error) if error.kind() == std::io::ErrorKind::BrokenPipe => Stdout::ReaderGone,
        Err(error) => {
            eprintln!("error: cannot write to stdout: {error}");
            Stdout::Failed
        }
    }
}

/// `console.say(format_args!(…))` as a `println!`.
macro_rules! say {
    ($console:expr, $($arg:tt)*) => {
        $console.say(format_args!($($arg)*))
    };
}
pub(crate) use say;

#[cfg(test)]
mod tests {
    use super::{Console, Style, printable};

    #[test]
    fn exactly_one_thread_ends_an_interrupted_command() {
        // The handler first: it owns the exit, and the command's thread must not end it too.
        let console = Console::new("capture", Style::Quiet);
        assert!(console.interrupted(0, &[]));
        assert!(console.interrupt_owns_the_exit());
        assert!(!console.interrupted(0, &[]), "a second signal exits no second time");
        // The command first: the handler then leaves the exit to it.
        let console = Console::new("capture", Style::Quiet);
        let _ = console.end_with(0, None);
        assert!(!console.interrupted(0, &[]) && !console.interrupt_owns_the_exit());
    }

    #[test]
    fn names_print_without_driving_the_terminal() {
        assert_eq!(printable("bumper"), "bumper");
        assert_eq!(printable("a\u{1b}[2Jb\nc"), "a\\u{1b}[2Jb\\u{a}c");
        assert_eq!(printable("x\u{202e}y"), "x\\u{202e}y");
        assert_eq!(printable("Stoßfänger"), "Stoßfänger");
    }
}
