//! Issue 34: `ufcsr manifest` never lists a tile the analysis would
//! refuse. A frame that is a link leading out of the manifest's folder used
//! to be listed (the analysis then refused the archive, naming the link);
//! now the manifest command refuses it, naming the link and where it leads,
//! and writes nothing. A link that stays inside is fine.

use crate::common;

use std::path::Path;

use common::*;

fn manifest(cwd: &Path, args: &[&str]) -> std::process::Output {
    analyzer().current_dir(cwd).arg("manifest").args(args).output().unwrap()
}

#[test]
fn a_frame_linked_from_outside_the_folder_is_refused_and_one_inside_is_listed() {
    let dir = tempfile::tempdir().unwrap();
    let shots = dir.path().join("shots");
    rgb_png(&shots.join("frame_0000.png"), 2, 1, &[1, BG]);
    // The PIdT is the palette's size (4 × 4), as manifest now checks.
    rgb_png(&shots.join("pidt.png"), 4, 4, &[0xFF0000; 16]);
    rgb_png(&dir.path().join("elsewhere.png"), 2, 1, &[2, BG]);
    std::os::unix::fs::symlink("../elsewhere.png", shots.join("frame_0001.png")).unwrap();
    let args = ["shots", "--pattern", "frame_{frame}.png", "--pidt", "shots/pidt.png", "--palette-size", "4"];
    let output = manifest(dir.path(), &args);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("frame_0001.png") && stderr.contains("outside"), "{stderr}");
    assert!(!shots.join("manifest.json").exists(), "a manifest was written");

    // A link to a frame inside the manifest's folder (here the one above) stays listed.
    std::fs::remove_file(shots.join("frame_0001.png")).unwrap();
    rgb_png(&dir.path().join("kept/original.png"), 2, 1, &[2, BG]);
    std::os::unix::fs::symlink("../kept/original.png", shots.join("frame_0001.png")).unwrap();
    let output = manifest(dir.path(), &[&args[..], &["--out", "."]].concat());
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    assert!(dir.path().join("manifest.json").is_file());
}
