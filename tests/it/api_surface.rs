//! The libraries' roots stay lists of entry points (issue 45 §7): at most 120
//! names re-exported at each crate root, and the public modules beside them are
//! the few documented ones (docs/architecture.md), each opening with a `//!`
//! doc. Counted from the sources with `syn`, so a new `pub use` at a root is
//! seen without building the crate's docs.

use std::path::Path;

use syn::{Item, UseTree};

/// The names one `use` tree brings in (a glob counts as one).
fn names(tree: &UseTree) -> usize {
    match tree {
        UseTree::Path(path) => names(&path.tree),
        UseTree::Name(_) | UseTree::Rename(_) | UseTree::Glob(_) => 1,
        UseTree::Group(group) => group.items.iter().map(names).sum(),
    }
}

/// (names re-exported at the root, the root's public modules).
fn surface(lib: &Path) -> (usize, Vec<String>) {
    let file = syn::parse_file(&std::fs::read_to_string(lib).unwrap()).unwrap();
    let mut count = 0;
    let mut modules = Vec::new();
    for item in &file.items {
        match item {
            Item::Use(u) if matches!(u.vis, syn::Visibility::Public(_)) => count += names(&u.tree),
            Item::Mod(m) if matches!(m.vis, syn::Visibility::Public(_)) => modules.push(m.ident.to_string()),
            _ => {}
        }
    }
    (count, modules)
}

#[test]
fn each_crate_root_exports_at_most_120_names_and_only_the_documented_modules() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    for (lib, allowed) in [
        ("src/lib.rs", &["files", "format", "output", "placement"][..]),
        ("capture/src/lib.rs", &["design", "fuzz_entry", "scene", "study"][..]),
    ] {
        let (count, modules) = surface(&root.join(lib));
        assert!(count <= 120, "{lib} re-exports {count} names at its root (at most 120)");
        for module in &modules {
            assert!(
                allowed.contains(&module.as_str()),
                "{lib}: public module {module} is not in docs/architecture.md"
            );
            let dir = root.join(lib).parent().unwrap().to_path_buf();
            let file = [dir.join(module).join("mod.rs"), dir.join(format!("{module}.rs"))]
                .into_iter()
                .find(|p| p.is_file())
                .unwrap();
            let text = std::fs::read_to_string(&file).unwrap();
            assert!(text.starts_with("//!"), "{} opens without a //! doc", file.display());
        }
    }
}
