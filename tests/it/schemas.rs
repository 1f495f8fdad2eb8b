//! The published JSON Schemas (`docs/schemas/`) hold for what ufcsr really
//! writes and reads: `result.json` from `ufcsr::analyze` and `merge` in the
//! settings that change its shape, and the bundled example's manifest. The
//! schemas are closed where the format is fixed, so a new or renamed field in
//! the code fails here until the schema (and `docs/archive-format.md`) says so.

use std::path::{Path, PathBuf};

use serde_json::{Value, json};
use ufcsr::{
    AnalyzeOptions, Dedupe, HeatmapOptions, Manifest, Scale, Shard, TrimMode, analyze, output::write_results,
};

fn workspace_file(relative: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(relative)
}

fn example() -> PathBuf {
    workspace_file("fixtures/example")
}

#[path = "../../docs/schemas/validator.rs"]
pub(crate) mod validator;

use validator::{Schema, read_json};

fn result_schema() -> Schema {
    Schema::load(&workspace_file("docs/schemas/result.schema.json"))
}

fn manifest_schema() -> Schema {
    Schema::load(&workspace_file("docs/schemas/manifest.schema.json"))
}

/// A change made to a valid document.
type Edit = fn(&mut Value);

/// Analyses the example with `options` into `out` and reads back result.json.
fn analyse_example(options: AnalyzeOptions, out: &Path) -> Value {
    let mut analysis = analyze(&options, None).expect("analysis of the example");
    write_results(&mut analysis, out).expect("write results");
    read_json(&out.join("result.json"))
}

#[test]
fn example_result_json_matches_the_result_schema() {
    // As `ufcsr analyze fixtures/example` runs it: manifest, PIdT, frames.csv
    // on, so `resolution` and `measures` are there.
    let dir = tempfile::tempdir().unwrap();
    let options = AnalyzeOptions { archive: example(), frames: true, ..AnalyzeOptions::default() };
    let result = analyse_example(options, dir.path());
    assert!(result.get("measures").is_some() && result.get("resolution").is_some());
    assert!(result["parts"].as_array().is_some_and(|parts| !parts.is_empty()));
    result_schema().assert_valid(&result, "the example's result.json");
}

#[test]
fn result_json_of_every_shape_matches_the_result_schema() {
    let schema = result_schema();
    let dir = tempfile::tempdir().unwrap();
    // Deduplicated per eye-frame, a shard, a byte threshold (empty-tile
    // candidates listed), a log scale with a fixed top: `dedupe`,
    // `settings.shard`, `trim.empty_tiles` and `heatmap_max` filled in.
    let mut shards = Vec::new();
    for index in 0..2 {
        let options = AnalyzeOptions {
            archive: example(),
            dedupe: Dedupe::Frame,
            shard: Some(Shard::new(index, 2).unwrap()),
            trim: TrimMode::Bytes(30_000),
            heatmap: HeatmapOptions { scale: Scale::Log, max: Some(5) },
            ..AnalyzeOptions::default()
        };
        let out = dir.path().join(format!("shard-{index}"));
        let result = analyse_example(options, &out);
        assert!(result["dedupe"].is_object() && result["settings"]["shard"].is_object());
        assert!(!result["settings"]["trim"]["empty_tiles"].as_array().unwrap().is_empty());
        schema.assert_valid(&result, &format!("shard {index}'s result.json"));
        shards.push(out.join("result.json"));
    }
    // The shards merged: no `shard` any more.
    let mut merged = ufcsr::merge_results(&shards).expect("merge");
    write_results(&mut merged, &dir.path().join("merged")).expect("write merged");
    let result = read_json(&dir.path().join("merged/result.json"));
    assert!(result["settings"].get("shard").is_none());
    schema.assert_valid(&result, "the merged result.json");
    // Without the manifest: no PIdT, so no parts and `unlabelled` null; the
    // PIdT-sized PNG is left out (`images.skipped`).
    let options = AnalyzeOptions {
        archive: example(),
        ignore_manifest: true,
        exclude: vec![example().join("results")],
        frames: true,
        ..AnalyzeOptions::default()
    };
    let result = analyse_example(options, &dir.path().join("no-manifest"));
    assert!(result["unlabelled"].is_null() && result["images"]["skipped"] == json!(1));
    schema.assert_valid(&result, "the result.json of the example without its manifest");
}

#[test]
fn result_schema_refuses_unknown_fields_other_versions_and_zero_counts() {
    let schema = result_schema();
    let dir = tempfile::tempdir().unwrap();
    let valid =
        analyse_example(AnalyzeOptions { archive: example(), ..AnalyzeOptions::default() }, dir.path());
    schema.assert_valid(&valid, "the example's result.json");
    let edits: [(&str, Edit); 5] = [
        ("an unknown top-level field", |r| r["elapsed_seconds"] = json!(1.5)),
        ("an unknown field in a part", |r| r["parts"][0]["rank"] = json!(1)),
        ("another schema version", |r| r["schema"] = json!("ufcsr-result/2")),
        ("a listed texel with count 0", |r| r["texel_counts"]["count"][0] = json!(0)),
        ("a lower-case colour", |r| r["settings"]["background"][0] = json!("#000fff")),
    ];
    for (what, edit) in edits {
        let mut edited = valid.clone();
        edit(&mut edited);
        assert!(schema.check(&edited).is_err(), "the result schema accepted {what}");
    }
}

#[test]
fn example_manifest_matches_the_manifest_schema() {
    let manifest = read_json(&example().join("manifest.json"));
    manifest_schema().assert_valid(&manifest, "fixtures/example/manifest.json");
}

/// A hand-written manifest as docs/archive-format.md shows it.
fn hand_written_manifest() -> Value {
    json!({
        "schema": "ufcsr-manifest/1",
        "palette": {"canonical": [4096, 4096]},
        "pidt": "pidt.png",
        "parts": "parts.csv",
        "background": ["#000FFF"],
        "tiles": [
            {"file": "tiles/f0000_left_r2_c3.png", "frame": 0, "eye": "left", "row": 2, "col": 3,
             "time_s": 0.0, "distance_m": 41.7},
            {"frame": 0, "eye": "left", "row": 0, "col": 0, "empty": true}
        ]
    })
}

#[test]
fn manifest_schema_agrees_with_the_analyzer_on_hand_written_manifests() {
    let schema = manifest_schema();
    let variants: [(&str, Edit, bool); 9] = [
        ("as documented", |_| {}, true),
        ("only tiles", |m| *m = json!({"tiles": m["tiles"].clone()}), true),
        (
            "numbered eyes and a field of its own",
            |m| {
                m["tiles"][0]["eye"] = json!(0);
                m["tiles"][1]["eye"] = json!(1);
                m["camera"] = json!("unity");
            },
            true,
        ),
        ("a palette image", |m| m["palette"] = json!("palette.png"), true),
        ("a tile with neither file nor empty", |m| m["tiles"][1]["empty"] = json!(false), false),
        ("an empty tile that names a file", |m| m["tiles"][1]["file"] = json!("tiles/x.png"), false),
        ("a file outside the archive", |m| m["tiles"][0]["file"] = json!("../x.png"), false),
        ("a third eye number", |m| m["tiles"][0]["eye"] = json!(2), false),
        ("another schema version", |m| m["schema"] = json!("ufcsr-manifest/2"), false),
    ];
    for (what, edit, accepted) in variants {
        let mut manifest = hand_written_manifest();
        edit(&mut manifest);
        let by_schema = schema.check(&manifest);
        let by_analyzer = Manifest::parse(Path::new("manifest.json"), manifest.to_string().as_bytes());
        assert_eq!(by_schema.is_ok(), accepted, "schema on a manifest with {what}: {by_schema:?}");
        assert_eq!(
            by_analyzer.is_ok(),
            accepted,
            "analyzer on a manifest with {what}: {:?}",
            by_analyzer.err()
        );
    }
}

/// The command that regenerates `docs/schemas/` from the types in `src/format/`.
const REGENERATE: &str = "UFCSR_WRITE_SCHEMAS=1 cargo test -p ufcsr --test it schemas::committed";

#[test]
fn committed_schemas_equal_the_generated_ones() {
    let write = std::env::var_os("UFCSR_WRITE_SCHEMAS").is_some_and(|v| v == "1");
    let mut stale = Vec::new();
    for format in ufcsr::format::SCHEMAS {
        let path = workspace_file("docs/schemas").join(format.schema_file);
        let generated = format.text();
        if write {
            std::fs::write(&path, &generated).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        } else if std::fs::read_to_string(&path).ok().as_deref() != Some(generated.as_str()) {
            stale.push(format.schema_file);
        }
    }
    assert!(
        stale.is_empty(),
        "docs/schemas/{} differ from the schemas generated from src/format/ (never edit them by hand); \
         regenerate them with\n    {REGENERATE}",
        stale.join(", docs/schemas/")
    );
}

#[test]
fn every_generated_schema_compiles_as_draft_2020_12() {
    for format in ufcsr::format::SCHEMAS {
        Schema::load(&workspace_file("docs/schemas").join(format.schema_file));
    }
}
