//! The capture library's error type: every failure says what and where.
//!
//! Binaries turn these into messages with `anyhow`; the library never panics
//! on bad input.

use std::path::PathBuf;

/// Everything that can go wrong while capturing.
#[derive(Debug, thiserror::Error)]
pub enum CaptureError {
    /// An error from the shared `ufcsr` crate (manifest, atomic writes).
    #[error(transparent)]
    Ufcsr(#[from] ufcsr::Error),

    /// A file could not be read or written.
    #[error("{}: {source}", path.display())]
    Io { path: PathBuf, source: std::io::Error },

    /// A scene, scenario or mesh file has bad content.
    #[error("{}: {message}", path.display())]
    BadFile { path: PathBuf, message: String },

    /// Options or scene settings that cannot work.
    #[error("{0}")]
    BadOptions(String),

    /// The vehicle does not fit in the palette, or its UVs are unusable.
    #[error("unwrap: {0}")]
    Unwrap(String),

    /// No GPU adapter or device could be created, or the GPU failed.
    #[error("gpu: {0}")]
    Gpu(String),

    /// A PNG could not be encoded or decoded.
    #[error("{}: png: {message}", path.display())]
    Png { path: PathBuf, message: String },

    /// `error` came after `written` were written (each whole, atomically):
    /// the command line lists them and exits 1 ("done, with failures"), not
    /// 2 ("nothing done").
    #[error("{error}")]
    AfterWriting { written: Vec<PathBuf>, error: Box<CaptureError> },
}

impl CaptureError {
    /// An I/O error on `path`.
    pub fn io(path: impl Into<PathBuf>, source: std::io::Error) -> CaptureError {
        CaptureError::Io { path: path.into(), source }
    }

    /// A content problem in `path`.
    pub fn bad_file(path: impl Into<PathBuf>, message: impl Into<String>) -> CaptureError {
        CaptureError::BadFile { path: path.into(), message: message.into() }
    }
}

/// The capture library's result type.
pub type Result<T, E = CaptureError> = std::result::Result<T, E>;
