//! `ufcsr-capture`: an old name of `ufcsr`, kept for scripts and never
//! shown: `ufcsr-capture demo …` runs `ufcsr capture demo …`,
//! `ufcsr-capture study …` runs `ufcsr study …` (see `ufcsr_cli`).

#![forbid(unsafe_code)]

fn main() -> std::process::ExitCode {
    ufcsr_cli::main(ufcsr_cli::Program::Capture)
}
