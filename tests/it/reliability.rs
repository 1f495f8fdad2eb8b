//! Reliability regressions found by hostile testing: special files never
//! hang, corrupted image data that keeps valid chunk CRCs is caught by the
//! zlib checksum, results never overwrite inputs, and trimming skips only
//! files byte-identical to a verified empty tile.

use crate::common;

use std::path::Path;
use std::sync::mpsc;
use std::time::Duration;

use common::*;
use ufcsr::{AnalyzeOptions, PaletteChoice, TrimMode, analyze};

const BACKGROUND: u32 = 0x000FFF;

/// An RGB PNG whose zlib stream uses stored (uncompressed) blocks: its size
/// depends only on its dimensions, and a changed pixel byte still inflates.
fn stored_png(path: &Path, width: u32, height: u32, colors: &[u32]) {
    let mut raw = Vec::new();
    for row in colors.chunks(width as usize) {
        raw.push(0u8);
        raw.extend(rgb_bytes(row));
    }
    png_from_filtered_rows(path, width, height, &raw, 0, flate2::Compression::none());
}

fn options(archive: &Path, trim: TrimMode) -> AnalyzeOptions {
    AnalyzeOptions {
        archive: archive.to_path_buf(),
        palette: Some(PaletteChoice::Canonical { width: 4, height: 4 }),
        trim,
        ..Default::default()
    }
}

/// Runs an analysis on a thread and fails (instead of hanging) after 30 s.
fn analyze_within_bounds(options: AnalyzeOptions) -> Result<ufcsr::Analysis, String> {
    let (sender, receiver) = mpsc::channel();
    std::thread::spawn(move || {
        let _ = sender.send(analyze(&options, None).map_err(|e| e.to_string()));
    });
    receiver.recv_timeout(Duration::from_secs(30)).expect("the analysis hung")
}

#[cfg(unix)]
fn mkfifo(path: &Path) {
    let status = std::process::Command::new("mkfifo").arg(path).status().expect("run mkfifo");
    assert!(status.success());
}

#[cfg(unix)]
#[test]
fn a_fifo_named_like_a_tile_is_reported_as_failed_not_waited_on() {
    let dir = tempfile::tempdir().unwrap();
    rgb_png(&dir.path().join("a.png"), 2, 1, &[1, BACKGROUND]);
    mkfifo(&dir.path().join("b.png"));
    let analysis = analyze_within_bounds(options(dir.path(), TrimMode::Auto)).unwrap();
    let result = &analysis.result;
    assert_eq!((result.images.decoded, result.images.failed), (1, 1));
    assert!(
        result.failures[0].file == "b.png" && result.failures[0].error.contains("FIFO"),
        "{:?}",
        result.failures
    );
}

#[cfg(unix)]
#[test]
fn a_fifo_as_manifest_or_legend_is_a_clear_error() {
    let dir = tempfile::tempdir().unwrap();
    rgb_png(&dir.path().join("a.png"), 2, 1, &[1, BACKGROUND]);
    mkfifo(&dir.path().join("manifest.json"));
    let error = analyze_within_bounds(options(dir.path(), TrimMode::Auto)).err().unwrap();
    assert!(error.contains("manifest.json") && error.contains("FIFO"), "{error}");

    let other = tempfile::tempdir().unwrap();
    rgb_png(&other.path().join("a.png"), 2, 1, &[1, BACKGROUND]);
    mkfifo(&other.path().join("legend.csv"));
    rgb_png(&other.path().join("pidt.png"), 4, 4, &[0xFF0000; 16]);
    let mut with_legend = options(other.path(), TrimMode::Auto);
    with_legend.legend = Some(other.path().join("legend.csv"));
    with_legend.pidt = Some(other.path().join("pidt.png"));
    let error = analyze_within_bounds(with_legend).err().unwrap();
    assert!(error.contains("legend.csv") && error.contains("FIFO"), "{error}");
}

#[test]
fn corrupted_image_data_with_valid_crcs_fails_the_zlib_checksum() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("a.png");
    stored_png(&path, 2, 1, &[1, BACKGROUND]);
    // Texel 1 is bytes 00 00 01 in the stored block; make it texel 2 and fix
    // the IDAT chunk's CRC, so only the zlib Adler-32 can tell.
    let mut bytes = std::fs::read(&path).unwrap();
    let idat = bytes.windows(4).position(|w| w == b"IDAT").unwrap();
    let length = u32::from_be_bytes(bytes[idat - 4..idat].try_into().unwrap()) as usize;
    let body = idat + 4..idat + 4 + length;
    let pixel = bytes[body.clone()].windows(4).position(|w| w == [0, 0, 0, 1]).unwrap() + body.start + 3;
    bytes[pixel] = 2;
    let mut crc = crc32fast::Hasher::new();
    crc.update(&bytes[idat..body.end]);
    bytes[body.end..body.end + 4].copy_from_slice(&crc.finalize().to_be_bytes());
    std::fs::write(&path, &bytes).unwrap();

    let analysis = analyze_within_bounds(options(dir.path(), TrimMode::Off)).unwrap();
    assert_eq!(
        (analysis.result.images.decoded, analysis.result.images.failed),
        (0, 1),
        "{:?}",
        analysis.result
    );
    assert_eq!(analysis.texel_counts.iter().sum::<u32>(), 0, "a corrupted image was counted");
}

#[test]
fn trimming_skips_only_files_identical_to_a_verified_empty_tile() {
    let dir = tempfile::tempdir().unwrap();
    // Stored blocks: all three files have the same size; c has a texel.
    stored_png(&dir.path().join("a.png"), 2, 1, &[BACKGROUND, BACKGROUND]);
    stored_png(&dir.path().join("b.png"), 2, 1, &[BACKGROUND, BACKGROUND]);
    stored_png(&dir.path().join("c.png"), 2, 1, &[3, BACKGROUND]);
    let sizes: Vec<u64> = ["a", "b", "c"]
        .iter()
        .map(|n| std::fs::metadata(dir.path().join(format!("{n}.png"))).unwrap().len())
        .collect();
    assert!(sizes.iter().all(|&s| s == sizes[0]), "{sizes:?}");
    let analysis = analyze_within_bounds(options(dir.path(), TrimMode::Auto)).unwrap();
    // a is the verified reference and b is identical to it: both trimmed.
    assert_eq!((analysis.result.images.trimmed, analysis.result.images.decoded), (2, 1));
    assert_eq!(
        analysis.texel_counts[3], 1,
        "c has the empty tile's size but other bytes: it must be counted"
    );
}

#[test]
fn results_never_overwrite_an_input() {
    let dir = tempfile::tempdir().unwrap();
    let archive = known_archive(dir.path());
    // The legend is called parts.csv and lives in the archive: --out ARCHIVE
    // would replace it with the output table.
    let legend = archive.join("parts.csv");
    std::fs::copy(dir.path().join("parts.csv"), &legend).unwrap();
    let mut options = known_options(dir.path());
    options.legend = Some(legend.clone());
    let before = std::fs::read(&legend).unwrap();
    let mut analysis = analyze(&options, None).unwrap();
    let error = ufcsr::output::write_results(&mut analysis, &archive).unwrap_err().to_string();
    assert!(error.contains("overwrite the input") && error.contains("parts.csv"), "{error}");
    assert_eq!(std::fs::read(&legend).unwrap(), before);
    // Anywhere else is fine.
    ufcsr::output::write_results(&mut analysis, &dir.path().join("results")).unwrap();
}

#[test]
fn a_huge_heatmap_maximum_builds_no_huge_table() {
    // --max 4000000000 used to allocate a colour per possible count (12 GB).
    let counts = [0u32, 1, 5, 2];
    let options = ufcsr::HeatmapOptions { scale: ufcsr::Scale::Linear, max: Some(4_000_000_000) };
    let rgb = ufcsr::output::render_heatmap(&counts, 2, options);
    assert_eq!(rgb.len(), 12);
    // Every count is far below the maximum: all at the bottom of the scale.
    assert_eq!(&rgb[3..6], &ufcsr::output::plasma(0.0));
}

#[test]
fn images_mostly_of_no_palette_colour_are_said_to_be_no_palette_renders_and_end_with_failures() {
    // All stray (an ordinary picture), then two stray against one palette pixel.
    for pixels in [&[0xFFFFFF, 0xFFFFFE][..], &[0xFFFFFF, 0xFFFFFE, 1][..]] {
        let dir = tempfile::tempdir().unwrap();
        rgb_png(&dir.path().join("a.png"), pixels.len() as u32, 1, pixels);
        let analysis = analyze_within_bounds(options(dir.path(), TrimMode::Off)).unwrap();
        assert!(!analysis.is_complete(), "{pixels:?}: exit 1, done with failures");
        let first = &analysis.result.warnings[0];
        assert!(first.contains("not palette renders") && first.contains("FCSP"), "{first}");
    }
    // A tie (one stray, one palette pixel) is a render with a stray pixel: complete.
    let dir = tempfile::tempdir().unwrap();
    rgb_png(&dir.path().join("a.png"), 2, 1, &[1, 0xFFFFFF]);
    assert!(analyze_within_bounds(options(dir.path(), TrimMode::Off)).unwrap().is_complete());
}

#[test]
fn stray_pixels_are_a_warning_in_result_json_too() {
    let dir = tempfile::tempdir().unwrap();
    rgb_png(&dir.path().join("a.png"), 2, 1, &[1, 0xFFFFFF]);
    let analysis = analyze_within_bounds(options(dir.path(), TrimMode::Off)).unwrap();
    assert_eq!(analysis.result.stray_pixels, 1);
    assert!(
        analysis.result.warnings.iter().any(|w| w.contains("1 stray pixels") && w.contains("1 images")),
        "{:?}",
        analysis.result.warnings
    );
}
