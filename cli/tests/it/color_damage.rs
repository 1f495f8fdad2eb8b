//! Colour-management and filtering damage is caught by name (issue 20
//! item 4): frames rendered correctly give no colour warning, and the same
//! frames damaged as wrong renderer settings damage them — antialiasing,
//! linear filtering, dithering, an sRGB/Raw mismatch, a Filmic-like tone
//! curve — each give the warning that names it; `--strict-colors` turns the
//! warnings into exit 2 with nothing written.
//!
//! The palette is canonical 4096×256: as on the full 4096² palette, nearly
//! every damaged colour is another palette colour (red stays below 16), so
//! stray pixels cannot reveal the damage.

use std::path::{Path, PathBuf};

use crate::common::{analyzer, rgb_png};

const BG: u32 = 0x000FFF;
const PALETTE_W: u32 = 4096;
const PALETTE_H: u32 = 256;
/// Frames of 512×512 pixels: four of them are 2^20 decoded pixels.
const SIDE: u32 = 512;
/// Two UV islands of 120×120 texels: their top-left texels.
const ISLANDS: [(f64, f64); 2] = [(100.0, 8.0), (2000.0, 130.0)];
const ISLAND: f64 = 120.0;
/// Pixels per texel of each frame: magnified, 1:1, minified, magnified.
const SCALES: [f64; 4] = [2.0, 1.0, 0.5, 2.0];

/// The continuous texel coordinate a pixel centre of frame `scale` shows,
/// or `None` for background: a square per island, side by side (a seam).
fn texel_at(x: u32, y: u32, scale: f64) -> Option<(f64, f64)> {
    let half = ISLAND * scale;
    let (left, top) = (f64::from(SIDE) / 2.0 - half, f64::from(SIDE) / 2.0 - half / 2.0);
    let (px, py) = (f64::from(x) + 0.5 - left, f64::from(y) + 0.5 - top);
    if px < 0.0 || py < 0.0 || px >= 2.0 * half || py >= half {
        return None;
    }
    let island = usize::from(px >= half);
    let (u0, v0) = ISLANDS[island];
    Some((u0 + (px - half * island as f64) / scale, v0 + py / scale))
}

fn color_of(u: u32, v: u32) -> u32 {
    v * PALETTE_W + u
}

/// A frame rendered correctly: nearest sampling.
fn correct_frame(scale: f64) -> Vec<u32> {
    (0..SIDE * SIDE)
        .map(|i| match texel_at(i % SIDE, i / SIDE, scale) {
            Some((u, v)) => color_of(u as u32, v as u32),
            None => BG,
        })
        .collect()
}

fn channels(color: u32) -> [f64; 3] {
    [f64::from(color >> 16), f64::from((color >> 8) & 0xFF), f64::from(color & 0xFF)]
}

fn pack(channels: [f64; 3]) -> u32 {
    let byte = |c: f64| c.round().clamp(0.0, 255.0) as u32;
    (byte(channels[0]) << 16) | (byte(channels[1]) << 8) | byte(channels[2])
}

/// Per-channel weighted mean of colours, as a renderer blends RGB8 samples.
fn blend(colors: &[(u32, f64)]) -> u32 {
    let mut sum = [0.0; 3];
    let total: f64 = colors.iter().map(|(_, w)| w).sum();
    for &(color, weight) in colors {
        for (s, c) in sum.iter_mut().zip(channels(color)) {
            *s += c * weight / total;
        }
    }
    pack(sum)
}

/// Antialiasing: every pixel the mean of its 2×2 block (a 2-pixel box filter).
fn antialiased(frame: &[u32]) -> Vec<u32> {
    let at = |x: u32, y: u32| frame[(y.min(SIDE - 1) * SIDE + x.min(SIDE - 1)) as usize];
    (0..SIDE * SIDE)
        .map(|i| {
            let (x, y) = (i % SIDE, i / SIDE);
            blend(&[(at(x, y), 1.0), (at(x + 1, y), 1.0), (at(x, y + 1), 1.0), (at(x + 1, y + 1), 1.0)])
        })
        .collect()
}

/// Linear filtering: the four texels around the sample point mixed bilinearly.
fn linear_frame(scale: f64) -> Vec<u32> {
    (0..SIDE * SIDE)
        .map(|i| match texel_at(i % SIDE, i / SIDE, scale) {
            Some((u, v)) => {
                let (u, v) = (u - 0.5, v - 0.5);
                let (u0, v0) = (u.floor(), v.floor());
                let (fu, fv) = (u - u0, v - v0);
                let (u0, v0) = (u0 as u32, v0 as u32);
                blend(&[
                    (color_of(u0, v0), (1.0 - fu) * (1.0 - fv)),
                    (color_of(u0 + 1, v0), fu * (1.0 - fv)),
                    (color_of(u0, v0 + 1), (1.0 - fu) * fv),
                    (color_of(u0 + 1, v0 + 1), fu * fv),
                ])
            }
            None => BG,
        })
        .collect()
}

/// Dithering: ±1 (or 0) of noise on every channel of every pixel.
fn dithered(frame: &[u32]) -> Vec<u32> {
    let mut state = 0x2545_F491_4F6C_DD1Du64;
    let mut noise = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state % 3) as f64 - 1.0
    };
    frame.iter().map(|&c| pack(channels(c).map(|v| v + noise()))).collect()
}

/// A per-channel tone curve on every pixel (values 0..1).
fn toned(frame: &[u32], curve: fn(f64) -> f64) -> Vec<u32> {
    frame.iter().map(|&c| pack(channels(c).map(|v| 255.0 * curve(v / 255.0)))).collect()
}

/// The sRGB/Raw mismatch: an sRGB texture decoded to linear and written as is.
fn srgb_decode(v: f64) -> f64 {
    if v <= 0.04045 { v / 12.92 } else { ((v + 0.055) / 1.055).powf(2.4) }
}

/// A Filmic-like S curve: darker shadows, brighter highlights.
fn s_curve(v: f64) -> f64 {
    v * v * (3.0 - 2.0 * v)
}

/// An archive of `frames` with the islands' PIdT and legend beside it.
fn archive(dir: &Path, name: &str, frames: &[Vec<u32>]) -> PathBuf {
    let archive = dir.join(name);
    for (i, frame) in frames.iter().enumerate() {
        rgb_png(&archive.join(format!("f{i:04}.png")), SIDE, SIDE, frame);
    }
    let pidt = dir.join("pidt.png");
    if !pidt.exists() {
        let labels: Vec<u32> = (0..PALETTE_W * PALETTE_H)
            .map(|texel| {
                let (u, v) = (f64::from(texel % PALETTE_W), f64::from(texel / PALETTE_W));
                let inside = |(u0, v0): (f64, f64)| u >= u0 && u < u0 + ISLAND && v >= v0 && v < v0 + ISLAND;
                if inside(ISLANDS[0]) {
                    0xFF0000
                } else if inside(ISLANDS[1]) {
                    0x00FF00
                } else {
                    0x000000
                }
            })
            .collect();
        rgb_png(&pidt, PALETTE_W, PALETTE_H, &labels);
        std::fs::write(dir.join("parts.csv"), "name,color\nbody,#FF0000\nglass,#00FF00\n").unwrap();
    }
    archive
}

fn options(dir: &Path, archive: &Path) -> ufcsr::AnalyzeOptions {
    ufcsr::AnalyzeOptions {
        archive: archive.to_path_buf(),
        palette: Some(ufcsr::PaletteChoice::Canonical { width: PALETTE_W, height: PALETTE_H }),
        pidt: Some(dir.join("pidt.png")),
        legend: Some(dir.join("parts.csv")),
        frames: false,
        ..Default::default()
    }
}

/// The checks of an analysis of `frames`, and its warnings.
fn checks(dir: &Path, name: &str, frames: &[Vec<u32>]) -> (ufcsr::ColorChecks, Vec<String>) {
    let archive = archive(dir, name, frames);
    let analysis = ufcsr::analyze(&options(dir, &archive), None).unwrap();
    let checks = analysis.result.color_checks.clone().expect("a pixel count has colour checks");
    eprintln!(
        "{name}: unlabelled {:?}, background {:?}, {:?}, jumps {:?}; stray {}",
        checks.unlabelled_count_share,
        checks.background_pixel_share,
        checks.neighbours,
        checks.jump_share,
        analysis.result.stray_pixels
    );
    (checks, analysis.result.warnings)
}

fn named(checks: &ufcsr::ColorChecks) -> Vec<&str> {
    checks.warnings.iter().map(|w| w.check.as_str()).collect()
}

fn correct_frames() -> Vec<Vec<u32>> {
    SCALES.iter().map(|&s| correct_frame(s)).collect()
}

#[test]
fn correct_frames_give_no_color_warning() {
    let dir = tempfile::tempdir().unwrap();
    let (checks, warnings) = checks(dir.path(), "correct", &correct_frames());
    assert_eq!(checks.warnings, [], "{warnings:?}");
    assert_eq!(checks.unlabelled_count_share, Some(0.0));
    assert!(checks.jump_share.unwrap() < 0.005, "{checks:?}");
    // (Other warnings, e.g. the resolution's, are not about colours.)
    assert!(
        !warnings.iter().any(|w| w.contains("colour damage") || w.contains("unlabelled")),
        "{warnings:?}"
    );
}

#[test]
fn blended_frames_are_flagged_as_texel_jumps() {
    let dir = tempfile::tempdir().unwrap();
    let aa: Vec<Vec<u32>> = correct_frames().iter().map(|f| antialiased(f)).collect();
    let linear: Vec<Vec<u32>> = SCALES.iter().map(|&s| linear_frame(s)).collect();
    let dither: Vec<Vec<u32>> = correct_frames().iter().map(|f| dithered(f)).collect();
    for (name, frames) in [("antialiased", aa), ("linear", linear), ("dithered", dither)] {
        let (checks, warnings) = checks(dir.path(), name, &frames);
        assert!(named(&checks).contains(&"texel-jumps"), "{name}: {checks:?}");
        let line = warnings.iter().find(|w| w.starts_with("colour damage (texel-jumps): ")).unwrap();
        assert!(
            line.contains("% of ") && line.contains("(threshold 3 %)") && line.contains("fix: "),
            "{line}"
        );
    }
}

#[test]
fn tone_curves_are_flagged_as_lost_background_and_unlabelled_counts() {
    let dir = tempfile::tempdir().unwrap();
    let srgb: Vec<Vec<u32>> = correct_frames().iter().map(|f| toned(f, srgb_decode)).collect();
    let filmic: Vec<Vec<u32>> = correct_frames().iter().map(|f| toned(f, s_curve)).collect();
    for (name, frames) in [("srgb-raw", srgb), ("s-curve", filmic)] {
        let (checks, warnings) = checks(dir.path(), name, &frames);
        let named = named(&checks);
        assert!(
            named.contains(&"unlabelled-counts") && named.contains(&"no-background"),
            "{name}: {checks:?}"
        );
        assert!(checks.background_pixel_share.unwrap() < 0.001, "{name}: {checks:?}");
        assert!(warnings.iter().any(|w| w.contains("% of counts on unlabelled texels (threshold 1 %)")));
    }
}

#[test]
fn strict_colors_fails_a_damaged_capture_and_passes_a_correct_one() {
    let dir = tempfile::tempdir().unwrap();
    let damaged: Vec<Vec<u32>> = correct_frames().iter().map(|f| antialiased(f)).collect();
    let run = |archive: &Path, out: &Path| {
        analyzer()
            .arg(archive)
            .args(["--palette-size", "4096x256", "--strict-colors", "-q", "--frames-csv", "off"])
            .arg("--pidt")
            .arg(dir.path().join("pidt.png"))
            .arg("--parts")
            .arg(dir.path().join("parts.csv"))
            .arg("--out")
            .arg(out)
            .output()
            .unwrap()
    };
    let archive_damaged = archive(dir.path(), "damaged", &damaged);
    let out = dir.path().join("out-damaged");
    let output = run(&archive_damaged, &out);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains(&archive_damaged.display().to_string()), "{stderr}");
    assert!(stderr.contains("colour damage (texel-jumps)") && stderr.contains("--strict-colors"), "{stderr}");
    assert!(!out.join("result.json").exists(), "nothing is written");

    let archive_correct = archive(dir.path(), "correct", &correct_frames());
    let output = run(&archive_correct, &dir.path().join("out-correct"));
    assert_eq!(output.status.code(), Some(0), "{}", String::from_utf8_lossy(&output.stderr));
}
