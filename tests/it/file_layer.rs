//! The one file layer is enforced, not hoped for (issue 34): clippy.toml
//! forbids `std::fs`'s opening, reading, writing, renaming and removing, every
//! crate denies the lint, and only the layer (`src/files/`) allows it, each
//! time saying why. A new command that writes with `std::fs::write` does not
//! build under `cargo clippy -- -D warnings` (CI); this test keeps the rule
//! from being switched off quietly. It reads files only (no cargo inside).

use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The methods that must stay forbidden outside the layer: std's file
/// functions of the one list of path-taking functions (`path_openers`).
fn forbidden() -> impl Iterator<Item = &'static str> {
    crate::path_openers::PATH_TAKING.iter().copied().filter(|path| path.starts_with("std::fs::"))
}

#[test]
fn clippy_toml_forbids_direct_file_access_and_names_the_layer_function_to_use() {
    let config = std::fs::read_to_string(root().join("clippy.toml")).unwrap();
    let section = &config[config.find("disallowed-methods").expect("no disallowed-methods in clippy.toml")..];
    for method in forbidden() {
        let entry = format!("path = \"{method}\"");
        let line = section.lines().find(|line| line.contains(&entry));
        let line = line.unwrap_or_else(|| panic!("clippy.toml does not forbid {method}"));
        assert!(
            line.contains("reason") && line.contains("ufcsr::"),
            "{method}: its reason names no layer function"
        );
    }
}

#[test]
fn every_crate_denies_the_lint() {
    // One table for the three crates (issue 41): the root's [workspace.lints].
    let text = std::fs::read_to_string(root().join("Cargo.toml")).unwrap();
    let start = text.find("[workspace.lints.clippy]").expect("Cargo.toml: no [workspace.lints.clippy]");
    let table = &text[start..];
    let table = &table[..table[1..].find("\n[").map_or(table.len(), |end| end + 1)];
    for lint in ["disallowed_methods = \"deny\"", "disallowed_types = \"deny\""] {
        assert!(table.contains(lint), "[workspace.lints.clippy] does not set {lint}");
    }
    for manifest in ["Cargo.toml", "capture/Cargo.toml", "cli/Cargo.toml"] {
        let text = std::fs::read_to_string(root().join(manifest)).unwrap();
        assert!(text.contains("\n[lints]\nworkspace = true\n"), "{manifest}: no `[lints] workspace = true`");
        assert!(!text.contains("[lints.clippy]"), "{manifest}: a table of its own beside the workspace's");
        // No crate brings its own clippy.toml: clippy finds the root one
        // by looking up from each crate's folder.
        let own = root().join(manifest).with_file_name("clippy.toml");
        assert!(
            manifest == "Cargo.toml" || !own.exists(),
            "{} would hide the root clippy.toml",
            own.display()
        );
    }
}

/// Every `.rs` file under `dir`.
fn sources(dir: &Path, found: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap().flatten() {
        let path = entry.path();
        if path.is_dir() {
            sources(&path, found);
        } else if path.extension().is_some_and(|e| e == "rs") {
            found.push(path);
        }
    }
}

#[test]
fn only_the_file_layer_allows_direct_file_access_and_says_why() {
    let mut files = Vec::new();
    for dir in ["src", "capture/src", "cli/src"] {
        sources(&root().join(dir), &mut files);
    }
    let layer = root().join("src/files");
    let mut allowed_in_layer = 0;
    for file in files {
        let text = std::fs::read_to_string(&file).unwrap();
        for (number, line) in text.lines().enumerate() {
            if !line.contains("clippy::disallowed_methods") && !line.contains("clippy::disallowed_types") {
                continue;
            }
            let at = format!("{}:{}", file.display(), number + 1);
            if line.contains("cfg_attr(test, allow(") {
                // Unit tests only: the crate's production build is still held to it.
                continue;
            }
            assert!(file.starts_with(&layer), "{at}: only src/files/ may allow direct file access");
            assert!(line.contains("// the layer:"), "{at}: say why it is safe there (`// the layer: …`)");
            allowed_in_layer += 1;
        }
    }
    assert!(allowed_in_layer > 0, "the layer itself must use std::fs somewhere");
}
