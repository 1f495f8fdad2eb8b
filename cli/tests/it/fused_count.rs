//! `--count`: counting tiles straight from the GPU readback must give the
//! same `result.json`, byte for byte, as writing PNG tiles and analysing the
//! archive with `ufcsr::analyze` (trimming off: the fused path has no files
//! to trim, and the renderer already lists empty tiles as such).

use std::path::Path;
use std::process::Command;

use ufcsr::{AnalyzeOptions, Dedupe, TrimMode};

fn capture(out: &Path, extra: &[&str]) {
    let status = Command::new(env!("CARGO_BIN_EXE_ufcsr-capture"))
        .args(["demo", "--scenario", "B", "--out"])
        .arg(out)
        .args(["--ppd", "4", "--palette-size", "512", "-q"])
        .args(extra)
        .stdout(std::process::Stdio::null())
        .status()
        .expect("run ufcsr-capture");
    assert!(status.success(), "ufcsr-capture {extra:?} failed (is a Vulkan or GL driver installed?)");
}

fn analyse_png_archive(archive: &Path, dedupe: Dedupe, trim: TrimMode) -> Vec<u8> {
    // frames.csv and the measures on, as the CLI runs it and as --count tallies them.
    let options = AnalyzeOptions {
        archive: archive.to_path_buf(),
        dedupe,
        trim,
        frames: true,
        ..AnalyzeOptions::default()
    };
    let mut analysis = ufcsr::analyze(&options, None).expect("analyse the PNG archive");
    let out = archive.join("png-results");
    let written = ufcsr::output::write_results(&mut analysis, &out).unwrap();
    std::fs::read(written.result_json).unwrap()
}

/// `result.json` with `settings.archive_identity` blanked: it digests the
/// manifest file (which each capture rewrites), not what was counted.
fn without_identity(bytes: &[u8]) -> Vec<u8> {
    let mut value: serde_json::Value = serde_json::from_slice(bytes).unwrap();
    value["settings"]["archive_identity"] = serde_json::Value::Null;
    serde_json::to_vec_pretty(&value).unwrap()
}

#[test]
fn counting_from_the_renderer_equals_the_png_round_trip() {
    let dir = tempfile::tempdir().unwrap();
    let archive = dir.path().join("archive");
    for (dedupe, flag) in [(Dedupe::Image, "image"), (Dedupe::Frame, "frame"), (Dedupe::EyePair, "eye-pair")]
    {
        capture(&archive, &["--frames", "0-180/3"]);
        let png = analyse_png_archive(&archive, dedupe, TrimMode::Off);
        let png_auto = analyse_png_archive(&archive, dedupe, TrimMode::Auto);

        capture(&archive, &["--frames", "0-180/3", "--count", "--dedupe", flag]);
        // The archive identity digests the manifest on disk, which the --count run rewrote.
        let png = without_identity(&png);
        let png_auto = without_identity(&png_auto);
        let fused = without_identity(&std::fs::read(archive.join("results/result.json")).unwrap());
        // Per eye-frame and part: the same pixels, texels and solid angles, to the bit.
        let frames = |dir: &str| std::fs::read_to_string(archive.join(dir).join("frames.csv")).unwrap();
        assert_eq!(frames("png-results"), frames("results"), "--dedupe {flag}: frames.csv differs");
        // The per-texel angular area, summed by the same kernel pass from the
        // readback as from the decoded PNGs: the same integers, the same file.
        let area = |dir: &str| std::fs::read(archive.join(dir).join(ufcsr::TEXEL_AREA_FILE)).expect(dir);
        assert!(area("png-results") == area("results"), "--dedupe {flag}: texel-area.f32 differs");
        assert!(
            png == fused,
            "--count --dedupe {flag} differs from the PNG path:\n{}\n---\n{}",
            String::from_utf8_lossy(&png[..png.len().min(3000)]),
            String::from_utf8_lossy(&fused[..fused.len().min(3000)])
        );
        // No tile file is left behind, and the archive says so.
        let tiles = std::fs::read_dir(archive.join("tiles")).map(|d| d.count()).unwrap_or(0);
        assert_eq!(tiles, 0, "--count wrote or kept tiles");

        // With default trimming only the trimming report may differ.
        let strip = |bytes: &[u8]| {
            let mut value: serde_json::Value = serde_json::from_slice(bytes).unwrap();
            value["settings"]["trim"] = serde_json::Value::Null;
            value
        };
        assert_eq!(strip(&png_auto), strip(&fused), "--dedupe {flag}: more than the trim report differs");
    }
}

#[test]
fn a_counted_archive_is_not_analysed_again_as_png() {
    let dir = tempfile::tempdir().unwrap();
    let archive = dir.path().join("archive");
    capture(&archive, &["--count", "--frames", "90-100"]);
    let options = AnalyzeOptions { archive: archive.clone(), ..AnalyzeOptions::default() };
    let error = ufcsr::analyze(&options, None).err().expect("a counted archive has no tiles to analyse");
    let message = error.to_string();
    assert!(message.contains("manifest.json") && message.contains("--count"), "{message}");
}

#[test]
fn a_small_study_compares_every_setting_with_the_finest() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("study");
    let status = Command::new(env!("CARGO_BIN_EXE_ufcsr-capture"))
        .args([
            "study",
            "demo",
            "--scenario",
            "B",
            "--ppd",
            "4,3",
            "--frame-step",
            "1,6",
            "--palette-size",
            "256",
            // Precision only (the accuracy against the exact measure: study_accuracy.rs).
            "--no-exact",
        ])
        .arg("--out")
        .arg(&out)
        .stdout(std::process::Stdio::null())
        .status()
        .expect("run ufcsr study");
    assert!(status.success());
    let study: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("study.json")).unwrap()).unwrap();
    let rows = study["rows"].as_array().unwrap();
    assert_eq!(rows.len(), 4);
    // The finest setting has no precision error and, without an exact
    // reference, is on the Pareto front.
    assert_eq!((rows[0]["ppd"].as_f64(), rows[0]["frame_step"].as_u64()), (Some(4.0), Some(1)));
    assert_eq!(rows[0]["precision"]["share_l1_pp"].as_f64(), Some(0.0));
    assert_eq!(rows[0]["pareto"].as_bool(), Some(true));
    assert!(rows.iter().all(|r| r["precision"]["share_l1_pp"].as_f64().unwrap() >= 0.0));
    assert!(rows.iter().all(|r| r["error_vs_exact"].is_null()));
    let csv = std::fs::read_to_string(out.join("study.csv")).unwrap();
    assert_eq!(csv.lines().count(), 5, "{csv}");
    assert!(out.join("study.svg").is_file());
}
