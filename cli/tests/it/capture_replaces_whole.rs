//! Issue 34, a capture replaces an archive as a whole: a capture into a
//! folder holding a complete archive removes the old manifest before it
//! writes anything, so a capture killed halfway never leaves scenario A's
//! manifest over a mix of A's and B's tiles (the analyzer would count them
//! under it).

use std::path::Path;

/// The tiles in `archive/tiles`.
fn tiles(archive: &Path) -> usize {
    std::fs::read_dir(archive.join("tiles")).map_or(0, |entries| entries.count())
}

#[cfg(unix)]
#[test]
fn a_capture_killed_over_a_complete_archive_leaves_no_old_manifest_over_mixed_tiles() {
    let dir = tempfile::tempdir().unwrap();
    let archive = dir.path().join("archive");
    let capture = |scenario: &str| {
        let mut command = std::process::Command::new(env!("CARGO_BIN_EXE_ufcsr-capture"));
        command.args(["demo", "--scenario", scenario, "--ppd", "2", "--palette-size", "256", "-q", "--out"]);
        command.arg(&archive).env("XDG_RUNTIME_DIR", dir.path());
        command
    };
    let done = capture("A").output().unwrap();
    let stderr = String::from_utf8_lossy(&done.stderr);
    assert!(done.status.success(), "{stderr}");
    // -q is quiet: none of the set-up lines (adapter, eye and tiles, scissor) on stderr (issue 44 §6).
    for line in ["adapter:", "px/°", "left out:"] {
        assert!(!stderr.contains(line), "-q printed {line:?}: {stderr}");
    }
    let old_manifest = std::fs::read(archive.join("manifest.json")).unwrap();
    let old_tiles = tiles(&archive);
    assert!(old_tiles > 1);

    // Scenario B into the same folder, killed (SIGKILL: no handler runs) as
    // soon as the old tiles start to go, the moment the folder turns mixed.
    let mut running =
        capture("B").stdout(std::process::Stdio::null()).stderr(std::process::Stdio::null()).spawn().unwrap();
    let finished = loop {
        if let Some(status) = running.try_wait().unwrap() {
            break Some(status);
        }
        if tiles(&archive) != old_tiles {
            running.kill().unwrap();
            running.wait().unwrap();
            break None;
        }
        std::thread::sleep(std::time::Duration::from_millis(2));
    };
    match std::fs::read(archive.join("manifest.json")) {
        // Killed: no manifest at all (the analyzer cannot count the mix under A's).
        Err(_) => assert!(finished.is_none()),
        Ok(manifest) => {
            assert!(finished.is_some_and(|s| s.success()), "a manifest was left by a killed capture");
            assert_ne!(manifest, old_manifest, "the finished capture left scenario A's manifest");
        }
    }
}

#[cfg(unix)]
#[test]
fn a_link_planted_where_a_scenario_sub_folder_goes_is_replaced_not_written_through() {
    let dir = tempfile::tempdir().unwrap();
    let elsewhere = dir.path().join("elsewhere");
    std::fs::create_dir(&elsewhere).unwrap();
    let out = dir.path().join("all");
    std::fs::create_dir(&out).unwrap();
    std::os::unix::fs::symlink(&elsewhere, out.join("B")).unwrap();
    let ran = crate::hardening::tiny_capture(&["demo", "--scenario", "all"], &out, &[]);
    assert!(ran.success, "{}", ran.stderr);
    assert_eq!(std::fs::read_dir(&elsewhere).unwrap().count(), 0, "written through the link at all/B");
    assert!(!std::fs::symlink_metadata(out.join("B")).unwrap().file_type().is_symlink());
    assert!(out.join("B/manifest.json").is_file());
}

#[test]
fn a_recapture_without_placement_leaves_no_placement_table_of_the_earlier_capture() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("archive");
    let first = crate::hardening::tiny_capture(&["demo", "--scenario", "A"], &out, &[]);
    assert!(first.success, "{}", first.stderr);
    // What a capture of A with --placement left in results/, and a file of the user's.
    std::fs::create_dir_all(out.join("results")).unwrap();
    for name in ["placement-frames.csv", "placement-patches.csv", "notes.txt"] {
        std::fs::write(out.join("results").join(name), "scenario A").unwrap();
    }
    let again = crate::hardening::tiny_capture(&["demo", "--scenario", "B"], &out, &[]);
    assert!(again.success, "{}", again.stderr);
    assert!(!out.join("results/placement-frames.csv").exists(), "A's table is left beside B's archive");
    assert!(!out.join("results/placement-patches.csv").exists());
    assert!(out.join("results/notes.txt").is_file(), "a file of the user's was removed");
}
