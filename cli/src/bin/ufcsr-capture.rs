//! `ufcsr-capture`: record UFCSR archives of a vehicle approaching a pedestrian.
//!
//! Thin edge: parse the command line and hand it to [`cli::run`] (one
//! `run_*` per subcommand), then turn errors into an exit code, the same
//! codes as `ufcsr-analyze`: 0 done; 1 done, but with failures
//! ([`cli::DoneWithFailures`], e.g. `verify` finding stray pixels); 2 nothing
//! done (bad options — clap's usage errors too —, unreadable inputs, a failed
//! capture, which writes no manifest); 130 interrupted.

#[path = "../capture/mod.rs"]
mod cli;
#[path = "../command_docs.rs"]
mod command_docs;

use std::process::ExitCode;

use clap::Parser;

/// A private runtime folder for Mesa, removed when the program ends.
///
/// Mesa's window-system probe prints `error: XDG_RUNTIME_DIR is invalid or
/// not set` (twice) while it looks for a display, which a headless capture
/// never uses; a run without a valid `XDG_RUNTIME_DIR` gets its own 0700
/// folder, so the message a user sees is only ever about their capture.
struct PrivateRuntimeDir(Option<std::path::PathBuf>);

impl PrivateRuntimeDir {
    fn create() -> PrivateRuntimeDir {
        let valid =
            std::env::var_os("XDG_RUNTIME_DIR").is_some_and(|dir| std::path::Path::new(&dir).is_dir());
        if valid || cfg!(not(unix)) {
            return PrivateRuntimeDir(None);
        }
        let dir = std::env::temp_dir().join(format!("ufcsr-runtime-{}", std::process::id()));
        let mut builder = std::fs::DirBuilder::new();
        #[cfg(unix)]
        std::os::unix::fs::DirBuilderExt::mode(&mut builder, 0o700);
        if builder.create(&dir).is_err() {
            return PrivateRuntimeDir(None);
        }
        // SAFETY: main does this right after parsing the command line, before
        // any other thread exists (the interrupt handler and the GPU's
        // threads start later).
        unsafe { std::env::set_var("XDG_RUNTIME_DIR", &dir) };
        ufcsr::remove_on_interrupt(&dir);
        PrivateRuntimeDir(Some(dir))
    }
}

impl Drop for PrivateRuntimeDir {
    fn drop(&mut self) {
        if let Some(dir) = &self.0 {
            let _ = std::fs::remove_dir_all(dir);
        }
    }
}

fn main() -> ExitCode {
    // Parsing may exit (--help, usage errors) and so comes first: the
    // runtime folder is removed when main returns, or by the interrupt handler.
    let cli = cli::Cli::parse();
    let _runtime_dir = PrivateRuntimeDir::create();
    ufcsr::remove_temporaries_on_interrupt();
    let (json, command) = (cli.json, cli.command_name());
    match cli::run(cli) {
        Ok(()) => {
            if json {
                println!("{}", cli::json_summary(command, 0, None));
            }
            ExitCode::SUCCESS
        }
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
            let code = if error.downcast_ref::<cli::DoneWithFailures>().is_some() { 1 } else { 2 };
            if json && code == 1 {
                cli::fact("failures", &message);
            }
            if json {
                // Done with failures still wrote its files; nothing done wrote none.
                let summary = cli::json_summary(command, code, (code == 2).then_some(message.as_str()));
                println!("{summary}");
            }
            ExitCode::from(code)
        }
    }
}
