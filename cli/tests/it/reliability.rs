//! The capture's half of issue 19 beyond items 10–14 (`hardening.rs`): no
//! command writes over one of its inputs (item 2), `assemble` accounts for
//! every frame and tile (item 8), `batch plan` validates the plan when
//! planning (item 17), and a Unity export gets the scene file's bounds and
//! messages.

use std::path::{Path, PathBuf};

use crate::hardening::{capture, fixture, refused, tiny_capture};

/// `dir/own/`: the fixture's glTF box truck as `vehicle.glb` and a scene
/// file naming it, as a user keeps a vehicle and its scene in one folder.
fn own_vehicle_folder(dir: &Path) -> (PathBuf, PathBuf) {
    let own = dir.join("own");
    std::fs::create_dir_all(&own).unwrap();
    std::fs::copy(fixture("box-truck.glb"), own.join("vehicle.glb")).unwrap();
    let scene = own.join("scene.json");
    std::fs::write(
        &scene,
        r#"{"vehicle": {"mesh": "vehicle.glb"}, "occluders": [{"ground": {"z": 0}}],
  "scenarios": {"S": {"duration_s": 3.0, "position": [{"t": 0, "value": [10, 0, 0]}], "yaw_deg": [{"t": 0, "value": 0}]}}}"#,
    )
    .unwrap();
    (own, scene)
}

// ---- item 2: never overwrite an input ----

#[test]
fn a_capture_into_the_folder_of_its_own_mesh_is_refused_and_leaves_the_mesh_alone() {
    let dir = tempfile::tempdir().unwrap();
    let (own, scene) = own_vehicle_folder(dir.path());
    let mesh = std::fs::read(own.join("vehicle.glb")).unwrap();
    // The folder itself, and the same folder under another spelling.
    for out in [own.clone(), own.join(".").join("..").join("own")] {
        let ran = tiny_capture(&["scene", scene.to_str().unwrap()], &out, &[]);
        refused(&ran, &["vehicle.glb would overwrite the input", "choose another output"], "scene");
        assert_eq!(std::fs::read(own.join("vehicle.glb")).unwrap(), mesh, "the mesh was replaced");
        assert!(!own.join("manifest.json").exists() && !own.join("pidt.png").exists(), "wrote outputs");
    }
    // --count and --scenario all write the same files.
    let ran = tiny_capture(&["scene", scene.to_str().unwrap()], &own, &["--count"]);
    refused(&ran, &["would overwrite the input"], "--count");
    // Another folder is fine.
    let ran = tiny_capture(&["scene", scene.to_str().unwrap()], &dir.path().join("archive"), &[]);
    assert!(ran.success, "{}", ran.stderr);
}

#[test]
fn inputs_inside_the_folders_a_capture_owns_or_named_like_its_files_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let (own, _) = own_vehicle_folder(dir.path());
    // A mesh inside out/tiles, where a capture removes old tiles.
    let tiles = own.join("tiles");
    std::fs::create_dir_all(&tiles).unwrap();
    std::fs::copy(fixture("box-truck.glb"), tiles.join("truck.glb")).unwrap();
    let scene = dir.path().join("tiles-scene.json");
    let text = std::fs::read_to_string(own.join("scene.json")).unwrap();
    std::fs::write(&scene, text.replace("vehicle.glb", "own/tiles/truck.glb")).unwrap();
    let ran = tiny_capture(&["scene", scene.to_str().unwrap()], &own, &[]);
    refused(&ran, &["writing into", "tiles would overwrite the input", "truck.glb"], "mesh in tiles/");
    // The scene file itself as the archive's manifest.json.
    let manifest = dir.path().join("archive").join("manifest.json");
    std::fs::create_dir_all(manifest.parent().unwrap()).unwrap();
    std::fs::write(&manifest, text.replace("vehicle.glb", "../own/vehicle.glb")).unwrap();
    let ran = tiny_capture(&["scene", manifest.to_str().unwrap()], manifest.parent().unwrap(), &[]);
    refused(&ran, &["manifest.json would overwrite the input"], "scene file as manifest.json");
    // An external palette kept as the archive's own palette.png.
    let palette = dir.path().join("archive").join("palette.png");
    ufcsr::write_canonical_png(&palette, [256, 256]).unwrap();
    let before = std::fs::read(&palette).unwrap();
    let ran = tiny_capture(&["demo"], manifest.parent().unwrap(), &["--palette", palette.to_str().unwrap()]);
    refused(&ran, &["palette.png would overwrite the input"], "--palette");
    assert_eq!(std::fs::read(&palette).unwrap(), before);
}

#[test]
fn inspect_and_views_refuse_to_write_over_their_inputs() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("inspect");
    std::fs::create_dir_all(&out).unwrap();
    // An OBJ whose MTL is named like inspect's legend.
    std::fs::copy(fixture("box-truck.mtl"), out.join("inspect-parts.csv")).unwrap();
    let obj = out.join("truck.obj");
    let text = std::fs::read_to_string(fixture("box-truck.obj")).unwrap();
    let text: String = text.lines().filter(|l| !l.starts_with("mtllib")).collect::<Vec<_>>().join("\n");
    std::fs::write(&obj, format!("mtllib inspect-parts.csv\n{text}\n")).unwrap();
    let ran = capture(&["inspect", obj.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    refused(&ran, &["inspect-parts.csv would overwrite the input"], "inspect");
    // views: a model kept where a view goes.
    let archive = dir.path().join("archive");
    assert!(tiny_capture(&["demo"], &archive, &["--count"]).success);
    let results = archive.join("results");
    std::fs::copy(results.join("heatmap.glb"), results.join("views.png")).unwrap();
    let model = results.join("views.png");
    let ran = capture(&["views", results.to_str().unwrap(), "--model", model.to_str().unwrap()]);
    refused(&ran, &["views.png would overwrite the input"], "views");
}

// ---- item 1's rule in the capture: no write through a link ----

#[cfg(unix)]
#[test]
fn a_capture_replaces_a_linked_tiles_folder_and_leaves_the_folder_it_points_to_alone() {
    let dir = tempfile::tempdir().unwrap();
    let elsewhere = dir.path().join("elsewhere");
    std::fs::create_dir_all(&elsewhere).unwrap();
    // Named like a tile the capture writes (and like one it removes).
    std::fs::write(elsewhere.join("f0060_left_r2_c2.png"), b"precious").unwrap();
    std::fs::write(elsewhere.join("f0007_left_r0_c0.png"), b"precious too").unwrap();
    let out = dir.path().join("archive");
    std::fs::create_dir_all(&out).unwrap();
    std::os::unix::fs::symlink(&elsewhere, out.join("tiles")).unwrap();
    let ran = tiny_capture(&["demo"], &out, &[]);
    assert!(ran.success, "{}", ran.stderr);
    assert!(!std::fs::symlink_metadata(out.join("tiles")).unwrap().file_type().is_symlink());
    assert!(out.join("tiles/f0060_left_r2_c2.png").is_file());
    let left: Vec<_> = std::fs::read_dir(&elsewhere).unwrap().flatten().map(|e| e.file_name()).collect();
    assert_eq!(left.len(), 2, "{left:?}");
    assert_eq!(std::fs::read(elsewhere.join("f0060_left_r2_c2.png")).unwrap(), b"precious");
    // assemble removes the parts it joined: never through a link.
    let shards = dir.path().join("sharded");
    std::fs::create_dir_all(&shards).unwrap();
    std::os::unix::fs::symlink(&elsewhere, shards.join("shards")).unwrap();
    let ran = capture(&["assemble", shards.to_str().unwrap()]);
    refused(&ran, &["shards: is a link"], "linked shards/");
}

// ---- item 17: batch plans are validated when planning ----

/// `batch plan` of a batch file with `text` in `dir`.
fn plan(dir: &Path, text: &str) -> crate::hardening::Ran {
    let batch = dir.join("batch.json");
    std::fs::write(&batch, text).unwrap();
    capture(&["batch", "plan", batch.to_str().unwrap(), "--program", "ufcsr-capture"])
}

#[test]
fn batch_plan_refuses_what_every_task_would_fail_on_naming_the_batch_file() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    for (text, expect) in [
        (r#"{"out": "runs", "scenes": ["demo"], "dedupe": "bogus"}"#, "unknown variant `bogus`"),
        (r#"{"out": "runs", "scenes": ["demo"], "palette_size": "big"}"#, "palette_size: "),
        (r#"{"out": "runs", "scenes": ["demo"], "palette_size": "0x0"}"#, "palette_size: "),
        (
            r#"{"out": "runs\nrm -rf x", "scenes": ["demo"]}"#,
            "out: \"runs\\nrm -rf x\" has a control character",
        ),
        (
            r#"{"out": "runs", "scenes": ["demo"], "extra_args": ["--out", "x"]}"#,
            "--out is an option the plan sets",
        ),
        (r#"{"out": "runs", "scenes": ["demo"], "ppd": [10, 10]}"#, "tasks 0 and 1 would both write into"),
        (r#"{"out": "runs", "scenes": ["demo"], "scenarios": ["A", "a"]}"#, "would both write into"),
    ] {
        let ran = plan(d, text);
        refused(&ran, &["batch.json", expect], text);
        assert!(ran.stdout.is_empty(), "{text}: planned {}", ran.stdout);
    }
    // A scene without the scenario asked for: the batch file, the scene and the scenario named.
    let (_, scene) = own_vehicle_folder(d);
    let text = format!(r#"{{"out": "runs", "scenes": ["demo", "{}"], "scenarios": ["A"]}}"#, scene.display());
    let ran = plan(d, &text);
    refused(
        &ran,
        &["batch.json", "scenes[1]", "scene.json", "no scenario \"A\"; the scene has S"],
        "scenario",
    );
}

#[test]
fn a_valid_batch_plans_one_line_per_task() {
    let dir = tempfile::tempdir().unwrap();
    let ran = plan(
        dir.path(),
        r#"{"out": "my runs", "scenes": ["demo"], "scenarios": ["A", "B"], "ppd": [10, 6], "dedupe": "eye-pair", "palette_size": "512x256"}"#,
    );
    assert!(ran.success, "{}", ran.stderr);
    let lines: Vec<&str> = ran.stdout.lines().collect();
    assert_eq!(lines.len(), 4, "{}", ran.stdout);
    assert!(
        lines[3].contains("--scenario B --ppd 6") && lines[3].contains("--dedupe eye-pair"),
        "{}",
        lines[3]
    );
    assert!(lines[3].ends_with("--out 'my runs/0-demo/B/ppd6-step1'"), "{}", lines[3]);
}

// ---- item 8: assemble accounts for every frame and tile ----

/// Edits shard `index` of 2's part manifest in `archive` with `edit`.
fn edit_part(archive: &Path, index: u32, edit: impl Fn(&mut serde_json::Value)) {
    let path = archive.join(format!("shards/manifest-{index}-of-2.json"));
    let mut manifest: serde_json::Value = serde_json::from_slice(&std::fs::read(&path).unwrap()).unwrap();
    edit(&mut manifest);
    std::fs::write(&path, serde_json::to_vec_pretty(&manifest).unwrap()).unwrap();
}

#[test]
fn assemble_refuses_a_part_manifest_that_lost_frames_or_tiles() {
    let dir = tempfile::tempdir().unwrap();
    let archive = dir.path().join("archive");
    for (edit, expect) in [
        (
            (|m: &mut serde_json::Value| {
                m["tiles"] = serde_json::json!([]);
                m["frames"] = serde_json::json!([]);
            }) as fn(&mut serde_json::Value),
            "has 0 frame records where shard 1/2 takes 2 of the 4 selected frames (missing: 60, 180)",
        ),
        (
            |m| {
                m["frames"].as_array_mut().unwrap().pop();
            },
            "missing: 180",
        ),
        (
            |m| {
                m["tiles"].as_array_mut().unwrap().pop();
            },
            "but the shard wrote",
        ),
        (
            |m| m["capture"]["shard"]["selected_frames"] = serde_json::json!([0, 60, 120]),
            "its selected frames differ",
        ),
    ] {
        let _ = std::fs::remove_dir_all(&archive);
        for shard in ["0/2", "1/2"] {
            assert!(tiny_capture(&["demo"], &archive, &["--shard", shard]).success);
        }
        edit_part(&archive, 1, edit);
        let ran = capture(&["assemble", archive.to_str().unwrap()]);
        refused(&ran, &["manifest-1-of-2.json", expect], expect);
        assert!(!archive.join("manifest.json").exists(), "{expect}: assembled");
    }
    // Untouched, the same shards assemble, every frame there.
    let _ = std::fs::remove_dir_all(&archive);
    for shard in ["0/2", "1/2"] {
        assert!(tiny_capture(&["demo"], &archive, &["--shard", shard]).success);
    }
    let ran = capture(&["assemble", archive.to_str().unwrap()]);
    assert!(ran.success && ran.stdout.contains("2 shards, 4 frames"), "{}{}", ran.stdout, ran.stderr);
}

// ---- item 13, variations: resolution and near plane ----

#[test]
fn a_resolution_beyond_bounds_or_a_vanishing_near_plane_is_an_error_not_a_panic_or_an_empty_archive() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("archive");
    // --ppd 1e9 overflowed the eye size (a panic; in a release build a wrapped size).
    let ran = capture(&["demo", "--out", out.to_str().unwrap(), "-q", "--ppd", "1e9"]);
    refused(&ran, &["--ppd 1000000000 must be in (0, 1000] pixels per degree"], "--ppd 1e9");
    assert!(!ran.stderr.contains("panicked"), "{}", ran.stderr);
    // A near plane of 1e-300 m rendered nothing and exited 0.
    refused(
        &tiny_capture(&["demo"], &out, &["--rig", r#"{"near_m": 1e-300}"#]),
        &["near_m 1e-300 and far_m 1e3: need 0.001 m ≤ near < far"],
        "near 1e-300",
    );
    assert!(!out.join("manifest.json").exists());
    // A batch with such a ppd is refused when planning, naming the batch file.
    let batch = dir.path().join("batch.json");
    std::fs::write(&batch, r#"{"out": "runs", "scenes": ["demo"], "ppd": [1e9]}"#).unwrap();
    let ran = capture(&["batch", "plan", batch.to_str().unwrap()]);
    refused(&ran, &["batch.json", "--ppd 1000000000 must be in"], "batch ppd");
}

// ---- a Unity export gets the scene file's bounds and messages ----

/// The fuzz seed's two-key Unity export, edited by `edit`, in `dir`.
fn unity_export(dir: &Path, edit: impl Fn(&mut serde_json::Value)) -> PathBuf {
    let seed = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fuzz/seeds/unity/two-keys.json");
    let mut export: serde_json::Value = serde_json::from_slice(&std::fs::read(seed).unwrap()).unwrap();
    edit(&mut export);
    let path = dir.join("export.json");
    std::fs::write(&path, serde_json::to_vec(&export).unwrap()).unwrap();
    path
}

#[test]
fn a_unity_export_beyond_bounds_or_without_scenarios_is_refused_naming_its_file() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("archive");
    for (edit, expect) in [
        (
            (|u: &mut serde_json::Value| u["scenarios"] = serde_json::json!({}))
                as fn(&mut serde_json::Value),
            "the Unity export has no scenarios",
        ),
        (
            |u| u["scenarios"]["A"]["duration_s"] = serde_json::json!(-3),
            "scenario A: duration_s -3 must be between 0",
        ),
        (|u| u["pedestrian"]["far"] = serde_json::json!(1e9), "rig: far_m 1e9 is beyond ±1e6 m"),
        (|u| u["capture"]["fps"] = serde_json::json!(1e7), "rig: fps 10000000 must be in (0, 1000]"),
        (
            |u| u["scenarios"]["A"]["vehicle"][0]["keys"][1]["value"] = serde_json::json!([1e300, 0, 0]),
            "scenario A: track key at t=3 has a time, value or slope beyond ±1e6",
        ),
    ] {
        let export = unity_export(dir.path(), edit);
        refused(
            &tiny_capture(&["unity", export.to_str().unwrap()], &out, &[]),
            &["export.json", expect],
            expect,
        );
        assert!(!out.join("manifest.json").exists(), "{expect}");
    }
    // Unedited, the export captures.
    let export = unity_export(dir.path(), |_| {});
    let ran = tiny_capture(&["unity", export.to_str().unwrap()], &out, &[]);
    assert!(ran.success, "{}", ran.stderr);
}

// ---- found by fuzzing: glTF accessors the gltf crate trusts ----

#[test]
fn gltf_accessors_of_the_wrong_type_or_beyond_their_buffer_are_refused_by_both_loaders() {
    let regressions = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fuzz/regressions/gltf");
    for (name, expect) in [
        (
            "texcoord-accessor-of-the-wrong-type.gltf",
            "the TEXCOORD_0 accessor is Vec4 of F32; glTF wants Vec2",
        ),
        (
            "indices-of-type-float.gltf",
            "the indices accessor is Scalar of F32; glTF wants Scalar of U8 or U16 or U32",
        ),
        (
            "position-count-2-to-the-62.gltf",
            "the POSITION accessor (4611686018427387904 elements from byte 0) runs past",
        ),
        ("sparse-positions.gltf", "the POSITION accessor is sparse"),
        (
            "stride-shorter-than-a-position.gltf",
            "the POSITION accessor has 3 elements of 12 bytes 4 bytes apart",
        ),
        (
            "view-past-its-buffer.gltf",
            "the TEXCOORD_0 accessor is in a buffer view that runs past its buffer",
        ),
        (
            "position-accessor-that-does-not-exist.gltf",
            "not a glTF model: primitive 0 of mesh 0 has POSITION accessor",
        ),
        ("glb-length-shorter-than-its-header.glb", "its GLB header gives a length under 12 bytes"),
    ] {
        let path = regressions.join(name);
        let vehicle =
            ufcsr_capture::load_vehicle(&path, ufcsr_capture::scene::PartSource::Node, &Default::default());
        let error = vehicle.unwrap_err().to_string();
        assert!(error.contains(name) && error.contains(expect), "capture, {name}: {error}");
        let error = ufcsr::VehicleModel::read(&path).unwrap_err().to_string();
        assert!(error.contains(name) && error.contains(expect), "analyzer, {name}: {error}");
    }
}

#[test]
fn obj_face_indices_beyond_any_model_are_an_error_naming_the_line() {
    let dir = tempfile::tempdir().unwrap();
    for (face, expect) in [
        (
            "f 1 2 9223372036854775807",
            "line 5: index \"9223372036854775807\" is neither from 1 to 2147483648",
        ),
        ("f 1/0 2/1 3/1", "line 5: index \"0\""),
        (
            "f 1/-2 2/1 3/1",
            "line 5: index \"-2\" is neither from 1 to 2147483648 nor a relative index within the 1",
        ),
        ("f 1 2 -9223372036854775808", "line 5: index \"-9223372036854775808\""),
    ] {
        let obj = dir.path().join("far.obj");
        std::fs::write(&obj, format!("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\n{face}\n")).unwrap();
        let error =
            ufcsr_capture::load_vehicle(&obj, ufcsr_capture::scene::PartSource::Node, &Default::default())
                .unwrap_err()
                .to_string();
        assert!(error.contains("far.obj") && error.contains(expect), "{face}: {error}");
    }
    // Relative indices within what came before are fine.
    let obj = dir.path().join("relative.obj");
    std::fs::write(&obj, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\n").unwrap();
    assert!(
        ufcsr_capture::load_vehicle(&obj, ufcsr_capture::scene::PartSource::Node, &Default::default())
            .is_ok()
    );
}

#[test]
fn an_mtl_color_with_two_numbers_is_an_error_naming_the_line_not_a_panic_in_tobj() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("short.mtl"), "newmtl paint\nKd 0.5 0.5\n").unwrap();
    let obj = dir.path().join("truck.obj");
    let text = std::fs::read_to_string(fixture("box-truck.obj")).unwrap();
    std::fs::write(&obj, text.replace("mtllib box-truck.mtl", "mtllib short.mtl")).unwrap();
    let ran = capture(&["inspect", obj.to_str().unwrap(), "--out", dir.path().join("out").to_str().unwrap()]);
    refused(&ran, &["short.mtl: line 2: Kd needs three numbers (r g b)"], "short Kd");
    assert!(!ran.stderr.contains("panicked"), "{}", ran.stderr);
}
