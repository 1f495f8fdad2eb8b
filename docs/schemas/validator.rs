//! Validating a document against the schemas in this folder, with the `boon`
//! crate: shared by the analyzer's and the capture's schema tests (each
//! includes this file with `#[path]`), and an example for Rust users of the
//! formats.

#![allow(dead_code)]

use std::path::Path;

use serde_json::Value;

/// A JSON file, parsed; panics naming the file.
pub fn read_json(path: &Path) -> Value {
    let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    serde_json::from_slice(&bytes).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// A compiled schema (checked against draft 2020-12's meta-schema while
/// compiling).
pub struct Schema {
    schemas: boon::Schemas,
    index: boon::SchemaIndex,
}

impl Schema {
    /// `schema_file` read and compiled.
    pub fn load(schema_file: &Path) -> Schema {
        let location = format!("file:///{}", schema_file.file_name().unwrap().to_string_lossy());
        let mut compiler = boon::Compiler::new();
        compiler.add_resource(&location, read_json(schema_file)).expect("add schema");
        let mut schemas = boon::Schemas::new();
        let index = compiler
            .compile(&location, &mut schemas)
            .unwrap_or_else(|e| panic!("{}: {e:#}", schema_file.display()));
        Schema { schemas, index }
    }

    /// `Err` with every violation, each with its location.
    pub fn check(&self, document: &Value) -> Result<(), String> {
        self.schemas.validate(document, self.index).map_err(|error| format!("{error:#}"))
    }

    /// Panics with every violation when `document` (`what`, for the message)
    /// does not match.
    pub fn assert_valid(&self, document: &Value, what: &str) {
        if let Err(error) = self.check(document) {
            panic!("{what} does not match its schema:\n{error}");
        }
    }
}
