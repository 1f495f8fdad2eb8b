//! `ufcsr`: the whole command tree, like `git` — `ufcsr analyze ARCHIVE`,
//! `ufcsr merge …`, `ufcsr capture demo …`, `ufcsr study …`, `ufcsr
//! completions bash`, … (`ufcsr --help` lists them; see `ufcsr_cli`).

#![forbid(unsafe_code)]

fn main() -> std::process::ExitCode {
    ufcsr_cli::main(ufcsr_cli::Program::Ufcsr)
}
