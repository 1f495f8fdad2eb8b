//! `ufcsr report`: the comparison page of two results of the bundled
//! example (per image and per frame) names both, ranks the second against the
//! first, draws both heatmaps in angular area on one scale (the count when a
//! result lacks `texel-area.f32`), and refuses a single result. Its rendering in a real browser is
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
            .args(["--dedupe", dedupe, "--texel-area", "on", "-q", "--out"])
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
    for text in [
        "per-image",
        "per-frame",
        "Kendall",
        "count ranking differences against per-image",
        "Ranking by angular area against per-image",
        "5 / 5",
        "deg²·s",
    ] {
        assert!(page.contains(text), "the page lacks {text:?}");
    }
    // The quoted measure leads: its table comes before the paper-compatible count shares.
    let at = |text: &str| page.find(text).unwrap_or_else(|| panic!("the page lacks {text:?}"));
    assert!(at(ufcsr::output::RANKED_HEADING) < at("Paper-compatible: count shares"));
    // One colour scale by default, and the page says so; the pictures are drawn again for it.
    assert!(page.contains(ufcsr::output::SHARED_SCALE) && !page.contains(ufcsr::output::OWN_SCALES));
    assert!(compared.join("result-1/views.png").is_file() && compared.join("result-2/views.png").is_file());
    // The heatmaps show the quoted measure, angular area, on one scale whose
    // top is the largest texel of either result (read back from texel-area.f32).
    assert!(page.contains(ufcsr::output::AREA_HEATMAPS) && !page.contains(ufcsr::output::COUNT_HEATMAPS));
    let summary = ufcsr::read_result_summary(&per_image.join("result.json")).unwrap();
    let (width, height) = (summary.settings.palette.width, summary.settings.palette.height);
    let largest = [&per_image, &per_frame]
        .iter()
        .flat_map(|dir| ufcsr::read_texel_area(&dir.join(ufcsr::TEXEL_AREA_FILE), width, height).unwrap())
        .fold(0f32, f32::max);
    assert!(largest > 0.0);
    assert!(
        page.contains(&format!("plasma from 0 to {largest:.3e} deg²·s per texel")),
        "the shared area scale's top is not the largest texel ({largest:.3e})"
    );
    // A result without per-texel areas: the page falls back to the count and says why.
    std::fs::remove_file(per_frame.join(ufcsr::TEXEL_AREA_FILE)).unwrap();
    let count_page = dir.path().join("compared-count");
    let output = Command::new(env!("CARGO_BIN_EXE_ufcsr-analyze"))
        .arg("report")
        .arg(&per_image)
        .arg(&per_frame)
        .arg("--out")
        .arg(&count_page)
        .output()
        .unwrap();
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    let page = std::fs::read_to_string(count_page.join("report.html")).unwrap();
    assert!(page.contains(ufcsr::output::COUNT_HEATMAPS) && page.contains("texel-area.f32"));
    assert!(page.contains("(the largest count of any result)"));
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

#[test]
fn labels_name_the_columns_and_own_scales_keeps_each_results_pictures() {
    let dir = tempfile::tempdir().unwrap();
    let example = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fixtures/example");
    let out = dir.path().join("capA").join("results");
    let status = Command::new(env!("CARGO_BIN_EXE_ufcsr-analyze"))
        .arg(&example)
        .args(["-q", "--views-scale", "1", "--out"])
        .arg(&out)
        .status()
        .unwrap();
    assert!(status.success());
    let compared = dir.path().join("compared");
    let output = Command::new(env!("CARGO_BIN_EXE_ufcsr-analyze"))
        .arg("report")
        .arg(&out)
        .arg(&out)
        .args(["--label", "60 px/°", "--label", "baseline", "--own-scales", "--out"])
        .arg(&compared)
        .output()
        .unwrap();
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    let page = std::fs::read_to_string(compared.join("report.html")).unwrap();
    assert!(page.contains("<th>60 px/°</th><th>baseline</th>"), "the labels are not the column headers");
    assert!(!page.contains("<th>capA</th>"), "the folder name is still a label");
    assert!(page.contains(ufcsr::output::OWN_SCALES) && !page.contains(ufcsr::output::SHARED_SCALE));
    assert!(compared.join("result-1-views.png").is_file());
    // More labels than results is a mistake, said before anything is written.
    let output = Command::new(env!("CARGO_BIN_EXE_ufcsr-analyze"))
        .arg("report")
        .arg(&out)
        .arg(&out)
        .args(["--label", "a", "--label", "b", "--label", "c", "--out"])
        .arg(dir.path().join("three"))
        .output()
        .unwrap();
    assert!(!output.status.success());
    assert!(String::from_utf8_lossy(&output.stderr).contains("3 labels"));
}

/// `--area-max` on the command line sets the top of the angular-area scale:
/// recorded in result.json and said on the page; 0 is refused by name.
#[test]
fn area_max_on_the_command_line_is_recorded_and_zero_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let example = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fixtures/example");
    let analyse = |max: &str, out: &std::path::Path| {
        Command::new(env!("CARGO_BIN_EXE_ufcsr-analyze"))
            .arg(&example)
            .args(["-q", "--views-scale", "1", "--texel-area", "on", "--area-max", max, "--out"])
            .arg(out)
            .output()
            .unwrap()
    };
    let out = dir.path().join("results");
    let output = analyse("0.001", &out);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    let json = std::fs::read_to_string(out.join("result.json")).unwrap();
    assert!(json.contains("\"heatmap_area_max\": 0.001"), "not recorded");
    let page = std::fs::read_to_string(out.join("report.html")).unwrap();
    assert!(page.contains("1.000e-3 deg²·s (--area-max)"), "the page does not say the scale's top");
    let output = analyse("0", &dir.path().join("zero"));
    assert!(!output.status.success());
    assert!(String::from_utf8_lossy(&output.stderr).contains("--area-max"));
}
