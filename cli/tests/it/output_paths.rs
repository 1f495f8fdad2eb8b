//! Issue 34: an output never replaces what it should not. A single-file
//! output (`palette --out`, `heatmap --out`) that is a FIFO or a link (to
//! `/dev/null`, to a file elsewhere) is refused and left as it was, never
//! renamed over; a link planted where a sub-folder of the output goes
//! (`--each --out DIR/A`, `placement-views`) is replaced by a real folder,
//! never written through; `placement` never replaces its own inputs (a
//! table named `placement.csv`, a `--mesh` named `placement.json`).

use crate::common;

use std::ffi::OsStr;
use std::os::unix::fs::FileTypeExt;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use common::*;

fn analyze<S: AsRef<OsStr>>(args: &[S]) -> Output {
    analyzer().args(args).output().unwrap()
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

fn fifo(path: &Path) -> PathBuf {
    assert!(Command::new("mkfifo").arg(path).status().expect("mkfifo").success());
    path.to_path_buf()
}

fn link(target: &Path, path: &Path) -> PathBuf {
    std::os::unix::fs::symlink(target, path).unwrap();
    path.to_path_buf()
}

/// A hostile output: what it is, its path, and a check that it is still that.
type Hostile = (&'static str, PathBuf, Box<dyn Fn() -> bool>);

/// The hostile single-file outputs in `dir`.
fn hostile_outputs(dir: &Path) -> Vec<Hostile> {
    let elsewhere = dir.join("elsewhere.png");
    std::fs::write(&elsewhere, "mine").unwrap();
    let fifo_path = fifo(&dir.join("fifo.png"));
    let null_link = link(Path::new("/dev/null"), &dir.join("null.png"));
    let file_link = link(&elsewhere, &dir.join("link.png"));
    let is_fifo = {
        let path = fifo_path.clone();
        move || std::fs::symlink_metadata(&path).is_ok_and(|m| m.file_type().is_fifo())
    };
    let is_link =
        |path: PathBuf| move || std::fs::symlink_metadata(&path).is_ok_and(|m| m.file_type().is_symlink());
    let file_kept = {
        let (link, elsewhere) = (file_link.clone(), elsewhere.clone());
        move || {
            std::fs::symlink_metadata(&link).is_ok_and(|m| m.file_type().is_symlink())
                && std::fs::read_to_string(&elsewhere).unwrap() == "mine"
        }
    };
    vec![
        ("a FIFO", fifo_path, Box::new(is_fifo)),
        ("a link to /dev/null", null_link.clone(), Box::new(is_link(null_link))),
        ("a link to a file elsewhere", file_link, Box::new(file_kept)),
    ]
}

#[test]
fn single_file_outputs_that_are_fifos_or_links_are_refused_and_left_as_they_were() {
    let dir = tempfile::tempdir().unwrap();
    known_archive(dir.path());
    let result = dir.path().join("result");
    let analysed = analyze(&[
        dir.path().join("archive").as_os_str(),
        "--palette-size".as_ref(),
        "4x4".as_ref(),
        "--pidt".as_ref(),
        dir.path().join("pidt.png").as_os_str(),
        "--parts".as_ref(),
        dir.path().join("parts.csv").as_os_str(),
        "-q".as_ref(),
        "--out".as_ref(),
        result.as_os_str(),
    ]);
    assert!(analysed.status.success(), "{}", text(&analysed.stderr));
    for (what, out, unchanged) in hostile_outputs(dir.path()) {
        let runs: [Vec<&OsStr>; 2] = [
            vec!["palette".as_ref(), "--size".as_ref(), "8".as_ref(), "--out".as_ref(), out.as_os_str()],
            vec!["heatmap".as_ref(), result.as_os_str(), "--out".as_ref(), out.as_os_str()],
        ];
        for args in runs {
            let output = analyze(&args);
            let stderr = text(&output.stderr);
            assert_eq!(
                output.status.code(),
                Some(2),
                "{} --out {what}: {stderr}",
                text(args[0].as_encoded_bytes())
            );
            assert!(stderr.contains(&out.display().to_string()), "{what}: the path is not named: {stderr}");
            assert!(unchanged(), "{what}: replaced by {}", text(args[0].as_encoded_bytes()));
        }
    }
    assert!(Path::new("/dev/null").exists());
}

#[test]
fn each_out_never_writes_through_a_link_at_an_archive_s_folder() {
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
    let out = dir.path().join("out");
    let elsewhere = dir.path().join("elsewhere");
    std::fs::create_dir_all(&out).unwrap();
    std::fs::create_dir_all(&elsewhere).unwrap();
    link(&elsewhere, &out.join("A"));
    let each =
        analyze(&[parent.as_os_str(), "--each".as_ref(), "-q".as_ref(), "--out".as_ref(), out.as_os_str()]);
    assert_eq!(each.status.code(), Some(0), "{}", text(&each.stderr));
    assert_eq!(std::fs::read_dir(&elsewhere).unwrap().count(), 0, "written through the link");
    assert!(!std::fs::symlink_metadata(out.join("A")).unwrap().file_type().is_symlink());
    assert!(out.join("A/result.json").is_file() && out.join("B/result.json").is_file());
}

/// The placement tests' archive (`common::placement_archive`) at `dir/archive`.
fn placement_archive(dir: &Path, vehicle: bool) -> PathBuf {
    crate::common::placement_archive(dir, "archive", vehicle)
}

#[test]
fn placement_never_replaces_its_input_table_or_mesh() {
    let dir = tempfile::tempdir().unwrap();
    let archive = placement_archive(dir.path(), false);
    // The table given as a file named placement.csv, --out its own folder.
    let table = dir.path().join("placement.csv");
    std::fs::copy(archive.join("results/placement-frames.csv"), &table).unwrap();
    let before = std::fs::read(&table).unwrap();
    let output = analyze(&[
        "placement".as_ref(),
        table.as_os_str(),
        "--min-dwell-s".as_ref(),
        "0".as_ref(),
        "-q".as_ref(),
        "--out".as_ref(),
        dir.path().as_os_str(),
    ]);
    let stderr = text(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("overwrite the input") && stderr.contains("placement.csv"), "{stderr}");
    assert_eq!(std::fs::read(&table).unwrap(), before, "the input table was replaced");

    // A --mesh named placement.json in --out.
    let out = dir.path().join("out");
    std::fs::create_dir_all(&out).unwrap();
    let mesh = out.join("placement.json");
    let example = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fixtures/example");
    std::fs::copy(example.join("vehicle.glb"), &mesh).unwrap();
    let before = std::fs::read(&mesh).unwrap();
    let output = analyze(&[
        "placement".as_ref(),
        archive.as_os_str(),
        "--min-dwell-s".as_ref(),
        "0".as_ref(),
        "--mesh".as_ref(),
        mesh.as_os_str(),
        "-q".as_ref(),
        "--out".as_ref(),
        out.as_os_str(),
    ]);
    let stderr = text(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("overwrite the input") && stderr.contains("placement.json"), "{stderr}");
    assert_eq!(std::fs::read(&mesh).unwrap(), before, "the mesh was replaced");
    assert!(!out.join("placement.csv").exists(), "written before refusing");
}

#[test]
fn placement_views_through_a_link_are_written_into_a_real_folder() {
    let dir = tempfile::tempdir().unwrap();
    let archive = placement_archive(dir.path(), true);
    let out = dir.path().join("out");
    let elsewhere = dir.path().join("elsewhere");
    std::fs::create_dir_all(&out).unwrap();
    std::fs::create_dir_all(&elsewhere).unwrap();
    link(&elsewhere, &out.join("placement-views"));
    let output = analyze(&[
        "placement".as_ref(),
        archive.as_os_str(),
        "--min-dwell-s".as_ref(),
        "0".as_ref(),
        "-q".as_ref(),
        "--out".as_ref(),
        out.as_os_str(),
    ]);
    assert!(output.status.success(), "{}", text(&output.stderr));
    assert_eq!(std::fs::read_dir(&elsewhere).unwrap().count(), 0, "written through the link");
    let views = out.join("placement-views");
    assert!(std::fs::symlink_metadata(&views).unwrap().is_dir());
    assert!(std::fs::read_dir(&views).unwrap().count() > 0, "no views written");
}

/// `ufcsr views RESULTS` writes `RESULTS/views/*.png` and
/// `RESULTS/views.png`: a link planted at `RESULTS/views` (to a folder
/// elsewhere) is replaced by a real folder, never written through; a link at
/// `views.png` (to a file elsewhere) is refused and left as it was.
#[test]
fn capture_views_never_write_through_a_link_at_results_views() {
    let dir = tempfile::tempdir().unwrap();
    let archive = dir.path().join("archive");
    let counted = Command::new(env!("CARGO_BIN_EXE_ufcsr-capture"))
        .args([
            "demo",
            "--count",
            "-q",
            "--ppd",
            "2",
            "--palette-size",
            "256",
            "--frames",
            "150,180",
            "--out",
        ])
        .arg(&archive)
        .env("XDG_RUNTIME_DIR", dir.path())
        .output()
        .unwrap();
    assert!(counted.status.success(), "{}", text(&counted.stderr));
    let results = archive.join("results");
    let elsewhere = dir.path().join("elsewhere");
    std::fs::create_dir(&elsewhere).unwrap();
    std::fs::write(elsewhere.join("keep.txt"), "mine").unwrap();
    // A default result set has no views/ (each view alone is a `--figures all` variant); one of an
    // older run would be replaced by the link too.
    if results.join("views").exists() {
        std::fs::remove_dir_all(results.join("views")).unwrap();
    }
    std::os::unix::fs::symlink(&elsewhere, results.join("views")).unwrap();
    let views = |results: &Path| {
        Command::new(env!("CARGO_BIN_EXE_ufcsr-capture"))
            .arg("views")
            .arg(results)
            .env("XDG_RUNTIME_DIR", dir.path())
            .output()
            .unwrap()
    };
    let output = views(&results);
    assert!(output.status.success(), "{}", text(&output.stderr));
    let names: Vec<_> = std::fs::read_dir(&elsewhere).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert_eq!(names, ["keep.txt"], "views were written through the link");
    let kind = std::fs::symlink_metadata(results.join("views")).unwrap().file_type();
    assert!(kind.is_dir() && results.join("views/front.png").is_file());
    // views.png a link to a file elsewhere: refused, the file kept.
    let outside = elsewhere.join("outside.png");
    std::fs::write(&outside, "not a picture").unwrap();
    std::fs::remove_file(results.join("views.png")).unwrap();
    std::os::unix::fs::symlink(&outside, results.join("views.png")).unwrap();
    let output = views(&results);
    assert_eq!(output.status.code(), Some(2), "{}", text(&output.stderr));
    assert!(text(&output.stderr).contains("views.png") && text(&output.stderr).contains("link"));
    assert_eq!(std::fs::read_to_string(&outside).unwrap(), "not a picture");
}

/// The study's folders (`ppdN-stepM/`, the exact reference's `exact/`) and
/// the observers' (`observer-NNN/`) are made real: a link planted at one is
/// replaced, and the folder it names gets nothing. `exact/` used to be
/// written through.
#[test]
fn study_and_observers_never_write_through_a_link_at_their_folders() {
    let dir = tempfile::tempdir().unwrap();
    let scene = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fixtures/scenes/demo.json");
    let elsewhere = dir.path().join("elsewhere");
    std::fs::create_dir(&elsewhere).unwrap();
    std::fs::write(elsewhere.join("keep.txt"), "mine").unwrap();
    let small = ["--scenario", "A", "--ppd", "2", "--palette-size", "256", "--frame-step", "90", "-q"];
    let cases: [(&str, &[&str], &[&str]); 2] = [
        ("study", &["--exact-sample", "0.05"], &["ppd2-step90", "exact"]),
        ("observers", &["--kerb=-6.5,-4.5:-4.5,-6.5", "--observers", "1", "--seed", "7"], &["observer-000"]),
    ];
    for (command, extra, folders) in cases {
        let out = dir.path().join(command);
        std::fs::create_dir(&out).unwrap();
        for folder in folders {
            link(&elsewhere, &out.join(folder));
        }
        let ran = Command::new(env!("CARGO_BIN_EXE_ufcsr-capture"))
            .arg(command)
            .arg(&scene)
            .args(small)
            .args(extra)
            .arg("--out")
            .arg(&out)
            .env("XDG_RUNTIME_DIR", dir.path())
            .output()
            .unwrap();
        assert!(ran.status.success(), "{command}: {}", text(&ran.stderr));
        let names: Vec<_> = std::fs::read_dir(&elsewhere).unwrap().map(|e| e.unwrap().file_name()).collect();
        assert_eq!(names, ["keep.txt"], "{command} wrote through a link");
        for folder in folders {
            let kind = std::fs::symlink_metadata(out.join(folder)).unwrap().file_type();
            assert!(
                kind.is_dir() && out.join(folder).join("results/result.json").is_file(),
                "{command} {folder}"
            );
        }
    }
}
