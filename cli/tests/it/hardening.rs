//! The capture as hardened as the analyzer (issue 19, items 10–14) and
//! impossible scenes as errors or named warnings (issue 17, build item 3).
//!
//! Every command runs under a time limit: a hang is a failure, not a stuck
//! test run. Special files are made in a temporary folder.

use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// What a finished command said.
pub(crate) struct Ran {
    pub success: bool,
    pub stdout: String,
    pub stderr: String,
}

/// Runs `ufcsr-capture ARGS`, failing the test if it takes over a minute.
pub(crate) fn capture(args: &[&str]) -> Ran {
    let mut child = Command::new(env!("CARGO_BIN_EXE_ufcsr-capture"))
        .args(args)
        .env("XDG_RUNTIME_DIR", std::env::temp_dir())
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run ufcsr-capture");
    let start = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        if start.elapsed() > Duration::from_secs(120) {
            child.kill().unwrap();
            child.wait().unwrap();
            panic!("ufcsr-capture {args:?} hung");
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let (mut stdout, mut stderr) = (String::new(), String::new());
    child.stdout.take().unwrap().read_to_string(&mut stdout).unwrap();
    child.stderr.take().unwrap().read_to_string(&mut stderr).unwrap();
    Ran { success: status.success(), stdout, stderr }
}

/// A tiny capture: 4 frames, 3 px/°, a 256² palette.
const TINY: [&str; 7] = ["--ppd", "3", "--palette-size", "256", "--frames", "0-180/60", "-q"];

pub(crate) fn tiny_capture(command: &[&str], out: &Path, extra: &[&str]) -> Ran {
    let mut args: Vec<&str> = command.to_vec();
    args.extend(["--out", out.to_str().unwrap()]);
    args.extend(TINY);
    args.extend(extra);
    capture(&args)
}

pub(crate) fn refused(ran: &Ran, expect: &[&str], what: &str) {
    assert!(!ran.success, "{what}: accepted\n{}", ran.stdout);
    for text in expect {
        assert!(ran.stderr.contains(text), "{what}: no {text:?} in: {}", ran.stderr);
    }
}

#[cfg(unix)]
fn fifo(path: &Path) -> PathBuf {
    let status = Command::new("mkfifo").arg(path).status().expect("mkfifo");
    assert!(status.success());
    path.to_path_buf()
}

#[cfg(unix)]
fn link(target: &str, path: &Path) -> PathBuf {
    std::os::unix::fs::symlink(target, path).unwrap();
    path.to_path_buf()
}

pub(crate) fn fixture(name: &str) -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../fixtures/scenes")).join(name)
}

/// A scene file with the demo truck standing still at the origin, facing +x.
fn static_scene(dir: &Path, vehicle: &str, extra: &str) -> PathBuf {
    let path = dir.join("static.json");
    let text = format!(
        r#"{{ "vehicle": {vehicle}, "occluders": [{{"ground": {{"z": 0}}}}], {extra}
  "scenarios": {{"S": {{"duration_s": 3.0, "position": [{{"t": 0, "value": [0, 0, 0]}}],
  "yaw_deg": [{{"t": 0, "value": 0}}]}}}}}}"#
    );
    std::fs::write(&path, text).unwrap();
    path
}

/// The manifest's `warnings` (empty when it has none).
fn manifest_warnings(out: &Path) -> Vec<String> {
    let manifest = ufcsr::Manifest::load_from_dir(out).unwrap().expect("a manifest");
    manifest.warnings
}

// ---- glTF files for the tests ----

fn base64(bytes: &[u8]) -> String {
    const ALPHABET: &[u8] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut text = String::new();
    for chunk in bytes.chunks(3) {
        let n = chunk.iter().enumerate().fold(0u32, |n, (i, &b)| n | u32::from(b) << (16 - 8 * i));
        for i in 0..4 {
            if i <= chunk.len() {
                text.push(ALPHABET[(n >> (18 - 6 * i) & 63) as usize] as char);
            } else {
                text.push('=');
            }
        }
    }
    text
}

/// One triangle with UVs; `uri` (None: a data: URI of the bytes) is the
/// buffer, `mode` the primitive mode (4: triangles), `scale` the node's.
fn gltf_triangle(positions: [[f32; 3]; 3], uri: Option<&str>, mode: u32, scale: f32) -> String {
    let mut bytes: Vec<u8> = positions.iter().flatten().flat_map(|v| v.to_le_bytes()).collect();
    bytes.extend([0.0f32, 0.0, 1.0, 0.0, 0.0, 1.0].iter().flat_map(|v| v.to_le_bytes()));
    let uri = uri
        .map_or_else(|| format!("data:application/octet-stream;base64,{}", base64(&bytes)), str::to_string);
    format!(
        r#"{{"asset": {{"version": "2.0"}}, "scene": 0, "scenes": [{{"nodes": [0]}}],
  "nodes": [{{"mesh": 0, "name": "body", "scale": [{scale:e}, {scale:e}, {scale:e}]}}],
  "meshes": [{{"name": "body", "primitives": [{{"attributes": {{"POSITION": 0, "TEXCOORD_0": 1}}, "mode": {mode}}}]}}],
  "buffers": [{{"uri": "{uri}", "byteLength": 60}}],
  "bufferViews": [{{"buffer": 0, "byteOffset": 0, "byteLength": 36}}, {{"buffer": 0, "byteOffset": 36, "byteLength": 24}}],
  "accessors": [
    {{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]}},
    {{"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC2"}}]}}"#
    )
}

const TRIANGLE: [[f32; 3]; 3] = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];

// ---- item 10: hangs ----

#[cfg(unix)]
#[test]
fn fifos_as_any_capture_input_are_refused_by_name_without_hanging() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let out = d.join("out");
    let out = out.to_str().unwrap();
    for name in ["scene.json", "scene"] {
        let scene = fifo(&d.join(name));
        refused(&capture(&["scene", scene.to_str().unwrap(), "--out", out]), &["FIFO", name], name);
    }
    for name in ["inspect.json", "inspect.glb", "inspect.obj"] {
        let input = fifo(&d.join(name));
        refused(&capture(&["inspect", input.to_str().unwrap(), "--out", out]), &["FIFO", name], name);
    }
    // The scene's mesh, its unity file, and `capture unity`'s input.
    fifo(&d.join("vehicle.glb"));
    let scene = static_scene(d, r#"{"mesh": "vehicle.glb"}"#, "");
    refused(&capture(&["scene", scene.to_str().unwrap(), "--out", out]), &["FIFO", "vehicle.glb"], "mesh");
    let unity = fifo(&d.join("unity.json"));
    let scene = d.join("with-unity.json");
    std::fs::write(&scene, r#"{"vehicle": {"mesh": "demo"}, "unity": "unity.json"}"#).unwrap();
    refused(&capture(&["scene", scene.to_str().unwrap(), "--out", out]), &["FIFO", "unity.json"], "unity");
    refused(
        &capture(&["unity", unity.to_str().unwrap(), "--out", out]),
        &["FIFO", "unity.json"],
        "capture unity",
    );
    // An OBJ's mtllib: tobj would open it itself.
    fifo(&d.join("pipe.mtl"));
    let obj = d.join("piped.obj");
    std::fs::write(
        &obj,
        format!("mtllib pipe.mtl\n{}", std::fs::read_to_string(fixture("box-truck.obj")).unwrap()),
    )
    .unwrap();
    refused(&capture(&["inspect", obj.to_str().unwrap(), "--out", out]), &["FIFO", "pipe.mtl"], "mtllib");
}

#[cfg(unix)]
#[test]
fn a_fifo_vehicle_named_by_a_manifest_is_reported_as_a_fifo_not_as_missing() {
    let dir = tempfile::tempdir().unwrap();
    let archive = dir.path().join("archive");
    assert!(tiny_capture(&["demo"], &archive, &[]).success);
    std::fs::remove_file(archive.join("vehicle.glb")).unwrap();
    fifo(&archive.join("vehicle.glb"));
    let options = ufcsr::AnalyzeOptions { archive: archive.clone(), ..ufcsr::AnalyzeOptions::default() };
    let analysis = ufcsr::analyze(&options, None).unwrap();
    let warning = analysis.result.warnings.iter().find(|w| w.contains("vehicle.glb")).expect("a warning");
    assert!(warning.contains("FIFO") && !warning.contains("missing"), "{warning}");
}

// ---- item 11: runaway memory ----

#[cfg(unix)]
#[test]
fn links_to_dev_zero_and_buffers_outside_the_model_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let out = d.join("out");
    let out = out.to_str().unwrap();
    let scene = link("/dev/zero", &d.join("zero.json"));
    refused(&capture(&["scene", scene.to_str().unwrap(), "--out", out]), &["a device"], "scene → /dev/zero");
    let obj = link("/dev/zero", &d.join("zero.obj"));
    refused(&capture(&["inspect", obj.to_str().unwrap(), "--out", out]), &["a device"], "OBJ → /dev/zero");
    link("/dev/zero", &d.join("zero.mtl"));
    let obj = d.join("zero-mtl.obj");
    std::fs::write(
        &obj,
        format!("mtllib zero.mtl\n{}", std::fs::read_to_string(fixture("box-truck.obj")).unwrap()),
    )
    .unwrap();
    refused(&capture(&["inspect", obj.to_str().unwrap(), "--out", out]), &["zero.mtl"], "mtllib → /dev/zero");
    let nested = d.join("a/b");
    std::fs::create_dir_all(&nested).unwrap();
    let gltf = nested.join("zero.gltf");
    std::fs::write(&gltf, gltf_triangle(TRIANGLE, Some("../../dev/zero"), 4, 1.0)).unwrap();
    refused(
        &capture(&["inspect", gltf.to_str().unwrap(), "--out", out]),
        &["../../dev/zero", "inside its own folder"],
        "buffer URI ../../dev/zero",
    );
}

#[test]
fn frame_rates_and_frame_counts_beyond_bounds_are_errors() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("archive");
    refused(
        &tiny_capture(&["demo"], &out, &["--rig", r#"{"fps": 1e7}"#]),
        &["fps 10000000", "1000"],
        "fps 1e7",
    );
    // 1000 fps is allowed, but not for 20 minutes (1.2 million frames).
    let scene = dir.path().join("long.json");
    std::fs::write(
        &scene,
        r#"{"vehicle": {"mesh": "demo"}, "rig": {"fps": 1000},
  "scenarios": {"S": {"duration_s": 1200, "position": [{"t": 0, "value": [10, 0, 0]}], "yaw_deg": [{"t": 0, "value": 0}]}}}"#,
    )
    .unwrap();
    refused(
        &tiny_capture(&["scene", scene.to_str().unwrap()], &out, &[]),
        &["1.2e6 frames", "1e6"],
        "frames",
    );
    assert!(!out.join("manifest.json").exists());
}

// ---- item 12: coordinates ----

#[test]
fn inspect_refuses_huge_coordinates_and_node_scales_naming_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let out = d.join("out");
    let out = out.to_str().unwrap();
    let obj = d.join("far.obj");
    std::fs::write(&obj, "o far\nv 0 0 0\nv 1e30 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\n")
        .unwrap();
    refused(
        &capture(&["inspect", obj.to_str().unwrap(), "--out", out]),
        &["far.obj", "beyond ±1e5 m"],
        "1e30 m",
    );
    for scale in [1e12_f32, 1e38] {
        let gltf = d.join(format!("scaled-{scale:e}.gltf"));
        std::fs::write(&gltf, gltf_triangle(TRIANGLE, None, 4, scale)).unwrap();
        let name = gltf.file_name().unwrap().to_str().unwrap().to_string();
        refused(
            &capture(&["inspect", gltf.to_str().unwrap(), "--out", out]),
            &[&name, "beyond ±1e5 m"],
            &name,
        );
    }
    // Within bounds, but 10 km at 2000 px/m would be a 20-million-pixel-wide picture.
    let wide = d.join("wide.obj");
    std::fs::write(&wide, "o wide\nv 0 0 0\nv 1e4 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    refused(
        &capture(&["inspect", wide.to_str().unwrap(), "--out", out, "--pixels-per-metre", "2000"]),
        &["20000000 pixels wide, more than 16384", "at most 1.638"],
        "a huge picture",
    );
    // The same triangle at scale 1 inspects fine.
    let gltf = d.join("unit.gltf");
    std::fs::write(&gltf, gltf_triangle(TRIANGLE, None, 4, 1.0)).unwrap();
    let ran = capture(&["inspect", gltf.to_str().unwrap(), "--out", out]);
    assert!(ran.success, "{}", ran.stderr);
    assert!(ran.stdout.contains("triangles: 1;"), "{}", ran.stdout);
}

// ---- item 13: rig bounds ----

#[test]
fn rig_values_beyond_physical_bounds_are_errors_like_track_keys() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("archive");
    for (rig, expect) in [
        (r#"{"eye_height_m": 1e308}"#, "eye_height_m 1e308 is beyond ±1e6 m: not a street scene"),
        (r#"{"pedestrian": [1e15, 0, 0]}"#, "is beyond ±1e6 m: not a street scene"),
        (r#"{"look_at_vehicle": [0, 1e300, 0]}"#, "look_at_vehicle [0.0, 1e300, 0.0] is beyond ±1e6 m"),
        (r#"{"ipd_m": 1e6}"#, "ipd_m 1000000 must be between 0 and 1 m"),
        (r#"{"ipd_m": -1}"#, "ipd_m -1 must be between 0 and 1 m"),
        (r#"{"far_m": 1e9}"#, "far_m 1e9 is beyond ±1e6 m"),
    ] {
        refused(&tiny_capture(&["demo"], &out, &["--rig", rig]), &[expect], rig);
        assert!(!out.join("manifest.json").exists(), "{rig}: wrote a manifest");
    }
    // Occluders too.
    let scene = dir.path().join("boxed.json");
    let text = std::fs::read_to_string(static_scene(dir.path(), r#"{"mesh": "demo"}"#, "")).unwrap();
    let boxed = r#""occluders": [{"box": {"min": [0, 0, 0], "max": [1e308, 1, 1]}}]"#;
    std::fs::write(&scene, text.replace(r#""occluders": [{"ground": {"z": 0}}]"#, boxed)).unwrap();
    let ran = tiny_capture(&["scene", scene.to_str().unwrap()], &out, &[]);
    refused(
        &ran,
        &["boxed.json", "occluders[0] (box #0): 1e308 is beyond ±1e6: not a street scene"],
        "occluder box",
    );
    // The same bounds hold in a scene file.
    let scene = static_scene(dir.path(), r#"{"mesh": "demo"}"#, r#""rig": {"ipd_m": -1},"#);
    refused(
        &tiny_capture(&["scene", scene.to_str().unwrap()], &out, &[]),
        &["static.json", "ipd_m -1"],
        "scene",
    );
}

// ---- item 14: --mesh (the analyzer's reader of heatmap meshes) ----

#[test]
fn heatmap_meshes_with_non_finite_positions_or_no_triangles_are_refused_by_their_name() {
    let dir = tempfile::tempdir().unwrap();
    let nan = dir.path().join("nan.gltf");
    std::fs::write(
        &nan,
        gltf_triangle([[0.0, 0.0, 0.0], [f32::NAN, 0.0, 0.0], [0.0, 1.0, 0.0]], None, 4, 1.0),
    )
    .unwrap();
    let error = ufcsr::VehicleModel::read(&nan).unwrap_err().to_string();
    assert!(error.contains("nan.gltf") && error.contains("not finite"), "{error}");
    let inf = dir.path().join("inf.gltf");
    std::fs::write(
        &inf,
        gltf_triangle([[0.0, 0.0, 0.0], [f32::INFINITY, 0.0, 0.0], [0.0, 1.0, 0.0]], None, 4, 1.0),
    )
    .unwrap();
    assert!(ufcsr::VehicleModel::read(&inf).unwrap_err().to_string().contains("not finite"));
    // Points (mode 0): no triangles; named under the mesh's own file.
    let points = dir.path().join("points.gltf");
    std::fs::write(&points, gltf_triangle(TRIANGLE, None, 0, 1.0)).unwrap();
    let error = ufcsr::VehicleModel::read(&points).unwrap_err().to_string();
    assert!(error.contains("points.gltf") && error.contains("not triangles"), "{error}");
    assert!(!error.contains("staging"), "{error}");
}

#[test]
fn a_gltf_heatmap_mesh_may_keep_its_buffer_in_a_data_uri_or_beside_it() {
    let dir = tempfile::tempdir().unwrap();
    let inline = dir.path().join("inline.gltf");
    std::fs::write(&inline, gltf_triangle(TRIANGLE, None, 4, 1.0)).unwrap();
    let model = ufcsr::VehicleModel::read(&inline).unwrap();
    assert_eq!(model.parts.len(), 1);
    // Another program's glTF is in glTF's axes (+Y up, front +Z): glTF (x, y, z) is the vehicle's (z, x, y).
    let vehicle_frame: Vec<[f32; 3]> = TRIANGLE.iter().map(|&[x, y, z]| [z, x, y]).collect();
    assert_eq!(model.parts[0].positions, vehicle_frame);
    assert_eq!(model.parts[0].uvs, vec![[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]);
    let mut bytes: Vec<u8> = TRIANGLE.iter().flatten().flat_map(|v| v.to_le_bytes()).collect();
    bytes.extend([0.0f32, 0.0, 1.0, 0.0, 0.0, 1.0].iter().flat_map(|v| v.to_le_bytes()));
    std::fs::write(dir.path().join("beside.bin"), bytes).unwrap();
    let beside = dir.path().join("beside.gltf");
    std::fs::write(&beside, gltf_triangle(TRIANGLE, Some("beside.bin"), 4, 1.0)).unwrap();
    assert_eq!(ufcsr::VehicleModel::read(&beside).unwrap(), model);
}

// ---- issue 17, item 3: impossible scenes ----

#[test]
fn the_near_plane_cutting_the_vehicle_is_a_warning_naming_the_frames() {
    let dir = tempfile::tempdir().unwrap();
    let scene = static_scene(dir.path(), r#"{"mesh": "demo"}"#, "");
    let out = dir.path().join("archive");
    // The truck's right side is at y = -1.0: the eyes are 0.2 m from it.
    let rig = r#"{"pedestrian": [0, -1.2, 0], "eye_height_m": 1.0, "look_at_vehicle": [0, 0, 1]}"#;
    let ran = tiny_capture(&["scene", scene.to_str().unwrap()], &out, &["--rig", rig]);
    assert!(ran.success, "{}", ran.stderr);
    let expect = "the near plane (0.3 m) cuts the vehicle open in frames 0, 60, 120, 180";
    assert!(ran.stderr.contains(expect), "{}", ran.stderr);
    assert!(manifest_warnings(&out).iter().any(|w| w.contains(expect)));
    // 3 m away nothing is cut.
    let rig = r#"{"pedestrian": [0, -4, 0], "look_at_vehicle": [0, 0, 1]}"#;
    let ran = tiny_capture(&["scene", scene.to_str().unwrap()], &out, &["--rig", rig]);
    assert!(ran.success && !ran.stderr.contains("near plane"), "{}", ran.stderr);
    assert!(manifest_warnings(&out).is_empty());
}

#[test]
fn the_vehicle_beyond_the_far_plane_is_a_warning_naming_the_frames() {
    let dir = tempfile::tempdir().unwrap();
    let scene = static_scene(dir.path(), r#"{"mesh": "demo"}"#, "");
    let out = dir.path().join("archive");
    let ran = tiny_capture(
        &["scene", scene.to_str().unwrap()],
        &out,
        &["--rig", r#"{"pedestrian": [-5000, 0, 0]}"#],
    );
    assert!(ran.success, "{}", ran.stderr);
    // The truck's front is 5000 + 2.95 m (and a little for the eye offset) away.
    let expect = "beyond the far plane (1000 m) in frames 0, 60, 120, 180 (up to 5003.0 m away)";
    assert!(ran.stderr.contains(expect), "{}", ran.stderr);
    assert!(manifest_warnings(&out).iter().any(|w| w.contains(expect)));
    // The analyzer carries the capture's warning into its result.
    let options = ufcsr::AnalyzeOptions { archive: out.clone(), ..ufcsr::AnalyzeOptions::default() };
    let analysis = ufcsr::analyze(&options, None).unwrap();
    assert!(
        analysis.result.warnings.iter().any(|w| w.starts_with("the capture warned: ") && w.contains(expect))
    );
}

#[test]
fn an_eye_inside_the_vehicle_is_an_error_naming_the_frames() {
    let dir = tempfile::tempdir().unwrap();
    let scene = static_scene(dir.path(), r#"{"mesh": "demo"}"#, "");
    let out = dir.path().join("archive");
    // In the cab, 1.5 m above the ground.
    let rig = r#"{"pedestrian": [0.5, 0, 0], "eye_height_m": 1.5}"#;
    let ran = tiny_capture(&["scene", scene.to_str().unwrap()], &out, &["--rig", rig]);
    refused(&ran, &["both eyes are inside the vehicle in frames 0, 60, 120, 180"], "eye in the cab");
    assert!(!out.join("manifest.json").exists());
    // Above the open bed (inside the bounding box, outside the hull): no error.
    let rig = r#"{"pedestrian": [-1.5, 0, 0], "eye_height_m": 1.4}"#;
    let ran = tiny_capture(&["scene", scene.to_str().unwrap()], &out, &["--rig", rig]);
    assert!(ran.success && !ran.stderr.contains("inside the vehicle"), "{}", ran.stderr);
}

#[test]
fn a_teleporting_track_is_a_warning_naming_its_keys() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("teleport.json");
    // 222 m in 1 ms, between frames 60 and 61.
    std::fs::write(
        &scene,
        r#"{"vehicle": {"mesh": "demo"}, "occluders": [{"ground": {"z": 0}}], "rig": {"pedestrian": [0, -8, 0]},
  "scenarios": {"T": {"duration_s": 3.0,
    "position": [{"t": 1.0, "value": [0, 0, 0]}, {"t": 1.001, "value": [222, 0, 0]}],
    "yaw_deg": [{"t": 0, "value": 0}]}}}"#,
    )
    .unwrap();
    let out = dir.path().join("archive");
    let ran = tiny_capture(&["scene", scene.to_str().unwrap()], &out, &[]);
    assert!(ran.success, "{}", ran.stderr);
    let expect =
        "faster than 100 m/s between frames (up to 13320.0 m/s) at position keys 0–1 (t 1.000–1.001 s)";
    assert!(ran.stderr.contains(expect), "{}", ran.stderr);
    assert!(ran.stderr.contains("harder than 3 g"), "{}", ran.stderr);
    assert!(manifest_warnings(&out).iter().any(|w| w.contains(expect)));
}

#[test]
fn the_demo_scenarios_warn_about_nothing_and_their_manifests_have_no_warnings() {
    let dir = tempfile::tempdir().unwrap();
    for scenario in ["A", "B", "C", "D"] {
        let out = dir.path().join(scenario);
        let ran = tiny_capture(&["demo", "--scenario", scenario], &out, &[]);
        assert!(ran.success && !ran.stderr.contains("warning"), "{scenario}: {}", ran.stderr);
        let manifest = ufcsr::Manifest::load_from_dir(&out).unwrap().unwrap();
        assert!(manifest.warnings.is_empty(), "{scenario}");
    }
}
