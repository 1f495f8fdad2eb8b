//! `ufcsr-capture` ends with the analyzer's exit codes: 0 done, 1 done but
//! with failures, 2 nothing done; `ufcsr --version` answers.

use std::path::Path;
use std::process::{Command, Output};

use ufcsr_capture::read_rgb_png;

fn capture(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_ufcsr-capture")).args(args).env("XDG_RUNTIME_DIR", dir).output().unwrap()
}

#[test]
fn the_capture_exits_0_when_done_1_with_failures_and_2_when_nothing_was_done() {
    let dir = tempfile::tempdir().unwrap();
    let archive = dir.path().join("archive");
    let archive_text = archive.to_str().unwrap();
    let small = ["--ppd", "2", "--palette-size", "256", "--frames", "180", "--out", archive_text];
    let done = capture(dir.path(), &[&["demo", "--scenario", "A"][..], &small].concat());
    assert_eq!(done.status.code(), Some(0), "{}", String::from_utf8_lossy(&done.stderr));
    assert_eq!(capture(dir.path(), &["verify", archive_text]).status.code(), Some(0));

    // One pixel of one tile turned to a colour outside the 256² palette: verify finishes, with failures.
    let tile = std::fs::read_dir(archive.join("tiles")).unwrap().next().unwrap().unwrap().path();
    let ([width, height], mut rgb) = read_rgb_png(&tile).unwrap();
    rgb[..3].copy_from_slice(&[255, 255, 255]);
    ufcsr::files::write_rgb_png(&tile, [width, height], &rgb, png::Compression::Fast).unwrap();
    let failed = capture(dir.path(), &["verify", archive_text]);
    assert_eq!(failed.status.code(), Some(1), "{}", String::from_utf8_lossy(&failed.stderr));
    assert!(String::from_utf8_lossy(&failed.stderr).contains("1 pixels are neither background"));

    // Nothing done: a bad value, a missing scene file, a usage error.
    let bad_value = capture(dir.path(), &[&["demo", "--scenario", "Z"][..], &small].concat());
    assert_eq!(bad_value.status.code(), Some(2), "{}", String::from_utf8_lossy(&bad_value.stderr));
    let missing = capture(dir.path(), &["scene", "no-such-scene.json", "--out", archive_text]);
    assert_eq!(missing.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&missing.stderr).contains("no-such-scene.json"));
    assert_eq!(capture(dir.path(), &["demo", "--no-such-option"]).status.code(), Some(2));
}

#[test]
fn ufcsr_and_its_old_name_print_ufcsr_and_the_version() {
    for (program, name) in
        [(env!("CARGO_BIN_EXE_ufcsr"), "ufcsr"), (env!("CARGO_BIN_EXE_ufcsr-capture"), "ufcsr")]
    {
        let output = Command::new(program).arg("--version").output().unwrap();
        assert!(output.status.success(), "{name} --version");
        let text = String::from_utf8_lossy(&output.stdout);
        assert_eq!(text.trim(), format!("{name} {}", env!("CARGO_PKG_VERSION")));
    }
}

#[test]
fn a_capture_without_a_runtime_folder_prints_no_mesa_noise() {
    let dir = tempfile::tempdir().unwrap();
    let archive = dir.path().join("archive");
    let output = Command::new(env!("CARGO_BIN_EXE_ufcsr-capture"))
        .args(["demo", "--ppd", "2", "--palette-size", "256", "--frames", "180", "--quiet", "--out"])
        .arg(&archive)
        .env_remove("XDG_RUNTIME_DIR")
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{stderr}");
    assert!(!stderr.contains("XDG_RUNTIME_DIR"), "{stderr}");
}

#[test]
fn every_capture_command_takes_quiet_and_threads_and_quiet_keeps_stdout_empty() {
    let dir = tempfile::tempdir().unwrap();
    for command in [
        "demo",
        "scene",
        "unity",
        "inspect",
        "views",
        "batch",
        "study",
        "observers",
        "assemble",
        "verify",
        "man",
    ] {
        let help = capture(dir.path(), &[command, "--help"]);
        let text = String::from_utf8_lossy(&help.stdout);
        for option in ["-q, --quiet", "-j, --threads <THREADS>"] {
            assert!(text.contains(option), "ufcsr-capture {command} --help lacks {option}:\n{text}");
        }
    }
    let archive = dir.path().join("archive");
    let archive_text = archive.to_str().unwrap();
    let small = ["--ppd", "2", "--palette-size", "256", "--frames", "180", "--out", archive_text];
    let quiet = capture(dir.path(), &[&["demo", "-q", "-j", "1"][..], &small].concat());
    assert!(quiet.status.success(), "{}", String::from_utf8_lossy(&quiet.stderr));
    assert!(quiet.stdout.is_empty(), "{}", String::from_utf8_lossy(&quiet.stdout));
    let verify = capture(dir.path(), &["verify", archive_text, "--quiet"]);
    assert!(verify.status.success() && verify.stdout.is_empty());
    assert!(!capture(dir.path(), &["verify", archive_text]).stdout.is_empty());
    let too_many = capture(dir.path(), &["verify", archive_text, "-j", "5000"]);
    assert_eq!(too_many.status.code(), Some(2));
}

#[test]
fn a_counted_capture_says_it_wrote_no_pngs_and_lists_every_result_file() {
    let dir = tempfile::tempdir().unwrap();
    let archive = dir.path().join("archive");
    let output = capture(
        dir.path(),
        &[
            "demo",
            "--count",
            "--ppd",
            "2",
            "--palette-size",
            "256",
            "--frames",
            "150,180",
            "--out",
            archive.to_str().unwrap(),
        ],
    );
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    assert!(stdout.contains("counting included, no PNGs") && stdout.contains("none written"), "{stdout}");
    assert!(!stdout.contains("encoding included") && !stdout.contains("decoded"), "{stdout}");
    for file in ["result.json", "parts.csv", "frames.csv", "heatmap.png", "timings.json", "report.html"] {
        assert!(stdout.contains(file), "{file} is not listed:\n{stdout}");
        assert!(archive.join("results").join(file).is_file(), "{file}");
    }
}

#[test]
fn completions_and_man_pages_are_generated_from_the_command_line() {
    let dir = tempfile::tempdir().unwrap();
    let completions = capture(dir.path(), &["completions", "bash"]);
    let script = String::from_utf8_lossy(&completions.stdout);
    assert!(completions.status.success() && script.contains("ufcsr") && script.contains("observers"));
    let pages = dir.path().join("man");
    let man = capture(dir.path(), &["man", "--out", pages.to_str().unwrap()]);
    assert!(man.status.success(), "{}", String::from_utf8_lossy(&man.stderr));
    for page in ["ufcsr.1", "ufcsr-observers.1", "ufcsr-study.1"] {
        let roff = std::fs::read_to_string(pages.join(page)).unwrap();
        assert!(roff.contains(".TH"), "{page}");
    }
    assert_eq!(capture(dir.path(), &["completions", "tcsh"]).status.code(), Some(2));
}

/// The one JSON object a `--json` run prints.
fn json_of(output: &Output) -> serde_json::Value {
    let text = String::from_utf8_lossy(&output.stdout);
    serde_json::from_str(text.trim()).unwrap_or_else(|e| panic!("not one JSON object ({e}): {text}"))
}

#[test]
fn json_says_what_each_command_did_and_wrote() {
    let dir = tempfile::tempdir().unwrap();
    let archive = dir.path().join("archive");
    let archive_text = archive.to_str().unwrap();
    let small = ["--ppd", "2", "--palette-size", "256", "--frames", "150,180", "--out", archive_text];
    let counted = capture(dir.path(), &[&["demo", "--count", "--json"][..], &small].concat());
    let summary = json_of(&counted);
    assert_eq!((summary["command"].as_str(), summary["exit_code"].as_u64()), (Some("demo"), Some(0)));
    let written: Vec<&str> =
        summary["written"].as_array().unwrap().iter().map(|f| f.as_str().unwrap()).collect();
    for file in ["manifest.json", "pidt.png", "vehicle.glb", "results/result.json", "results/frames.csv"] {
        let path = archive.join(file);
        assert!(written.contains(&path.to_str().unwrap()), "{file} not in {written:?}");
        assert!(path.is_file(), "{file}");
    }
    assert_eq!(summary["scenarios"][0]["frames"], 2);
    assert!(summary["grand_totals"][0].as_u64().unwrap() > 0);

    let png = dir.path().join("png");
    let captured = capture(
        dir.path(),
        &[
            "demo",
            "--json",
            "--ppd",
            "2",
            "--palette-size",
            "256",
            "--frames",
            "180",
            "--out",
            png.to_str().unwrap(),
        ],
    );
    assert_eq!(json_of(&captured)["exit_code"], 0);
    let verified = json_of(&capture(dir.path(), &["verify", png.to_str().unwrap(), "--json"]));
    assert_eq!((verified["stray_pixels"].as_u64(), verified["exit_code"].as_u64()), (Some(0), Some(0)));
    assert!(verified["vehicle_pixels"].as_u64().unwrap() > 0);

    // Nothing done: exit code 2, nothing written, the error named.
    let failed = capture(dir.path(), &["demo", "--scenario", "Z", "--json", "--out", archive_text]);
    let summary = json_of(&failed);
    assert_eq!(failed.status.code(), Some(2));
    assert_eq!(
        (summary["exit_code"].as_u64(), summary["written"].as_array().map(Vec::len)),
        (Some(2), Some(0))
    );
    assert!(summary["error"].as_str().unwrap().contains('Z'), "{summary}");
}
