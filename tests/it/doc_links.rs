//! The documentation's relative links resolve: every `[text](target)` in
//! `README.md`, `capture/README.md` and `docs/**/*.md` names a file or folder
//! that exists, and every `#anchor` names a heading of its target page (with
//! the anchors GitHub derives from headings). Links to other sites are not
//! followed.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

fn workspace() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The Markdown pages the links are checked in.
fn pages() -> Vec<PathBuf> {
    let root = workspace();
    let mut pages = vec![root.join("README.md"), root.join("capture/README.md")];
    let mut folders = vec![root.join("docs")];
    while let Some(folder) = folders.pop() {
        for entry in std::fs::read_dir(&folder).unwrap().flatten() {
            let path = entry.path();
            if path.is_dir() {
                folders.push(path);
            } else if path.extension().is_some_and(|e| e == "md") {
                pages.push(path);
            }
        }
    }
    pages.sort();
    pages
}

/// The page's text outside fenced code blocks, line by line.
fn prose_lines(text: &str) -> Vec<&str> {
    let mut in_fence = false;
    let mut lines = Vec::new();
    for line in text.lines() {
        if line.trim_start().starts_with("```") {
            in_fence = !in_fence;
        } else if !in_fence {
            lines.push(line);
        }
    }
    lines
}

/// GitHub's anchor for a heading: lower case, spaces to `-`, everything but
/// letters, digits, `-` and `_` dropped; repeats get `-1`, `-2`...
fn anchors(text: &str) -> BTreeSet<String> {
    let mut anchors = BTreeSet::new();
    for line in prose_lines(text) {
        let Some(heading) = line.strip_prefix('#') else { continue };
        let title = heading.trim_start_matches('#').trim();
        let slug: String = title
            .chars()
            .filter_map(|c| match c {
                ' ' => Some('-'),
                c if c.is_alphanumeric() || c == '-' || c == '_' => Some(c),
                _ => None,
            })
            .flat_map(char::to_lowercase)
            .collect();
        let mut unique = slug.clone();
        let mut repeat = 0;
        while anchors.contains(&unique) {
            repeat += 1;
            unique = format!("{slug}-{repeat}");
        }
        anchors.insert(unique);
    }
    anchors
}

/// Every link target of a line, `[text](target)` and `![alt](target)`,
/// outside inline code.
fn link_targets(line: &str) -> Vec<String> {
    let mut targets = Vec::new();
    let mut in_code = false;
    let bytes = line.as_bytes();
    let mut index = 0;
    while index < bytes.len() {
        match bytes[index] {
            b'`' => in_code = !in_code,
            b']' if !in_code && bytes.get(index + 1) == Some(&b'(') => {
                if let Some(length) = line[index + 2..].find(')') {
                    targets.push(line[index + 2..index + 2 + length].trim().to_string());
                    index += 2 + length;
                }
            }
            _ => {}
        }
        index += 1;
    }
    targets
}

fn broken_links(page: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(page).unwrap();
    let folder = page.parent().unwrap();
    let mut broken = Vec::new();
    for line in prose_lines(&text) {
        for target in link_targets(line) {
            if target.contains("://") || target.starts_with("mailto:") {
                continue;
            }
            let (file, anchor) = target.split_once('#').unwrap_or((&target, ""));
            let path = if file.is_empty() { page.to_path_buf() } else { folder.join(file) };
            if !path.exists() {
                broken.push(format!("{target}: no file {}", path.display()));
                continue;
            }
            if !anchor.is_empty() {
                let target_text = std::fs::read_to_string(&path).unwrap_or_default();
                if !anchors(&target_text).contains(anchor) {
                    broken.push(format!("{target}: no heading with the anchor #{anchor}"));
                }
            }
        }
    }
    broken
}

#[test]
fn every_relative_link_in_the_documentation_resolves() {
    let pages = pages();
    assert!(pages.len() > 3, "found only {pages:?}");
    let mut broken = Vec::new();
    for page in &pages {
        for problem in broken_links(page) {
            broken.push(format!("{}: {problem}", page.strip_prefix(workspace()).unwrap().display()));
        }
    }
    assert!(broken.is_empty(), "broken links:\n{}", broken.join("\n"));
}

#[test]
fn heading_anchors_follow_github() {
    let text = "# The analyzer: `ufcsr-analyze`\n## manifest.json (`ufcsr-manifest/1`)\n\
                ## Counting without PNGs: `--count`\n## Tests\n## Tests\n```\n# not a heading\n```\n";
    let expected = [
        "the-analyzer-ufcsr-analyze",
        "manifestjson-ufcsr-manifest1",
        "counting-without-pngs---count",
        "tests",
        "tests-1",
    ];
    assert_eq!(anchors(text), expected.iter().map(|a| a.to_string()).collect());
    assert_eq!(link_targets("see [a](x.md#b) and `[c](d)` ![e](f.png)"), ["x.md#b", "f.png"]);
}

/// The README stays a front page (issue 45): at most 200 lines, its first
/// commands the two a fresh machine runs (the bundled example, then the exact
/// test command `.ci/run` ends with), and no project history in user text.
#[test]
fn the_readme_is_at_most_200_lines_and_opens_with_the_two_commands() {
    let root = workspace();
    let readme = std::fs::read_to_string(root.join("README.md")).unwrap();
    let lines = readme.lines().count();
    assert!(lines <= 200, "README.md has {lines} lines (at most 200)");
    let fenced: Vec<&str> = readme
        .split("```")
        .skip(1)
        .step_by(2)
        .map(|block| block.trim().trim_start_matches("sh").trim())
        .collect();
    assert_eq!(fenced.first(), Some(&"cargo run --release -- fixtures/example"), "first command");
    assert_eq!(fenced.get(1), Some(&"cargo test --workspace --locked"), "second command");
    let ci = std::fs::read_to_string(root.join(".ci/run")).unwrap();
    let last = ci.lines().rev().find(|l| !l.trim().is_empty()).unwrap().trim();
    assert_eq!(last, "cargo test --workspace --locked", ".ci/run must end with the README's test command");
    for history in ["issue 3", "issue 4", "withdrawn", "measured before the study"] {
        assert!(!readme.contains(history), "README.md carries project history: {history:?}");
    }
}
