//! Round trip: `ufcsr capture demo` at a low `--ppd` with a few frames, then
//! checks of the archive — our own (no stray pixel, every pixel's texel
//! labelled, hidden frames contribute nothing, frontal parts outrank rear
//! parts, same bytes on every run) and the analyzer's (`ufcsr::analyze`, the
//! library behind `ufcsr-analyze`), whose per-eye-frame part totals must
//! equal the independent tally made here.

use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::path::{Path, PathBuf};
use std::process::Command;

use ufcsr::{AnalyzeOptions, Color, Dedupe, Manifest};
use ufcsr_capture::{read_rgb_png, verify};

const FRONT: [&str; 3] = ["front_bumper", "grill", "hood"];
const REAR: [&str; 2] = ["tailgate", "rear_bumper"];

fn capture(out: &Path, extra: &[&str]) {
    let status = Command::new(env!("CARGO_BIN_EXE_ufcsr-capture"))
        .args(["demo", "--out"])
        .arg(out)
        .args(["--ppd", "3", "--palette-size", "256", "-q"])
        .args(extra)
        .status()
        .expect("run ufcsr-capture");
    assert!(status.success(), "ufcsr-capture failed (is a Vulkan or GL driver installed?)");
}

/// Per-part totals: each texel counted once per eye-frame, as the analyzer's
/// `--dedupe frame` would.
fn part_totals(dir: &Path) -> BTreeMap<String, u64> {
    let manifest = Manifest::load_from_dir(dir).unwrap().unwrap();
    let (size, pidt) = read_rgb_png(&dir.join("pidt.png")).unwrap();
    let legend = std::fs::read_to_string(dir.join("parts.csv")).unwrap();
    let names: HashMap<Color, String> = legend
        .lines()
        .skip(1)
        .filter_map(|line| line.rsplit_once(','))
        .map(|(name, color)| (color.parse().unwrap(), name.to_string()))
        .collect();
    let mut seen: BTreeMap<(u32, String), BTreeSet<u32>> = BTreeMap::new();
    for tile in &manifest.tiles {
        let Some(file) = &tile.file else { continue };
        let (_, rgb) = read_rgb_png(&dir.join(file)).unwrap();
        let texels = seen.entry((tile.frame, tile.eye.clone())).or_default();
        for p in rgb.chunks_exact(3) {
            let color = Color::from_rgb(p[0], p[1], p[2]);
            if color != Color::DEFAULT_BACKGROUND {
                texels.insert(color.packed());
            }
        }
    }
    let mut totals = BTreeMap::new();
    for texels in seen.values() {
        for &texel in texels {
            assert!(texel < size[0] * size[1]);
            let i = texel as usize * 3;
            let label = Color::from_rgb(pidt[i], pidt[i + 1], pidt[i + 2]);
            let name =
                names.get(&label).unwrap_or_else(|| panic!("texel {texel} has unlabelled colour {label}"));
            *totals.entry(name.clone()).or_insert(0) += 1;
        }
    }
    totals
}

fn sum(totals: &BTreeMap<String, u64>, parts: &[&str]) -> u64 {
    parts.iter().map(|p| totals.get(*p).copied().unwrap_or(0)).sum()
}

/// The analyzer on an archive with its manifest's settings.
fn analyze(archive: &Path, dedupe: Dedupe) -> ufcsr::Analysis {
    let options = AnalyzeOptions { archive: archive.to_path_buf(), dedupe, ..Default::default() };
    ufcsr::analyze(&options, None).expect("ufcsr::analyze")
}

#[test]
fn demo_capture_round_trips_through_the_checks_and_the_analyzer() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("demo");
    capture(&out, &["--scenario", "all", "--frames", "0-180/20"]);
    for scenario in ["A", "B", "C", "D"] {
        let archive = out.join(scenario);
        let (vehicle, stray) = verify(&archive).unwrap();
        assert_eq!(stray, 0, "scenario {scenario}");
        assert!(vehicle > 1000, "scenario {scenario}: {vehicle} vehicle pixels");

        // Frame 0: the truck is behind a corner building, so nothing of it is
        // written (tiles culled or rendered as pure background).
        let manifest = Manifest::load_from_dir(&archive).unwrap().unwrap();
        let first: Vec<_> = manifest.tiles.iter().filter(|t| t.frame == 0).collect();
        assert_eq!(first.len(), 50);
        assert!(first.iter().all(|t| t.empty), "scenario {scenario}: frame 0 has vehicle tiles");
        let frames = manifest.frame_records();
        assert_eq!(frames.len(), 10);
        assert_eq!(frames[9].time_s, Some(3.0));

        let totals = part_totals(&archive);
        let (front, rear) = (sum(&totals, &FRONT), sum(&totals, &REAR));
        eprintln!("scenario {scenario}: front {front}, rear {rear} texel-views");
        assert!(front > rear, "scenario {scenario}: front {front} ≤ rear {rear}");

        // The analyzer: no stray pixel, the hidden frame's tiles trimmed,
        // front beats rear, and per eye-frame totals equal the tally above.
        let per_image = analyze(&archive, Dedupe::Image);
        let result = &per_image.result;
        assert_eq!(result.stray_pixels, 0, "analyzer, scenario {scenario}");
        assert_eq!(result.images.failed, 0, "analyzer, scenario {scenario}");
        assert!(result.images.listed_empty >= 50, "frame 0 is listed empty");
        let total = |result: &ufcsr::AnalysisResult, names: &[&str]| -> u64 {
            result.parts.iter().filter(|p| names.contains(&p.name.as_str())).map(|p| p.total).sum()
        };
        let (front, rear) = (total(result, &FRONT), total(result, &REAR));
        assert!(front > rear, "analyzer, scenario {scenario}: front {front} ≤ rear {rear}");
        let per_frame = analyze(&archive, Dedupe::Frame);
        for part in &per_frame.result.parts {
            let expected = totals.get(&part.name).copied().unwrap_or(0);
            assert_eq!(part.total, expected, "scenario {scenario}, part {}", part.name);
        }
        assert_eq!(per_frame.result.unlabelled.as_ref().map(|u| u.total), Some(0));
    }
}

#[test]
fn captures_are_deterministic_and_resume_skips_written_tiles() {
    let dir = tempfile::tempdir().unwrap();
    let (one, two) = (dir.path().join("one"), dir.path().join("two"));
    for out in [&one, &two] {
        capture(out, &["--scenario", "D", "--frames", "120,180"]);
    }
    let files = |root: &Path| -> BTreeMap<PathBuf, Vec<u8>> {
        let mut files = BTreeMap::new();
        let mut stack = vec![root.to_path_buf()];
        while let Some(dir) = stack.pop() {
            for entry in std::fs::read_dir(&dir).unwrap() {
                let path = entry.unwrap().path();
                if path.is_dir() {
                    stack.push(path);
                } else {
                    files.insert(
                        path.strip_prefix(root).unwrap().to_path_buf(),
                        std::fs::read(&path).unwrap(),
                    );
                }
            }
        }
        files
    };
    let first = files(&one);
    assert!(first.keys().any(|p| p.starts_with("tiles")));
    assert!(first == files(&two), "two captures differ");
    // Resume: remove one tile and spoil another, capture again; both come
    // back and the rest are not rewritten.
    let mut tiles = first.keys().filter(|p| p.starts_with("tiles"));
    let (removed, spoiled) = (tiles.next().unwrap().clone(), tiles.next().unwrap().clone());
    std::fs::remove_file(one.join(&removed)).unwrap();
    std::fs::write(one.join(&spoiled), b"not a png").unwrap();
    capture(&one, &["--scenario", "D", "--frames", "120,180", "--resume"]);
    assert!(files(&one) == first, "resumed capture differs");
    // A fresh capture into the same folder removes tiles of the old one.
    std::fs::write(one.join("tiles/f0999_left_r0_c0.png"), b"stale").unwrap();
    capture(&one, &["--scenario", "D", "--frames", "120,180"]);
    assert!(files(&one) == first, "stale tile survived a fresh capture");
}

#[test]
fn committed_demo_archive_fixture_is_clean() {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fixtures/example");
    let (vehicle, stray) = verify(&dir).unwrap();
    assert_eq!(stray, 0);
    assert!(vehicle > 10_000, "{vehicle}");
    let manifest = Manifest::load_from_dir(&dir).unwrap().unwrap();
    assert_eq!(manifest.tiles.len(), 10 * 2 * 25);
    assert!(part_totals(&dir).get("windshield").copied().unwrap_or(0) > 0);
}

#[test]
fn verify_rejects_an_archive_with_a_stray_pixel() {
    let source = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fixtures/example");
    let dir = tempfile::tempdir().unwrap();
    let copy = dir.path().join("archive");
    std::fs::create_dir_all(copy.join("tiles")).unwrap();
    for file in ["manifest.json", "pidt.png", "parts.csv"] {
        std::fs::copy(source.join(file), copy.join(file)).unwrap();
    }
    let manifest = Manifest::load_from_dir(&source).unwrap().unwrap();
    let files: Vec<PathBuf> = manifest.tiles.iter().filter_map(|t| t.file.clone()).collect();
    for file in &files {
        std::fs::copy(source.join(file), copy.join(file)).unwrap();
    }
    let run = || Command::new(env!("CARGO_BIN_EXE_ufcsr-capture")).arg("verify").arg(&copy).output().unwrap();
    assert!(run().status.success());
    // White is index 16777215, far outside a 512² palette.
    let (size, mut rgb) = read_rgb_png(&copy.join(&files[0])).unwrap();
    rgb[..3].copy_from_slice(&[255, 255, 255]);
    ufcsr::files::write_rgb_png(&copy.join(&files[0]), [size[0], size[1]], &rgb, png::Compression::Fast)
        .unwrap();
    let output = run();
    assert!(!output.status.success());
    assert!(String::from_utf8_lossy(&output.stdout).contains("1 stray pixels"), "{output:?}");
}
