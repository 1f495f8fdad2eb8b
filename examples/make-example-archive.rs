//! Writes the small synthetic example archive bundled under `fixtures/example/`.
//!
//! `cargo run --release --example make-example-archive -- fixtures/example`

use std::path::PathBuf;

use ufcsr::synthetic::{ArchiveSpec, write_archive};

fn main() -> anyhow::Result<()> {
    let dir: PathBuf =
        std::env::args_os().nth(1).map(PathBuf::from).unwrap_or_else(|| "fixtures/example".into());
    let spec = ArchiveSpec {
        frames: 6,
        eyes: 2,
        rows: 3,
        cols: 3,
        tile_width: 128,
        tile_height: 160,
        palette: (256, 256),
        object_block: 2,
        texels_per_pixel: (0.2, 2.0),
        parts: 8,
        compression: png::Compression::High,
        seed: 2026,
    };
    let summary = write_archive(&dir, &spec)?;
    println!(
        "{}: {} tiles ({} with the object), {} KiB",
        dir.display(),
        summary.tiles,
        summary.object_tiles,
        summary.bytes / 1024
    );
    Ok(())
}
