//! The library's error type: every failure names the file and the problem.
//!
//! Binaries turn these into messages with `anyhow` at their edge; the library
//! itself never panics on bad input.

use std::io;
use std::path::{Path, PathBuf};

/// Everything that can go wrong while reading inputs or writing results.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A file could not be opened, read, mapped or written. (The I/O error
    /// is part of the message rather than a `source`, so reports that print
    /// an error's chain do not repeat it.)
    #[error("{}: {cause}", path.display())]
    Io { path: PathBuf, cause: io::Error },

    /// A file is not a PNG we can decode (corrupt, truncated, not a PNG at all).
    #[error("{}: not a readable PNG: {message}", path.display())]
    Png { path: PathBuf, message: String },

    /// A PNG decodes but its colours cannot be mapped to 24-bit RGB exactly.
    #[error("{}: {message}", path.display())]
    UnsupportedPng { path: PathBuf, message: String },

    /// An image does not have the size it must have (PIdT vs palette, ...).
    #[error("{}: image is {found_width}×{found_height}, expected {expected_width}×{expected_height} ({what})", path.display())]
    WrongSize {
        path: PathBuf,
        what: String,
        expected_width: u32,
        expected_height: u32,
        found_width: u32,
        found_height: u32,
    },

    /// A palette image repeats a colour, so a pixel could not name one texel.
    #[error(
        "{}: palette colours must be unique, but {repeats} texels repeat an earlier colour; e.g. {color} at (x {x}, y {y}) first appears at (x {first_x}, y {first_y})",
        path.display()
    )]
    DuplicatePaletteColor {
        path: PathBuf,
        repeats: u64,
        color: crate::Color,
        x: u32,
        y: u32,
        first_x: u32,
        first_y: u32,
    },

    /// A legend, manifest or result file has bad content.
    #[error("{}: {message}", path.display())]
    BadFile { path: PathBuf, message: String },

    /// Options that cannot work together or are out of range.
    #[error("{0}")]
    BadOptions(String),

    /// The archive holds no image to analyse.
    #[error("{}: no PNG images found (looked for *.png below this folder)", path.display())]
    NoImages { path: PathBuf },

    /// `--strict` was given and an image failed.
    #[error("stopped at the first failed image (--strict): {0}")]
    Strict(Box<Error>),
}

impl Error {
    /// An I/O error on `path`.
    pub fn io(path: &Path, source: io::Error) -> Error {
        Error::Io { path: path.to_path_buf(), cause: source }
    }

    /// A content problem in `path`.
    pub fn bad_file(path: &Path, message: impl Into<String>) -> Error {
        Error::BadFile { path: path.to_path_buf(), message: message.into() }
    }
}

/// The library's result type.
pub type Result<T, E = Error> = std::result::Result<T, E>;
