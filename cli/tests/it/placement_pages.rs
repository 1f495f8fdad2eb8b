//! The chosen placements shown (issue 18): `ufcsr placement` draws
//! the best sets on the archive's vehicle (`placement.png`,
//! `placement-views/`), a result's `report.html` shows the placement section
//! when a placement folder lies beside the result (and says so when it
//! cannot be read), and `ufcsr report` adds it when given a
//! placement folder. Known answers: on the bundled example's truck, `hood`
//! is legible 7 of 10 frames and `grill` the other 3, so the best one is
//! the hood alone (one colour) and the best two cover every frame (two).

use std::path::{Path, PathBuf};
use std::process::Command;

fn example() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fixtures/example")
}

/// An archive with the example's vehicle.glb and a table where `hood` is
/// legible in frames 0–6 and `grill` in 7–9 (`common::placement_archive`).
fn archive(dir: &Path) -> PathBuf {
    crate::common::placement_archive(dir, "archive", true)
}

/// Pixels of a PNG that are strongly orange (the first colour) and blue (the second).
fn orange_and_blue(path: &Path) -> (usize, usize) {
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
    let mut reader = decoder.read_info().unwrap();
    let mut pixels = vec![0; reader.output_buffer_size().unwrap()];
    let frame = reader.next_frame(&mut pixels).unwrap();
    let rgb = &pixels[..frame.buffer_size()];
    let orange =
        rgb.chunks_exact(3).filter(|p| p[0] > 110 && i32::from(p[0]) - i32::from(p[2]) > 100).count();
    let blue = rgb.chunks_exact(3).filter(|p| i32::from(p[2]) - i32::from(p[0]) > 80).count();
    (orange, blue)
}

fn analyze(args: &[&std::ffi::OsStr]) -> std::process::Output {
    let output = Command::new(env!("CARGO_BIN_EXE_ufcsr-analyze")).args(args).output().unwrap();
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    output
}

#[test]
fn the_best_sets_are_drawn_on_the_vehicle_and_shown_on_both_pages() {
    let dir = tempfile::tempdir().unwrap();
    let archive = archive(dir.path());
    let results = dir.path().join("results");
    let placement = results.join("placement");
    analyze(&[
        "placement".as_ref(),
        archive.as_os_str(),
        // Runs of 0.7 and 0.3 s: every legible frame counts.
        "--min-dwell-s".as_ref(),
        "0".as_ref(),
        "-q".as_ref(),
        "--out".as_ref(),
        placement.as_os_str(),
    ]);
    let document: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(placement.join("placement.json")).unwrap()).unwrap();
    assert_eq!(document["combinations"][0]["members"][0]["candidates"], serde_json::json!(["hood"]));
    let (orange, blue) = orange_and_blue(&placement.join("placement-views/part-best-1.png"));
    assert!(
        orange > 500 && blue == 0,
        "best 1: the hood in one colour ({orange} orange, {blue} blue pixels)"
    );
    let (orange, blue) = orange_and_blue(&placement.join("placement-views/part-best-2.png"));
    assert!(orange > 50 && blue > 50, "best 2: grill and hood in two colours ({orange}, {blue})");
    assert!(placement.join("placement.png").is_file());

    // The result's page, written with the placement folder beside it.
    analyze(&[example().as_os_str(), "-q".as_ref(), "--out".as_ref(), results.as_os_str()]);
    let page = std::fs::read_to_string(results.join("report.html")).unwrap();
    for text in
        ["Where should the eHMI go?", "ISO 9241-3", "src=\"placement/placement.png\"", "<td>hood</td>"]
    {
        assert!(page.contains(text), "report.html lacks {text:?}");
    }

    // `report` given one result and the placement folder.
    let compared = dir.path().join("compared");
    analyze(&[
        "report".as_ref(),
        results.as_os_str(),
        placement.as_os_str(),
        "--out".as_ref(),
        compared.as_os_str(),
    ]);
    let page = std::fs::read_to_string(compared.join("report.html")).unwrap();
    assert!(
        page.contains("Where should the eHMI go? (placement)") && page.contains("src=\"placement-1.png\"")
    );
    assert!(compared.join("placement-1.png").is_file());
}

#[test]
fn an_unreadable_placement_beside_a_result_is_a_warning_on_its_page() {
    let dir = tempfile::tempdir().unwrap();
    let results = dir.path().join("results");
    std::fs::create_dir_all(results.join("placement")).unwrap();
    std::fs::write(results.join("placement/placement.json"), "{\"schema\": \"ufcsr-result/1\"}").unwrap();
    analyze(&[example().as_os_str(), "-q".as_ref(), "--out".as_ref(), results.as_os_str()]);
    let page = std::fs::read_to_string(results.join("report.html")).unwrap();
    assert!(page.contains("class=\"warn\">") && page.contains("not a placement result"), "{page}");
}

#[cfg(unix)]
#[test]
fn report_keeps_a_result_folder_that_also_holds_a_placement_and_a_placement_views_link_is_not_followed() {
    let dir = tempfile::tempdir().unwrap();
    let archive = archive(dir.path());
    let first = dir.path().join("R1");
    let second = dir.path().join("R2");
    for results in [&first, &second] {
        analyze(&[example().as_os_str(), "-q".as_ref(), "--out".as_ref(), results.as_os_str()]);
    }
    // placement.json written into R1 itself, through a planted placement-views link.
    let elsewhere = dir.path().join("elsewhere");
    std::fs::create_dir(&elsewhere).unwrap();
    std::os::unix::fs::symlink(&elsewhere, first.join("placement-views")).unwrap();
    analyze(&[
        "placement".as_ref(),
        archive.as_os_str(),
        "--min-dwell-s".as_ref(),
        "0".as_ref(),
        "-q".as_ref(),
        "--mesh".as_ref(),
        example().join("vehicle.glb").as_os_str(),
        "--out".as_ref(),
        first.as_os_str(),
    ]);
    assert_eq!(std::fs::read_dir(&elsewhere).unwrap().count(), 0, "written through the placement-views link");
    assert!(!std::fs::symlink_metadata(first.join("placement-views")).unwrap().file_type().is_symlink());
    let compared = dir.path().join("compared");
    analyze(&[
        "report".as_ref(),
        first.as_os_str(),
        second.as_os_str(),
        "--out".as_ref(),
        compared.as_os_str(),
    ]);
    let page = std::fs::read_to_string(compared.join("report.html")).unwrap();
    assert!(page.contains("<th>R1</th><th>R2</th>"), "a result was dropped from the page");
    assert!(page.contains("Where should the eHMI go? (R1)"), "the placement was dropped from the page");
}
