//! Shell completions and man pages, generated from the same clap
//! definitions as `--help` for whichever program runs (`ufcsr completions
//! bash`, `ufcsr man`, …), so each documents itself and never
//! drifts from what it accepts. Under `--json` the script or page goes into
//! the one JSON object (`script`, `page`) instead of stdout.

use std::path::{Path, PathBuf};

use anyhow::Context;
use clap::Subcommand;

use crate::console::{Completion, Console};

/// The commands that document the program.
#[derive(Subcommand)]
pub(crate) enum DocsCommand {
    /// Print a shell completion script (bash, zsh, fish, elvish, powershell) on stdout.
    ///
    /// Example: `ufcsr completions bash > ~/.local/share/bash-completion/completions/ufcsr`
    /// (the same for ufcsr and ufcsr capture)
    Completions {
        /// The shell: bash, zsh, fish, elvish or powershell.
        #[arg(value_enum)]
        shell: clap_complete::Shell,
    },
    /// Print the man page (roff) on stdout, or write one page per command into --out.
    ///
    /// Example: `ufcsr man --out ~/.local/share/man/man1` (then `man ufcsr-merge`)
    Man {
        /// Write PROGRAM.1 and one PROGRAM-COMMAND.1 per command (PROGRAM-COMMAND-SUBCOMMAND.1
        /// below it) into this folder (default: print the main page on stdout).
        #[arg(long, short, value_name = "DIR")]
        out: Option<PathBuf>,
    },
}

impl DocsCommand {
    /// The command's name, as `--json` reports it.
    pub(crate) fn name(&self) -> &'static str {
        match self {
            DocsCommand::Completions { .. } => "completions",
            DocsCommand::Man { .. } => "man",
        }
    }
}

/// Runs `docs` for `command`, the tree of the program named `program`.
pub(crate) fn run(
    docs: DocsCommand,
    command: clap::Command,
    program: &str,
    console: &Console,
) -> anyhow::Result<Completion> {
    match docs {
        DocsCommand::Completions { shell } => {
            let script = completions(shell, command, program);
            console.fact("script", String::from_utf8_lossy(&script));
            console.product(&script);
        }
        DocsCommand::Man { out: None } => {
            let page = render(command)?;
            console.fact("page", String::from_utf8_lossy(&page));
            console.product(&page);
        }
        DocsCommand::Man { out: Some(dir) } => {
            for path in write_man_pages(command, program, &dir, console)? {
                eprintln!("wrote {}", path.display());
            }
        }
    }
    Ok(Completion::Done)
}

/// `program`'s completion script for `shell`.
fn completions(shell: clap_complete::Shell, mut command: clap::Command, program: &str) -> Vec<u8> {
    let mut script = Vec::new();
    clap_complete::generate(shell, &mut command, program, &mut script);
    script
}

/// One man page in roff.
fn render(page: clap::Command) -> anyhow::Result<Vec<u8>> {
    let mut roff = Vec::new();
    clap_mangen::Man::new(page).render(&mut roff).context("rendering the man page")?;
    Ok(roff)
}

/// Every page of `command` (named `name`) and of the commands below it, as
/// (page name, command).
fn pages(command: &clap::Command, name: &str) -> Vec<(String, clap::Command)> {
    // clap names are 'static; a handful of bytes, once per process.
    let title: &'static str = Box::leak(name.to_string().into_boxed_str());
    let mut found = vec![(name.to_string(), command.clone().name(title))];
    for sub in command.get_subcommands().filter(|sub| sub.get_name() != "help") {
        found.extend(pages(sub, &format!("{name}-{}", sub.get_name())));
    }
    found
}

/// Writes `PROGRAM.1` and one page per command into `dir`; returns the pages.
fn write_man_pages(
    command: clap::Command,
    program: &str,
    dir: &Path,
    console: &Console,
) -> anyhow::Result<Vec<PathBuf>> {
    ufcsr::files::create_output_dir(dir)?;
    let mut written = Vec::new();
    for (name, page) in pages(&command, program) {
        let path = dir.join(format!("{name}.1"));
        ufcsr::files::write_bytes_atomically(&path, &render(page)?)?;
        console.wrote(&path);
        written.push(path);
    }
    Ok(written)
}
