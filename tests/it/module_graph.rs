//! No module cycles, in any crate of the workspace: the analyzer (`src/`),
//! the capture (`capture/src/`) and the command line (`cli/src/`, when it
//! exists), each library and each binary (`main.rs` with `cli/`, every
//! `bin/*.rs`) a crate of its own.
//!
//! Every file is a node. A crate's files are found as the compiler finds
//! them, from the crate root along its `mod` declarations (a `#[cfg(test)]`
//! module is test code and left out, so is any item under `#[cfg(test)]`).
//! Every path in a file's code — `use` trees, paths in types and
//! expressions, `crate::`/`super::` paths inside macro bodies — is resolved
//! as rustc would resolve it, to the file that defines what it names:
//! `crate::`, `super::`, `self::` and a child module's name are followed
//! module by module, and a name a module re-exports (`pub use x::Y`,
//! `pub use x::*`, also the crate root's flat list) is followed to the file
//! it comes from, so a re-export hides no cycle. Comments and doc links are
//! no dependency.
//!
//! Allowed: a file using its own folder's `mod.rs` (or the crate root) —
//! what a folder is; every other edge counts, and two checks must pass:
//! the files form no cycle, and neither do the siblings of any folder (the
//! files and sub-folders of one folder, with a sub-folder standing for all
//! it holds), so `scene/` must not need `job/` when `job/` needs `scene/`
//! even through different files. A failure names every cycle.
//!
//! The resolver follows the project's own tool (`../shared/tools/filegraph`)
//! and reads the source with `syn`; `cargo-modules` would do the same but is
//! not available offline.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

use syn::visit::Visit;

/// A module path: `job::capture_job` is `["job", "capture_job"]`; the crate root is `[]`.
type Module = Vec<String>;

/// File-level edges: from a file's module to the modules of the files it uses.
type Edges = BTreeMap<Module, BTreeSet<Module>>;

/// Cycles that are known and owned by another change, each with why: the
/// test fails when one is gone, so the list only shrinks.
const KNOWN_CYCLES: &[(&str, &str)] = &[];

/// One crate: its files by module, the source folder's name for messages.
struct CrateTree {
    /// `capture/src/` and the like, prefixed to file names in messages.
    label: String,
    files: BTreeMap<Module, SourceFile>,
}

struct SourceFile {
    /// The path below the source folder: `job/capture_job.rs`.
    path: String,
    syntax: syn::File,
}

/// True for `#[cfg(test)]`, `#[cfg(all(test, …))]` and the like.
fn is_test_only(attrs: &[syn::Attribute]) -> bool {
    attrs.iter().any(|a| {
        a.path().is_ident("cfg")
            && a.meta.require_list().is_ok_and(|list| {
                list.tokens.to_string().split(|c: char| !c.is_alphanumeric() && c != '_').any(|w| w == "test")
            })
    })
}

/// The attributes of the items that can be test-only.
fn item_attrs(item: &syn::Item) -> &[syn::Attribute] {
    match item {
        syn::Item::Const(i) => &i.attrs,
        syn::Item::Enum(i) => &i.attrs,
        syn::Item::Fn(i) => &i.attrs,
        syn::Item::Impl(i) => &i.attrs,
        syn::Item::Macro(i) => &i.attrs,
        syn::Item::Mod(i) => &i.attrs,
        syn::Item::Static(i) => &i.attrs,
        syn::Item::Struct(i) => &i.attrs,
        syn::Item::Trait(i) => &i.attrs,
        syn::Item::Type(i) => &i.attrs,
        syn::Item::Use(i) => &i.attrs,
        _ => &[],
    }
}

/// The folder a file's child modules live in: beside a crate root or a
/// `mod.rs`, in `foo/` for `foo.rs`.
fn child_folder(path: &str, is_root: bool) -> String {
    let (folder, file) = path.rsplit_once('/').map_or(("", path), |(d, f)| (d, f));
    let join = |a: &str, b: &str| if a.is_empty() { b.to_string() } else { format!("{a}/{b}") };
    if is_root || file == "mod.rs" { folder.to_string() } else { join(folder, file.trim_end_matches(".rs")) }
}

/// The crate whose root is `root` (a path below the source folder), its
/// files found along the `mod` declarations; `read` gives a file's text.
fn crate_tree(label: &str, root: &str, read: &dyn Fn(&str) -> Option<String>) -> CrateTree {
    let mut files = BTreeMap::new();
    let mut pending = vec![(Module::new(), root.to_string())];
    while let Some((module, path)) = pending.pop() {
        let text = read(&path).unwrap_or_else(|| panic!("{label}{path}: not found"));
        let syntax = syn::parse_file(&text).unwrap_or_else(|e| panic!("{label}{path}: {e}"));
        let folder = child_folder(&path, module.is_empty());
        for item in &syntax.items {
            let syn::Item::Mod(m) = item else { continue };
            if m.content.is_some() || is_test_only(&m.attrs) {
                continue;
            }
            let name = m.ident.to_string();
            let prefix = if folder.is_empty() { String::new() } else { format!("{folder}/") };
            let candidates = [format!("{prefix}{name}.rs"), format!("{prefix}{name}/mod.rs")];
            let found = candidates.into_iter().find(|c| read(c).is_some());
            let found = found.unwrap_or_else(|| panic!("{label}{path}: no file for `mod {name}`"));
            pending.push((module.iter().cloned().chain([name]).collect(), found));
        }
        files.insert(module, SourceFile { path, syntax });
    }
    CrateTree { label: label.to_string(), files }
}

/// A name a module re-exports: `(module, name)`, `*` for a glob.
type ReExported = (Module, String);

/// A path as named, with the module it is named in.
type Named = (Module, Vec<String>);

/// The paths one file names, each with the module it is named in (a file's
/// own module, or an inline module in it), and its re-exports.
#[derive(Default)]
struct Names {
    scope: Module,
    paths: Vec<Named>,
    /// `(module, name) → path`: `pub use a::B as C` in `m` is `(m, C) → a::B`;
    /// a glob re-export is the name `*`.
    re_exports: Vec<(ReExported, Named)>,
}

/// `use` trees flattened: `a::{b, c::D as E}` gives `(b, [a, b])` and `(E, [a, c, D])`.
fn use_paths(tree: &syn::UseTree, prefix: &mut Vec<String>, out: &mut Vec<(String, Vec<String>)>) {
    match tree {
        syn::UseTree::Path(p) => {
            prefix.push(p.ident.to_string());
            use_paths(&p.tree, prefix, out);
            prefix.pop();
        }
        syn::UseTree::Name(n) => {
            out.push((n.ident.to_string(), [&prefix[..], &[n.ident.to_string()]].concat()))
        }
        syn::UseTree::Rename(r) => {
            out.push((r.rename.to_string(), [&prefix[..], &[r.ident.to_string()]].concat()))
        }
        syn::UseTree::Glob(_) => out.push(("*".to_string(), prefix.clone())),
        syn::UseTree::Group(g) => g.items.iter().for_each(|item| use_paths(item, prefix, out)),
    }
}

impl<'a> Visit<'a> for Names {
    fn visit_item(&mut self, item: &'a syn::Item) {
        if is_test_only(item_attrs(item)) {
            return;
        }
        match item {
            syn::Item::Mod(m) => {
                self.scope.push(m.ident.to_string());
                syn::visit::visit_item_mod(self, m);
                self.scope.pop();
            }
            syn::Item::Use(u) if u.leading_colon.is_none() => {
                let mut flat = Vec::new();
                use_paths(&u.tree, &mut Vec::new(), &mut flat);
                for (name, path) in flat {
                    if !matches!(u.vis, syn::Visibility::Inherited) {
                        self.re_exports
                            .push(((self.scope.clone(), name), (self.scope.clone(), path.clone())));
                    }
                    self.paths.push((self.scope.clone(), path));
                }
            }
            syn::Item::Use(_) => {}
            _ => syn::visit::visit_item(self, item),
        }
    }

    fn visit_path(&mut self, path: &'a syn::Path) {
        if path.leading_colon.is_none() {
            self.paths
                .push((self.scope.clone(), path.segments.iter().map(|s| s.ident.to_string()).collect()));
        }
        syn::visit::visit_path(self, path);
    }

    /// Macro bodies are tokens, not syntax: `crate :: a :: b` and `super :: x` in them.
    fn visit_macro(&mut self, mac: &'a syn::Macro) {
        let text = mac.tokens.to_string();
        let tokens: Vec<&str> = text.split_whitespace().collect();
        for (i, token) in tokens.iter().enumerate() {
            if !matches!(*token, "crate" | "super" | "self") || tokens.get(i + 1) != Some(&"::") {
                continue;
            }
            let mut path = vec![token.to_string()];
            let mut j = i + 2;
            while let Some(segment) =
                tokens.get(j).filter(|s| s.chars().all(|c| c.is_alphanumeric() || c == '_'))
            {
                path.push(segment.to_string());
                if tokens.get(j + 1) != Some(&"::") {
                    break;
                }
                j += 2;
            }
            self.paths.push((self.scope.clone(), path));
        }
        syn::visit::visit_macro(self, mac);
    }
}

/// `path`, named in module `scope`, from the crate root: `crate::`,
/// `super::`, `self::` and a child module's name; `None` for anything else
/// (another crate, a local name, a type's associated item).
fn absolute(scope: &[String], path: &[String], modules: &BTreeSet<Module>) -> Option<Vec<String>> {
    let first = path.first()?;
    match first.as_str() {
        "crate" => Some(path[1..].to_vec()),
        "self" => Some([scope, &path[1..]].concat()),
        "super" => {
            let ups = path.iter().take_while(|s| *s == "super").count();
            let base = scope.get(..scope.len().checked_sub(ups)?)?;
            Some([base, &path[ups..]].concat())
        }
        _ => {
            let relative = [scope, path].concat();
            modules.contains(&relative[..scope.len() + 1]).then_some(relative)
        }
    }
}

/// The file module that defines what `path` (from the crate root) names:
/// the longest prefix that is a module, then through the re-exports of the
/// module the path continues in.
fn resolve(
    path: &[String],
    files: &BTreeSet<Module>,
    re_exports: &BTreeMap<ReExported, Vec<String>>,
    depth: usize,
) -> Option<Module> {
    let mut length = path.len();
    while !files.contains(&path[..length]) {
        length = length.checked_sub(1)?;
    }
    let module = path[..length].to_vec();
    let Some(name) = path.get(length).filter(|_| depth < 16) else { return Some(module) };
    let named =
        re_exports.get(&(module.clone(), name.clone())).map(|target| [target, &path[length + 1..]].concat());
    let globbed =
        re_exports.get(&(module.clone(), "*".to_string())).map(|target| [target, &path[length..]].concat());
    for target in named.into_iter().chain(globbed) {
        if target != path
            && let Some(found) = resolve(&target, files, re_exports, depth + 1)
        {
            return Some(found);
        }
    }
    Some(module)
}

/// Every file's edges in one crate, with the edges into a file's own
/// ancestors (its folder's `mod.rs`, the crate root) left out.
fn crate_edges(tree: &CrateTree) -> Edges {
    let modules: BTreeSet<Module> = tree.files.keys().cloned().collect();
    let mut names: BTreeMap<&Module, Names> = BTreeMap::new();
    for (module, file) in &tree.files {
        let mut found = Names { scope: module.clone(), ..Names::default() };
        found.visit_file(&file.syntax);
        names.insert(module, found);
    }
    // Re-exports of inline modules count too: any scope, resolved to absolute paths.
    let mut all_modules = modules.clone();
    for found in names.values() {
        all_modules.extend(found.paths.iter().map(|(scope, _)| scope.clone()));
    }
    let re_exports: BTreeMap<ReExported, Vec<String>> = names
        .values()
        .flat_map(|found| &found.re_exports)
        .filter_map(|(key, (scope, path))| Some((key.clone(), absolute(scope, path, &all_modules)?)))
        .collect();
    let mut edges = Edges::new();
    for (module, found) in &names {
        for (scope, path) in &found.paths {
            let Some(target) =
                absolute(scope, path, &all_modules).and_then(|path| resolve(&path, &modules, &re_exports, 0))
            else {
                continue;
            };
            if !module.starts_with(&target) {
                edges.entry((*module).clone()).or_default().insert(target);
            }
        }
    }
    edges
}

/// The strongly connected components of more than one node (Tarjan).
fn cycles(edges: &Edges) -> Vec<Vec<Module>> {
    struct Walk<'e> {
        edges: &'e Edges,
        index: BTreeMap<Module, usize>,
        low: BTreeMap<Module, usize>,
        stack: Vec<Module>,
        found: Vec<Vec<Module>>,
    }
    fn strong(walk: &mut Walk, node: &Module) {
        let n = walk.index.len();
        walk.index.insert(node.clone(), n);
        walk.low.insert(node.clone(), n);
        walk.stack.push(node.clone());
        for next in walk.edges.get(node).into_iter().flatten() {
            if !walk.index.contains_key(next) {
                strong(walk, next);
                let low = walk.low[node].min(walk.low[next]);
                walk.low.insert(node.clone(), low);
            } else if walk.stack.contains(next) {
                let low = walk.low[node].min(walk.index[next]);
                walk.low.insert(node.clone(), low);
            }
        }
        if walk.low[node] == walk.index[node] {
            let at = walk.stack.iter().position(|m| m == node).unwrap();
            let mut component = walk.stack.split_off(at);
            component.sort();
            if component.len() > 1 {
                walk.found.push(component);
            }
        }
    }
    let mut walk =
        Walk { edges, index: BTreeMap::new(), low: BTreeMap::new(), stack: Vec::new(), found: Vec::new() };
    let nodes: BTreeSet<&Module> =
        edges.iter().flat_map(|(from, to)| std::iter::once(from).chain(to)).collect();
    for node in nodes {
        if !walk.index.contains_key(node) {
            strong(&mut walk, node);
        }
    }
    walk.found
}

/// The edges between siblings: for an edge from `a` to `b`, the children of
/// their deepest common folder that hold them.
fn sibling_edges(edges: &Edges) -> Edges {
    let mut siblings = Edges::new();
    for (from, targets) in edges {
        for to in targets {
            let common = from.iter().zip(to).take_while(|(a, b)| a == b).count();
            if common < from.len() && common < to.len() {
                siblings.entry(from[..=common].to_vec()).or_default().insert(to[..=common].to_vec());
            }
        }
    }
    siblings
}

/// Every cycle of a crate, as lines naming its files (or folders) and the
/// edges that close it.
fn cycle_report(tree: &CrateTree) -> Vec<String> {
    let edges = crate_edges(tree);
    let mut report = Vec::new();
    let mut seen = Vec::new();
    for (kind, graph) in [("files", &edges), ("siblings", &sibling_edges(&edges))] {
        // A file by its path; a folder (a sibling that is a folder) by its own.
        let name = |module: &Module| match tree.files.get(module) {
            Some(file) if kind == "files" || !file.path.ends_with("mod.rs") => {
                format!("{}{}", tree.label, file.path)
            }
            _ => format!("{}{}/", tree.label, module.join("/")),
        };
        // Files of one folder are siblings too: their cycle is named once.
        for component in cycles(graph).into_iter().filter(|c| !seen.contains(c)).collect::<Vec<_>>() {
            seen.push(component.clone());
            let members: Vec<String> = component.iter().map(name).collect();
            let inside: Vec<String> = component
                .iter()
                .flat_map(|from| {
                    graph[from].iter().filter(|to| component.contains(to)).map(move |to| (from, to))
                })
                .map(|(from, to)| format!("{} → {}", name(from), name(to)))
                .collect();
            report.push(format!("{kind}: {} ({})", members.join(" "), inside.join(", ")));
        }
    }
    report
}

/// The crate roots below a source folder: the library, the binary, `bin/*.rs`.
fn crate_roots(src: &Path) -> Vec<String> {
    let mut roots: Vec<String> =
        ["lib.rs", "main.rs"].into_iter().filter(|r| src.join(r).is_file()).map(String::from).collect();
    if let Ok(bins) = std::fs::read_dir(src.join("bin")) {
        let mut bins: Vec<String> = bins
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .filter(|name| name.ends_with(".rs"))
            .map(|name| format!("bin/{name}"))
            .collect();
        bins.sort();
        roots.extend(bins);
    }
    roots
}

/// Every crate of the workspace, read from disk.
fn workspace_crates() -> Vec<CrateTree> {
    let repo = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let mut crates = Vec::new();
    for folder in ["src", "capture/src", "cli/src"] {
        let src = repo.join(folder);
        for root in crate_roots(&src) {
            let read = |path: &str| std::fs::read_to_string(src.join(path)).ok();
            crates.push(crate_tree(&format!("{folder}/"), &root, &read));
        }
    }
    crates
}

#[test]
fn no_crate_of_the_workspace_has_a_module_cycle() {
    let crates = workspace_crates();
    let files: usize = crates.iter().map(|c| c.files.len()).sum();
    assert!(
        crates.len() >= 3 && files > 150,
        "only {files} files in {} crates: is the tree where it was?",
        crates.len()
    );
    if std::env::var_os("UFCSR_PRINT_MODULE_EDGES").is_some() {
        for tree in &crates {
            for (from, to) in sibling_edges(&crate_edges(tree)) {
                let to: Vec<String> = to.iter().map(|m| m.join("::")).collect();
                eprintln!("{}{} → {}", tree.label, from.join("::"), to.join(", "));
            }
        }
    }
    let mut cycles: Vec<String> = crates.iter().flat_map(cycle_report).collect();
    for (members, why) in KNOWN_CYCLES {
        let before = cycles.len();
        cycles.retain(|c| {
            !c.starts_with(&format!("files: {members} ("))
                && !c.starts_with(&format!("siblings: {members} ("))
        });
        assert!(cycles.len() < before, "the cycle {members} is gone ({why}): remove it from KNOWN_CYCLES");
    }
    assert!(cycles.is_empty(), "module cycles:\n{}", cycles.join("\n"));
}

/// A crate held in memory: `(path, text)` pairs below its source folder.
fn tree_of(files: &[(&str, &str)]) -> CrateTree {
    let files: BTreeMap<String, String> = files.iter().map(|(p, t)| (p.to_string(), t.to_string())).collect();
    crate_tree("mem/", "lib.rs", &|path| files.get(path).cloned())
}

#[test]
fn a_cycle_through_a_re_export_is_found_and_named() {
    let lib = "mod html; pub use html::Page;";
    let html = "mod escape; mod page; pub use page::Page;";
    let page = "use super::escape::escape; pub struct Page; fn f() -> String { escape() }";
    let escape = "pub fn escape() -> String { let _ = crate::Page; String::new() }";
    let tree = tree_of(&[
        ("lib.rs", lib),
        ("html/mod.rs", html),
        ("html/page.rs", page),
        ("html/escape.rs", escape),
    ]);
    assert_eq!(
        cycle_report(&tree),
        ["files: mem/html/escape.rs mem/html/page.rs (mem/html/escape.rs → mem/html/page.rs, \
          mem/html/page.rs → mem/html/escape.rs)"]
    );
    let escape = "pub fn escape() -> String { String::new() }";
    let tree = tree_of(&[
        ("lib.rs", lib),
        ("html/mod.rs", html),
        ("html/page.rs", page),
        ("html/escape.rs", escape),
    ]);
    assert_eq!(cycle_report(&tree), Vec::<String>::new());
}

#[test]
fn folders_that_need_each_other_are_a_cycle_even_through_different_files() {
    let lib = "mod job; mod scene;";
    let job = "pub mod run; pub mod sink;";
    let scene = "pub mod mesh; pub mod track;";
    let run = "use crate::scene::mesh::Mesh; pub struct Run;";
    let track = "pub fn t() { let _ = crate::job::sink::Sink; }";
    let tree = tree_of(&[
        ("lib.rs", lib),
        ("job/mod.rs", job),
        ("job/run.rs", run),
        ("job/sink.rs", "pub struct Sink;"),
        ("scene/mod.rs", scene),
        ("scene/mesh.rs", "pub struct Mesh;"),
        ("scene/track.rs", track),
    ]);
    assert_eq!(
        cycle_report(&tree),
        ["siblings: mem/job/ mem/scene/ (mem/job/ → mem/scene/, mem/scene/ → mem/job/)"]
    );
}

#[test]
fn a_folder_and_its_files_tests_and_comments_are_no_cycle() {
    // mod.rs uses its child and the child what mod.rs defines: what a folder is.
    let lib = "mod count; /// [`crate::count::scan`]\npub use count::scan::Scan;";
    let count = "pub mod scan; pub struct Kernel; pub fn k() -> scan::Scan { scan::Scan }";
    let scan = "use super::Kernel; pub struct Scan; fn f(_: Kernel) {}\n\
                #[cfg(test)] mod tests { use crate::other::Thing; }\n\
                #[cfg(test)] fn helper() { let _ = crate::other::Thing; }";
    let other = "// crate::count::scan::Scan in a comment\npub struct Thing; fn f() { let _ = crate::Scan; }";
    let lib = format!("{lib} mod other;");
    let tree =
        tree_of(&[("lib.rs", &lib), ("count/mod.rs", count), ("count/scan.rs", scan), ("other.rs", other)]);
    assert_eq!(cycle_report(&tree), Vec::<String>::new());
    let edges = crate_edges(&tree);
    let module = |s: &str| s.split("::").filter(|s| !s.is_empty()).map(String::from).collect::<Module>();
    assert_eq!(edges[&module("other")], BTreeSet::from([module("count::scan")]));
    assert!(
        !edges.contains_key(&module("count::scan")),
        "a test's or a parent's module is no edge: {edges:?}"
    );
}

#[test]
fn paths_are_resolved_from_where_they_are_named() {
    let modules: BTreeSet<Module> =
        [vec![], vec!["a".to_string()], vec!["a".into(), "b".into()]].into_iter().collect();
    let path = |s: &str| s.split("::").map(String::from).collect::<Vec<_>>();
    let scope = path("a::b");
    assert_eq!(absolute(&scope, &path("super::super::c::D"), &modules), Some(path("c::D")));
    assert_eq!(absolute(&scope, &path("self::x"), &modules), Some(path("a::b::x")));
    assert_eq!(absolute(&path("a"), &path("b::X"), &modules), Some(path("a::b::X")));
    assert_eq!(absolute(&scope, &path("std::fs"), &modules), None);
    assert_eq!(absolute(&scope, &path("super::super::super::x"), &modules), None);
    let mut tokens = Names::default();
    tokens.visit_macro(&syn::parse_quote!(format!("{}", crate::output::numbers::grouped(1))));
    assert!(
        tokens.paths.contains(&(Module::new(), path("crate::output::numbers::grouped"))),
        "{:?}",
        tokens.paths
    );
}
