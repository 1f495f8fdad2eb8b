//! Shell completions and man pages for a command line, generated from the
//! same clap definitions as `--help`, so both binaries (`ufcsr-analyze` and
//! `ufcsr-capture`) document themselves the same way and never drift from
//! what they accept. Behind the `cli` feature: the library proper needs no
//! command-line crates.

use std::path::Path;

use ufcsr::{Error, Result, write_bytes_atomically};

/// Prints `program`'s completion script for `shell` on stdout (generated
/// whole first: clap_complete panics when stdout closes early, as under `| head`).
pub fn print_completions(shell: clap_complete::Shell, mut command: clap::Command, program: &str) {
    let mut script = Vec::new();
    clap_complete::generate(shell, &mut command, program, &mut script);
    // Nothing to report on a failed stdout: the reader has gone.
    let _ = write_stdout(&script);
}

/// Writes `bytes` on stdout; a reader that closed early (`| head`) is not an error.
fn write_stdout(bytes: &[u8]) -> std::io::Result<()> {
    match std::io::Write::write_all(&mut std::io::stdout(), bytes) {
        Err(error) if error.kind() == std::io::ErrorKind::BrokenPipe => Ok(()),
        other => other,
    }
}

/// Prints `program`'s man page on stdout, or, with `out`, writes
/// `PROGRAM.1` and one `PROGRAM-COMMAND.1` per subcommand into that folder;
/// returns the pages written.
pub fn write_man_pages(
    command: clap::Command,
    program: &str,
    out: Option<&Path>,
) -> Result<Vec<std::path::PathBuf>> {
    let render = |page: clap::Command, to: &Path| -> Result<Vec<u8>> {
        let mut roff = Vec::new();
        clap_mangen::Man::new(page).render(&mut roff).map_err(|e| Error::io(to, e))?;
        Ok(roff)
    };
    let Some(dir) = out else {
        let roff = render(command, Path::new("stdout"))?;
        write_stdout(&roff).map_err(|e| Error::io(Path::new("stdout"), e))?;
        return Ok(Vec::new());
    };
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    let mut pages = vec![(format!("{program}.1"), command.clone())];
    for sub in command.get_subcommands().filter(|sub| sub.get_name() != "help") {
        // clap names are 'static; a handful of bytes, once per process.
        let name: &'static str = Box::leak(format!("{program}-{}", sub.get_name()).into_boxed_str());
        pages.push((format!("{name}.1"), sub.clone().name(name)));
    }
    let mut written = Vec::new();
    for (file, page) in pages {
        let path = dir.join(file);
        write_bytes_atomically(&path, &render(page, &path)?)?;
        written.push(path);
    }
    Ok(written)
}
