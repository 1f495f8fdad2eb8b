//! No module cycles in the capture's library: parents and children share a
//! folder, and siblings (the files and sub-folders of one folder, the folders
//! of `src/` among them) depend on each other one way only. A parent's
//! `mod.rs` may use its children and children their parent (that is what a
//! folder is), but `scene/` must not need `archive/` when `archive/` needs
//! `scene/`, nor `render/renderer.rs` need `render/pipeline.rs` and back.
//!
//! `cargo-modules` would do this properly but is not available offline; like
//! the analyzer's `tests/it/module_graph.rs` this reads the source text,
//! which is enough because the library names other modules only through
//! `crate::` and `super::` paths. A path to an item a folder's `mod.rs`
//! re-exports (`crate::scene::Scene`) counts as a path to the file it is
//! re-exported from (`scene::scene_file`), so a re-export hides no cycle.
//! The binary (`main.rs`, `cli/`, `bin/`) is another crate and is left out.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// Modules and the modules each one uses.
type Edges = BTreeMap<String, BTreeSet<String>>;

/// Every `.rs` file under `dir`, except the binary's.
fn library_files(dir: &Path, top: bool, files: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        if top && ["main.rs", "cli", "bin"].contains(&name.as_str()) {
            continue;
        }
        if path.is_dir() {
            library_files(&path, false, files);
        } else if name.ends_with(".rs") {
            files.push(path);
        }
    }
}

/// The module path of a file: `scene/mesh.rs` → `[scene, mesh]`,
/// `texture/pidt/mod.rs` → `[texture, pidt]`, `lib.rs` → `[]`.
fn module_of(src: &Path, file: &Path) -> Vec<String> {
    let relative = file.strip_prefix(src).unwrap().with_extension("");
    let mut parts: Vec<String> = relative.iter().map(|p| p.to_string_lossy().into_owned()).collect();
    if parts.last().is_some_and(|p| p == "mod" || p == "lib") {
        parts.pop();
    }
    parts
}

/// The paths a text names after `crate::` or `super::`, as absolute module
/// paths of the module `here` (brace groups expanded one level:
/// `crate::{a::b, c::d}` names `a::b` and `c::d`).
fn named_paths(text: &str, here: &[String]) -> Vec<Vec<String>> {
    let mut paths = Vec::new();
    for (prefix, base) in
        [("crate::", Vec::new()), ("super::", here[..here.len().saturating_sub(1)].to_vec())]
    {
        let mut rest = text;
        while let Some(at) = rest.find(prefix) {
            // `self::super::` or `super::super::` are not used in the crate.
            let preceded_by_word = rest[..at].chars().last().is_some_and(|c| c.is_alphanumeric() || c == '_');
            rest = &rest[at + prefix.len()..];
            if preceded_by_word {
                continue;
            }
            let tail: String =
                rest.chars().take_while(|c| c.is_alphanumeric() || "_:{}, \n".contains(*c)).collect();
            let tail =
                tail.strip_prefix('{').map_or(tail.as_str(), |inner| inner.split('}').next().unwrap_or(""));
            for path in tail.split(',') {
                let segments: Vec<String> = path
                    .trim()
                    .split("::")
                    .map(|s| s.trim().chars().take_while(|c| c.is_alphanumeric() || *c == '_').collect())
                    .take_while(|s: &String| !s.is_empty() && s != "self")
                    .collect();
                if !segments.is_empty() {
                    paths.push(base.iter().cloned().chain(segments).collect());
                }
            }
        }
    }
    paths
}

/// The items each folder's `mod.rs` re-exports, by the child they come from:
/// `pub use scene_file::{Scene, SceneFile};` gives `(scene, Scene) → scene_file`.
fn re_exports(modules: &BTreeMap<Vec<String>, String>) -> BTreeMap<(Vec<String>, String), String> {
    let mut items = BTreeMap::new();
    for (module, text) in modules {
        let mut rest = text.as_str();
        while let Some(at) = rest.find("pub use ") {
            rest = &rest[at + "pub use ".len()..];
            let statement = rest.split(';').next().unwrap_or("");
            let Some((child, list)) = statement.split_once("::") else { continue };
            let child = child.trim().to_string();
            let child_path: Vec<String> = module.iter().cloned().chain([child.clone()]).collect();
            if !modules.contains_key(&child_path) {
                continue;
            }
            let list = list.trim().trim_start_matches('{').trim_end_matches('}');
            for item in list.split(',') {
                // `a::B` re-exports `B` from `child::a`; `B as C` names `C`.
                let name = item.split(" as ").last().unwrap_or("").rsplit("::").next().unwrap_or("").trim();
                // `pub use child::*`: any item not re-exported by name.
                if !name.is_empty() {
                    items.insert((module.clone(), name.to_string()), child.clone());
                }
            }
        }
    }
    items
}

/// `path` cut to the module it names: the longest prefix that is a module,
/// then one step further down if the next segment is an item that module
/// re-exports from a child (by name, or with `pub use child::*`).
fn resolve(
    path: &[String],
    modules: &BTreeMap<Vec<String>, String>,
    items: &BTreeMap<(Vec<String>, String), String>,
) -> Vec<String> {
    let mut module: Vec<String> = Vec::new();
    for segment in path {
        let mut next = module.clone();
        next.push(segment.clone());
        if modules.contains_key(&next) {
            module = next;
        } else if let Some(child) = items
            .get(&(module.clone(), segment.clone()))
            .or_else(|| items.get(&(module.clone(), "*".to_string())))
        {
            module.push(child.clone());
        } else {
            break;
        }
    }
    module
}

/// Edges between siblings: for a reference from `from` to `to`, the children
/// of their deepest common folder that hold them (none when one holds the other).
fn sibling_edge(from: &[String], to: &[String]) -> Option<(Vec<String>, Vec<String>)> {
    let common = from.iter().zip(to).take_while(|(a, b)| a == b).count();
    (common < from.len() && common < to.len()).then(|| (from[..=common].to_vec(), to[..=common].to_vec()))
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

/// References that still run backwards, each with why, as (from module, to
/// module). The test fails when one is gone, so the list only shrinks.
const KNOWN_BACKWARD: &[(&str, &str, &str)] = &[];

/// The sibling edges of the library under `src`, as `a::b → a::c`, and the
/// known backward references that were found (left out of the edges).
fn library_edges(src: &Path) -> (Edges, BTreeSet<(String, String)>) {
    let mut files = Vec::new();
    library_files(src, true, &mut files);
    // Comments (docs linking to other modules) are no dependency.
    let modules: BTreeMap<Vec<String>, String> = files
        .iter()
        .map(|file| {
            let text = std::fs::read_to_string(file).unwrap();
            let code: Vec<&str> = text.lines().filter(|line| !line.trim_start().starts_with("//")).collect();
            (module_of(src, file), code.join("\n"))
        })
        .collect();
    let items = re_exports(&modules);
    let mut edges: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    let mut known = BTreeSet::new();
    for (module, text) in &modules {
        for path in named_paths(text, module) {
            let target = resolve(&path, &modules, &items);
            let (here, there) = (module.join("::"), target.join("::"));
            if KNOWN_BACKWARD.iter().any(|(from, to, _)| here == *from && there == *to) {
                known.insert((here, there));
                continue;
            }
            if let Some((from, to)) = sibling_edge(module, &target) {
                edges.entry(from.join("::")).or_default().insert(to.join("::"));
            }
        }
    }
    (edges, known)
}

#[test]
fn capture_modules_form_no_cycle() {
    let src = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("src");
    let (edges, known) = library_edges(&src);
    for (from, to, why) in KNOWN_BACKWARD {
        assert!(
            known.contains(&(from.to_string(), to.to_string())),
            "{from} no longer uses {to} ({why}): remove it from KNOWN_BACKWARD"
        );
    }
    assert!(
        edges.get("job").is_some_and(|to| to.contains("scene")),
        "no edge job → scene found: is capture/src/ where it was? {edges:?}"
    );
    if std::env::var_os("UFCSR_PRINT_MODULE_EDGES").is_some() {
        for (from, to) in &edges {
            eprintln!("{from} → {}", to.iter().cloned().collect::<Vec<_>>().join(", "));
        }
    }
    if let Some(cycle) = find_cycle(&edges) {
        panic!("modules of the capture form a cycle: {}", cycle.join(" → "));
    }
}

#[test]
fn a_cycle_between_siblings_is_found_and_a_parent_is_no_sibling() {
    let module = |s: &str| s.split("::").map(String::from).collect::<Vec<_>>();
    assert_eq!(
        sibling_edge(&module("render::renderer"), &module("render::pipeline")).unwrap().1,
        module("render::pipeline")
    );
    assert_eq!(
        sibling_edge(&module("scene::mesh"), &module("render::gpu")).unwrap(),
        (module("scene"), module("render"))
    );
    assert_eq!(sibling_edge(&module("study::plot"), &module("study")), None);
    let mut edges: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    edges.entry("a".into()).or_default().insert("b".into());
    edges.entry("b".into()).or_default().insert("c".into());
    assert_eq!(find_cycle(&edges), None);
    edges.entry("c".into()).or_default().insert("a".into());
    assert_eq!(find_cycle(&edges).unwrap(), ["a", "b", "c", "a"]);
    let here = module("texture::pidt::own");
    let paths = named_paths("use super::painted::X;\nuse crate::{scene::mesh::Mesh, error::Result};", &here);
    assert_eq!(
        paths,
        [module("scene::mesh::Mesh"), module("error::Result"), module("texture::pidt::painted::X")]
    );
    let mut modules = BTreeMap::new();
    modules.insert(module("scene"), "pub use scene_file::{Scene, SceneFile as File};".to_string());
    modules.insert(module("scene::scene_file"), String::new());
    let items = re_exports(&modules);
    assert_eq!(resolve(&module("scene::File"), &modules, &items), module("scene::scene_file"));
    assert_eq!(resolve(&module("scene::Scene::demo"), &modules, &items), module("scene::scene_file"));
    assert_eq!(resolve(&module("scene::Other"), &modules, &items), module("scene"));
    modules.insert(module("render"), "pub use renderer::*;".to_string());
    modules.insert(module("render::renderer"), String::new());
    let items = re_exports(&modules);
    assert_eq!(resolve(&module("render::Vertex"), &modules, &items), module("render::renderer"));
}
