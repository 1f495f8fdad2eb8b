//! A bus-sized palette end to end (issue 43 §3): a capture whose palette
//! needs more than 2²⁴ texels (8192 × 4096, 32-bit texel ids), counted,
//! analysed into its result set and report, and answered by `placement`
//! with the placement drawn on the vehicle and shown on the report, as a
//! 4096² capture is.

use std::path::Path;
use std::process::Command;

fn ufcsr(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_ufcsr")).args(args).output().expect("run ufcsr")
}

fn ok(output: &std::process::Output, what: &str) -> String {
    assert!(output.status.success(), "{what}: {}", String::from_utf8_lossy(&output.stderr));
    String::from_utf8_lossy(&output.stdout).into_owned()
}

fn json(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// `ufcsr capture demo` of scenario D at 3 px/° and a 8192 × 4096 palette into `out`, with `extra`.
fn capture(out: &Path, extra: &[&str]) {
    let base =
        ["capture", "demo", "--scenario", "D", "--ppd", "3", "--frames", "150-180/30", "--palette-size"];
    let args = [&base[..], &["8192x4096", "--out", out.to_str().unwrap(), "-q"], extra].concat();
    ok(&ufcsr(&args), "capture");
}

#[test]
fn a_palette_above_2_24_texels_is_captured_analysed_reported_and_placed_end_to_end() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("bus");
    capture(&out, &[]);
    let manifest = json(&out.join("manifest.json"));
    assert_eq!(manifest["texel_ids"], "rgba32", "{manifest}");
    let out_text = out.to_str().unwrap();
    ok(&ufcsr(&["analyze", out_text, "-q"]), "analyze");
    let results = out.join("results");
    let result = json(&results.join("result.json"));
    assert_eq!(result["stray_pixels"], 0, "{result}");
    assert!(result["pixels"]["texel"].as_u64().unwrap() > 1000, "{result}");
    assert!(results.join("heatmap.png").is_file() && results.join("texel-area.f32").is_file());
    // 8192 × 4096 f32 values after the header: the palette's size, not 2²⁴.
    let area = std::fs::metadata(results.join("texel-area.f32")).unwrap().len();
    assert!(area >= 4 * 8192 * 4096, "texel-area.f32 holds {area} bytes");

    // The placement answer from the exact measure of the same palette (a
    // sample of its texels, to keep the test short), beside the result.
    let exact = dir.path().join("bus-exact");
    capture(&exact, &["--measure", "unobstructed", "--sample", "1/256", "--placement"]);
    let placement = results.join("placement");
    let stdout = ok(
        &ufcsr(&["placement", exact.to_str().unwrap(), "--out", placement.to_str().unwrap()]),
        "placement",
    );
    assert!(stdout.contains("legible"), "{stdout}");
    let answer = json(&placement.join("placement.json"));
    assert!(answer["combinations"].as_array().is_some_and(|sets| !sets.is_empty()), "{answer}");
    assert!(placement.join("placement.png").is_file(), "the best sets are drawn on the vehicle");

    ok(&ufcsr(&["analyze", out_text, "-q"]), "analyze with the placement beside the result");
    let page = std::fs::read_to_string(results.join("report.html")).unwrap();
    assert!(page.contains("Where should the eHMI go?"), "the report shows the placement");
}

/// `study` and `batch plan` take a bus-sized palette as `capture` does (their captures count
/// 32-bit ids: `--count`), where they refused anything above 2²⁴ texels.
#[test]
fn a_study_and_a_batch_take_a_palette_above_2_24_texels() {
    let dir = tempfile::tempdir().unwrap();
    let study = dir.path().join("study");
    let args = ["study", "demo", "--scenario", "D", "--ppd", "3", "--frame-step", "30", "--palette-size"];
    let more = ["8192x4096", "--exact-sample", "1/1024", "--out", study.to_str().unwrap()];
    let said = ok(&ufcsr(&[&args[..], &more].concat()), "study");
    assert!(said.contains("of 13520776 texels"), "not the bus-sized palette's texels: {said}");
    assert!(study.join("study.csv").is_file());

    let batch = dir.path().join("batch.json");
    let plan = serde_json::json!({"out": dir.path().join("runs"), "scenes": ["demo"], "scenarios": ["D"],
                                  "ppd": [3], "frame_step": [30], "palette_size": "8192x4096"});
    std::fs::write(&batch, plan.to_string()).unwrap();
    let lines = ok(&ufcsr(&["batch", "plan", batch.to_str().unwrap()]), "batch plan");
    assert!(lines.contains("--palette-size 8192x4096 --count"), "{lines}");
}

/// The highest texel id a `result.json` counted: its `texel_counts` list ids as deltas.
fn highest_texel_id(result: &Path) -> u64 {
    let deltas = json(result)["texel_counts"]["texel_delta"].clone();
    deltas.as_array().unwrap().iter().map(|d| d.as_u64().unwrap()).sum()
}

/// `ufcsr observers` of scenario D (two observers, 2 px/°, every 90th frame) at `palette` into `out`.
fn observers(out: &Path, palette: &str) -> serde_json::Value {
    let args =
        ["observers", "demo", "--scenario", "D", "--ppd", "2", "--frame-step", "90", "--observers", "2"];
    let more = ["--resolution-check", "none", "--views-scale", "1", "--palette-size", palette, "--out"];
    let said = ok(&ufcsr(&[&args[..], &more, &[out.to_str().unwrap()]].concat()), "observers");
    assert!(said.contains("2 observers drawn from the population (seed 1)"), "{said}");
    json(&out.join("observers.json"))
}

/// `observers` takes a bus-sized palette (it captures through `--count`, which counts 32-bit
/// ids), where it refused anything above 2²⁴ texels: each observer's capture draws 32-bit ids,
/// counts texels above 2²⁴, and its parts' angular areas are those of a 1024² palette (the
/// palette only names the texels a pixel shows).
#[test]
fn observers_take_a_palette_above_2_24_texels() {
    let dir = tempfile::tempdir().unwrap();
    let bus = observers(&dir.path().join("bus"), "8192x4096");
    let small = observers(&dir.path().join("small"), "1024");
    for observer in ["observer-000", "observer-001"] {
        let manifest = json(&dir.path().join("bus").join(observer).join("manifest.json"));
        assert_eq!(manifest["texel_ids"], "rgba32", "{manifest}");
        assert_eq!(manifest["palette"]["canonical"], serde_json::json!([8192, 4096]), "{manifest}");
        let highest = highest_texel_id(&dir.path().join("bus").join(observer).join("results/result.json"));
        assert!((1 << 24..8192 * 4096).contains(&highest), "highest texel id {highest}");
    }
    assert_eq!(bus["parts"], small["parts"]);
    for (big, small) in
        bus["observers"].as_array().unwrap().iter().zip(small["observers"].as_array().unwrap())
    {
        assert_eq!(big["eye_height_m"], small["eye_height_m"], "the same observers");
        let areas = |o: &serde_json::Value| -> Vec<f64> {
            o["angular_area_deg2_s"].as_array().unwrap().iter().map(|a| a.as_f64().unwrap()).collect()
        };
        let (a, b) = (areas(big), areas(small));
        assert!(a.iter().sum::<f64>() > 100.0, "{a:?}");
        assert!(a.iter().zip(&b).all(|(a, b)| (a - b).abs() <= 1e-9 * b.abs().max(1.0)), "{a:?}\n{b:?}");
    }
}

/// A one-task design (a van on the static street-2, one unit) at `palette`² and `sample` into
/// `dir/NAME`: planned, run and merged; its task's candidates.
fn design(dir: &Path, name: &str, palette: u32, sample: f64) -> Vec<serde_json::Value> {
    let file = dir.join(format!("{name}.json"));
    let design = serde_json::json!({
        "schema": "ufcsr-design/1",
        "name": name,
        "vehicles": [{"name": "van", "body": "van", "display_m": [0.4, 0.15]}],
        "scenarios": [{"name": "street-2", "kind": "street", "position": 2}],
        "measure": {"sample": sample, "palette": palette, "frame_step": 30, "patch_spacing_m": 0.3}
    });
    std::fs::write(&file, design.to_string()).unwrap();
    let (file, out) = (file.to_str().unwrap(), dir.join(name));
    let out = out.to_str().unwrap();
    let lines = ok(&ufcsr(&["design", "plan", file, "--out", out, "--program", "ufcsr"]), "design plan");
    assert_eq!(lines.lines().count(), 1, "{lines}");
    ok(&ufcsr(&["design", "run", file, "--out", out, "--task", "0"]), "design run");
    ok(&ufcsr(&["design", "merge", file, "--out", out]), "design merge");
    let result = json(&Path::new(out).join("design.json"));
    assert_eq!((result["tasks"].as_u64(), result["cells"].as_array().map(Vec::len)), (Some(1), Some(1)));
    let task = json(&Path::new(out).join("tasks/task-0000/task.json"));
    task["units"][0]["candidates"].as_array().unwrap().clone()
}

/// A design's `measure.palette` may be 8192 (2²⁶ texels, allowed since designs began, first
/// run here): its unit's exact measure draws 32-bit ids over the whole palette, and plan, run
/// and merge take it. A sample of 1/1024 of its texels measures the van's parts within 5 % of
/// the whole 256² palette, and both name the same candidates (the patches are laid out from the
/// van's mesh, not the palette).
#[test]
fn a_design_measures_a_palette_of_8192_squared() {
    let dir = tempfile::tempdir().unwrap();
    let bus = design(dir.path(), "bus", 8192, 1.0 / 1024.0);
    let unit = dir.path().join("bus/tasks/task-0000/unit-000");
    let manifest = json(&unit.join("manifest.json"));
    assert_eq!(manifest["texel_ids"], "rgba32", "{manifest}");
    assert_eq!(manifest["palette"]["canonical"], serde_json::json!([8192, 8192]), "{manifest}");
    let highest = highest_texel_id(&unit.join("results/result.json"));
    assert!((1 << 25..1 << 26).contains(&highest), "highest texel id {highest}");
    let small = design(dir.path(), "small", 256, 1.0);
    let names = |c: &[serde_json::Value]| {
        let mut names: Vec<String> = c.iter().map(|c| c["name"].as_str().unwrap().to_string()).collect();
        names.sort();
        names
    };
    assert_eq!(names(&bus), names(&small));
    let parts = |c: &[serde_json::Value]| -> f64 {
        c.iter().filter(|c| c["kind"] == "part").map(|c| c["angular_area_deg2_s"].as_f64().unwrap()).sum()
    };
    let (bus, small) = (parts(&bus), parts(&small));
    assert!(small > 100.0 && (bus - small).abs() <= 0.05 * small, "8192²: {bus} deg²·s, 256²: {small}");
}
