//! Issue 45 §5: a default analysis of the bundled example (`cargo run --
//! fixtures/example`, the README's first command) wrote 37 files, 18 of
//! them plot variants. By default it writes at most 20 — each figure once,
//! a plot as two-column PNG and PDF — and `--figures all` adds the variants
//! (SVGs, one-column plots, each view alone in `views/`).

use std::path::{Path, PathBuf};

/// Every file below `dir`, relative to it, sorted.
fn files_below(dir: &Path) -> Vec<String> {
    let mut found = Vec::new();
    let mut folders = vec![dir.to_path_buf()];
    while let Some(folder) = folders.pop() {
        for entry in std::fs::read_dir(&folder).unwrap().flatten() {
            if entry.file_type().unwrap().is_dir() {
                folders.push(entry.path());
            } else {
                found.push(entry.path().strip_prefix(dir).unwrap().to_string_lossy().into_owned());
            }
        }
    }
    found.sort();
    found
}

/// `cargo run -- fixtures/example --out OUT` (the workspace's default binary) with `extra`; the
/// files it wrote.
fn analyse_example(out: &Path, extra: &[&str]) -> Vec<String> {
    let example = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fixtures/example");
    let status =
        crate::common::analyzer().arg(&example).arg("--out").arg(out).arg("-q").args(extra).status().unwrap();
    assert!(status.success());
    files_below(out)
}

#[test]
fn a_default_analysis_of_the_example_writes_at_most_20_files_and_the_variants_on_request() {
    let dir = tempfile::tempdir().unwrap();
    let default = analyse_example(&dir.path().join("default"), &[]);
    assert!(default.len() <= 20, "{} files: {default:?}", default.len());
    // Each figure once: the page's PNG and the paper's PDF of every plot, the views' sheet.
    for plot in ["visibility-time", "visibility-distance", "parts"] {
        for ext in ["png", "pdf"] {
            assert!(default.contains(&format!("plots/{plot}.{ext}")), "no plots/{plot}.{ext}: {default:?}");
        }
    }
    assert!(default.iter().any(|f| f == "views.png") && default.iter().any(|f| f == "views.pdf"));
    assert!(!default.iter().any(|f| f.starts_with("views/") || f.contains("-1col") || f.ends_with(".svg")));
    let all = analyse_example(&dir.path().join("all"), &["--figures", "all"]);
    for variant in
        ["plots/parts.svg", "plots/parts-1col.pdf", "plots/visibility-time-1col.png", "views/front.png"]
    {
        assert!(all.iter().any(|f| f == variant), "--figures all wrote no {variant}");
    }
    assert!(default.iter().all(|f| all.contains(f)), "--figures all leaves out a default file");
}
