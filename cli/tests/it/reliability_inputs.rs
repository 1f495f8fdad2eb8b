//! Issue 19, inputs: no silent wrong number. A zlib stream without its
//! Adler-32 trailer (or with a wrong one the png crate never reads) fails
//! the tile or the PIdT; one tile reached under two paths counts once; an
//! earlier run's results inside an archive without a manifest are not
//! frames; a result of another schema, a blank JSON part name and an
//! interlaced tile's bad palette index are clear errors.

use crate::common;

use std::io::Write;
use std::path::Path;

use common::*;
use ufcsr::{AnalyzeOptions, analyze};

/// A PNG built by hand: IHDR fields, an optional PLTE, and the IDAT data
/// split into the given chunks.
fn png_bytes(width: u32, height: u32, color: [u8; 5], plte: Option<&[u8]>, idats: &[&[u8]]) -> Vec<u8> {
    let mut header = Vec::new();
    header.extend(width.to_be_bytes());
    header.extend(height.to_be_bytes());
    header.extend(color);
    let mut chunks: Vec<(&[u8; 4], &[u8])> = vec![(b"IHDR", &header)];
    chunks.extend(plte.map(|plte| (b"PLTE", plte)));
    chunks.extend(idats.iter().map(|idat| (b"IDAT", *idat)));
    chunks.push((b"IEND", &[]));
    png_from_chunks(&chunks)
}

const RGB8: [u8; 5] = [8, 2, 0, 0, 0];

/// The zlib stream (stored blocks) of RGB rows of packed colours, filter 0.
fn zlib_rows(width: u32, colors: &[u32]) -> Vec<u8> {
    let mut raw = Vec::new();
    for row in colors.chunks(width as usize) {
        raw.push(0u8);
        raw.extend(rgb_bytes(row));
    }
    let mut zlib = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::none());
    zlib.write_all(&raw).unwrap();
    zlib.finish().unwrap()
}

fn options(archive: &Path) -> AnalyzeOptions {
    small_palette_options(archive)
}

#[test]
fn a_tile_without_its_zlib_checksum_fails_instead_of_counting() {
    let dir = tempfile::tempdir().unwrap();
    let zlib = zlib_rows(2, &[1, BG]);
    let body = &zlib[..zlib.len() - 4];
    // Damaged: texel 1 became texel 2, and the trailer that would tell is gone.
    let mut damaged = body.to_vec();
    let pixel = damaged.windows(3).position(|w| w == [0, 0, 1]).unwrap() + 2;
    damaged[pixel] = 2;
    std::fs::write(dir.path().join("a.png"), png_bytes(2, 1, RGB8, None, &[&damaged])).unwrap();
    // Whole data but no trailer.
    std::fs::write(dir.path().join("b.png"), png_bytes(2, 1, RGB8, None, &[body])).unwrap();
    // A wrong trailer in its own IDAT chunk (the png crate stops reading after the last row).
    let mut wrong = zlib[zlib.len() - 4..].to_vec();
    wrong[0] ^= 0xFF;
    std::fs::write(dir.path().join("c.png"), png_bytes(2, 1, RGB8, None, &[body, &wrong])).unwrap();
    // The same, intact: counted.
    std::fs::write(dir.path().join("d.png"), png_bytes(2, 1, RGB8, None, &[body, &zlib[zlib.len() - 4..]]))
        .unwrap();
    let analysis = analyze(&options(dir.path()), None).unwrap();
    let result = &analysis.result;
    assert_eq!((result.images.decoded, result.images.failed), (1, 3), "{:?}", result.failures);
    for failure in &result.failures {
        assert!(failure.error.contains("Adler-32"), "{failure:?}");
    }
    assert_eq!((analysis.texel_counts[1], analysis.texel_counts[2]), (1, 0));
}

#[test]
fn a_pidt_without_its_zlib_checksum_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    rgb_png(&dir.path().join("archive/a.png"), 2, 1, &[1, BG]);
    let zlib = zlib_rows(4, &[0xFF0000; 16]);
    std::fs::write(dir.path().join("pidt.png"), png_bytes(4, 4, RGB8, None, &[&zlib[..zlib.len() - 4]]))
        .unwrap();
    std::fs::write(dir.path().join("parts.csv"), "name,color\nA,#FF0000\n").unwrap();
    let options = AnalyzeOptions {
        pidt: Some(dir.path().join("pidt.png")),
        legend: Some(dir.path().join("parts.csv")),
        ..options(&dir.path().join("archive"))
    };
    let error = failure(&options);
    assert!(error.contains("pidt.png") && error.contains("Adler-32"), "{error}");
}

/// A manifest listing `files` as the tiles of frame 0, left eye, one per column.
fn manifest_with(files: &[&str]) -> String {
    let tiles: Vec<String> = files
        .iter()
        .enumerate()
        .map(|(col, file)| format!(r#"{{"frame":0,"eye":"left","row":0,"col":{col},"file":"{file}"}}"#))
        .collect();
    format!(
        r#"{{"schema":"ufcsr-manifest/1","palette":{{"canonical":[4,4]}},"tiles":[{}]}}"#,
        tiles.join(",")
    )
}

#[test]
fn one_tile_listed_under_two_paths_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    rgb_png(&dir.path().join("tiles/x.png"), 2, 1, &[1, BG]);
    std::fs::write(dir.path().join("manifest.json"), manifest_with(&["tiles/x.png", "./tiles/./x.png"]))
        .unwrap();
    let error = failure(&AnalyzeOptions { archive: dir.path().to_path_buf(), ..Default::default() });
    assert!(error.contains("listed twice") && error.contains("manifest.json"), "{error}");
    #[cfg(unix)]
    {
        std::os::unix::fs::symlink(dir.path().join("tiles"), dir.path().join("alias")).unwrap();
        std::fs::write(dir.path().join("manifest.json"), manifest_with(&["tiles/x.png", "alias/x.png"]))
            .unwrap();
        let error = failure(&AnalyzeOptions { archive: dir.path().to_path_buf(), ..Default::default() });
        assert!(error.contains("same file"), "{error}");
    }
}

#[cfg(unix)]
#[test]
fn a_tile_reached_through_a_folder_link_counts_once_without_a_manifest() {
    let dir = tempfile::tempdir().unwrap();
    rgb_png(&dir.path().join("tiles/x.png"), 2, 1, &[1, BG]);
    std::os::unix::fs::symlink(dir.path().join("tiles"), dir.path().join("alias")).unwrap();
    let analysis = analyze(&options(dir.path()), None).unwrap();
    assert_eq!(analysis.result.images.decoded, 1);
    assert_eq!(analysis.texel_counts[1], 1, "one tile counted twice");
    assert_eq!(analysis.result.images.skipped, 1);
    assert!(
        analysis.result.warnings.iter().any(|w| w.contains("x.png") && w.contains("folder link")),
        "{:?}",
        analysis.result.warnings
    );
}

#[test]
fn an_earlier_runs_results_inside_the_archive_are_not_frames() {
    let dir = tempfile::tempdir().unwrap();
    rgb_png(&dir.path().join("a.png"), 2, 1, &[1, BG]);
    let mut analysis = analyze(&options(dir.path()), None).unwrap();
    // Written somewhere the next run does not exclude (not its --out).
    ufcsr::output::write_results(&mut analysis, &dir.path().join("old-results")).unwrap();
    rgb_png(&dir.path().join("old-results/plots/parts.png"), 2, 1, &[2, BG]);
    let analysis = analyze(&options(dir.path()), None).unwrap();
    assert_eq!(analysis.result.images.found, 1, "an earlier run's output was counted as a frame");
    assert_eq!(analysis.texel_counts[2], 0);
    // heatmap.png, plots/parts.png (and the plot PNGs the first run drew, with a font).
    assert!(analysis.result.images.skipped >= 2, "{:?}", analysis.result.images);
    assert!(
        analysis.result.warnings.iter().any(|w| w.contains("old-results") && w.contains("earlier run")),
        "{:?}",
        analysis.result.warnings
    );
}

#[test]
fn heatmap_refuses_a_result_of_another_schema() {
    let dir = tempfile::tempdir().unwrap();
    rgb_png(&dir.path().join("a.png"), 2, 1, &[1, BG]);
    let mut analysis = analyze(&options(dir.path()), None).unwrap();
    let written = ufcsr::output::write_results(&mut analysis, &dir.path().join("out")).unwrap();
    let text = std::fs::read_to_string(&written.result_json).unwrap();
    let newer = dir.path().join("newer.json");
    std::fs::write(&newer, text.replace("ufcsr-result/1", "ufcsr-result/2")).unwrap();
    let error = ufcsr::read_texel_counts(&newer).err().expect("a newer schema is refused").to_string();
    assert!(error.contains("ufcsr-result/2") && error.contains("update ufcsr"), "{error}");
    let output =
        analyzer().arg("heatmap").arg(&newer).arg("--out").arg(dir.path().join("h.png")).output().unwrap();
    assert_eq!(output.status.code(), Some(2));
    assert!(!dir.path().join("h.png").exists());
}

#[test]
fn a_json_legend_refuses_empty_and_blank_part_names() {
    for name in ["", "   "] {
        let text = format!(r##"[{{"name":"A","color":"#FF0000"}},{{"name":"{name}","color":"#00FF00"}}]"##);
        let error =
            ufcsr::Legend::parse(Path::new("legend.json"), text.into_bytes()).err().unwrap().to_string();
        assert!(
            error.contains("legend.json") && error.contains("part 2") && error.contains("blank"),
            "{error}"
        );
    }
}

#[test]
fn an_interlaced_indexed_tile_reports_the_image_row_of_a_bad_index() {
    // 8×8, 8-bit indexed, Adam7; all index 0 but pixel (2, 2), index 5 of 3.
    let (width, height) = (8u32, 8u32);
    let mut indices = [0u8; 64];
    indices[2 * 8 + 2] = 5;
    const PASSES: [(u32, u32, u32, u32); 7] =
        [(0, 0, 8, 8), (4, 0, 8, 8), (0, 4, 4, 8), (2, 0, 4, 4), (0, 2, 2, 4), (1, 0, 2, 2), (0, 1, 1, 2)];
    let mut raw = Vec::new();
    for (x0, y0, dx, dy) in PASSES {
        for y in (y0..height).step_by(dy as usize) {
            raw.push(0u8);
            raw.extend((x0..width).step_by(dx as usize).map(|x| indices[(y * width + x) as usize]));
        }
    }
    let mut zlib = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::default());
    zlib.write_all(&raw).unwrap();
    let zlib = zlib.finish().unwrap();
    let dir = tempfile::tempdir().unwrap();
    let plte = rgb_bytes(&[1, 2, BG]);
    std::fs::write(
        dir.path().join("a.png"),
        png_bytes(width, height, [8, 3, 0, 0, 1], Some(&plte), &[&zlib]),
    )
    .unwrap();
    let analysis = analyze(&options(dir.path()), None).unwrap();
    let failure = &analysis.result.failures[0];
    assert!(failure.error.contains("pixel (2, 2) has palette index 5"), "{}", failure.error);
}

/// `manifest_with`'s manifest with `field` set to `value` (a JSON value).
fn manifest_naming(field: &str, value: &str) -> String {
    let mut manifest = manifest_with(&["tiles/x.png"]);
    if field == "palette" {
        manifest = manifest.replace(r#""palette":{"canonical":[4,4]},"#, "");
    }
    format!("{},\"{field}\":{value}}}", manifest.trim_end_matches('}'))
}

#[test]
fn every_path_a_manifest_names_stays_inside_the_archive_folder() {
    let outside = tempfile::tempdir().unwrap();
    let dir = tempfile::tempdir().unwrap();
    rgb_png(&dir.path().join("tiles/x.png"), 2, 1, &[1, BG]);
    rgb_png(&outside.path().join("pidt.png"), 4, 4, &[1; 16]);
    let absolute = serde_json::to_string(&outside.path().join("pidt.png")).unwrap();
    let cases = [
        ("pidt", "\"../pidt.png\"".to_string()),
        ("pidt", absolute.clone()),
        ("parts", "\"../parts.csv\"".to_string()),
        ("palette", absolute),
        ("vehicle", "\"../vehicle.glb\"".to_string()),
    ];
    for (field, value) in cases {
        std::fs::write(dir.path().join("manifest.json"), manifest_naming(field, &value)).unwrap();
        let error = failure(&AnalyzeOptions { archive: dir.path().to_path_buf(), ..Default::default() });
        assert!(
            error.contains("manifest.json")
                && error.contains(field)
                && error.contains("inside the archive folder"),
            "{field} {value}: {error}"
        );
    }
    #[cfg(unix)]
    {
        // A tile or a PIdT that is a link to a file outside: refused, naming what it leads to.
        std::fs::rename(dir.path().join("tiles/x.png"), outside.path().join("x.png")).unwrap();
        std::os::unix::fs::symlink(outside.path().join("x.png"), dir.path().join("tiles/x.png")).unwrap();
        std::fs::write(dir.path().join("manifest.json"), manifest_with(&["tiles/x.png"])).unwrap();
        let error = failure(&AnalyzeOptions { archive: dir.path().to_path_buf(), ..Default::default() });
        assert!(
            error.contains("tiles/x.png") && error.contains("leads outside the archive folder"),
            "{error}"
        );
        std::os::unix::fs::symlink(outside.path().join("pidt.png"), dir.path().join("pidt.png")).unwrap();
        std::fs::remove_file(dir.path().join("tiles/x.png")).unwrap();
        rgb_png(&dir.path().join("tiles/x.png"), 2, 1, &[1, BG]);
        std::fs::write(dir.path().join("manifest.json"), manifest_naming("pidt", "\"pidt.png\"")).unwrap();
        let error = failure(&AnalyzeOptions { archive: dir.path().to_path_buf(), ..Default::default() });
        assert!(error.contains("pidt pidt.png leads outside"), "{error}");
        // A link that stays inside the archive is fine.
        std::fs::create_dir(dir.path().join("elsewhere")).unwrap();
        std::fs::rename(dir.path().join("tiles/x.png"), dir.path().join("elsewhere/x.png")).unwrap();
        std::os::unix::fs::symlink(dir.path().join("elsewhere/x.png"), dir.path().join("tiles/x.png"))
            .unwrap();
        std::fs::write(dir.path().join("manifest.json"), manifest_with(&["tiles/x.png"])).unwrap();
        let analysis = analyze(&options(dir.path()), None).unwrap();
        assert_eq!(analysis.result.images.decoded, 1);
    }
}
