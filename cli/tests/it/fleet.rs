//! Several measured vehicles in one capture (issue 43 §3), with known
//! answers: a scene that measures the demo truck and a van following it
//! 9 m behind writes one archive per vehicle, and `ufcsr analyze OUT`
//! gives each the very counts (every texel, every part) of a capture of
//! that vehicle alone with the other as an ordinary occluder; the follower
//! is hidden by the lead in some frames, so the occluder matters. Bad and
//! duplicate names are refused naming the scene file, `where` answers for
//! each vehicle from its own exact measure (the others occluding it), and
//! `study`, which measures one vehicle, refuses such a scene naming it.

use std::path::{Path, PathBuf};
use std::process::Command;

use serde_json::{Value, json};

/// Both vehicles drive along +x (yaw 0) towards a pedestrian standing just
/// beside their lane ahead of them, so the lead hides part of the follower;
/// every key, time (4 fps) and offset is a dyadic number, so the follower's
/// pose is the same float whether it follows the lead or has keys of its own.
fn scene(lead_x: [f64; 2], occluders: Value, lead_name: Option<&str>) -> Value {
    scene_with(json!({"mesh": "demo"}), lead_x, occluders, lead_name)
}

/// [`scene`] with `vehicle` as the scene's own vehicle.
fn scene_with(mut vehicle: Value, lead_x: [f64; 2], occluders: Value, lead_name: Option<&str>) -> Value {
    if let Some(name) = lead_name {
        vehicle["measure"] = json!(name);
    }
    json!({
        "name": "street",
        "vehicle": vehicle,
        "occluders": occluders,
        "rig": {"pedestrian": [0.0, -2.5, 0.0], "eye_pixels": [320, 400], "tiles": [1, 1], "fps": 4,
                "look_at_vehicle": [0.0, 0.0, 0.95]},
        "scenarios": {"S": {"duration_s": 1.0,
                            "position": [{"t": 0.0, "value": [lead_x[0], 0.0, 0.0]},
                                         {"t": 1.0, "value": [lead_x[1], 0.0, 0.0]}],
                            "yaw_deg": [{"t": 0.0, "value": 0.0}]}}
    })
}

const LEAD: [f64; 2] = [-16.0, -8.0];
const FOLLOWER: [f64; 2] = [-25.0, -17.0];

fn write_scene(dir: &Path, name: &str, scene: &Value) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, serde_json::to_vec_pretty(scene).unwrap()).unwrap();
    path
}

fn ufcsr(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_ufcsr")).args(args).output().expect("run ufcsr")
}

/// `ufcsr capture scene SCENE --out OUT` (small: 256² palette, 320×400 eyes), then `ufcsr
/// analyze OUT`; stdout of both.
fn capture_and_analyze(scene: &Path, out: &Path) -> String {
    let (scene, out_text) = (scene.to_str().unwrap(), out.to_str().unwrap());
    let captured = ufcsr(&["capture", "scene", scene, "--out", out_text, "--palette-size", "256"]);
    assert!(captured.status.success(), "capture: {}", String::from_utf8_lossy(&captured.stderr));
    let analysed = ufcsr(&["analyze", out_text, "--figures", "off", "-q"]);
    assert!(analysed.status.success(), "analyze: {}", String::from_utf8_lossy(&analysed.stderr));
    String::from_utf8_lossy(&captured.stdout).into_owned()
}

/// An archive's counts: every texel's and every part's (the summary's parts).
fn counts(archive: &Path) -> (Value, Value) {
    let result: Value =
        serde_json::from_slice(&std::fs::read(archive.join("results/result.json")).unwrap()).unwrap();
    (result["texel_counts"].clone(), result["parts"].clone())
}

fn grand_total(archive: &Path) -> u64 {
    let result: Value =
        serde_json::from_slice(&std::fs::read(archive.join("results/result.json")).unwrap()).unwrap();
    result["grand_total"].as_u64().unwrap()
}

/// The follower is a van of the family (its own `model`), the lead the demo truck.
#[test]
fn a_two_vehicle_capture_gives_each_vehicle_the_counts_of_capturing_it_alone_with_the_other_as_occluder() {
    let dir = tempfile::tempdir().unwrap();
    let follower = |measure: Option<&str>| {
        let mut spec = json!({"follow": {"ahead_m": -9.0}, "model": {"body": "van"}});
        if let Some(name) = measure {
            spec["measure"] = json!(name);
        }
        json!([{ "vehicle": spec }])
    };
    let fleet = write_scene(dir.path(), "fleet.json", &scene(LEAD, follower(Some("follower")), Some("lead")));
    let lead_alone = write_scene(dir.path(), "lead.json", &scene(LEAD, follower(None), None));
    // The van as the scene's vehicle, on keys 9 m behind, and the truck following it 9 m ahead.
    let van = json!({"body": "van"});
    let lead_ahead = json!([{"vehicle": {"follow": {"ahead_m": 9.0}, "model": {"mesh": "demo"}}}]);
    let follower_alone =
        write_scene(dir.path(), "follower.json", &scene_with(van.clone(), FOLLOWER, lead_ahead, None));
    let follower_unhidden =
        write_scene(dir.path(), "nothing.json", &scene_with(van, FOLLOWER, json!([]), None));

    let out = dir.path().join("fleet");
    let said = capture_and_analyze(&fleet, &out);
    assert!(said.contains("2 passes"), "{said}");
    assert!(!out.join("manifest.json").exists(), "a one-vehicle archive at the top");
    for (name, source) in [("lead", "vehicle"), ("follower", "occluders[0]")] {
        let manifest_path = out.join(name).join("manifest.json");
        crate::schemas::assert_file_valid(&crate::schemas::schema("manifest.schema.json"), &manifest_path);
        let manifest: Value = serde_json::from_slice(&std::fs::read(&manifest_path).unwrap()).unwrap();
        let measured = &manifest["scene"]["measured"];
        assert_eq!(measured["name"], name);
        assert_eq!(measured["source"], source);
        assert_eq!(measured["fleet"], json!(["lead", "follower"]));
        let report = std::fs::read_to_string(out.join(name).join("results/report.html")).unwrap();
        assert!(
            report.contains(&format!("{name} ({source}), one of the 2")),
            "{name}: the report does not name it"
        );
    }

    let alone = dir.path().join("alone");
    capture_and_analyze(&lead_alone, &alone.join("lead"));
    capture_and_analyze(&follower_alone, &alone.join("follower"));
    let parts = |archive: &Path| std::fs::read_to_string(archive.join("parts.csv")).unwrap();
    assert!(parts(&out.join("lead")) != parts(&out.join("follower")), "the van has the truck's parts");
    for name in ["lead", "follower"] {
        assert_eq!(parts(&out.join(name)), parts(&alone.join(name)), "{name}: other parts");
        let (fleet_texels, fleet_parts) = counts(&out.join(name));
        let (alone_texels, alone_parts) = counts(&alone.join(name));
        assert!(grand_total(&out.join(name)) > 0, "{name} is never seen");
        assert!(fleet_texels == alone_texels, "{name}: the per-texel counts differ from its capture alone");
        assert_eq!(fleet_parts, alone_parts, "{name}: the part totals differ from its capture alone");
    }
    // Without the lead in front of it, the follower is seen more: the lead hid some of it.
    capture_and_analyze(&follower_unhidden, &alone.join("unhidden"));
    assert!(
        grand_total(&alone.join("unhidden")) > grand_total(&out.join("follower")),
        "the lead never hid the follower: the test shows nothing"
    );
    stale_and_broken_archives_are_named(&fleet, &out);
}

/// After the fleet capture of `fleet` into `out`: an archive of another capture left in `out` is
/// named (`analyze OUT` would analyse it too); one vehicle's broken archive is named, the other
/// analysed, exit 1.
fn stale_and_broken_archives_are_named(fleet: &Path, out: &Path) {
    // An archive of another capture left in OUT is named: `analyze OUT` would analyse it too.
    std::fs::create_dir(out.join("old")).unwrap();
    std::fs::copy(out.join("lead/manifest.json"), out.join("old/manifest.json")).unwrap();
    let again = ufcsr(&[
        "capture",
        "scene",
        fleet.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--palette-size",
        "256",
        "-q",
    ]);
    let stderr = String::from_utf8_lossy(&again.stderr);
    assert!(again.status.success(), "{stderr}");
    assert!(
        stderr.contains(&format!("{} holds an archive that is none of", out.join("old").display())),
        "{stderr}"
    );
    std::fs::remove_dir_all(out.join("old")).unwrap();
    // One vehicle's archive broken: it is named, the other is analysed, exit 1.
    std::fs::write(out.join("lead/pidt.png"), b"not a png").unwrap();
    std::fs::remove_dir_all(out.join("follower/results")).unwrap();
    let analysed = ufcsr(&["analyze", out.to_str().unwrap(), "--figures", "off"]);
    let (stdout, stderr) =
        (String::from_utf8_lossy(&analysed.stdout), String::from_utf8_lossy(&analysed.stderr));
    assert_eq!(analysed.status.code(), Some(1), "{stdout}{stderr}");
    assert!(stderr.contains(&out.join("lead").display().to_string()), "{stderr}");
    assert!(stdout.contains(&format!("{}: analysed", out.join("follower").display())), "{stdout}");
    assert!(stdout.contains(&format!("{}: not analysed", out.join("lead").display())), "{stdout}");
    assert!(out.join("follower/results/result.json").is_file());
}

#[test]
fn bad_or_repeated_vehicle_names_are_refused_naming_the_scene_file() {
    let dir = tempfile::tempdir().unwrap();
    let named = |measure: &str, lead: Option<&str>| {
        scene(LEAD, json!([{"vehicle": {"follow": {"ahead_m": -9.0}, "measure": measure}}]), lead)
    };
    let modelled = |model: Value| {
        scene(
            LEAD,
            json!([{"vehicle": {"follow": {"ahead_m": -9.0}, "measure": "car", "model": model}}]),
            None,
        )
    };
    for (file, scene, expected) in [
        ("up.json", named("../up", None), "not a plain folder name"),
        ("results.json", named("results", None), "keeps for itself"),
        ("twice.json", named("Vehicle", None), "already names"),
        ("lead-twice.json", named("car", Some("CAR")), "already names"),
        ("bad-lead.json", named("car", Some("a b")), "vehicle.measure"),
        ("inner.json", modelled(json!({"mesh": "demo", "measure": "car"})), "model.measure"),
        (
            "bus.json",
            modelled(json!({"body": "tram"})),
            "occluders[0] (vehicle #0) model: vehicle.body \"tram\"",
        ),
    ] {
        let path = write_scene(dir.path(), file, &scene);
        let out = dir.path().join("out");
        let refused = ufcsr(&["capture", "scene", path.to_str().unwrap(), "--out", out.to_str().unwrap()]);
        let stderr = String::from_utf8_lossy(&refused.stderr);
        assert_eq!(refused.status.code(), Some(2), "{file}: {stderr}");
        assert!(stderr.contains(file) && stderr.contains(expected), "{file}: {stderr}");
        assert!(!out.exists(), "{file}: wrote {}", out.display());
    }
    // `study` measures one vehicle: it refuses, naming the vehicles and the way round it.
    let fleet = write_scene(dir.path(), "fleet.json", &named("follower", None));
    let refused =
        ufcsr(&["study", "scene", fleet.to_str().unwrap(), "--out", dir.path().join("s").to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&refused.stderr);
    assert_eq!(refused.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("measures 2 vehicles (vehicle, follower)") && stderr.contains("capture scene"),
        "{stderr}"
    );
}

#[test]
fn where_answers_for_each_measured_vehicle_from_its_own_exact_measure() {
    let dir = tempfile::tempdir().unwrap();
    let follower = json!([{"vehicle": {"follow": {"ahead_m": -9.0}, "measure": "follower"}}]);
    let fleet = write_scene(dir.path(), "fleet.json", &scene(LEAD, follower, Some("lead")));
    let lead_ahead = json!([{"vehicle": {"follow": {"ahead_m": 9.0}}}]);
    let follower_alone = write_scene(dir.path(), "follower.json", &scene(FOLLOWER, lead_ahead, None));
    let out = dir.path().join("where");
    let small = ["--palette-size", "256", "--sample", "1/4"];
    let answered = ufcsr(
        &[&["where", "scene", fleet.to_str().unwrap(), "--out", out.to_str().unwrap()], &small[..]].concat(),
    );
    let said = String::from_utf8_lossy(&answered.stdout);
    assert!(answered.status.success(), "{}", String::from_utf8_lossy(&answered.stderr));
    for name in ["lead", "follower"] {
        assert!(said.contains(&format!("== vehicle {name}")), "{said}");
        assert!(out.join("answer").join(name).join("placement.json").is_file(), "{name}: no answer");
        assert!(
            said.contains(&format!("ufcsr placement {}", out.join("runs").join(name).display())),
            "{said}"
        );
    }
    // The follower's exact measure is that of the follower alone, the lead occluding it.
    let alone = dir.path().join("alone");
    let measured = ufcsr(
        &[
            &["capture", "scene", follower_alone.to_str().unwrap(), "--out", alone.to_str().unwrap()],
            &["--measure", "unobstructed", "--placement", "--display", "0.40x0.15"][..],
            &small[..],
        ]
        .concat(),
    );
    assert!(measured.status.success(), "{}", String::from_utf8_lossy(&measured.stderr));
    assert!(counts(&out.join("runs/follower/S")) == counts(&alone), "the follower's exact measure differs");
    let frames = |archive: &Path| std::fs::read(archive.join("results/placement-frames.csv")).unwrap();
    assert!(frames(&out.join("runs/follower/S")) == frames(&alone), "the follower's placement table differs");
}

/// The test scene measuring `lead` and a copy of it following 9 m behind (`follower`), written in
/// `dir`.
fn lead_and_copy(dir: &Path) -> PathBuf {
    let follower = json!([{ "vehicle": {"follow": {"ahead_m": -9.0}, "measure": "follower"} }]);
    write_scene(dir, "fleet.json", &scene(LEAD, follower, Some("lead")))
}

/// A several-vehicle capture split in shards is assembled by one `ufcsr assemble OUT`, vehicle by
/// vehicle, as the capture's last line says, and its analysis gives each vehicle the counts of the
/// unsplit capture; a vehicle whose shards are missing is named and the other assembled (exit 1).
#[test]
fn a_sharded_several_vehicle_capture_is_assembled_vehicle_by_vehicle_by_one_command() {
    let dir = tempfile::tempdir().unwrap();
    let fleet = lead_and_copy(dir.path());
    let whole = dir.path().join("whole");
    capture_and_analyze(&fleet, &whole);

    let split = dir.path().join("split");
    let (fleet_text, split_text) = (fleet.to_str().unwrap(), split.to_str().unwrap());
    for shard in ["0/2", "1/2"] {
        let args =
            ["capture", "scene", fleet_text, "--out", split_text, "--palette-size", "256", "--shard", shard];
        let captured = ufcsr(&args);
        assert!(captured.status.success(), "shard {shard}: {}", String::from_utf8_lossy(&captured.stderr));
        let said = String::from_utf8_lossy(&captured.stdout);
        assert!(said.contains(&format!("`ufcsr assemble {split_text}`")), "{said}");
    }
    let assembled = ufcsr(&["assemble", split_text]);
    assert!(assembled.status.success(), "assemble: {}", String::from_utf8_lossy(&assembled.stderr));
    assert!(String::from_utf8_lossy(&assembled.stdout).contains("assembled 2 of 2 vehicle archives"));
    let analysed = ufcsr(&["analyze", split_text, "--figures", "off", "-q"]);
    assert!(analysed.status.success(), "analyze: {}", String::from_utf8_lossy(&analysed.stderr));
    for name in ["lead", "follower"] {
        assert!(counts(&split.join(name)) == counts(&whole.join(name)), "{name}: the shards count otherwise");
    }

    // Shards of one vehicle only: the other vehicle is named, this one assembled.
    let half = dir.path().join("half");
    for shard in ["0/2", "1/2"] {
        let args = ["capture", "scene", fleet_text, "--out", half.to_str().unwrap(), "--palette-size", "256"];
        assert!(ufcsr(&[&args[..], &["--shard", shard]].concat()).status.success());
    }
    std::fs::remove_dir_all(half.join("follower/shards")).unwrap();
    std::fs::create_dir(half.join("follower/shards")).unwrap();
    let assembled = ufcsr(&["assemble", half.to_str().unwrap()]);
    assert_eq!(assembled.status.code(), Some(1), "{}", String::from_utf8_lossy(&assembled.stderr));
    let stderr = String::from_utf8_lossy(&assembled.stderr);
    assert!(stderr.contains("follower") && stderr.contains("no shard manifest"), "{stderr}");
    assert!(half.join("lead/manifest.json").is_file(), "the lead was not assembled");
}

/// A batch task of a several-vehicle scene counts every vehicle into its task folder (one
/// `OUT/NAME/results` each), and its command says where they are, not to analyse them again.
#[test]
fn a_batch_task_of_a_several_vehicle_scene_counts_each_vehicle_in_its_folder() {
    let dir = tempfile::tempdir().unwrap();
    let fleet = lead_and_copy(dir.path());
    let runs = dir.path().join("runs");
    let batch = json!({"out": runs, "scenes": [fleet], "scenarios": ["S"], "ppd": [3], "frame_step": [2],
                       "dedupe": "image", "palette_size": "256"});
    let batch_file = write_scene(dir.path(), "batch.json", &batch);
    let planned = ufcsr(&["batch", "plan", batch_file.to_str().unwrap()]);
    assert!(planned.status.success(), "plan: {}", String::from_utf8_lossy(&planned.stderr));
    let line = String::from_utf8_lossy(&planned.stdout).lines().next().unwrap().replace(" --quiet", "");
    let ran = Command::new("sh").args(["-c", &line]).output().unwrap();
    assert!(ran.status.success(), "{line}: {}", String::from_utf8_lossy(&ran.stderr));
    let said = String::from_utf8_lossy(&ran.stdout);
    assert!(said.contains("NAME/results (counted)") && !said.contains("ufcsr analyze"), "{said}");
    let task = runs.join("0-fleet/S/ppd3-step2");
    for name in ["lead", "follower"] {
        assert!(grand_total(&task.join(name)) > 0, "{name}: no counted result in {}", task.display());
    }
}

/// `inspect` of a scene that measures several vehicles inspects each into `OUT/NAME` (the
/// fixture's truck and its sedan, each with its own parts), and refuses a repeated name as the
/// capture does.
#[test]
fn inspect_of_a_several_vehicle_scene_inspects_each_vehicle_into_its_folder() {
    let dir = tempfile::tempdir().unwrap();
    let fleet = Path::new(env!("CARGO_MANIFEST_DIR")).join("../fixtures/scenes/fleet.json");
    let out = dir.path().join("inspect");
    let inspected = ufcsr(&["inspect", fleet.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    assert!(inspected.status.success(), "{}", String::from_utf8_lossy(&inspected.stderr));
    let said = String::from_utf8_lossy(&inspected.stdout);
    let parts = |name: &str| std::fs::read_to_string(out.join(name).join("inspect-parts.csv")).unwrap();
    assert!(said.contains("vehicle truck") && said.contains("vehicle lead-car"), "{said}");
    assert!(parts("truck").contains("grill") && parts("truck") != parts("lead-car"), "one vehicle twice");
    assert!(!out.join("inspect-parts.csv").exists(), "the main vehicle alone at the top");

    let twice = json!({"vehicle": {"mesh": "demo", "measure": "car"},
                       "occluders": [{"vehicle": {"follow": {"ahead_m": 9.0}, "measure": "CAR"}}]});
    let twice = write_scene(dir.path(), "twice.json", &twice);
    let refused =
        ufcsr(&["inspect", twice.to_str().unwrap(), "--out", dir.path().join("x").to_str().unwrap()]);
    assert_eq!(refused.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&refused.stderr);
    assert!(stderr.contains("twice.json") && stderr.contains("occluders[0]"), "{stderr}");
}
