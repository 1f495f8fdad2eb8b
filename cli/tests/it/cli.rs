//! The `ufcsr-analyze` binary: exit codes, outputs, determinism across
//! thread counts, and heatmap regeneration from result.json.

use crate::common;

use common::*;

fn run(args: &[&std::ffi::OsStr]) -> std::process::Output {
    analyzer().args(args).output().unwrap()
}

#[test]
fn result_json_is_byte_identical_whatever_the_thread_count() {
    let dir = tempfile::tempdir().unwrap();
    let spec = ufcsr::synthetic::ArchiveSpec {
        frames: 3,
        rows: 2,
        cols: 3,
        tile_width: 64,
        tile_height: 80,
        palette: [256, 256],
        ..Default::default()
    };
    let archive = dir.path().join("archive");
    ufcsr::synthetic::write_archive(&archive, &spec).unwrap();
    let mut outputs = Vec::new();
    for threads in ["1", "2", "5"] {
        let out = dir.path().join(format!("out{threads}"));
        let status = run(&[
            archive.as_os_str(),
            "--threads".as_ref(),
            threads.as_ref(),
            "--quiet".as_ref(),
            "--out".as_ref(),
            out.as_os_str(),
        ]);
        assert!(status.status.success(), "{}", String::from_utf8_lossy(&status.stderr));
        outputs.push((
            std::fs::read(out.join("result.json")).unwrap(),
            std::fs::read(out.join("heatmap.png")).unwrap(),
        ));
    }
    assert!(outputs.windows(2).all(|w| w[0] == w[1]));

    // Regenerating the heatmap from result.json gives the same bytes.
    let regenerated = dir.path().join("again.png");
    let status = run(&[
        "heatmap".as_ref(),
        dir.path().join("out1/result.json").as_os_str(),
        "--out".as_ref(),
        regenerated.as_os_str(),
    ]);
    assert!(status.status.success(), "{}", String::from_utf8_lossy(&status.stderr));
    assert_eq!(std::fs::read(&regenerated).unwrap(), outputs[0].1);

    // With another scale the regenerated heatmap differs.
    let log = dir.path().join("log.png");
    let status = run(&[
        "heatmap".as_ref(),
        dir.path().join("out1/result.json").as_os_str(),
        "--out".as_ref(),
        log.as_os_str(),
        "--scale".as_ref(),
        "log".as_ref(),
    ]);
    assert!(status.status.success());
    assert_ne!(std::fs::read(&log).unwrap(), outputs[0].1);
}

#[test]
fn exit_codes_table_and_json_summary() {
    let dir = tempfile::tempdir().unwrap();
    let archive = known_archive(dir.path());
    let pidt = dir.path().join("pidt.png");
    let parts = dir.path().join("parts.csv");
    let out = dir.path().join("out");
    let common_args = [
        archive.as_os_str(),
        "--palette-size".as_ref(),
        "4x4".as_ref(),
        "--pidt".as_ref(),
        pidt.as_os_str(),
        "--parts".as_ref(),
        parts.as_os_str(),
        "--out".as_ref(),
        out.as_os_str(),
    ];
    let ok = run(&common_args);
    assert_eq!(ok.status.code(), Some(0), "{}", String::from_utf8_lossy(&ok.stderr));
    let table = String::from_utf8_lossy(&ok.stdout);
    assert!(table.contains("5 found, 2 trimmed (empty), 3 decoded, 0 failed"), "{table}");
    assert!(table.contains("grand total") && table.contains("A "), "{table}");
    let stderr = String::from_utf8_lossy(&ok.stderr);
    assert!(stderr.contains("d.png: 1 stray pixels"), "{stderr}");
    for file in ["result.json", "parts.csv", "heatmap.png", "timings.json"] {
        assert!(out.join(file).is_file(), "{file}");
    }
    assert!(
        !std::fs::read_dir(&out).unwrap().any(|e| e.unwrap().file_name().to_string_lossy().contains(".tmp"))
    );

    let mut json_args = common_args.to_vec();
    json_args.push("--json".as_ref());
    let json = run(&json_args);
    let summary: serde_json::Value = serde_json::from_slice(&json.stdout).unwrap();
    assert_eq!(summary["result"]["grand_total"], 6);
    assert_eq!(summary["result"]["images"]["found"], 5);

    // A broken tile: exit 1, the rest still counted and written.
    std::fs::write(archive.join("broken.png"), b"\x89PNG\r\n\x1a\nnope").unwrap();
    let failed = run(&common_args);
    assert_eq!(failed.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&failed.stderr).contains("broken.png"));
    let mut strict_args = common_args.to_vec();
    strict_args.push("--strict".as_ref());
    assert_eq!(run(&strict_args).status.code(), Some(2));

    // Usage errors: exit 2 with a message.
    let bad = run(&[archive.as_os_str(), "--background".as_ref(), "blue".as_ref()]);
    assert_eq!(bad.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&bad.stderr).contains("blue"));
    let missing = run(&["/definitely/not/here".as_ref()]);
    assert_eq!(missing.status.code(), Some(2));
}

#[test]
fn interrupted_writes_leave_no_partial_result() {
    // A result folder that is a file: the run fails cleanly, nothing partial.
    let dir = tempfile::tempdir().unwrap();
    let archive = known_archive(dir.path());
    let blocked = dir.path().join("blocked");
    std::fs::write(&blocked, b"a file, not a folder").unwrap();
    let status = run(&[
        archive.as_os_str(),
        "--palette-size".as_ref(),
        "4".as_ref(),
        "--out".as_ref(),
        blocked.as_os_str(),
    ]);
    assert_eq!(status.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&status.stderr).contains("blocked"));
}
