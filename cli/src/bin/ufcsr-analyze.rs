//! `ufcsr-analyze`: an old name of `ufcsr`, kept for scripts and never
//! shown: `ufcsr-analyze ARCHIVE` runs `ufcsr analyze ARCHIVE`,
//! `ufcsr-analyze merge …` runs `ufcsr merge …` (see `ufcsr_cli`).

#![forbid(unsafe_code)]

fn main() -> std::process::ExitCode {
    ufcsr_cli::main(ufcsr_cli::Program::Analyze)
}
