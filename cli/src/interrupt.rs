//! Ctrl-C and SIGTERM: every program removes the temporary files and staging
//! folders its run has open (earlier outputs stay whole: every write is
//! atomic), says so — or, for a capture rewriting its archive folder in
//! place, that the folder is left unfinished and marked so (issue 41) —
//! prints the one JSON object under `--json`, and exits 130.
//! The libraries only keep the list of temporaries ([`ufcsr::files::remove_temporaries`]);
//! catching the signal is the command line's.

use crate::console::{Console, exit_code};

/// Installs the handler for this process's run, reporting through `console`.
pub(crate) fn remove_temporaries_on_interrupt(console: &Console) {
    let console = console.clone();
    let installed = ctrlc::set_handler(move || {
        let removed = ufcsr::files::remove_temporaries();
        if console.interrupted(removed, &ufcsr::files::unfinished_outputs()) {
            std::process::exit(i32::from(exit_code::INTERRUPTED));
        }
    });
    if let Err(error) = installed {
        eprintln!("warning: no interrupt handler ({error}); an interrupted run may leave temporary files");
    }
}
