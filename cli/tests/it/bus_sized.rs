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
