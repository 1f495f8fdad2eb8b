//! No path is opened outside the file layer, by std or by a dependency
//! (issue 41). clippy.toml forbade `std::fs`, but `csv::Writer::from_path`
//! wrote `results/unobstructed-parts.csv` through a link planted there (and
//! blocked on a FIFO), and plotters' `SVGBackend::new` wrote `study.svg`
//! through one: dependencies open paths themselves. clippy (with the type
//! information) holds the rule in CI; this test holds the list: every
//! path-taking function and type of std and of the dependencies that is
//! known here must be in clippy.toml, and the source of the three crates,
//! read with `syn`, must call none of them outside `src/files/` in code
//! that is not a test — so a new path-taking constructor fails here even
//! when nobody runs clippy, and removing an entry from clippy.toml fails too.
//!
//! A call is recognised as written, with the file's `use` declarations
//! applied to its first segment (`use csv::Writer as W; W::from_path(p)` is
//! `csv::Writer::from_path`), by its full path or its last two segments
//! (`SVGBackend::new` under `use plotters::prelude::*`); a method call by
//! names only path-taking dependency methods bear (`.from_path(p)` on a
//! `csv::WriterBuilder`); a type by its name anywhere in a path. Calls inside
//! macro arguments are not seen (clippy sees them).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use syn::visit::Visit;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The path-taking functions of std and of every dependency the three
/// crates use (csv, plotters, gltf, tobj, tempfile, clap_complete,
/// clap_mangen; image for when it becomes one), as clippy.toml spells them.
/// png, serde_json, walkdir (listing only), regex, wgpu, ab_glyph,
/// indicatif and the rest take no path.
pub(crate) const PATH_TAKING: &[&str] = &[
    "std::fs::write",
    "std::fs::read",
    "std::fs::read_to_string",
    "std::fs::rename",
    "std::fs::copy",
    "std::fs::create_dir",
    "std::fs::create_dir_all",
    "std::fs::remove_file",
    "std::fs::remove_dir",
    "std::fs::remove_dir_all",
    "std::fs::File::create",
    "std::fs::File::create_new",
    "std::fs::File::open",
    "std::fs::OpenOptions::open",
    "std::fs::DirBuilder::create",
    "std::fs::hard_link",
    "std::fs::soft_link",
    "std::os::unix::fs::symlink",
    "std::fs::set_permissions",
    "csv::Reader::from_path",
    "csv::ReaderBuilder::from_path",
    "csv::Writer::from_path",
    "csv::WriterBuilder::from_path",
    "plotters::prelude::SVGBackend::new",
    "plotters::prelude::BitMapBackend::new",
    "gltf::Gltf::open",
    "gltf::import",
    "gltf::import_buffers",
    "gltf::import_images",
    "gltf::buffer::Data::from_source",
    "gltf::image::Data::from_source",
    "tobj::load_obj",
    "tobj::load_mtl",
    "tempfile::tempfile_in",
    "tempfile::tempdir_in",
    "tempfile::spooled_tempfile_in",
    "tempfile::Builder::tempfile_in",
    "tempfile::Builder::tempdir_in",
    "tempfile::TempDir::new_in",
    "tempfile::TempDir::with_prefix_in",
    "tempfile::TempDir::with_suffix_in",
    "tempfile::NamedTempFile::new_in",
    "tempfile::NamedTempFile::with_prefix_in",
    "tempfile::NamedTempFile::with_suffix_in",
    "tempfile::NamedTempFile::persist",
    "tempfile::NamedTempFile::persist_noclobber",
    "tempfile::TempPath::persist",
    "tempfile::TempPath::persist_noclobber",
    "tempfile::SpooledTempFile::new_in",
    "clap_complete::generate_to",
    "clap_mangen::generate_to",
    "clap_mangen::Man::generate_to",
    "image::open",
    "image::image_dimensions",
    "image::ImageReader::open",
    "image::save_buffer",
    "image::save_buffer_with_format",
    "image::DynamicImage::save",
    "image::DynamicImage::save_with_format",
    "image::ImageBuffer::save",
    "image::ImageBuffer::save_with_format",
];

/// Types whose purpose is a file at a path.
const PATH_TYPES: &[&str] = &[
    "std::fs::OpenOptions",
    "std::fs::DirBuilder",
    "tempfile::NamedTempFile",
    "tempfile::TempPath",
    "tempfile::SpooledTempFile",
];

/// Method names that only path-taking methods of the dependencies bear,
/// caught when called on a value whose type syn cannot know.
const PATH_METHODS: &[&str] = &[
    "from_path",
    "persist",
    "persist_noclobber",
    "generate_to",
    "tempfile_in",
    "tempdir_in",
    "save_with_format",
];

/// The `path = "…"` entries of clippy.toml's list `key` (`disallowed-methods`).
fn clippy_list(key: &str) -> Vec<(String, String)> {
    let config = std::fs::read_to_string(root().join("clippy.toml")).unwrap();
    let start = config.find(&format!("{key} = [")).unwrap_or_else(|| panic!("clippy.toml has no {key}"));
    let body = &config[start..];
    let body = &body[..body.find("\n]").unwrap_or_else(|| panic!("clippy.toml: {key} is not closed"))];
    body.lines()
        .filter_map(|line| {
            let path = line.split("path = \"").nth(1)?.split('"').next()?.to_string();
            Some((path, line.to_string()))
        })
        .collect()
}

#[test]
fn clippy_toml_forbids_every_known_path_taking_function_and_type_naming_the_layer_s_way() {
    let methods = clippy_list("disallowed-methods");
    let types = clippy_list("disallowed-types");
    assert!(!methods.is_empty(), "clippy.toml's disallowed-methods is empty");
    assert!(!types.is_empty(), "clippy.toml's disallowed-types is empty");
    for (wanted, listed) in [(PATH_TAKING, &methods), (PATH_TYPES, &types)] {
        for path in wanted {
            assert!(listed.iter().any(|(p, _)| p == path), "clippy.toml does not forbid {path}");
        }
    }
    for (path, line) in methods.iter().chain(&types) {
        if path == "std::env::args" {
            continue; // not a file: std::env::args_os is the way
        }
        assert!(
            line.contains("reason = ") && line.contains("ufcsr::"),
            "{path}: its reason names no layer function"
        );
    }
}

/// A path's segments.
fn segments(path: &syn::Path) -> Vec<String> {
    path.segments.iter().map(|s| s.ident.to_string()).collect()
}

/// `use` trees flattened: the name each brings into scope and its path.
fn imports(tree: &syn::UseTree, prefix: &mut Vec<String>, out: &mut BTreeMap<String, Vec<String>>) {
    match tree {
        syn::UseTree::Path(p) => {
            prefix.push(p.ident.to_string());
            imports(&p.tree, prefix, out);
            prefix.pop();
        }
        syn::UseTree::Name(n) if n.ident != "self" => {
            out.insert(n.ident.to_string(), prefix.iter().cloned().chain([n.ident.to_string()]).collect());
        }
        syn::UseTree::Name(_) => {
            if let Some(last) = prefix.last() {
                out.insert(last.clone(), prefix.clone());
            }
        }
        syn::UseTree::Rename(r) => {
            out.insert(r.rename.to_string(), prefix.iter().cloned().chain([r.ident.to_string()]).collect());
        }
        syn::UseTree::Group(g) => g.items.iter().for_each(|item| imports(item, prefix, out)),
        syn::UseTree::Glob(_) => {}
    }
}

/// True for `#[test]`, `#[cfg(test)]` and `#[cfg(all(test, …))]`.
fn test_only(attrs: &[syn::Attribute]) -> bool {
    attrs.iter().any(|a| {
        a.path().is_ident("test")
            || (a.path().is_ident("cfg")
                && a.meta.require_list().is_ok_and(|list| {
                    list.tokens
                        .to_string()
                        .split(|c: char| !c.is_alphanumeric() && c != '_')
                        .any(|w| w == "test")
                }))
    })
}

/// Finds the path-taking calls and types in one file's code that is not a test.
struct Finder<'a> {
    imports: BTreeMap<String, Vec<String>>,
    functions: &'a [Vec<String>],
    types: &'a [Vec<String>],
    found: Vec<String>,
}

impl Finder<'_> {
    /// `path` with the file's `use` declarations applied to its first segment.
    fn expanded(&self, path: &syn::Path) -> Vec<String> {
        let mut written = segments(path);
        if path.leading_colon.is_none()
            && let Some(full) = written.first().and_then(|first| self.imports.get(first))
        {
            written.splice(0..1, full.iter().cloned());
        }
        written
    }
}

/// Whether `written` names `full`: all of it, or (two segments at least)
/// its end.
fn names(written: &[String], full: &[String]) -> bool {
    written == full || (written.len() >= 2 && full.ends_with(written))
}

impl<'ast> Visit<'ast> for Finder<'_> {
    fn visit_item(&mut self, item: &'ast syn::Item) {
        let attrs = match item {
            syn::Item::Fn(i) => &i.attrs,
            syn::Item::Mod(i) => &i.attrs,
            syn::Item::Impl(i) => &i.attrs,
            syn::Item::Const(i) => &i.attrs,
            syn::Item::Static(i) => &i.attrs,
            syn::Item::Use(i) => &i.attrs,
            _ => return syn::visit::visit_item(self, item),
        };
        if !test_only(attrs) {
            syn::visit::visit_item(self, item);
        }
    }

    fn visit_impl_item_fn(&mut self, item: &'ast syn::ImplItemFn) {
        if !test_only(&item.attrs) {
            syn::visit::visit_impl_item_fn(self, item);
        }
    }

    fn visit_expr_call(&mut self, call: &'ast syn::ExprCall) {
        if let syn::Expr::Path(function) = &*call.func {
            let written = self.expanded(&function.path);
            if let Some(full) = self.functions.iter().find(|full| names(&written, full)) {
                self.found.push(format!("{} (a call of {})", written.join("::"), full.join("::")));
            }
        }
        syn::visit::visit_expr_call(self, call);
    }

    fn visit_expr_method_call(&mut self, call: &'ast syn::ExprMethodCall) {
        let method = call.method.to_string();
        if PATH_METHODS.contains(&method.as_str()) {
            self.found.push(format!(".{method}(…) (a path-taking method of a dependency)"));
        }
        syn::visit::visit_expr_method_call(self, call);
    }

    fn visit_path(&mut self, path: &'ast syn::Path) {
        let written = self.expanded(path);
        for end in 1..=written.len() {
            let name = &written[end - 1];
            if let Some(full) = self.types.iter().find(|full| full.last() == Some(name)) {
                self.found.push(format!("{} (the type {})", written[..end].join("::"), full.join("::")));
            }
        }
        syn::visit::visit_path(self, path);
    }
}

/// The path-taking calls and types in `source`'s code that is not a test.
fn path_openers(source: &str, functions: &[Vec<String>], types: &[Vec<String>]) -> Vec<String> {
    let file = syn::parse_file(source).unwrap();
    let mut imported = BTreeMap::new();
    // Every `use` of the file, in modules too (a name means one thing per file here).
    struct Uses<'a>(&'a mut BTreeMap<String, Vec<String>>);
    impl<'ast> Visit<'ast> for Uses<'_> {
        fn visit_item_use(&mut self, item: &'ast syn::ItemUse) {
            imports(&item.tree, &mut Vec::new(), self.0);
        }
    }
    Uses(&mut imported).visit_file(&file);
    let mut finder = Finder { imports: imported, functions, types, found: Vec::new() };
    finder.visit_file(&file);
    finder.found
}

/// The lists as segments: the known ones and all clippy.toml forbids.
fn forbidden() -> (Vec<Vec<String>>, Vec<Vec<String>>) {
    let split = |path: &str| path.split("::").map(str::to_string).collect::<Vec<_>>();
    let mut functions: Vec<Vec<String>> = PATH_TAKING.iter().map(|p| split(p)).collect();
    functions.extend(clippy_list("disallowed-methods").iter().map(|(p, _)| split(p)));
    let mut types: Vec<Vec<String>> = PATH_TYPES.iter().map(|p| split(p)).collect();
    types.extend(clippy_list("disallowed-types").iter().map(|(p, _)| split(p)));
    functions.sort();
    functions.dedup();
    types.sort();
    types.dedup();
    (functions, types)
}

#[test]
fn the_finder_sees_a_path_taking_call_however_it_is_written_and_not_in_tests() {
    let (functions, types) = forbidden();
    let find = |source: &str| path_openers(source, &functions, &types);
    let caught = [
        "fn f(p: &Path) { let w = csv::Writer::from_path(p); }",
        "use plotters::prelude::*; fn f(p: &Path) { let r = SVGBackend::new(p, (9, 6)); }",
        "use plotters::prelude::BitMapBackend as B; fn f(p: &Path) { B::new(p, (9, 6)); }",
        "use csv::Writer as W; fn f(p: &Path) { W::from_path(p); }",
        "use std::fs; fn f(p: &Path) { fs::write(p, b\"\"); }",
        "use gltf::import; fn f(p: &Path) { import(p); }",
        "fn f(p: &Path) { csv::WriterBuilder::new().from_path(p); }",
        "fn f(p: &Path) { let b = std::fs::DirBuilder::new(); }",
        "use tempfile::NamedTempFile; struct S { file: NamedTempFile }",
        "impl S { fn f(&self, p: &Path) { tobj::load_obj(p, &Default::default()); } }",
    ];
    for source in caught {
        assert!(!find(source).is_empty(), "not caught: {source}");
    }
    let fine = [
        "use plotters::prelude::*; fn f(s: &mut String) { SVGBackend::with_string(s, (9, 6)); }",
        "fn f() { let w = csv::Writer::from_writer(Vec::new()); Gpu::create(backend); }",
        "fn f(p: &Path) { ufcsr::files::write_bytes_atomically(p, b\"\"); crate::files::open_regular(p); }",
        "#[cfg(test)] mod tests { fn f(p: &Path) { csv::Writer::from_path(p); std::fs::write(p, b\"\"); } }",
        "#[test] fn t() { std::fs::write(\"x\", b\"\").unwrap(); }",
        "impl S { #[cfg(test)] fn f(p: &Path) { gltf::Gltf::open(p); } }",
    ];
    for source in fine {
        assert_eq!(find(source), Vec::<String>::new(), "{source}");
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

/// The files and folders of modules declared `#[cfg(test)] mod name;`.
fn test_module_paths(files: &[PathBuf]) -> Vec<PathBuf> {
    let mut out = Vec::new();
    for file in files {
        let syntax = syn::parse_file(&std::fs::read_to_string(file).unwrap()).unwrap();
        let stem = file.file_stem().unwrap().to_string_lossy();
        let folder =
            if ["mod", "lib", "main"].contains(&stem.as_ref()) || file.parent().unwrap().ends_with("bin") {
                file.parent().unwrap().to_path_buf()
            } else {
                file.with_extension("")
            };
        for item in &syntax.items {
            if let syn::Item::Mod(m) = item
                && m.content.is_none()
                && test_only(&m.attrs)
            {
                out.push(folder.join(format!("{}.rs", m.ident)));
                out.push(folder.join(m.ident.to_string()));
            }
        }
    }
    out
}

#[test]
fn no_path_is_opened_outside_the_file_layer_by_std_or_a_dependency() {
    let (functions, types) = forbidden();
    let mut files = Vec::new();
    for dir in ["src", "capture/src", "cli/src"] {
        sources(&root().join(dir), &mut files);
    }
    let layer = root().join("src/files");
    let tests = test_module_paths(&files);
    let mut found = Vec::new();
    let mut read = 0;
    for file in &files {
        if file.starts_with(&layer) || tests.iter().any(|t| file.starts_with(t)) {
            continue;
        }
        read += 1;
        let text = std::fs::read_to_string(file).unwrap();
        for what in path_openers(&text, &functions, &types) {
            found.push(format!("{}: {what}", file.strip_prefix(root()).unwrap_or(file).display()));
        }
    }
    assert!(read > 100, "only {read} source files read: is the layout still src/, capture/src/, cli/src/?");
    assert!(
        found.is_empty(),
        "path-taking calls outside src/files/ (hand them bytes or an impl Write from the file layer: \
         ufcsr::files::write_atomically, write_bytes_atomically, read_limited, open_regular):\n{}",
        found.join("\n")
    );
}
