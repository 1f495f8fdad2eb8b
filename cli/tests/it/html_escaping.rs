//! Issue 34 item 7: every string a page takes from a file is escaped. Each
//! string field of a real `result.json` and of a real `placement.json` is
//! given hostile markup in turn (every element of a list at once); the file
//! is either refused by name (a field the reader checks: a schema, an enum,
//! a colour) or shown, and then the comparison page (`report`) and a
//! result's own `report.html` (with the placement beside it) hold the markup
//! only escaped. The fields shown are counted, so a reader that starts
//! refusing everything cannot pass the test vacuously.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde_json::Value;

use crate::common;

const HOSTILE: &str = "<script>alert(1)</script><img src=x onerror=alert(2)>\"'&";

/// What must never reach a page unescaped.
const RAW: [&str; 2] = ["<script>alert(1)", "<img src=x"];

fn example() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fixtures/example")
}

/// Every string leaf of `value` as a JSON pointer, grouped by its path with
/// list indices left out (`/parts/name` holds every part's name).
fn string_fields(value: &Value, pointer: String, kind: String, found: &mut BTreeMap<String, Vec<String>>) {
    match value {
        Value::Object(map) => {
            for (key, item) in map {
                let key_escaped = key.replace('~', "~0").replace('/', "~1");
                string_fields(item, format!("{pointer}/{key_escaped}"), format!("{kind}/{key}"), found);
            }
        }
        Value::Array(items) => {
            for (index, item) in items.iter().enumerate() {
                string_fields(item, format!("{pointer}/{index}"), kind.clone(), found);
            }
        }
        Value::String(_) => found.entry(kind).or_default().push(pointer),
        _ => {}
    }
}

/// `document` with every string of `pointers` made hostile.
fn hostile(document: &Value, pointers: &[String]) -> Value {
    let mut changed = document.clone();
    for pointer in pointers {
        *changed.pointer_mut(pointer).unwrap() = Value::String(HOSTILE.into());
    }
    changed
}

fn copy_folder(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for entry in std::fs::read_dir(from).unwrap() {
        let entry = entry.unwrap();
        if entry.file_type().unwrap().is_file() {
            std::fs::copy(entry.path(), to.join(entry.file_name())).unwrap();
        }
    }
}

/// Runs `ufcsr analyze args`; `Some(page)` when it wrote `page`, `None` when
/// it refused the file named `file` (exit 2, the file named on stderr).
fn page_or_refusal(args: &[&Path], page: &Path, file: &str, what: &str) -> Option<String> {
    let output = common::analyzer().args(args).output().unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(!stderr.contains("panicked"), "{what}: {stderr}");
    if output.status.success() {
        return Some(std::fs::read_to_string(page).unwrap());
    }
    assert_eq!(output.status.code(), Some(2), "{what}: {stderr}");
    assert!(stderr.contains(file), "{what}: the refusal names no {file}: {stderr}");
    None
}

fn assert_escaped(page: &str, what: &str) {
    for raw in RAW {
        assert!(!page.contains(raw), "{what}: {raw} reached the page unescaped");
    }
}

#[test]
fn every_string_field_of_a_result_json_is_escaped_on_the_comparison_page() {
    let dir = tempfile::tempdir().unwrap();
    let reference = dir.path().join("A");
    assert!(
        common::analyzer().arg(example()).arg("--out").arg(&reference).arg("-q").status().unwrap().success()
    );
    let document: Value =
        serde_json::from_slice(&std::fs::read(reference.join("result.json")).unwrap()).unwrap();
    let mut fields = BTreeMap::new();
    string_fields(&document, String::new(), String::new(), &mut fields);
    let (mut shown, mut refused) = (Vec::new(), Vec::new());
    for (kind, pointers) in &fields {
        let changed = dir.path().join("changed");
        let _ = std::fs::remove_dir_all(&changed);
        copy_folder(&reference, &changed);
        std::fs::write(changed.join("result.json"), hostile(&document, pointers).to_string()).unwrap();
        let out = dir.path().join("page");
        // --own-scales: the pictures copied, not drawn again (the text is the same).
        let args =
            [Path::new("report"), &changed, &reference, Path::new("--own-scales"), Path::new("--out"), &out];
        match page_or_refusal(&args, &out.join("report.html"), "result.json", kind) {
            Some(page) => {
                assert_escaped(&page, kind);
                shown.push(kind.clone());
            }
            None => refused.push(kind.clone()),
        }
    }
    // The free text a result carries reaches the page: part names, the archive, the legend, notes.
    for kind in ["/parts/name", "/settings/archive", "/warnings", "/notes"] {
        assert!(shown.iter().any(|s| s == kind), "{kind} was refused, not shown: shown {shown:?}");
    }
    eprintln!("result.json: shown {shown:?}; refused {refused:?}");
    assert!(shown.len() >= 8, "only {} fields shown: {shown:?}; refused {refused:?}", shown.len());
}

#[test]
fn every_string_field_of_a_placement_json_is_escaped_on_both_pages() {
    let dir = tempfile::tempdir().unwrap();
    let archive = common::placement_archive(dir.path(), "archive", true);
    let placement = dir.path().join("P");
    let made = common::analyzer()
        .arg("placement")
        .arg(&archive)
        .args(["--min-dwell-s", "0", "-q", "--out"])
        .arg(&placement)
        .output()
        .unwrap();
    assert!(made.status.success(), "{}", String::from_utf8_lossy(&made.stderr));
    let result = dir.path().join("R");
    assert!(
        common::analyzer().arg(example()).arg("--out").arg(&result).arg("-q").status().unwrap().success()
    );
    let document: Value =
        serde_json::from_slice(&std::fs::read(placement.join("placement.json")).unwrap()).unwrap();
    let mut fields = BTreeMap::new();
    string_fields(&document, String::new(), String::new(), &mut fields);
    let mut shown = Vec::new();
    for (kind, pointers) in &fields {
        let changed = dir.path().join("changed");
        let _ = std::fs::remove_dir_all(&changed);
        copy_folder(&placement, &changed);
        std::fs::write(changed.join("placement.json"), hostile(&document, pointers).to_string()).unwrap();
        let out = dir.path().join("page");
        let args =
            [Path::new("report"), &result, &changed, Path::new("--own-scales"), Path::new("--out"), &out];
        if let Some(page) = page_or_refusal(&args, &out.join("report.html"), "placement.json", kind) {
            assert_escaped(&page, kind);
            shown.push(kind.clone());
        }
    }
    for kind in ["/candidates/name", "/combinations/members/candidates", "/notes"] {
        assert!(shown.iter().any(|s| s == kind), "{kind} was refused, not shown: shown {shown:?}");
    }
    eprintln!("placement.json: shown {shown:?} of {:?}", fields.keys().collect::<Vec<_>>());
    // Every field shown at once, beside a result: its own report.html.
    let all: Vec<String> = shown.iter().flat_map(|kind| fields[kind].clone()).collect();
    let own = dir.path().join("own");
    std::fs::create_dir_all(own.join("placement")).unwrap();
    std::fs::write(own.join("placement/placement.json"), hostile(&document, &all).to_string()).unwrap();
    let analysed = common::analyzer().arg(example()).arg("--out").arg(&own).arg("-q").output().unwrap();
    assert!(analysed.status.success(), "{}", String::from_utf8_lossy(&analysed.stderr));
    let page = std::fs::read_to_string(own.join("report.html")).unwrap();
    assert!(page.contains(&ufcsr::output::html_escape(HOSTILE)), "the placement is not on the page");
    assert_escaped(&page, "a result's own report.html with the placement beside it");
}
