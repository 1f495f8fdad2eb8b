//! `ufcsr-analyze`: the analyzer's commands under the grammar they always
//! had (`ufcsr-analyze ARCHIVE`, `ufcsr-analyze merge …`), the same commands
//! as `ufcsr analyze ARCHIVE`, `ufcsr merge …` (see `ufcsr_cli`).

#![forbid(unsafe_code)]

fn main() -> std::process::ExitCode {
    ufcsr_cli::main(ufcsr_cli::Program::Analyze)
}
