//! `ufcsr heatmap` re-draws the heatmap texture the analysis wrote: by
//! default what `heatmap.png` holds (the per-texel angular area, from the
//! folder's `texel-area.f32`), with `--texel-area off` the paper's count
//! (`heatmap-count.png`); and the analysis' console summary leads with the
//! angular area per part (issue 43 §1, issue 45 §5).

use std::path::PathBuf;

use crate::common::analyzer;

#[test]
fn heatmap_redraws_the_area_texture_by_default_and_the_count_with_texel_area_off() {
    let dir = tempfile::tempdir().unwrap();
    let example = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fixtures/example");
    let out = dir.path().join("results");
    let analysis = analyzer()
        .args([example.as_os_str(), "--figures".as_ref(), "off".as_ref(), "--out".as_ref(), out.as_os_str()])
        .output()
        .unwrap();
    assert!(analysis.status.success(), "{}", String::from_utf8_lossy(&analysis.stderr));
    let summary = String::from_utf8_lossy(&analysis.stdout);
    let quoted = summary.find("what to quote").expect("the summary does not lead with the area");
    assert!(quoted < summary.find("paper-compatible count").unwrap(), "{summary}");
    assert!(summary.contains("heatmap-count.png (paper-compatible count)"), "{summary}");
    assert!(summary.contains("angular area per texel, deg²·s"), "{summary}");
    let redraw = |name: &str, extra: &[&str]| {
        let png = dir.path().join(name);
        let mut command = analyzer();
        command.args(["heatmap".as_ref(), out.as_os_str(), "--out".as_ref(), png.as_os_str()]);
        let status = command.args(extra).output().unwrap();
        assert!(status.status.success(), "{}", String::from_utf8_lossy(&status.stderr));
        (std::fs::read(png).unwrap(), String::from_utf8_lossy(&status.stdout).into_owned())
    };
    let (area, said) = redraw("area.png", &[]);
    assert_eq!(area, std::fs::read(out.join("heatmap.png")).unwrap(), "not heatmap.png's angular area");
    assert!(said.contains("angular area, deg²·s per texel"), "{said}");
    let (count, said) = redraw("count.png", &["--texel-area", "off"]);
    assert_eq!(count, std::fs::read(out.join("heatmap-count.png")).unwrap(), "not the count's texture");
    assert!(said.contains("count per texel"), "{said}");
    assert_ne!(area, count);
    let (half, _) = redraw("half.png", &["--area-max", "1e9"]);
    assert_ne!(half, area, "--area-max moves the top of the scale");
}
