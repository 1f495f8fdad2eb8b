//! `docs/architecture.md` is checked against the tree: it names every
//! source folder of every crate (`src/…/`, `capture/src/…/`, and
//! `cli/src/…/` when that crate exists) as a path in backticks, and every
//! such folder path it names exists. A folder added, moved or removed
//! without the page saying so fails here, naming the folder.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

/// The source roots of the workspace's crates, relative to the repository.
const SOURCE_ROOTS: [&str; 3] = ["src", "capture/src", "cli/src"];

/// Every folder below `root` (relative to `repo`) that holds Rust or WGSL
/// source, as `root/a/b/`.
fn source_folders(repo: &Path, root: &str, found: &mut BTreeSet<String>) {
    let Ok(entries) = std::fs::read_dir(repo.join(root)) else { return };
    for entry in entries {
        let path = entry.unwrap().path();
        if path.is_dir() {
            let folder = format!("{root}/{}", path.file_name().unwrap().to_string_lossy());
            found.insert(format!("{folder}/"));
            source_folders(repo, &folder, found);
        }
    }
}

/// The folder paths a page names: backticked text that starts with a source
/// root and ends with `/` (`src/count/scan/`).
fn named_folders(page: &str) -> BTreeSet<String> {
    page.split('`')
        .skip(1)
        .step_by(2)
        .filter(|text| {
            text.ends_with('/') && SOURCE_ROOTS.iter().any(|root| text.starts_with(&format!("{root}/")))
        })
        .map(String::from)
        .collect()
}

/// What is wrong with the page against the folders: missing and stale paths.
fn page_problems(page: &str, folders: &BTreeSet<String>) -> Vec<String> {
    let named = named_folders(page);
    let missing = folders.difference(&named).map(|f| format!("`{f}` is not on the page"));
    let stale = named.difference(folders).map(|f| format!("`{f}` is on the page but not in the tree"));
    missing.chain(stale).collect()
}

#[test]
fn the_architecture_page_names_every_source_folder_and_no_other() {
    let repo = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let mut folders = BTreeSet::new();
    for root in SOURCE_ROOTS {
        source_folders(&repo, root, &mut folders);
    }
    assert!(folders.contains("capture/src/job/"), "is the tree where it was? {folders:?}");
    let page = std::fs::read_to_string(repo.join("docs/architecture.md")).unwrap();
    let problems = page_problems(&page, &folders);
    assert!(problems.is_empty(), "docs/architecture.md against the tree:\n{}", problems.join("\n"));
}

#[test]
fn a_folder_missing_from_the_page_or_gone_from_the_tree_is_named() {
    let folders: BTreeSet<String> =
        ["src/count/", "src/count/scan/", "capture/src/job/"].map(String::from).into();
    let page =
        "| `src/count/` | counting |\n| `capture/src/job/` | the job, `scripts/` |\n| `src/input/` | gone |";
    assert_eq!(
        page_problems(page, &folders),
        ["`src/count/scan/` is not on the page", "`src/input/` is on the page but not in the tree"]
    );
}
