//! `ufcsr-capture`: the capture's commands under the grammar they always had
//! (`ufcsr-capture demo …`, `ufcsr-capture study …`), the same commands as
//! `ufcsr capture demo …`, `ufcsr study …` (see `ufcsr_cli`).

#![forbid(unsafe_code)]

fn main() -> std::process::ExitCode {
    ufcsr_cli::main(ufcsr_cli::Program::Capture)
}
