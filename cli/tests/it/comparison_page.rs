//! `ufcsr-analyze report`: the comparison page of two results of the bundled
//! example (per image and per frame) names both, ranks the second against the
//! first, and refuses a single result. Its rendering in a real browser is
//! checked by `tests/external/report_browser.rs` where Chromium is installed.

use std::path::PathBuf;
use std::process::Command;

#[test]
fn the_comparison_page_names_both_results_and_ranks_the_second_against_the_first() {
    let dir = tempfile::tempdir().unwrap();
    let example = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fixtures/example");
    let analyse = |name: &str, dedupe: &str| {
        let out = dir.path().join(name).join("results");
        let status = Command::new(env!("CARGO_BIN_EXE_ufcsr-analyze"))
            .arg(&example)
            .args(["--dedupe", dedupe, "-q", "--out"])
            .arg(&out)
            .status()
            .unwrap();
        assert!(status.success());
        out
    };
    let (per_image, per_frame) = (analyse("per-image", "image"), analyse("per-frame", "frame"));
    let compared = dir.path().join("compared");
    let output = Command::new(env!("CARGO_BIN_EXE_ufcsr-analyze"))
        .arg("report")
        .arg(&per_image)
        .arg(per_frame.join("result.json"))
        .arg("--out")
        .arg(&compared)
        .output()
        .unwrap();
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    let report = compared.join("report.html");
    let page = std::fs::read_to_string(&report).unwrap();
    // Labelled by the result folders' parents; both compared, the second against the first.
    for text in
        ["per-image", "per-frame", "Kendall", "Ranking differences against per-image", "5 / 5", "deg²·s"]
    {
        assert!(page.contains(text), "the page lacks {text:?}");
    }
    // One result alone is no comparison.
    let alone = Command::new(env!("CARGO_BIN_EXE_ufcsr-analyze"))
        .arg("report")
        .arg(&per_image)
        .arg("--out")
        .arg(dir.path().join("alone"))
        .output()
        .unwrap();
    assert!(!alone.status.success());
}
