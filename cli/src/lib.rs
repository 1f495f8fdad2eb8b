//! The ufcsr command line: one command tree for the analyzer (`ufcsr`
//! library) and the capture (`ufcsr_capture`, behind the default feature
//! `capture`), reached through three thin binaries — `ufcsr` (the whole
//! tree), `ufcsr analyze` and `ufcsr capture` (the same commands under the
//! grammar they always had). Everything a command line needs lives here and
//! nowhere else: the clap definitions ([`program`], `analyze/`, `capture/`,
//! with the options more than one command shares in [`options`] and the
//! libraries' enums as choices in [`choices`]), one way to say what was done
//! ([`console`]: text, `--quiet`, or exactly one JSON object), one exit-code
//! map, the interrupt handler ([`interrupt`]), the progress bar
//! ([`progress`]), completions and man pages ([`command_docs`]). Parsing goes
//! one way: clap types here become the libraries' plain option structs.

#![deny(unsafe_code)]
// Unit tests may use std::fs directly (fixtures); production code goes through
// the file layer (clippy.toml, docs/reliability.md).
#![cfg_attr(test, allow(clippy::disallowed_methods, clippy::disallowed_types))]

mod advanced;
mod analyze;
#[cfg(feature = "capture")]
mod capture;
mod choices;
mod command_docs;
mod console;
mod interrupt;
mod options;
mod program;
mod progress;

pub use console::{Completion, EXIT_STATUS_HELP, exit_code};
pub use program::{Program, main};
