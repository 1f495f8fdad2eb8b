//! The identity of an analysed archive, recorded in every result so that
//! `merge` can refuse shards of different archives that happen to sit under
//! the same path (two captures analysed in turn at `run/archive`).
//!
//! It is a 64-bit FNV-1a digest of what decides the counts: the manifest's
//! bytes (with it: the tile list, frames and eyes), else the sorted tile
//! names with their sizes, and the palette, PIdT and legend files' bytes.
//! Not a cryptographic hash: it tells accidents apart, not forgeries.

use std::path::Path;

use crate::archive::archive_reader::Archive;

/// FNV-1a, 64 bits.
struct Digest(u64);

impl Digest {
    fn new() -> Digest {
        Digest(0xcbf2_9ce4_8422_2325)
    }

    fn add(&mut self, bytes: &[u8]) {
        for &byte in bytes {
            self.0 = (self.0 ^ u64::from(byte)).wrapping_mul(0x0000_0100_0000_01b3);
        }
        // A separator, so ("ab", "c") and ("a", "bc") differ.
        self.0 = (self.0 ^ 0xff).wrapping_mul(0x0000_0100_0000_01b3);
    }

    /// Adds a file's bytes, or a marker when it cannot be read (the
    /// analysis itself reports why).
    fn add_file(&mut self, path: &Path) {
        match crate::files::read_limited(path, crate::files::IMAGE_LIMIT) {
            Ok(bytes) => self.add(&bytes),
            Err(_) => self.add(b"unreadable"),
        }
    }
}

/// The archive's identity, 16 hex digits: `manifest` is the manifest file
/// when one was used; `files` the palette image, PIdT and legend read.
pub(crate) fn archive_identity(manifest: Option<&Path>, archive: &Archive, files: &[&Path]) -> String {
    let mut digest = Digest::new();
    match manifest {
        Some(path) => {
            digest.add(b"manifest");
            digest.add_file(path);
        }
        None => {
            digest.add(b"folder");
            for image in &archive.images {
                digest.add(image.name.as_bytes());
                let size = std::fs::metadata(&image.path).map_or(u64::MAX, |m| m.len());
                digest.add(&size.to_le_bytes());
            }
        }
    }
    for file in files {
        digest.add_file(file);
    }
    format!("{:016x}", digest.0)
}
