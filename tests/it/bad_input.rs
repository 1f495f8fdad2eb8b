//! Bad input: every kind gets a clear message naming the file, is counted,
//! and never stops the batch (unless `--strict`) or panics.

use crate::common;

use common::*;
use ufcsr::{AnalyzeOptions, PaletteChoice, TrimMode, analyze};

fn options(archive: &std::path::Path) -> AnalyzeOptions {
    small_palette_options(archive)
}

#[test]
fn broken_files_are_reported_by_name_and_the_batch_goes_on() {
    let dir = tempfile::tempdir().unwrap();
    let archive = dir.path();
    rgb_png(&archive.join("good.png"), 2, 1, &[1, 2]);
    rgb_png(&archive.join("truncated.png"), 8, 8, &[3; 64]);
    let bytes = std::fs::read(archive.join("truncated.png")).unwrap();
    std::fs::write(archive.join("truncated.png"), &bytes[..bytes.len() - 20]).unwrap();
    let mut corrupt = std::fs::read(archive.join("good.png")).unwrap();
    let middle = corrupt.len() / 2 + 4;
    corrupt[middle] ^= 0xFF;
    std::fs::write(archive.join("corrupt.png"), corrupt).unwrap();
    std::fs::write(archive.join("zero.png"), b"").unwrap();
    std::fs::write(archive.join("text.png"), b"this is not a png").unwrap();
    write_png(&archive.join("deep.png"), 1, 1, png::ColorType::Rgb, png::BitDepth::Sixteen, &[0; 6], None);

    let analysis = analyze(&options(archive), None).unwrap();
    let result = &analysis.result;
    assert_eq!((result.images.found, result.images.decoded, result.images.failed), (6, 1, 5));
    assert_eq!(analysis.texel_counts[1..3], [1, 1], "the good image still counts");
    assert_eq!(analysis.texel_counts[3], 0, "nothing of a failed image is counted");
    let message = |file: &str| {
        result.failures.iter().find(|f| f.file == file).map(|f| f.error.clone()).unwrap_or_default()
    };
    assert!(message("truncated.png").contains("truncated.png"), "{}", message("truncated.png"));
    assert!(message("corrupt.png").contains("corrupt.png"));
    assert!(message("zero.png").contains("empty file (0 bytes)"), "{}", message("zero.png"));
    assert!(message("text.png").contains("not a PNG"), "{}", message("text.png"));
    assert!(message("deep.png").contains("16-bit"), "{}", message("deep.png"));

    let strict = AnalyzeOptions { strict: true, ..options(archive) };
    let error = failure(&strict);
    assert!(error.contains("--strict") && error.contains(".png"), "{error}");
}

#[test]
fn palette_grey_rgba_and_interlaced_pngs_decode_to_the_right_texels() {
    let dir = tempfile::tempdir().unwrap();
    let archive = dir.path();
    // Indexed: palette entries are texel 1, texel 2 and the background.
    let palette = rgb_bytes(&[1, 2, BG]);
    write_png(
        &archive.join("indexed.png"),
        3,
        1,
        png::ColorType::Indexed,
        png::BitDepth::Eight,
        &[0, 1, 2],
        Some(&palette),
    );
    // Low bit depth indexed (2 bits per pixel, 3 pixels in one byte).
    write_png(
        &archive.join("indexed2.png"),
        3,
        1,
        png::ColorType::Indexed,
        png::BitDepth::Two,
        &[0b01_10_00_00],
        Some(&palette),
    );
    // RGBA: alpha is ignored.
    write_png(
        &archive.join("rgba.png"),
        2,
        1,
        png::ColorType::Rgba,
        png::BitDepth::Eight,
        &[0, 0, 3, 0, 0, 0, 4, 255],
        None,
    );
    // Interlaced 9×9: every pixel texel 5 except one texel 6 and the background.
    let mut colors = vec![5u32; 81];
    colors[40] = 6;
    colors[0] = BG;
    interlaced_rgb_png(&archive.join("interlaced.png"), 9, 9, &colors);

    let analysis = analyze(&options(archive), None).unwrap();
    assert_eq!(analysis.result.images.failed, 0, "{:?}", analysis.result.failures);
    assert_eq!(analysis.texel_counts[1..7], [2, 2, 1, 1, 1, 1]);
    assert_eq!(analysis.result.stray_pixels, 0);
    assert_eq!(analysis.result.background_pixels, 1 + 1 + 1);
}

#[test]
fn grey_pngs_expand_to_equal_channels() {
    let dir = tempfile::tempdir().unwrap();
    write_png(
        &dir.path().join("grey.png"),
        3,
        1,
        png::ColorType::Grayscale,
        png::BitDepth::Eight,
        &[0, 1, 2],
        None,
    );
    write_png(
        &dir.path().join("grey_alpha.png"),
        1,
        1,
        png::ColorType::GrayscaleAlpha,
        png::BitDepth::Eight,
        &[2, 9],
        None,
    );
    let options =
        AnalyzeOptions { archive: dir.path().to_path_buf(), trim: TrimMode::Off, ..Default::default() };
    let analysis = analyze(&options, None).unwrap();
    assert_eq!(analysis.texel_counts[0], 1);
    assert_eq!(analysis.texel_counts[0x010101], 1);
    assert_eq!(analysis.texel_counts[0x020202], 2);
}

#[test]
fn tiles_of_mixed_sizes_are_all_counted() {
    let dir = tempfile::tempdir().unwrap();
    rgb_png(&dir.path().join("small.png"), 1, 1, &[1]);
    rgb_png(&dir.path().join("wide.png"), 5, 1, &[1, 2, 2, 2, BG]);
    rgb_png(&dir.path().join("tall.png"), 1, 3, &[BG, BG, 9]);
    let analysis = analyze(&options(dir.path()), None).unwrap();
    assert_eq!(analysis.texel_counts[1..3], [2, 1]);
    assert_eq!(analysis.texel_counts[9], 1);
}

#[test]
fn wrong_sizes_missing_partners_and_empty_folders_are_clear_errors() {
    let dir = tempfile::tempdir().unwrap();
    let archive = known_archive(dir.path());
    let wrong = AnalyzeOptions {
        palette: Some(PaletteChoice::Canonical { width: 8, height: 8 }),
        ..known_options(dir.path())
    };
    let error = failure(&wrong);
    assert!(error.contains("pidt.png") && error.contains("4×4") && error.contains("8×8"), "{error}");

    // A palette image whose size differs from the PIdT.
    rgb_png(&dir.path().join("palette.png"), 2, 1, &[1, 2]);
    let wrong_palette = AnalyzeOptions {
        palette: Some(PaletteChoice::Image(dir.path().join("palette.png"))),
        ..known_options(dir.path())
    };
    let error = failure(&wrong_palette);
    assert!(error.contains("pidt.png") && error.contains("expected 2×1"), "{error}");

    // A PIdT whose header claims 60000×60000 is rejected before decoding.
    let mut huge = std::fs::read(dir.path().join("pidt.png")).unwrap();
    huge[16..20].copy_from_slice(&60000u32.to_be_bytes());
    huge[20..24].copy_from_slice(&60000u32.to_be_bytes());
    std::fs::write(dir.path().join("huge.png"), huge).unwrap();
    let error =
        failure(&AnalyzeOptions { pidt: Some(dir.path().join("huge.png")), ..known_options(dir.path()) });
    assert!(error.contains("huge.png") && error.contains("60000×60000"), "{error}");

    let no_legend = AnalyzeOptions { legend: None, ..known_options(dir.path()) };
    assert!(failure(&no_legend).contains("--parts"));

    let empty = dir.path().join("empty");
    std::fs::create_dir(&empty).unwrap();
    let error = failure(&options(&empty));
    assert!(error.contains("empty") && error.contains("no PNG images"), "{error}");

    let missing = failure(&options(&dir.path().join("nowhere")));
    assert!(missing.contains("nowhere") && missing.contains("not a folder"), "{missing}");

    std::fs::write(dir.path().join("bad.csv"), "name,color\nHood,#12345\n").unwrap();
    let bad_legend = AnalyzeOptions { legend: Some(dir.path().join("bad.csv")), ..known_options(dir.path()) };
    let error = failure(&bad_legend);
    assert!(error.contains("bad.csv") && error.contains("line 2"), "{error}");
    drop(archive);
}

#[test]
fn manifest_listing_a_missing_file_counts_it_as_failed() {
    let dir = tempfile::tempdir().unwrap();
    rgb_png(&dir.path().join("a.png"), 1, 1, &[1]);
    let manifest = r#"{"palette": {"canonical": [4, 4]}, "tiles": [
        {"file": "a.png", "frame": 0, "eye": "left", "row": 0, "col": 0},
        {"file": "gone.png", "frame": 0, "eye": "left", "row": 0, "col": 1}]}"#;
    std::fs::write(dir.path().join("manifest.json"), manifest).unwrap();
    let analysis =
        analyze(&AnalyzeOptions { archive: dir.path().to_path_buf(), ..Default::default() }, None).unwrap();
    assert_eq!((analysis.result.images.decoded, analysis.result.images.failed), (1, 1));
    assert!(analysis.result.failures[0].error.contains("gone.png"));

    std::fs::write(dir.path().join("manifest.json"), "{\"tiles\": 3}").unwrap();
    let error = failure(&AnalyzeOptions { archive: dir.path().to_path_buf(), ..Default::default() });
    assert!(error.contains("manifest.json") && error.contains("invalid manifest"), "{error}");
}
