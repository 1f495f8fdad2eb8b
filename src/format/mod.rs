//! The files the two crates exchange, as serde types: one file per format, each
//! deriving `Serialize`, `Deserialize` and `schemars::JsonSchema`, so a writer and
//! its readers share one definition and the schema can be generated from it.

mod study;

pub use study::{ErrorVsExact, ExactReference, ShareError, Study, StudyPick, StudyRow};
