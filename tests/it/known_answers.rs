//! Known-answer tests: hand-computed counts, part statistics and heatmap pixels.

use crate::common;

use common::*;
use ufcsr::{AnalyzeOptions, Dedupe, PaletteChoice, TrimMode, analyze};
use ufcsr::{HeatmapOptions, Scale, output::plasma};

#[test]
fn counts_once_per_image_and_joins_parts() {
    let dir = tempfile::tempdir().unwrap();
    known_archive(dir.path());
    let analysis = analyze(&known_options(dir.path()), None).unwrap();
    let result = &analysis.result;

    let mut expected = vec![0u32; 16];
    (expected[1], expected[2], expected[3], expected[5]) = (2, 2, 1, 1);
    assert_eq!(analysis.texel_counts, expected);

    assert_eq!(
        (result.images.found, result.images.trimmed, result.images.decoded, result.images.failed),
        (5, 2, 3, 0)
    );
    assert_eq!(result.texels_seen, 4);
    assert_eq!(result.max_count, 2);
    assert_eq!((result.stray_pixels, result.stray_colors), (1, 1));
    assert_eq!(result.stray_color_examples[0].to_string(), "#FFFFFF");
    assert_eq!(result.background_pixels, 2);
    assert_eq!(result.images_with_stray_pixels[0].file, "d.png");

    assert_eq!(result.grand_total, 6);
    let a = &result.parts[0];
    assert_eq!((a.name.as_str(), a.texels, a.total, a.peak), ("A", 4, 5, 2));
    assert_eq!((a.average, a.coverage), (1.25, 75.0));
    assert!((a.share - 500.0 / 6.0).abs() < 1e-12);
    let b = &result.parts[1];
    assert_eq!((b.texels, b.total, b.peak, b.average, b.coverage), (4, 1, 1, 0.25, 25.0));
    let c = &result.parts[2];
    assert_eq!((c.texels, c.total, c.average, c.share), (0, 0, 0.0, 0.0));
    assert!(
        result.warnings.iter().any(|w| w.contains("\"C\"") && w.contains("no texels")),
        "{:?}",
        result.warnings
    );

    let unlabelled = result.unlabelled.as_ref().unwrap();
    assert_eq!((unlabelled.texels, unlabelled.total), (8, 0));
    assert_eq!(unlabelled.colors[0].color.to_string(), "#0A0000");
}

#[test]
fn a_json_legend_gives_the_same_table_as_the_csv() {
    let dir = tempfile::tempdir().unwrap();
    known_archive(dir.path());
    let legend = r##"[{"name": "A", "color": "#FF0000"}, {"name": "B", "color": "#00ff00"}, {"name": "C", "color": "#0000FF"}]"##;
    std::fs::write(dir.path().join("parts.json"), legend).unwrap();
    let csv = analyze(&known_options(dir.path()), None).unwrap();
    let json = analyze(
        &AnalyzeOptions { legend: Some(dir.path().join("parts.json")), ..known_options(dir.path()) },
        None,
    )
    .unwrap();
    assert_eq!(json.result.parts, csv.result.parts);

    std::fs::write(dir.path().join("bad.json"), r#"[{"name": "A"}]"#).unwrap();
    let error =
        failure(&AnalyzeOptions { legend: Some(dir.path().join("bad.json")), ..known_options(dir.path()) });
    assert!(error.contains("bad.json") && error.contains("color"), "{error}");
}

#[test]
fn heatmap_pixels_follow_plasma() {
    let counts = [0, 2, 2, 1, 0, 1];
    let linear = ufcsr::output::render_heatmap(&counts, 3, HeatmapOptions::default());
    assert_eq!(&linear[0..3], &ufcsr::output::NEVER_SEEN, "never-seen texels are the no-data grey");
    assert_eq!(&linear[3..6], &plasma(1.0));
    assert_eq!(&linear[9..12], &plasma(0.5));
    let log = ufcsr::output::render_heatmap(&counts, 3, HeatmapOptions { scale: Scale::Log, max: None });
    assert_eq!(&log[9..12], &plasma(2f64.ln() / 3f64.ln()));
    let shared =
        ufcsr::output::render_heatmap(&counts, 3, HeatmapOptions { scale: Scale::Linear, max: Some(4) });
    assert_eq!(&shared[3..6], &plasma(0.5));
}

#[test]
fn background_color_that_is_a_palette_color_is_ignored() {
    let dir = tempfile::tempdir().unwrap();
    let archive = dir.path().join("archive");
    rgb_png(&archive.join("a.png"), 2, 1, &[7, 3]);
    let options = AnalyzeOptions {
        archive,
        palette: Some(PaletteChoice::Canonical { width: 4, height: 4 }),
        background: Some(vec![ufcsr::Color::from_packed(7)]),
        ..Default::default()
    };
    let analysis = analyze(&options, None).unwrap();
    assert_eq!(analysis.texel_counts[7], 0);
    assert_eq!(analysis.texel_counts[3], 1);
    assert_eq!(analysis.result.grand_total, 1, "without a PIdT: the sum over all texels");
    assert_eq!(analysis.result.background_pixels, 1);
    assert!(!analysis.result.notes.is_empty());
}

#[test]
fn custom_palette_in_any_layout() {
    let dir = tempfile::tempdir().unwrap();
    // A 3×1 palette whose colours are nothing like their indices.
    rgb_png(&dir.path().join("palette.png"), 3, 1, &[0xABCDEF, 0x123456, 0x00FF00]);
    let archive = dir.path().join("archive");
    rgb_png(&archive.join("a.png"), 2, 2, &[0x123456, 0x123456, 0x000001, BG]);
    rgb_png(&archive.join("b.png"), 2, 1, &[0x123456, 0xABCDEF]);
    let options = AnalyzeOptions {
        archive,
        palette: Some(PaletteChoice::Image(dir.path().join("palette.png"))),
        trim: TrimMode::Off,
        ..Default::default()
    };
    let analysis = analyze(&options, None).unwrap();
    assert_eq!(analysis.texel_counts, vec![1, 2, 0]);
    assert_eq!(analysis.result.stray_pixels, 1, "#000001 is not in this palette");
}

#[test]
fn palette_with_repeated_color_is_rejected_with_position() {
    let dir = tempfile::tempdir().unwrap();
    rgb_png(&dir.path().join("palette.png"), 2, 2, &[1, 2, 3, 2]);
    std::fs::create_dir(dir.path().join("archive")).unwrap();
    let options = AnalyzeOptions {
        archive: dir.path().join("archive"),
        palette: Some(PaletteChoice::Image(dir.path().join("palette.png"))),
        ..Default::default()
    };
    let error = failure(&options);
    assert!(error.contains("palette.png") && error.contains("1 texels repeat"), "{error}");
    assert!(error.contains("(x 1, y 1)") && error.contains("(x 1, y 0)"), "{error}");
}

#[test]
fn frame_dedupe_counts_a_texel_once_per_eye_frame() {
    let dir = tempfile::tempdir().unwrap();
    let archive = dir.path().join("archive");
    // Frame 0, left eye: two tiles both show texel 1; right eye shows 1 once.
    rgb_png(&archive.join("f0_l_0.png"), 2, 1, &[1, 2]);
    rgb_png(&archive.join("f0_l_1.png"), 2, 1, &[1, BG]);
    rgb_png(&archive.join("f0_r_0.png"), 2, 1, &[1, BG]);
    let manifest = r#"{"schema": "ufcsr-manifest/1", "palette": {"canonical": [4, 4]}, "tiles": [
        {"file": "f0_l_0.png", "frame": 0, "eye": "left", "row": 0, "col": 0},
        {"file": "f0_l_1.png", "frame": 0, "eye": "left", "row": 0, "col": 1},
        {"file": "f0_r_0.png", "frame": 0, "eye": "right", "row": 0, "col": 0},
        {"frame": 0, "eye": "right", "row": 0, "col": 1, "empty": true}]}"#;
    std::fs::write(archive.join("manifest.json"), manifest).unwrap();
    let per_image =
        analyze(&AnalyzeOptions { archive: archive.clone(), ..Default::default() }, None).unwrap();
    assert_eq!(per_image.texel_counts[1], 3);
    assert_eq!(per_image.result.images.found, 4);
    assert_eq!(per_image.result.images.listed_empty, 1);
    assert_eq!(per_image.result.images.trimmed, 1);
    let per_frame = analyze(
        &AnalyzeOptions { archive: archive.clone(), dedupe: Dedupe::Frame, ..Default::default() },
        None,
    )
    .unwrap();
    assert_eq!(per_frame.texel_counts[1], 2);
    assert_eq!(per_frame.texel_counts[2], 1);
    let dedupe = per_frame.result.dedupe.as_ref().unwrap();
    assert_eq!((dedupe.grand_total_per_image, dedupe.grand_total_per_frame), (4, 3));
    assert!((dedupe.change_percent + 25.0).abs() < 1e-9);

    let no_manifest =
        AnalyzeOptions { archive, dedupe: Dedupe::Frame, ignore_manifest: true, ..Default::default() };
    let error = failure(&no_manifest);
    assert!(error.contains("manifest"), "{error}");
}

#[test]
fn result_json_round_trips_and_regenerates_the_heatmap() {
    let dir = tempfile::tempdir().unwrap();
    known_archive(dir.path());
    let heatmap = HeatmapOptions { scale: Scale::Log, max: Some(5) };
    let mut analysis = analyze(&AnalyzeOptions { heatmap, ..known_options(dir.path()) }, None).unwrap();
    let out = dir.path().join("out");
    let written = ufcsr::output::write_results(&mut analysis, &out).unwrap();
    let stored = ufcsr::read_texel_counts(&written.result_json).unwrap();
    assert_eq!(stored.texel_counts, analysis.texel_counts);
    assert_eq!((stored.width, stored.height, stored.scale, stored.max), (4, 4, Scale::Log, Some(5)));
    let summary = ufcsr::read_result_summary(&written.result_json).unwrap();
    assert_eq!(summary, analysis.result);
    // parts.csv in the report's words, precision and order (A 5, B 1, C 0).
    let csv = std::fs::read_to_string(written.parts_csv.unwrap()).unwrap();
    assert_eq!(
        csv,
        "part,texels,total,peak,average,share_percent,coverage_percent,texels_seen\n\
         A,4,5,2,1.250,83.333,75.00,3\nB,4,1,1,0.250,16.667,25.00,1\nC,0,0,0,0.000,0.000,0.00,0\n"
    );
}

#[test]
fn parts_csv_in_the_papers_style_keeps_the_old_columns_precision_and_legend_order() {
    let dir = tempfile::tempdir().unwrap();
    known_archive(dir.path());
    // Legend C, A, B: the paper's style keeps it; the report's sorts by total.
    std::fs::write(dir.path().join("parts.csv"), "name,color\nC,#0000FF\nA,#FF0000\nB,#00FF00\n").unwrap();
    let mut analysis = analyze(&known_options(dir.path()), None).unwrap();
    let out = dir.path().join("out");
    let written = ufcsr::output::write_results_with(
        &mut analysis,
        &out,
        &ufcsr::output::ResultSetOptions { csv_style: ufcsr::output::CsvStyle::Paper, ..Default::default() },
    )
    .unwrap();
    let csv = std::fs::read_to_string(written.parts_csv.unwrap()).unwrap();
    // As the library computes them: 100 × (total / grand total), unrounded.
    let (share_a, share_b) = (100.0 * (5.0_f64 / 6.0), 100.0 * (1.0_f64 / 6.0));
    assert_eq!(
        csv,
        format!(
            "part_name,pixel_count,part_total_value,highest_value,average_value,total_percentage,coverage\n\
             C,0,0,0,0,0,0\nA,4,5,2,1.25,{share_a},75\nB,4,1,1,0.25,{share_b},25\n"
        )
    );
    let report = ufcsr::output::write_results(&mut analysis, &out).unwrap();
    let csv = std::fs::read_to_string(report.parts_csv.unwrap()).unwrap();
    let rows: Vec<&str> = csv.lines().skip(1).map(|row| row.split(',').next().unwrap()).collect();
    assert_eq!(rows, ["A", "B", "C"]);
}
