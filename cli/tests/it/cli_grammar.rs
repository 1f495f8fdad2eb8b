//! One grammar for every subcommand of `ufcsr-analyze`: each has `--help`
//! (exit 0) and refuses an unknown option (exit 2); each that does work
//! takes `--quiet`, `--json` and `--threads/-j`, is silent on stdout with
//! `--quiet`, prints one JSON object with `--json` (the command, its exit
//! code and every file written), and exits 2 with nothing written when its
//! input is bad. `completions` and `man` generate what they promise, and
//! ARCHIVE that is an archive's `tiles/` folder, or the parent of several
//! archives, stops with exit 2 naming the manifests (or `--each`).

use crate::common;

use std::ffi::OsStr;
use std::path::{Path, PathBuf};
use std::process::Output;

use common::*;

fn run<S: AsRef<OsStr>>(args: &[S]) -> Output {
    analyzer().args(args).output().unwrap()
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// The subcommands that do work, and `None` for the main command.
const WORKING: [Option<&str>; 5] = [None, Some("heatmap"), Some("merge"), Some("report"), Some("palette")];

#[test]
fn every_subcommand_has_help_and_refuses_unknown_options_with_exit_2() {
    for sub in WORKING.into_iter().chain([Some("completions"), Some("man")]) {
        let prefix: Vec<&str> = sub.into_iter().collect();
        let help = run(&[prefix.clone(), vec!["--help"]].concat());
        let shown = text(&help.stdout);
        assert_eq!(help.status.code(), Some(0), "{sub:?} --help");
        // The old name runs `ufcsr`'s command and never shows itself.
        assert!(shown.contains("Usage: ufcsr") && !shown.contains("ufcsr-analyze"), "{sub:?}: {shown}");
        if WORKING.contains(&sub) {
            for word in
                ["--quiet", "--json", "-j, --threads", "Exit status: 0 done; 1 done, but with failures"]
            {
                assert!(shown.contains(word), "{sub:?} --help lacks {word:?}:\n{shown}");
            }
        }
        let unknown = run(&[prefix, vec!["--no-such-option"]].concat());
        assert_eq!(unknown.status.code(), Some(2), "{sub:?} --no-such-option");
        assert!(text(&unknown.stderr).contains("--no-such-option"));
    }
    let version = run(&["--version"]);
    assert_eq!(version.status.code(), Some(0));
    assert!(text(&version.stdout).starts_with(concat!("ufcsr ", env!("CARGO_PKG_VERSION"))));
}

/// The known archive analysed into `dir/NAME`; returns that folder.
fn analysed(dir: &Path, name: &str) -> PathBuf {
    let out = dir.join(name);
    let archive = dir.join("archive");
    let status = run(&[
        archive.as_os_str(),
        "--palette-size".as_ref(),
        "4".as_ref(),
        "--pidt".as_ref(),
        dir.join("pidt.png").as_os_str(),
        "--parts".as_ref(),
        dir.join("parts.csv").as_os_str(),
        "-q".as_ref(),
        "--out".as_ref(),
        out.as_os_str(),
    ]);
    assert_eq!(status.status.code(), Some(0), "{}", text(&status.stderr));
    out
}

/// Each working subcommand's arguments for a good run writing under `out`.
fn good_runs(dir: &Path, out: &Path) -> Vec<(&'static str, Vec<PathBuf>)> {
    let first = analysed(dir, "first");
    let second = analysed(dir, "second");
    let p = |s: &str| PathBuf::from(s);
    vec![
        (
            "analyze",
            vec![
                dir.join("archive"),
                p("--palette-size"),
                p("4x4"),
                p("--pidt"),
                dir.join("pidt.png"),
                p("--parts"),
                dir.join("parts.csv"),
                p("--out"),
                out.join("analyze"),
            ],
        ),
        ("heatmap", vec![p("heatmap"), first.clone(), p("--out"), out.join("heatmap.png")]),
        ("merge", vec![p("merge"), first.join("result.json"), p("--out"), out.join("merged")]),
        ("report", vec![p("report"), first, second, p("--out"), out.join("report")]),
        ("palette", vec![p("palette"), p("--size"), p("8"), p("--out"), out.join("palette.png")]),
    ]
}

#[test]
fn quiet_json_and_threads_work_alike_on_every_working_subcommand() {
    let dir = tempfile::tempdir().unwrap();
    known_archive(dir.path());
    for (flags, tag) in [(vec!["-q", "-j", "2"], "quiet"), (vec!["--json", "--threads", "1"], "json")] {
        let out = dir.path().join(tag);
        for (command, args) in good_runs(dir.path(), &out) {
            let output = run(&[
                args.iter().map(|a| a.as_os_str()).collect::<Vec<_>>(),
                flags.iter().map(OsStr::new).collect(),
            ]
            .concat());
            assert_eq!(output.status.code(), Some(0), "{command} {flags:?}: {}", text(&output.stderr));
            if tag == "quiet" {
                assert!(output.stdout.is_empty(), "{command} -q printed {}", text(&output.stdout));
                continue;
            }
            let summary: serde_json::Value = serde_json::from_slice(&output.stdout)
                .unwrap_or_else(|e| panic!("{command} --json: {e}\n{}", text(&output.stdout)));
            assert_eq!(summary["command"], command);
            assert_eq!(summary["exit_code"], 0);
            let written = summary["written"].as_array().unwrap();
            assert!(!written.is_empty(), "{command}: nothing listed");
            for file in written {
                assert!(Path::new(file.as_str().unwrap()).is_file(), "{command}: {file} listed but absent");
            }
        }
    }
}

#[test]
fn every_working_subcommand_exits_2_with_nothing_written_on_bad_input() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("missing");
    let out = dir.path().join("out");
    let (heat, palette) = (out.join("h.png"), out.join("p.png"));
    let runs: [Vec<&OsStr>; 5] = [
        vec![missing.as_os_str(), "--out".as_ref(), out.as_os_str()],
        vec!["heatmap".as_ref(), missing.as_os_str(), "--out".as_ref(), heat.as_os_str()],
        vec!["merge".as_ref(), missing.as_os_str(), "--out".as_ref(), out.as_os_str()],
        vec!["report".as_ref(), missing.as_os_str(), missing.as_os_str(), "--out".as_ref(), out.as_os_str()],
        vec![
            "palette".as_ref(),
            "--size".as_ref(),
            "5000x5000".as_ref(),
            "--out".as_ref(),
            palette.as_os_str(),
        ],
    ];
    for args in runs {
        let output = run(&[args.clone(), vec!["--json".as_ref()]].concat());
        assert_eq!(output.status.code(), Some(2), "{args:?}: {}", text(&output.stderr));
        assert!(text(&output.stderr).starts_with("error: "), "{args:?}: {}", text(&output.stderr));
        let summary: serde_json::Value = serde_json::from_slice(&output.stdout).unwrap();
        assert_eq!(
            (summary["exit_code"].as_u64(), summary["written"].as_array().map(Vec::len)),
            (Some(2), Some(0))
        );
        assert!(
            !out.join("result.json").exists() && !out.join("h.png").exists() && !out.join("p.png").exists()
        );
    }
}

#[test]
fn completions_for_every_shell_and_man_pages_are_generated() {
    for shell in ["bash", "zsh", "fish", "elvish", "powershell"] {
        let output = run(&["completions", shell]);
        assert_eq!(output.status.code(), Some(0), "{shell}");
        let script = text(&output.stdout);
        assert!(script.contains("ufcsr") && script.contains("heatmap"), "{shell}: {script}");
    }
    assert_eq!(run(&["completions", "tcsh"]).status.code(), Some(2));
    let page = run(&["man"]);
    assert_eq!(page.status.code(), Some(0));
    assert!(text(&page.stdout).contains(".TH ufcsr"), "{}", text(&page.stdout));
    let dir = tempfile::tempdir().unwrap();
    let pages = run(&[OsStr::new("man"), "--out".as_ref(), dir.path().as_os_str()]);
    assert_eq!(pages.status.code(), Some(0), "{}", text(&pages.stderr));
    for name in ["ufcsr", "ufcsr-heatmap", "ufcsr-merge", "ufcsr-report"] {
        let page = std::fs::read_to_string(dir.path().join(format!("{name}.1"))).unwrap();
        assert!(page.contains(&format!(".TH {name}")), "{name}.1");
    }
}

#[test]
fn completions_and_man_pages_into_a_reader_that_stops_early_end_quietly() {
    // `ufcsr completions bash | head -1`: stdout closes after the
    // first line; the program must not panic on the broken pipe.
    for args in [&["completions", "bash"][..], &["man"]] {
        let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_ufcsr-analyze"))
            .args(args)
            .stdout(std::process::Stdio::piped())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        drop(child.stdout.take());
        let output = child.wait_with_output().unwrap();
        assert_eq!(output.status.code(), Some(0), "{args:?}: {}", text(&output.stderr));
        assert!(!text(&output.stderr).contains("panicked"), "{args:?}");
    }
}

#[test]
fn the_tiles_folder_of_an_archive_is_refused_naming_the_manifest_above() {
    let dir = tempfile::tempdir().unwrap();
    let example = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fixtures/example");
    let out = dir.path().join("out");
    let output = run(&[example.join("tiles").as_os_str(), "--out".as_ref(), out.as_os_str()]);
    assert_eq!(output.status.code(), Some(2));
    let message = text(&output.stderr);
    assert!(message.contains(&example.join("manifest.json").display().to_string()), "{message}");
    assert!(message.contains("--no-manifest"), "{message}");
    assert!(!out.exists(), "nothing written");
}

#[test]
fn a_folder_of_several_archives_is_refused_or_analysed_each_with_each() {
    let dir = tempfile::tempdir().unwrap();
    let parent = dir.path().join("all");
    let spec = ufcsr::synthetic::ArchiveSpec {
        frames: 2,
        rows: 1,
        cols: 2,
        tile_width: 16,
        tile_height: 16,
        palette: [64, 64],
        ..Default::default()
    };
    for name in ["A", "B"] {
        ufcsr::synthetic::write_archive(&parent.join(name), &spec).unwrap();
    }
    let output = run(&[parent.as_os_str()]);
    assert_eq!(output.status.code(), Some(2));
    let message = text(&output.stderr);
    for name in ["A", "B"] {
        assert!(
            message.contains(&parent.join(name).join("manifest.json").display().to_string()),
            "{message}"
        );
    }
    assert!(message.contains("--each"), "{message}");
    assert!(!parent.join("results").exists(), "nothing written");

    let out = dir.path().join("out");
    let each =
        run(&[parent.as_os_str(), "--each".as_ref(), "--json".as_ref(), "--out".as_ref(), out.as_os_str()]);
    assert_eq!(each.status.code(), Some(0), "{}", text(&each.stderr));
    let summary: serde_json::Value = serde_json::from_slice(&each.stdout).unwrap();
    assert_eq!(summary["archives"].as_array().unwrap().len(), 2);
    for name in ["A", "B"] {
        assert!(out.join(name).join("result.json").is_file(), "{name}");
    }
}
