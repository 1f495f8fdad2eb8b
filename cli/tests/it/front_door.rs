//! One front door: `ufcsr` is the whole command tree, and `ufcsr-analyze`
//! and `ufcsr-capture` are the same commands under their own grammar. Its
//! help and completions name every command; the analysis gives the same
//! files through either name; `--json` prints exactly one JSON object on a
//! usage error, on `completions`, on Ctrl-C; a stdout that cannot be
//! written ends with a message and an exit code, never a panic.

use std::path::Path;
use std::process::{Command, Output, Stdio};

/// Every command of the tree, as `ufcsr --help` lists it.
const COMMANDS: [&str; 18] = [
    "analyze",
    "merge",
    "report",
    "heatmap",
    "palette",
    "manifest",
    "placement",
    "capture",
    "where",
    "assemble",
    "batch",
    "study",
    "observers",
    "verify",
    "inspect",
    "views",
    "completions",
    "man",
];

fn ufcsr(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_ufcsr")).args(args).output().unwrap()
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// The one JSON object on stdout.
fn one_object(output: &Output) -> serde_json::Value {
    let stdout = text(&output.stdout);
    assert_eq!(stdout.trim_end().lines().count(), 1, "not one line: {stdout}");
    serde_json::from_str(stdout.trim()).unwrap_or_else(|e| panic!("not one JSON object ({e}): {stdout}"))
}

#[test]
fn ufcsr_help_lists_every_command_and_the_exit_codes() {
    let help = ufcsr(&["--help"]);
    assert_eq!(help.status.code(), Some(0));
    let shown = text(&help.stdout);
    for command in COMMANDS {
        assert!(shown.lines().any(|line| line.trim_start().starts_with(command)), "{command}:\n{shown}");
    }
    assert!(shown.contains("Exit status: 0 done"), "{shown}");
    let capture = text(&ufcsr(&["capture", "--help"]).stdout);
    for scene in ["demo", "scene", "unity"] {
        assert!(capture.lines().any(|line| line.trim_start().starts_with(scene)), "{scene}:\n{capture}");
    }
}

#[test]
fn ufcsr_completions_cover_every_command() {
    let output = ufcsr(&["completions", "bash"]);
    assert_eq!(output.status.code(), Some(0));
    let script = text(&output.stdout);
    for command in COMMANDS.iter().chain(&["demo", "scene", "unity", "plan"]) {
        assert!(script.contains(&format!("{command})")), "bash completion has no case for {command}");
    }
}

/// Every file of a result folder, by name.
fn files_of(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut files: Vec<(String, Vec<u8>)> = std::fs::read_dir(dir)
        .unwrap()
        .map(|entry| entry.unwrap().path())
        .filter(|path| path.is_file())
        .map(|path| (path.file_name().unwrap().to_string_lossy().into_owned(), std::fs::read(&path).unwrap()))
        .collect();
    files.sort();
    files
}

#[test]
fn ufcsr_analyze_and_ufcsr_dash_analyze_write_the_same_files() {
    let dir = tempfile::tempdir().unwrap();
    let archive = dir.path().join("archive");
    let spec = ufcsr::synthetic::ArchiveSpec {
        frames: 2,
        rows: 1,
        cols: 2,
        tile_width: 32,
        tile_height: 32,
        palette: [64, 64],
        ..Default::default()
    };
    ufcsr::synthetic::write_archive(&archive, &spec).unwrap();
    let (alias, tree) = (dir.path().join("alias"), dir.path().join("tree"));
    let by_alias = Command::new(env!("CARGO_BIN_EXE_ufcsr-analyze"))
        .arg(&archive)
        .args(["-q", "--frames-csv", "off", "--out"])
        .arg(&alias)
        .output()
        .unwrap();
    assert_eq!(by_alias.status.code(), Some(0), "{}", text(&by_alias.stderr));
    let by_tree = Command::new(env!("CARGO_BIN_EXE_ufcsr"))
        .arg("analyze")
        .arg(&archive)
        .args(["-q", "--frames-csv", "off", "--out"])
        .arg(&tree)
        .output()
        .unwrap();
    assert_eq!(by_tree.status.code(), Some(0), "{}", text(&by_tree.stderr));
    let (alias_files, tree_files) = (files_of(&alias), files_of(&tree));
    assert!(alias_files.iter().any(|(name, _)| name == "result.json"), "{alias_files:?}");
    let names = |files: &[(String, Vec<u8>)]| files.iter().map(|f| f.0.clone()).collect::<Vec<_>>();
    assert_eq!(names(&alias_files), names(&tree_files));
    for ((name, a), (_, b)) in alias_files.iter().zip(&tree_files) {
        // timings.json holds the run's own seconds; report.html shows them.
        if name != "timings.json" && name != "report.html" {
            assert!(a == b, "{name} differs");
        }
    }
}

#[test]
fn a_usage_error_under_json_is_one_json_object_with_exit_code_2() {
    let programs = [
        (env!("CARGO_BIN_EXE_ufcsr"), vec!["merge", "--no-such-option", "--json"], "merge"),
        // The old name's line is `ufcsr`'s (no archive named: the tree's own usage error).
        (env!("CARGO_BIN_EXE_ufcsr-analyze"), vec!["--json", "--no-such-option"], "ufcsr"),
        (env!("CARGO_BIN_EXE_ufcsr-capture"), vec!["demo", "--json", "--ppd"], "demo"),
        (env!("CARGO_BIN_EXE_ufcsr"), vec!["--json", "no-such-command"], "ufcsr"),
    ];
    for (program, args, command) in programs {
        let output = Command::new(program).args(&args).output().unwrap();
        assert_eq!(output.status.code(), Some(2), "{args:?}");
        let summary = one_object(&output);
        assert_eq!(summary["command"], command, "{summary}");
        assert_eq!(summary["exit_code"], 2);
        assert_eq!(summary["written"].as_array().map(Vec::len), Some(0));
        assert!(summary["error"].as_str().is_some_and(|e| !e.is_empty()), "{summary}");
        assert!(text(&output.stderr).contains("error"), "clap's message is still on stderr");
    }
    let help = ufcsr(&["--json", "study", "--help"]);
    assert_eq!(help.status.code(), Some(0));
    assert!(one_object(&help)["help"].as_str().unwrap().contains("--ppd"));
}

#[test]
fn completions_under_json_and_into_a_full_device() {
    let output = ufcsr(&["completions", "zsh", "--json"]);
    assert_eq!(output.status.code(), Some(0));
    assert!(one_object(&output)["script"].as_str().unwrap().contains("ufcsr"));
    if Path::new("/dev/full").exists() {
        let full = std::fs::OpenOptions::new().write(true).open("/dev/full").unwrap();
        let output = Command::new(env!("CARGO_BIN_EXE_ufcsr"))
            .args(["completions", "bash"])
            .stdout(Stdio::from(full))
            .output()
            .unwrap();
        assert_eq!(output.status.code(), Some(2), "{}", text(&output.stderr));
        let message = text(&output.stderr);
        assert!(message.contains("stdout") && !message.contains("panicked"), "{message}");
    }
}

#[test]
fn man_under_json_is_one_object_and_a_full_device_under_json_is_exit_2() {
    let page = ufcsr(&["--json", "man"]);
    assert_eq!(page.status.code(), Some(0));
    assert!(one_object(&page)["page"].as_str().unwrap().contains(".TH ufcsr"));
    // One page per command into --out: `written` lists exactly the pages there.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("man");
    let pages = ufcsr(&["--json", "man", "--out", out.to_str().unwrap()]);
    let summary = one_object(&pages);
    let mut listed: Vec<String> =
        summary["written"].as_array().unwrap().iter().map(|p| p.as_str().unwrap().to_string()).collect();
    let mut there: Vec<String> =
        std::fs::read_dir(&out).unwrap().map(|e| e.unwrap().path().display().to_string()).collect();
    listed.sort();
    there.sort();
    assert!(there.len() > COMMANDS.len() && listed == there, "{listed:?} against {there:?}");
    if Path::new("/dev/full").exists() {
        for args in [["--json", "completions", "bash"], ["--json", "man", "--quiet"]] {
            let full = std::fs::OpenOptions::new().write(true).open("/dev/full").unwrap();
            let output = Command::new(env!("CARGO_BIN_EXE_ufcsr"))
                .args(args)
                .stdout(Stdio::from(full))
                .output()
                .unwrap();
            assert_eq!(output.status.code(), Some(2), "{args:?}: {}", text(&output.stderr));
            assert!(text(&output.stderr).contains("cannot write to stdout"), "{args:?}");
        }
    }
}

#[test]
fn ctrl_c_under_json_is_one_json_object_with_exit_code_130() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("archive");
    let mut child = Command::new(env!("CARGO_BIN_EXE_ufcsr"))
        .args(["capture", "demo", "--scenario", "B", "--ppd", "30", "--palette-size", "1024", "--json"])
        .arg("--out")
        .arg(&out)
        .env("XDG_RUNTIME_DIR", dir.path())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // Interrupt once tiles are being written.
    let started = std::time::Instant::now();
    while started.elapsed() < std::time::Duration::from_secs(120) {
        let tiles = std::fs::read_dir(out.join("tiles")).map(|d| d.count()).unwrap_or(0);
        if tiles > 2 || child.try_wait().unwrap().is_some() {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    let pid = child.id().to_string();
    assert!(Command::new("kill").args(["-INT", &pid]).status().unwrap().success());
    let output = child.wait_with_output().unwrap();
    assert_eq!(output.status.code(), Some(130), "{}", text(&output.stderr));
    let summary = one_object(&output);
    assert_eq!((summary["command"].as_str(), summary["exit_code"].as_u64()), (Some("demo"), Some(130)));
    assert!(summary["error"].as_str().unwrap().starts_with("interrupted"), "{summary}");
    assert!(!out.join("manifest.json").exists());
}
