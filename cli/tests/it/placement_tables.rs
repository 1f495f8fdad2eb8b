//! Issue 34: a placement table is checked before it is scored. A third eye
//! name, a negative distance, a clock that runs backwards, a `frame_s`
//! beyond any scenario (1e308 used to become `inf`/`null`), mirrors that do
//! not name each other, and the same table given twice (twice by path,
//! through a link, or as `A` and `A/results`) are each refused with the
//! file, the line and the field named, and nothing is written.

use std::path::{Path, PathBuf};
use std::process::Command;

const HEADER: &str = "frame,time_s,eye,distance_m,candidate,kind,solid_angle_sr,visible_fraction,\
                      view_angle_deg,angular_height_deg,frame_s,mirror\n";

/// A sound table: `hood_left` and `hood_right` (mirrors of each other) seen
/// by both eyes in frames 0–3, 10 frames a second.
fn good_rows() -> Vec<String> {
    let mut rows = Vec::new();
    for frame in 0..4 {
        for eye in ["left", "right"] {
            for (part, mirror) in [("hood_left", "hood_right"), ("hood_right", "hood_left")] {
                rows.push(format!(
                    "{frame},{},{eye},{},{part},part,1e-3,1,10,1,0.1,{mirror}",
                    f64::from(frame) / 10.0,
                    30 - frame
                ));
            }
        }
    }
    rows
}

/// An archive folder whose `results/placement-frames.csv` holds `rows`.
fn archive(dir: &Path, name: &str, rows: &[String]) -> PathBuf {
    let archive = dir.join(name);
    std::fs::create_dir_all(archive.join("results")).unwrap();
    std::fs::write(archive.join("results/placement-frames.csv"), format!("{HEADER}{}\n", rows.join("\n")))
        .unwrap();
    archive
}

/// Runs `placement` on `inputs` into `dir/out`; returns (success, stderr).
fn placement(dir: &Path, inputs: &[&Path]) -> (bool, String) {
    let output = Command::new(env!("CARGO_BIN_EXE_ufcsr-analyze"))
        .arg("placement")
        .args(inputs)
        .args(["--min-dwell-s", "0", "-q", "--replicates", "20", "--out"])
        .arg(dir.join("out"))
        .output()
        .unwrap();
    (output.status.success(), String::from_utf8_lossy(&output.stderr).into_owned())
}

#[test]
fn a_sound_table_is_scored() {
    let dir = tempfile::tempdir().unwrap();
    let a = archive(dir.path(), "A", &good_rows());
    let (ok, stderr) = placement(dir.path(), &[&a]);
    assert!(ok, "{stderr}");
    assert!(dir.path().join("out/placement.json").is_file());
}

#[test]
fn a_bad_table_is_refused_naming_file_line_and_field() {
    // (what is changed in the good table, words the error must hold)
    let mut third_eye = good_rows();
    third_eye[3] = third_eye[3].replace(",right,", ",centre,");
    third_eye.push("0,0,centre2,30,hood_left,part,1e-3,1,10,1,0.1,hood_right".to_string());
    let mut negative = good_rows();
    negative[5] = negative[5].replace(",30,", ",-4,").replace(",29,", ",-4,");
    let mut backwards = good_rows();
    for row in backwards.iter_mut().filter(|r| r.starts_with("3,")) {
        let mut fields: Vec<&str> = row.split(',').collect();
        fields[1] = "0.05";
        *row = fields.join(",");
    }
    let mut huge_frame = good_rows();
    for row in &mut huge_frame {
        *row = row.replace(",0.1,hood", ",1e308,hood");
    }
    let mut one_sided = good_rows();
    for row in one_sided.iter_mut().filter(|r| r.contains(",hood_right,part")) {
        *row = row.replace(",hood_left", ",grill");
    }
    let mut own_mirror = good_rows();
    for row in own_mirror.iter_mut().filter(|r| r.contains(",hood_left,part")) {
        *row = row.replace(",hood_right", ",hood_left");
    }
    let cases: [(&str, Vec<String>, &[&str]); 6] = [
        ("third eye", third_eye, &["line", "third eye", "centre"]),
        ("negative distance", negative, &["line 7", "distance_m", "-4"]),
        ("backwards clock", backwards, &["line", "time_s", "backwards"]),
        ("huge frame_s", huge_frame, &["line 2", "frame_s", "1e308"]),
        ("one-sided mirror", one_sided, &["mirror", "hood_right", "each other"]),
        ("own mirror", own_mirror, &["mirror", "hood_left", "itself"]),
    ];
    for (what, rows, words) in cases {
        let dir = tempfile::tempdir().unwrap();
        let a = archive(dir.path(), "A", &rows);
        let (ok, stderr) = placement(dir.path(), &[&a]);
        assert!(!ok, "{what}: accepted");
        assert!(stderr.contains("placement-frames.csv"), "{what}: the file is not named: {stderr}");
        for word in words {
            assert!(stderr.contains(word), "{what}: {word:?} not in {stderr}");
        }
        assert!(!dir.path().join("out/placement.json").exists(), "{what}: wrote a result");
    }
}

#[test]
fn one_table_given_twice_is_refused_naming_it() {
    let dir = tempfile::tempdir().unwrap();
    let a = archive(dir.path(), "A", &good_rows());
    let b = archive(dir.path(), "B", &good_rows());
    let link = dir.path().join("link-to-A");
    std::os::unix::fs::symlink(&a, &link).unwrap();
    let results = a.join("results");
    let cases: [(&str, Vec<&Path>); 3] = [
        ("A twice", vec![&a, &b, &a]),
        ("through a link", vec![&a, &link]),
        ("A and A/results", vec![&a, &results]),
    ];
    for (what, inputs) in cases {
        let (ok, stderr) = placement(dir.path(), &inputs);
        assert!(!ok, "{what}: accepted");
        assert!(stderr.contains("twice") && stderr.contains("placement-frames.csv"), "{what}: {stderr}");
        assert!(!dir.path().join("out/placement.json").exists(), "{what}: wrote a result");
    }
    let (ok, stderr) = placement(dir.path(), &[&a, &b]);
    assert!(ok, "two archives: {stderr}");
}
