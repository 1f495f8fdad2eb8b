//! `ufcsr-capture views`: the analyzer's eight heatmap views drawn with the
//! capture's wgpu renderer must be the analyzer's CPU pictures, up to a
//! few pixels on triangle edges and texel boundaries (the two rasterisers
//! round differently there).

use std::path::Path;
use std::process::Command;

use ufcsr::{AnalyzeOptions, DIRECTIONS};

/// The bundled example analysed into `out` (CPU views, heatmap.glb): of
/// the count, or with `frames` of the per-texel angular area.
fn analyse_example(out: &Path) {
    analyse_example_with(out, false);
}

fn analyse_example_with(out: &Path, frames: bool) {
    let archive = Path::new(env!("CARGO_MANIFEST_DIR")).join("../fixtures/example");
    let options = AnalyzeOptions { archive, frames, texel_area: frames, ..AnalyzeOptions::default() };
    let mut analysis = ufcsr::analyze(&options, None).expect("analyse the example");
    ufcsr::write_results(&mut analysis, out).expect("write the example's results");
}

fn colors(path: &Path) -> Vec<u32> {
    ufcsr::read_color_image(path, |_| Ok(())).unwrap_or_else(|e| panic!("{e}")).colors
}

#[test]
fn gpu_views_are_the_cpu_views() {
    gpu_views_match_cpu_views(false);
}

/// With per-texel angular area kept (`texel-area.f32`), the GPU draws the
/// area by default, as the CPU views do; `--count` draws the count instead.
#[test]
fn gpu_views_of_angular_area_are_the_cpu_views_and_count_is_an_option() {
    let (dir, results) = gpu_views_match_cpu_views(true);
    let count_out = dir.path().join("gpu-count");
    let output = Command::new(env!("CARGO_BIN_EXE_ufcsr-capture"))
        .arg("views")
        .arg(&results)
        .arg("--count")
        .arg("--out")
        .arg(&count_out)
        .output()
        .expect("run ufcsr-capture views --count");
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    let (cpu, count) = (colors(&results.join("views/front.png")), colors(&count_out.join("views/front.png")));
    let differ = cpu.iter().zip(&count).filter(|(a, b)| a != b).count();
    assert!(differ * 20 > cpu.len(), "--count drew the area views ({differ} pixels differ)");
}

/// Analyses the example (with `frames`: angular area), draws its views with
/// the GPU and holds them to the CPU views; returns the folder and results.
fn gpu_views_match_cpu_views(frames: bool) -> (tempfile::TempDir, std::path::PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let results = dir.path().join("results");
    analyse_example_with(&results, frames);
    assert_eq!(results.join(ufcsr::TEXEL_AREA_FILE).is_file(), frames);
    let gpu_out = dir.path().join("gpu");
    let output = Command::new(env!("CARGO_BIN_EXE_ufcsr-capture"))
        .arg("views")
        .arg(&results)
        .arg("--out")
        .arg(&gpu_out)
        .output()
        .expect("run ufcsr-capture views");
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    let printed = String::from_utf8_lossy(&output.stdout);
    assert!(printed.contains("views.png"), "{printed}");
    let white = 0xFF_FFFF;
    let mut colored = 0;
    for (name, _) in DIRECTIONS {
        let cpu = colors(&results.join("views").join(format!("{name}.png")));
        let gpu = colors(&gpu_out.join("views").join(format!("{name}.png")));
        assert_eq!(cpu.len(), gpu.len(), "{name}");
        let differ = cpu.iter().zip(&gpu).filter(|(a, b)| a != b).count();
        let outline = cpu.iter().zip(&gpu).filter(|&(&a, &b)| (a == white) != (b == white)).count();
        eprintln!("{name}: {differ} of {} pixels differ, {outline} on the outline", cpu.len());
        // Measured: 0 to 121 pixels of 480,000 at the default 800×600 (front-left, texel
        // boundaries; shading and compass are drawn alike after either renderer).
        assert!(differ * 200 <= cpu.len(), "{name}: {differ} pixels differ");
        assert!(outline * 1000 <= cpu.len(), "{name}: {outline} pixels differ in coverage");
        // Shaded never-seen grey stays grey (r = g = b); the plasma scale has none.
        colored += gpu.iter().filter(|&&c| !(c >> 16 == c & 0xFF && (c >> 8) & 0xFF == c & 0xFF)).count();
    }
    assert!(colored > 10_000, "the GPU views show almost no heatmap ({colored} pixels)");
    assert!(gpu_out.join("views.png").is_file());
    (dir, results)
}

#[test]
fn views_without_a_model_name_the_missing_file() {
    let dir = tempfile::tempdir().unwrap();
    let results = dir.path().join("results");
    analyse_example(&results);
    std::fs::remove_file(results.join("heatmap.glb")).unwrap();
    let output = Command::new(env!("CARGO_BIN_EXE_ufcsr-capture"))
        .arg("views")
        .arg(&results)
        .output()
        .expect("run ufcsr-capture views");
    assert!(!output.status.success());
    let message = String::from_utf8_lossy(&output.stderr);
    assert!(message.contains("heatmap.glb") && message.contains("--model"), "{message}");
}
