//! The files the two crates exchange, as types: one file per format, each a
//! set of serde types that every writer and every reader uses, so that a
//! field is spelt once and a file that is present but malformed is an error
//! naming the file and the field — never a string-key look-up with a silent
//! default. Each document carries a schema string (`ufcsr-manifest/1`,
//! `ufcsr-result/1`…) and an unknown version is refused by name
//! ([`check_version`]).
//!
//! The JSON Schemas in `docs/schemas/` are generated from these types
//! (schemars) and never edited by hand: [`SCHEMAS`] lists every
//! (schema file, document type) pair, and the test
//! `tests/it/schemas.rs::committed_schemas_equal_the_generated_ones` fails
//! when a committed schema differs from the generated one. Regenerate them
//! with
//!
//! ```text
//! UFCSR_WRITE_SCHEMAS=1 cargo test -p ufcsr --test it schemas::committed
//! ```
//!
//! This module sits at the bottom of the crate: it uses only
//! [`crate::error`], [`crate::color`], serde and schemars, so that both the
//! analyzer's readers and the capture's writers can depend on it.
//!
//! ## Adding a format
//! Add `src/format/NAME.rs` (a `//!` doc, types deriving `Serialize`,
//! `Deserialize` and `schemars::JsonSchema`, a `pub const …_SCHEMA: &str`
//! version string checked with [`check_version`] where it is read), declare
//! it below with `pub mod NAME;`, and register its document type with one
//! line in [`SCHEMAS`], e.g.
//! `Format::of::<study::StudyFile>("study.schema.json"),`; then regenerate
//! the schemas with the command above.

pub(crate) mod design;
pub(crate) mod manifest;
pub(crate) mod observers;
pub(crate) mod placement;
pub(crate) mod placement_csv;
pub(crate) mod result;
pub(crate) mod study;
pub(crate) mod timings;

pub use design::{
    BestPlacement, BodyDimsOverride, CandidateSummary, CandidateValue, CellLevels, Crossing,
    DESIGN_RESULT_SCHEMA, DESIGN_SCHEMA, DESIGN_TASK_SCHEMA, Design, DesignMeasure, DesignPopulation,
    DesignResult, DesignTask, GroupSummary, LevelEffect, MainEffect, MeanInterval, ScenarioLevel,
    ScenarioSource, StreetScenario, TrafficKind, TrafficLevel, UnitValues, VehicleLevel,
};
pub use manifest::{
    CaptureRecord, DemoScenario, EyePose, EyeProjectionRecord, FollowRecord, FrameEntry, LabelsRecord,
    MeasuredRecord, OccluderPose, PaintedByPart, PedestrianSetting, PoseRecord, RigRecord, RigSettings,
    ScenarioRecord, SceneRecord, ShardRecord, TrackKey, TrafficRecord, UnwrapRecord,
};
pub use manifest::{MANIFEST_SCHEMA_RGBA32, TexelIds};
pub use observers::{
    CoarserCapture, DEFAULT_TRUNCATE_SD, DisplayOverObservers, OBSERVERS_SCHEMA, ObserverDisplayRecord,
    ObserverDisplays, ObserverPlace, ObserverPopulation, ObserverRecord, ObserverSampling, ObserverStudy,
    PartOverObservers, PopulationValue, ResolutionCheck, StatureGroup, US_ADULTS_SOURCE,
};
pub use placement::{
    ArchiveRecord, CandidateRecord, CombinationRecord, ExcludedRecord, ExclusionReason, ExposureRecord,
    MemberRecord, PlacementDocument, RunnerUpRecord, SensitivityRecord, SensitivitySet, ThresholdsRecord,
    UncertaintyRecord,
};
pub use placement_csv::{PLACEMENT_FRAMES_OPTIONAL, PLACEMENT_TABLE_LIMIT, PlacementFrameRow};
pub use result::{
    ColorTexels, CountMeasure, DedupeReport, FailedImage, ImageCounts, PartMeasure, PixelCounts, ResultFile,
    Settings, StrayImage, TexelCountsJson, TrimReport, UnlabelledReport,
};
pub use timings::{TIMINGS_SCHEMA, TimingsFile};

pub use study::{ErrorVsExact, ExactReference, ShareError, Study, StudyPick, StudyRow};

use std::path::Path;

use schemars::{JsonSchema, Schema};

use crate::error::{Error, Result};

/// One generated JSON Schema: the file it is written to in `docs/schemas/`
/// and the function that generates it from its document type.
#[derive(Clone, Copy)]
pub struct Format {
    /// File name in `docs/schemas/`, e.g. `manifest.schema.json`.
    pub schema_file: &'static str,
    /// Generates the schema (draft 2020-12).
    pub generate: fn() -> Schema,
}

impl Format {
    /// The entry for document type `T`, written to `schema_file`.
    pub const fn of<T: JsonSchema>(schema_file: &'static str) -> Format {
        Format { schema_file, generate: generate::<T> }
    }

    /// The schema as committed: pretty JSON and a final newline.
    pub fn text(&self) -> String {
        let schema = (self.generate)();
        let mut text = serde_json::to_string_pretty(&schema).unwrap_or_default();
        text.push('\n');
        text
    }
}

/// Every generated schema. One line per format (see the module documentation).
pub const SCHEMAS: &[Format] = &[
    Format::of::<manifest::Manifest>("manifest.schema.json"),
    Format::of::<result::ResultFile>("result.schema.json"),
    Format::of::<timings::TimingsFile>("timings.schema.json"),
    Format::of::<study::Study>("study.schema.json"),
    Format::of::<placement::PlacementDocument>("placement.schema.json"),
    Format::of::<observers::ObserverStudy>("observers.schema.json"),
    Format::of::<design::Design>("design.schema.json"),
    Format::of::<design::DesignTask>("design-task.schema.json"),
    Format::of::<design::DesignResult>("design-result.schema.json"),
];

/// The schema of `T`, draft 2020-12, with `$id` under the project's docs.
fn generate<T: JsonSchema>() -> Schema {
    let generator = schemars::generate::SchemaSettings::draft2020_12().into_generator();
    generator.into_root_schema_for::<T>()
}

/// Refuses a document whose schema string is not `expected` (such as
/// `ufcsr-manifest/1`): another version of the same format as one this
/// ufcsr does not know, anything else as not that format. `path` names the
/// file in the message.
pub fn check_version(path: &Path, found: &str, expected: &str) -> Result<()> {
    if found == expected {
        return Ok(());
    }
    let family = expected.split_once('/').map_or(expected, |(family, _)| family);
    let noun = family.strip_prefix("ufcsr-").unwrap_or(family);
    let hint = if found.starts_with(&format!("{family}/")) {
        format!("a version this ufcsr does not know (it reads {expected}); update ufcsr")
    } else {
        format!("not a ufcsr {noun} (expected {expected})")
    };
    Err(Error::bad_file(path, format!("schema {found:?}: {hint}")))
}

/// Parses a JSON document of type `T`, naming the file and, on a malformed
/// field, its path in the document (`rig.settings.fps: invalid type…`).
pub fn parse_json<T: serde::de::DeserializeOwned>(path: &Path, bytes: &[u8], what: &str) -> Result<T> {
    let mut deserializer = serde_json::Deserializer::from_slice(bytes);
    let value = serde_path_to_error::deserialize(&mut deserializer).map_err(|error| {
        let field = error.path().to_string();
        let place = if field == "." { String::new() } else { format!("{field}: ") };
        Error::bad_file(path, format!("invalid {what}: {place}{}", error.inner()))
    })?;
    deserializer.end().map_err(|error| Error::bad_file(path, format!("invalid {what}: {error}")))?;
    Ok(value)
}

/// For `skip_serializing_if` of flags written only when set.
pub(crate) fn is_false(value: &bool) -> bool {
    !*value
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn versions_are_refused_by_name() {
        let path = Path::new("manifest.json");
        assert!(check_version(path, "ufcsr-manifest/1", "ufcsr-manifest/1").is_ok());
        let newer = check_version(path, "ufcsr-manifest/2", "ufcsr-manifest/1").unwrap_err().to_string();
        assert!(newer.contains("manifest.json") && newer.contains("does not know"), "{newer}");
        let other = check_version(path, "ufcsr-result/1", "ufcsr-manifest/1").unwrap_err().to_string();
        assert!(other.contains("not a ufcsr manifest"), "{other}");
    }

    #[test]
    fn every_registered_schema_generates_and_names_a_distinct_file() {
        let mut files = std::collections::BTreeSet::new();
        for format in SCHEMAS {
            assert!(format.schema_file.ends_with(".schema.json"), "{}", format.schema_file);
            assert!(files.insert(format.schema_file), "{} registered twice", format.schema_file);
            assert!(format.text().contains("\"$schema\""), "{}", format.schema_file);
        }
    }
}
