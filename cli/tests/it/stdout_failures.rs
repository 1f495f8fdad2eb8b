//! Issue 34, output streams: a full device or a closed pipe on stdout ends
//! a run with a message on stderr and a documented exit code, never a panic
//! (exit 101): the analysis, with and without `--json`, `palette --json`,
//! `placement`, the capture's `demo` and `inspect`. Paths that are not
//! UTF-8 work.

use crate::common;

use std::path::PathBuf;
use std::process::{Command, Stdio};

fn example() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fixtures/example")
}

/// Runs `command` with stdout on `/dev/full`; returns its exit code and stderr.
fn into_full_device(mut command: Command) -> (Option<i32>, String) {
    let full = std::fs::OpenOptions::new().write(true).open("/dev/full").unwrap();
    let output = command.stdout(Stdio::from(full)).output().unwrap();
    (output.status.code(), String::from_utf8_lossy(&output.stderr).into_owned())
}

/// Runs `command` with stdout a pipe whose reader is gone before it writes.
fn into_closed_pipe(mut command: Command) -> (Option<i32>, String) {
    let mut child = command.stdout(Stdio::piped()).stderr(Stdio::piped()).spawn().unwrap();
    drop(child.stdout.take());
    let output = child.wait_with_output().unwrap();
    (output.status.code(), String::from_utf8_lossy(&output.stderr).into_owned())
}

#[cfg(unix)]
#[test]
fn a_full_device_or_a_closed_pipe_on_stdout_is_an_error_not_a_panic() {
    if !std::path::Path::new("/dev/full").exists() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    for how in ["full", "closed"] {
        for (what, command) in commands(dir.path()) {
            let (code, stderr) =
                if how == "full" { into_full_device(command) } else { into_closed_pipe(command) };
            assert!(code.is_some() && code != Some(101), "{what} into a {how} stdout: {code:?} {stderr}");
            assert!(!stderr.contains("panicked"), "{what} into a {how} stdout panicked: {stderr}");
        }
    }
}

/// The commands tried, each writing into `dir`.
fn commands(dir: &std::path::Path) -> Vec<(&'static str, Command)> {
    let mut analysis = common::analyzer();
    analysis.arg(example()).arg("--out").arg(dir.join("R"));
    let mut json = common::analyzer();
    json.arg(example()).arg("--json").arg("--out").arg(dir.join("J"));
    let mut palette = common::analyzer();
    palette.args(["palette", "--size", "8", "--json", "--out"]).arg(dir.join("p.png"));
    // placement on a two-candidate table; inspect on the example's model.
    let archive = dir.join("archive");
    std::fs::create_dir_all(archive.join("results")).unwrap();
    let mut table = String::from(
        "frame,time_s,eye,distance_m,candidate,kind,solid_angle_sr,visible_fraction,view_angle_deg,\
         angular_height_deg,frame_s\n",
    );
    for frame in 0..10 {
        for part in ["hood", "grill"] {
            table += &format!(
                "{frame},{},left,{},{part},part,1e-3,1,10,1,0.1\n",
                f64::from(frame) / 10.0,
                30 - frame
            );
        }
    }
    std::fs::write(archive.join("results/placement-frames.csv"), table).unwrap();
    let mut placement = common::analyzer();
    placement.arg("placement").arg(&archive).args(["--min-dwell-s", "0", "--out"]).arg(dir.join("P"));
    let mut inspect = Command::new(env!("CARGO_BIN_EXE_ufcsr-capture"));
    inspect.arg("inspect").arg(example().join("vehicle.glb")).arg("--out").arg(dir.join("I"));
    inspect.env("XDG_RUNTIME_DIR", dir);
    vec![
        ("analysis", analysis),
        ("analysis --json", json),
        ("palette --json", palette),
        ("placement", placement),
        ("inspect", inspect),
    ]
}

#[cfg(unix)]
#[test]
fn non_utf8_paths_work_or_are_refused_never_a_panic() {
    use std::os::unix::ffi::OsStrExt;
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join(std::ffi::OsStr::from_bytes(b"out-\xff"));
    let analysed = common::analyzer().arg(example()).arg("--json").arg("--out").arg(&out).output().unwrap();
    let stderr = String::from_utf8_lossy(&analysed.stderr);
    assert!(analysed.status.success() && !stderr.contains("panicked"), "{stderr}");
    assert!(out.join("result.json").is_file());
    let png = dir.path().join(std::ffi::OsStr::from_bytes(b"palette-\xfe.png"));
    let palette =
        common::analyzer().args(["palette", "--size", "8", "--json", "--out"]).arg(&png).output().unwrap();
    let stderr = String::from_utf8_lossy(&palette.stderr);
    assert!(palette.status.success() && !stderr.contains("panicked"), "{stderr}");
    assert!(png.is_file());
}

/// The capture's `demo` into a stdout that fails: a full device is named on
/// stderr and gives exit 1 (the archive was written, its summary was not
/// printed); a reader that has gone is not an error (exit 0). Never a panic.
#[cfg(unix)]
#[test]
fn demo_into_a_full_or_closed_stdout_ends_with_its_documented_exit_code() {
    if !std::path::Path::new("/dev/full").exists() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let demo = |name: &str| {
        let mut command = Command::new(env!("CARGO_BIN_EXE_ufcsr-capture"));
        command.args(["demo", "--ppd", "2", "--palette-size", "256", "--frames", "150,180", "--out"]);
        command.arg(dir.path().join(name)).env("XDG_RUNTIME_DIR", dir.path());
        command
    };
    for (how, (code, stderr), expected) in
        [("full", into_full_device(demo("full")), 1), ("closed", into_closed_pipe(demo("closed")), 0)]
    {
        assert_eq!(code, Some(expected), "demo into a {how} stdout: {stderr}");
        assert!(!stderr.contains("panicked"), "{how}: {stderr}");
        assert_eq!(stderr.contains("cannot write to stdout"), how == "full", "{how}: {stderr}");
        assert!(dir.path().join(how).join("manifest.json").is_file(), "{how}: no archive");
    }
}
