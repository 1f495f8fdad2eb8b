//! The files the two crates exchange, as types: one file per format, each a
//! set of serde types (`Serialize`, `Deserialize`, `schemars::JsonSchema`)
//! that every writer and every reader uses, so a field is spelt once.
//! (The `format` helper's branch adds the infrastructure and the other
//! formats; this branch adds [`observers`].)

pub mod observers;
