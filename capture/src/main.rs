//! `ufcsr-capture`: record UFCSR archives of a vehicle approaching a pedestrian.
//!
//! Thin edge: parse the command line and hand it to [`cli::run`] (one
//! `run_*` per subcommand), then turn errors into an exit code, the same
//! codes as `ufcsr-analyze`: 0 done; 1 done, but with failures
//! ([`cli::DoneWithFailures`], e.g. `verify` finding stray pixels); 2 nothing
//! done (bad options — clap's usage errors too —, unreadable inputs, a failed
//! capture, which writes no manifest); 130 interrupted.

mod cli;

use std::process::ExitCode;

use clap::Parser;

fn main() -> ExitCode {
    ufcsr::remove_temporaries_on_interrupt();
    match cli::run(cli::Cli::parse()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) => {
            // Library errors already name their cause; only add causes that
            // are not in the message yet (anyhow context, wrapped errors).
            let mut message = error.to_string();
            for cause in error.chain().skip(1) {
                let text = cause.to_string();
                if !message.contains(&text) {
                    message = format!("{message}: {text}");
                }
            }
            eprintln!("error: {message}");
            if error.downcast_ref::<cli::DoneWithFailures>().is_some() {
                ExitCode::from(1)
            } else {
                ExitCode::from(2)
            }
        }
    }
}
