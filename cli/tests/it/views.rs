//! `ufcsr views`: a result's eight heatmap views redrawn from its folder are
//! the analysis' own views, pixel for pixel (one renderer, on the CPU);
//! `--count` draws the count instead of the kept angular area; a result
//! without its model names the missing file.

use std::path::{Path, PathBuf};
use std::process::Command;

use ufcsr::{AnalyzeOptions, output::DIRECTIONS};

/// The bundled example analysed into `out` (views, each alone too, and heatmap.glb): of the
/// count, or with `area` of the per-texel angular area.
fn analyse_example(out: &Path, area: bool) {
    let archive = Path::new(env!("CARGO_MANIFEST_DIR")).join("../fixtures/example");
    let options = AnalyzeOptions { archive, frames: area, texel_area: area, ..AnalyzeOptions::default() };
    let mut analysis = ufcsr::analyze(&options, None).expect("analyse the example");
    let set = ufcsr::output::ResultSetOptions {
        figures: ufcsr::output::Figures::WithVariants,
        ..Default::default()
    };
    ufcsr::output::write_results_with(&mut analysis, out, &set).expect("write the example's results");
}

fn colors(path: &Path) -> Vec<u32> {
    ufcsr::read_color_image(path, |_| Ok(())).unwrap_or_else(|e| panic!("{e}")).colors
}

/// `ufcsr views RESULTS --out OUT` with `extra`; its standard error on failure.
fn views(results: &Path, out: &Path, extra: &[&str]) -> Result<String, String> {
    let output = Command::new(env!("CARGO_BIN_EXE_ufcsr"))
        .arg("views")
        .arg(results)
        .arg("--out")
        .arg(out)
        .args(extra)
        .output()
        .expect("run ufcsr views");
    match output.status.success() {
        true => Ok(String::from_utf8_lossy(&output.stdout).into_owned()),
        false => Err(String::from_utf8_lossy(&output.stderr).into_owned()),
    }
}

/// Analyses the example, redraws its views and holds every one to the
/// analysis' own; returns the folder and the results.
fn redrawn_views_are_the_analysis_views(area: bool) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let results = dir.path().join("results");
    analyse_example(&results, area);
    assert_eq!(results.join(ufcsr::TEXEL_AREA_FILE).is_file(), area);
    let redrawn = dir.path().join("redrawn");
    let printed = views(&results, &redrawn, &[]).unwrap_or_else(|e| panic!("{e}"));
    assert!(printed.contains("views.png"), "{printed}");
    for (name, _) in DIRECTIONS {
        let analysis = colors(&results.join("views").join(format!("{name}.png")));
        let again = colors(&redrawn.join("views").join(format!("{name}.png")));
        assert!(analysis == again, "{name}: the redrawn view differs from the analysis' view");
    }
    assert!(redrawn.join("views.png").is_file() && redrawn.join(ufcsr::output::VIEWS_PDF_FILE).is_file());
    (dir, results)
}

#[test]
fn redrawn_views_of_the_count_are_the_analysis_views() {
    redrawn_views_are_the_analysis_views(false);
}

/// With per-texel angular area kept (`texel-area.f32`), `views` draws the
/// area by default, as the analysis does; `--count` draws the count instead.
#[test]
fn redrawn_views_of_angular_area_are_the_analysis_views_and_count_is_an_option() {
    let (dir, results) = redrawn_views_are_the_analysis_views(true);
    let count_out = dir.path().join("count");
    views(&results, &count_out, &["--count"]).unwrap_or_else(|e| panic!("{e}"));
    let (area, count) =
        (colors(&results.join("views/front.png")), colors(&count_out.join("views/front.png")));
    let differ = area.iter().zip(&count).filter(|(a, b)| a != b).count();
    assert!(differ * 20 > area.len(), "--count drew the area views ({differ} pixels differ)");
}

#[test]
fn views_without_a_model_name_the_missing_file() {
    let dir = tempfile::tempdir().unwrap();
    let results = dir.path().join("results");
    analyse_example(&results, false);
    std::fs::remove_file(results.join("heatmap.glb")).unwrap();
    let message = views(&results, &dir.path().join("out"), &[]).unwrap_err();
    assert!(message.contains("heatmap.glb") && message.contains("--model"), "{message}");
}
