//! The typed file formats the crates exchange: one file per format, each a
//! serde type that also derives its JSON Schema (`schemars`), so a file is
//! written and read back through one definition and never by string keys.

pub mod placement;
