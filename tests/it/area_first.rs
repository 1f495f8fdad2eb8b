//! The result set leads with the measure to quote (issue 43 §1): when the
//! analysis measured the per-texel angular area, `heatmap.png` (and
//! `heatmap.glb`, which embeds it, and the report's first heatmap) show it,
//! and the paper's count is `heatmap-count.png`; without it (`--texel-area
//! off`) `heatmap.png` is the count as before and there is no count file.
//! Known answers on two texels whose counts and areas rank them oppositely.

use std::path::{Path, PathBuf};

/// The example's analysis with every texel unseen but two: texel 0 seen
/// most often (count 10, area 1 deg²·s) and texel 1 seen rarely but large
/// (count 1, area 4 deg²·s).
fn two_texel_analysis(texel_area: bool) -> ufcsr::Analysis {
    let example = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("fixtures/example");
    let options = ufcsr::AnalyzeOptions { archive: example, frames: true, texel_area, ..Default::default() };
    let mut analysis = ufcsr::analyze(&options, None).unwrap();
    assert_eq!(analysis.texel_angular_area.is_some(), texel_area);
    analysis.texel_counts.iter_mut().for_each(|count| *count = 0);
    analysis.texel_counts[..2].copy_from_slice(&[10, 1]);
    if let Some(area) = &mut analysis.texel_angular_area {
        area.iter_mut().for_each(|value| *value = 0.0);
        area[..2].copy_from_slice(&[1.0, 4.0]);
    }
    analysis
}

fn write(analysis: &mut ufcsr::Analysis, out: &Path) -> ufcsr::output::WrittenFiles {
    let options =
        ufcsr::output::ResultSetOptions { figures: ufcsr::output::Figures::None, ..Default::default() };
    ufcsr::output::write_results_with(analysis, out, &options).unwrap()
}

/// The first three texels' colours of a heatmap PNG.
fn first_texels(path: &Path) -> [[u8; 3]; 3] {
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
    let mut reader = decoder.read_info().unwrap();
    let mut rgb = vec![0; reader.output_buffer_size().unwrap()];
    reader.next_frame(&mut rgb).unwrap();
    [0, 1, 2].map(|texel| [rgb[texel * 3], rgb[texel * 3 + 1], rgb[texel * 3 + 2]])
}

#[test]
fn heatmap_png_follows_the_angular_area_and_heatmap_count_png_the_count() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("results");
    let mut analysis = two_texel_analysis(true);
    write(&mut analysis, &out);
    // An earlier version's angular-area heatmap is not left beside the new set.
    std::fs::write(out.join("heatmap-area.png"), b"stale").unwrap();
    let written = write(&mut analysis, &out);
    assert!(written.area_first());
    assert_eq!(
        written.heatmap_count_png.as_deref(),
        Some(out.join(ufcsr::output::COUNT_HEATMAP_FILE).as_path())
    );
    // Area: texel 1 (4 deg²·s) tops the scale, texel 0 (1 deg²·s) is at a quarter.
    assert_eq!(
        first_texels(&out.join(ufcsr::output::HEATMAP_FILE)),
        [ufcsr::output::plasma(0.25), ufcsr::output::plasma(1.0), ufcsr::output::NEVER_SEEN]
    );
    // Count: texel 0 (10) tops the scale, texel 1 (1) is at a tenth.
    assert_eq!(
        first_texels(&out.join("heatmap-count.png")),
        [ufcsr::output::plasma(1.0), ufcsr::output::plasma(0.1), ufcsr::output::NEVER_SEEN]
    );
    assert!(!out.join("heatmap-area.png").exists(), "the earlier name was left behind");
    // heatmap.glb carries heatmap.png, the angular area.
    let glb = std::fs::read(out.join("heatmap.glb")).unwrap();
    let png = std::fs::read(out.join("heatmap.png")).unwrap();
    assert!(glb.windows(png.len()).any(|w| w == png), "heatmap.glb does not embed heatmap.png");
    // The report shows the area texture first, the count after it.
    let page = std::fs::read_to_string(out.join("report.html")).unwrap();
    let area = page.find("src=\"heatmap.png\"").expect("no area texture on the page");
    let count = page.find("src=\"heatmap-count.png\"").expect("no count texture on the page");
    assert!(area < count);
    assert!(page.contains("angular area per texel (deg²·s)"));
}

#[test]
fn texel_area_off_keeps_the_count_in_heatmap_png_and_writes_no_count_file() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("results");
    let mut analysis = two_texel_analysis(false);
    let written = write(&mut analysis, &out);
    assert!(!written.area_first() && written.heatmap_count_png.is_none());
    assert_eq!(
        first_texels(&out.join("heatmap.png")),
        [ufcsr::output::plasma(1.0), ufcsr::output::plasma(0.1), ufcsr::output::NEVER_SEEN]
    );
    assert!(!out.join(ufcsr::output::COUNT_HEATMAP_FILE).exists());
    assert!(!out.join(ufcsr::TEXEL_AREA_FILE).exists());
    let page = std::fs::read_to_string(out.join("report.html")).unwrap();
    assert!(page.contains("src=\"heatmap.png\"") && !page.contains("heatmap-count.png"));
}
