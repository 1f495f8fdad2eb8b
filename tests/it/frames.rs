//! frames.csv and the resolution-independent measures: consistent with the
//! counts they sit beside, and no change to any existing field of
//! result.json or column of parts.csv.

use crate::common;

use std::path::{Path, PathBuf};

use ufcsr::{AnalyzeOptions, Dedupe, analyze, output::write_results};

fn example() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("fixtures/example")
}

fn run(options: &AnalyzeOptions, out: &Path) -> ufcsr::Analysis {
    let mut analysis = analyze(options, None).expect("analysis");
    write_results(&mut analysis, out).expect("write");
    analysis
}

/// `frames.csv` rows as (frame, eye, part, pixels, texels).
fn frame_rows(path: &Path) -> Vec<(u64, String, String, u64, u64)> {
    solid_angle_rows(path).into_iter().map(|(f, e, p, px, t, _)| (f, e, p, px, t)).collect()
}

/// `frames.csv` rows as (frame, eye, part, pixels, texels, solid angle in sr if known).
fn solid_angle_rows(path: &Path) -> Vec<(u64, String, String, u64, u64, Option<f64>)> {
    let mut reader = csv::Reader::from_path(path).expect("frames.csv");
    let header = reader.headers().unwrap().iter().collect::<Vec<_>>().join(",");
    assert_eq!(header, "frame,time_s,eye,distance_m,part,pixels,texels,solid_angle_sr");
    reader
        .records()
        .map(|row| {
            let row = row.unwrap();
            (
                row[0].parse().unwrap(),
                row[2].to_string(),
                row[4].to_string(),
                row[5].parse().unwrap(),
                row[6].parse().unwrap(),
                (!row[7].is_empty()).then(|| row[7].parse().unwrap()),
            )
        })
        .collect()
}

#[test]
fn frame_rows_add_up_to_the_counts() {
    let dir = tempfile::tempdir().unwrap();
    let options = AnalyzeOptions {
        archive: example(),
        dedupe: Dedupe::Frame,
        frames: true,
        ..AnalyzeOptions::default()
    };
    let analysis = run(&options, dir.path());
    let result = &analysis.result;
    let rows = frame_rows(&dir.path().join("frames.csv"));
    let solid = solid_angle_rows(&dir.path().join("frames.csv"));
    // Every eye-frame of the manifest (10 frames × 2 eyes), every part (+ unlabelled).
    let parts = result.parts.len() + 1;
    assert_eq!(rows.len(), 20 * parts);
    // Pixels by part add up to the texel pixels.
    assert_eq!(rows.iter().map(|r| r.3).sum::<u64>(), result.pixels.texel);
    // Once per eye-frame, a part's count total is the sum over eye-frames of its distinct texels seen.
    for part in &result.parts {
        let texels: u64 = rows.iter().filter(|r| r.2 == part.name).map(|r| r.4).sum();
        assert_eq!(texels, part.total, "{}", part.name);
    }
    // The measures sum the same rows.
    let measures = result.measures.as_ref().expect("measures");
    assert_eq!((measures.eyes, measures.eye_frames), (2, 20));
    let seconds = measures.seconds_per_frame.expect("fps in the manifest");
    assert!((seconds - 20.0 / 60.0).abs() < 1e-12, "every 20th frame at 60 fps: {seconds}");
    // The manifest gives the eyes' projection: every row has the solid angle of its pixels.
    assert!(solid.iter().all(|r| r.5.is_some_and(|sr| sr >= 0.0) && (r.3 == 0) == (r.5 == Some(0.0))));
    let deg2_per_sr = (180.0 / std::f64::consts::PI).powi(2);
    for part in &measures.parts {
        let pixels: u64 = rows.iter().filter(|r| r.2 == part.name).map(|r| r.3).sum();
        let seen = rows.iter().filter(|r| r.2 == part.name && r.3 > 0).count() as u64;
        assert_eq!((part.pixels, part.eye_frames_seen), (pixels, seen), "{}", part.name);
        let sr: f64 = solid.iter().filter(|r| r.2 == part.name).map(|r| r.5.unwrap()).sum();
        let area = sr * deg2_per_sr * seconds / 2.0;
        assert!((part.angular_area_deg2_s.unwrap() - area).abs() <= 1e-9 * area.max(1.0));
        // A pixel of this 107°, 640 px wide eye subtends at most the central pixel's solid angle.
        let pitch = 2.0 * (53.5f64).to_radians().tan() / 640.0;
        assert!(sr <= pixels as f64 * pitch * pitch * (1.0 + 1e-9), "{}", part.name);
        assert!((part.exposure_s.unwrap() - seen as f64 * seconds / 2.0).abs() < 1e-12);
        // Exposure cannot exceed the capture's length.
        assert!(part.exposure_s.unwrap() <= 10.0 * seconds + 1e-9);
    }
}

#[test]
fn frames_change_no_existing_field_or_column() {
    let dir = tempfile::tempdir().unwrap();
    for dedupe in [Dedupe::Image, Dedupe::Frame] {
        let off = AnalyzeOptions { archive: example(), dedupe, ..AnalyzeOptions::default() };
        let on = AnalyzeOptions { frames: true, ..off.clone() };
        run(&off, &dir.path().join("off"));
        run(&on, &dir.path().join("on"));
        let json = |name: &str| -> serde_json::Value {
            serde_json::from_slice(&std::fs::read(dir.path().join(name).join("result.json")).unwrap())
                .unwrap()
        };
        let mut with = json("on");
        assert!(with.as_object_mut().unwrap().remove("measures").is_some());
        assert_eq!(with, json("off"), "{dedupe:?}");
        assert!(!dir.path().join("off/frames.csv").exists());
        let csv = |name: &str| std::fs::read_to_string(dir.path().join(name).join("parts.csv")).unwrap();
        let (on_csv, off_csv) = (csv("on"), csv("off"));
        for (with, without) in on_csv.lines().zip(off_csv.lines()) {
            // Two more columns (part names here hold no commas).
            let kept: Vec<&str> = with.split(',').collect();
            assert_eq!(kept[..kept.len() - 2].join(","), without);
        }
        assert_eq!(on_csv.lines().count(), off_csv.lines().count());
    }
}

#[test]
fn without_a_manifest_there_is_a_row_block_per_image() {
    let dir = tempfile::tempdir().unwrap();
    let options = AnalyzeOptions {
        archive: example(),
        frames: true,
        ignore_manifest: true,
        ..AnalyzeOptions::default()
    };
    // Without the manifest the example has no PIdT: one pseudo-part for all texels.
    let options = AnalyzeOptions {
        palette: Some(ufcsr::PaletteChoice::Canonical { width: 512, height: 512 }),
        exclude: vec![example().join("pidt.png"), example().join("results")],
        ..options
    };
    let analysis = run(&options, dir.path());
    let rows = frame_rows(&dir.path().join("frames.csv"));
    assert_eq!(rows.len() as u64, analysis.result.images.decoded);
    assert!(rows.iter().all(|r| r.1.is_empty() && r.2 == "(all texels)"));
    assert_eq!(rows.iter().map(|r| r.3).sum::<u64>(), analysis.result.pixels.texel);
    assert_eq!(rows.iter().map(|r| r.4).sum::<u64>(), analysis.result.grand_total);
    let measures = analysis.result.measures.expect("measures");
    assert!(measures.parts[0].exposure_s.is_none() && !measures.notes.is_empty());
}

/// A stereo archive with a manifest: frame 0 shows texels {1, 2} to the left
/// eye (on two tiles, texel 2 on both) and {2, 3} to the right; frame 1
/// shows {2} to the left eye.
fn stereo_archive(dir: &Path) -> PathBuf {
    let archive = dir.join("stereo");
    std::fs::create_dir_all(&archive).unwrap();
    let bg = 0x000FFF;
    common::rgb_png(&archive.join("f0-left-0.png"), 2, 1, &[1, 2]);
    common::rgb_png(&archive.join("f0-left-1.png"), 2, 1, &[2, bg]);
    common::rgb_png(&archive.join("f0-right-0.png"), 2, 1, &[2, 3]);
    common::rgb_png(&archive.join("f1-left-0.png"), 2, 1, &[2, 2]);
    let tile = |file: &str, frame: u32, eye: &str, col: u32| serde_json::json!({"file": file, "frame": frame, "eye": eye, "row": 0, "col": col});
    let manifest = serde_json::json!({
        "schema": "ufcsr-manifest/1",
        "palette": {"canonical": [4, 4]},
        "background": ["#000FFF"],
        "tiles": [
            tile("f0-left-0.png", 0, "left", 0), tile("f0-left-1.png", 0, "left", 1),
            tile("f0-right-0.png", 0, "right", 0), tile("f1-left-0.png", 1, "left", 0),
        ],
    });
    std::fs::write(archive.join("manifest.json"), serde_json::to_vec(&manifest).unwrap()).unwrap();
    archive
}

#[test]
fn eye_pair_counts_a_texel_once_per_frame_over_both_eyes() {
    let dir = tempfile::tempdir().unwrap();
    let archive = stereo_archive(dir.path());
    let counts = |dedupe: Dedupe, frames: bool| {
        let options =
            AnalyzeOptions { archive: archive.clone(), dedupe, frames, ..AnalyzeOptions::default() };
        analyze(&options, None).expect("analysis").texel_counts[1..4].to_vec()
    };
    for frames in [false, true] {
        assert_eq!(counts(Dedupe::Image, frames), [1, 4, 1], "once per tile");
        assert_eq!(counts(Dedupe::Frame, frames), [1, 3, 1], "once per eye-frame");
        assert_eq!(counts(Dedupe::EyePair, frames), [1, 2, 1], "once per frame over both eyes");
    }
    // frames.csv keeps one block per eye-frame whatever the dedupe rule.
    let out = dir.path().join("out");
    let options = AnalyzeOptions {
        archive: archive.clone(),
        dedupe: Dedupe::EyePair,
        frames: true,
        ..AnalyzeOptions::default()
    };
    run(&options, &out);
    let rows = frame_rows(&out.join("frames.csv"));
    let expected = [(0, "left", 3, 2), (0, "right", 2, 2), (1, "left", 2, 1)];
    let got: Vec<(u64, &str, u64, u64)> = rows.iter().map(|r| (r.0, r.1.as_str(), r.3, r.4)).collect();
    assert_eq!(got, expected);
    // Measures without fps are omitted, with a note.
    let measures = analyze(&options, None).unwrap().result.measures.unwrap();
    assert_eq!(measures.eyes, 2);
    assert!(measures.parts[0].exposure_s.is_none() && !measures.notes.is_empty());
    // Eye-pair needs the manifest and refuses shards.
    let sharded = AnalyzeOptions { shard: Some(ufcsr::Shard::new(0, 2).unwrap()), ..options.clone() };
    assert!(analyze(&sharded, None).err().unwrap().to_string().contains("eye-pair"));
    assert_eq!("eye-pair".parse::<Dedupe>().unwrap(), Dedupe::EyePair);
}
