//! No module cycles in the analyzer: every `crate::a::…` path in `src/`
//! is an edge from the file's stage to stage `a`, and the graph of stages
//! must stay acyclic (input → count → result → output, all of them on
//! color, files and error; analyze and testing on top). `cargo-modules`
//! would do this properly but is not available offline; this reads the
//! source text, which is enough because the crate names other modules only
//! through `crate::` paths (a `super::` path stays inside its folder).
//!
//! A stage is the first folder (or file) below `src/`: `src/input/options.rs`
//! is stage `input`, `src/analyze.rs` stage `analyze`. Inside a folder, the
//! same check runs on its files (`result::model` → `result::frames`), so a
//! cycle between two files of one folder fails too.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// Every `.rs` file under `dir`.
fn rust_files(dir: &Path, files: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            rust_files(&path, files);
        } else if path.extension().is_some_and(|e| e == "rs") {
            files.push(path);
        }
    }
}

/// The module paths a file's text names after `crate::` (brace groups
/// expanded one level: `crate::{a::b, c::d}` names `a::b` and `c::d`).
fn named_paths(text: &str) -> Vec<Vec<String>> {
    let mut paths = Vec::new();
    let mut rest = text;
    while let Some(at) = rest.find("crate::") {
        rest = &rest[at + "crate::".len()..];
        let tail: String =
            rest.chars().take_while(|c| c.is_alphanumeric() || "_:{}, \n".contains(*c)).collect();
        let tail =
            tail.strip_prefix('{').map_or(tail.as_str(), |inner| inner.split('}').next().unwrap_or(""));
        for path in tail.split(',') {
            let segments: Vec<String> = path
                .trim()
                .split("::")
                .map(|s| s.trim().chars().take_while(|c| c.is_alphanumeric() || *c == '_').collect())
                .take_while(|s: &String| !s.is_empty())
                .collect();
            if !segments.is_empty() {
                paths.push(segments);
            }
        }
    }
    paths
}

/// A cycle in `edges`, if there is one.
fn find_cycle(edges: &BTreeMap<String, BTreeSet<String>>) -> Option<Vec<String>> {
    fn visit(
        node: &str,
        edges: &BTreeMap<String, BTreeSet<String>>,
        state: &mut BTreeMap<String, u8>,
        stack: &mut Vec<String>,
    ) -> Option<Vec<String>> {
        state.insert(node.to_string(), 1);
        stack.push(node.to_string());
        for next in edges.get(node).into_iter().flatten() {
            match state.get(next.as_str()) {
                Some(1) => {
                    let start = stack.iter().position(|n| n == next).unwrap();
                    return Some(stack[start..].iter().cloned().chain([next.clone()]).collect());
                }
                Some(_) => {}
                None => {
                    if let Some(cycle) = visit(next, edges, state, stack) {
                        return Some(cycle);
                    }
                }
            }
        }
        stack.pop();
        state.insert(node.to_string(), 2);
        None
    }
    let mut state = BTreeMap::new();
    for node in edges.keys() {
        if !state.contains_key(node.as_str())
            && let Some(cycle) = visit(node, edges, &mut state, &mut Vec::new())
        {
            return Some(cycle);
        }
    }
    None
}

#[test]
fn analyzer_modules_form_no_cycle() {
    let src = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    let top: Vec<PathBuf> = std::fs::read_dir(&src).unwrap().map(|e| e.unwrap().path()).collect();
    let name = |p: &PathBuf| p.file_stem().unwrap().to_string_lossy().into_owned();
    let folders: BTreeSet<String> = top.iter().filter(|p| p.is_dir()).map(name).collect();
    // Only paths that start with a stage are edges (not `crate::{a::B, C}`'s `C`).
    let stage_names: BTreeSet<String> = top.iter().map(name).collect();
    let mut stages: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    let mut files_in_folder: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for file in &files {
        let relative = file.strip_prefix(&src).unwrap().with_extension("");
        let parts: Vec<String> = relative.iter().map(|p| p.to_string_lossy().into_owned()).collect();
        if parts == ["lib"] || parts == ["main"] {
            continue;
        }
        let stage = parts[0].clone();
        // The file within its folder: `result/model.rs` → `model`; a folder's
        // mod.rs (and anything in a sub-folder) counts as the sub-module.
        let own = parts.get(1).filter(|p| p.as_str() != "mod").cloned();
        // Comments (docs linking to the crate's re-exports) are no dependency.
        let text: String = std::fs::read_to_string(file)
            .unwrap()
            .lines()
            .filter(|line| !line.trim_start().starts_with("//"))
            .collect::<Vec<_>>()
            .join("\n");
        for path in named_paths(&text) {
            let target = &path[0];
            if !stage_names.contains(target) {
                continue;
            }
            if target != &stage {
                stages.entry(stage.clone()).or_default().insert(target.clone());
            } else if let (Some(own), Some(other)) = (&own, path.get(1))
                && folders.contains(&stage)
                && other != own
            {
                files_in_folder
                    .entry(format!("{stage}::{own}"))
                    .or_default()
                    .insert(format!("{stage}::{other}"));
            }
        }
    }
    assert!(stages.contains_key("analyze"), "no edges found: is src/ where it was? {stages:?}");
    if let Some(cycle) = find_cycle(&stages) {
        panic!("the analyzer's stages form a cycle: {}", cycle.join(" → "));
    }
    if let Some(cycle) = find_cycle(&files_in_folder) {
        panic!("modules of one folder form a cycle: {}", cycle.join(" → "));
    }
}

#[test]
fn a_cycle_is_found_and_named() {
    let mut edges: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    edges.entry("a".into()).or_default().insert("b".into());
    edges.entry("b".into()).or_default().insert("c".into());
    assert_eq!(find_cycle(&edges), None);
    edges.entry("c".into()).or_default().insert("a".into());
    assert_eq!(find_cycle(&edges).unwrap(), ["a", "b", "c", "a"]);
    let paths = named_paths(
        "use crate::{input::options::X, result::model::{A, B}};\nlet y = crate::count::scan::f();",
    );
    assert_eq!(paths[0], ["input", "options", "X"]);
    assert_eq!(paths[1], ["result", "model"]);
    assert_eq!(paths.last().unwrap(), &["count", "scan", "f"]);
}
