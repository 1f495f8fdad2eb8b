//! `report.html` in a real browser: headless Chromium loads the page of the
//! bundled example; every image must render (a probe script added to a copy
//! of the page reports `naturalWidth` of each image and any error event) and
//! the screenshot must not be blank. A page with a missing image must fail
//! the same probe, so the check bites. Ignored (with the reason) where
//! Chromium is not installed; a failure when `CI` is set (`.ci/run` installs it).
//! The comparison page of several results (`ufcsr report`) and a
//! page with the placement section and its picture are checked the same way.

use std::path::{Path, PathBuf};
use std::process::Command;

use crate::need::{Outcome, missing};
use libtest_mimic::Completion;

const CHROMIUM: &str = "chromium (apt-get install chromium)";

const PROBE: &str = r#"<script>
window.__errors = [];
window.addEventListener("error", e => window.__errors.push(String(e.message || (e.target && e.target.src))), true);
window.addEventListener("load", () => {
  const images = [...document.images].map(i => (i.complete && i.naturalWidth > 0) ? 1 : 0).join("");
  document.body.setAttribute("data-probe", "images=" + images + ";errors=" + window.__errors.length);
});
</script></body>"#;

fn chromium() -> Option<&'static str> {
    ["chromium", "chromium-browser", "google-chrome"]
        .into_iter()
        .find(|name| Command::new(name).arg("--version").output().is_ok_and(|o| o.status.success()))
}

fn browser(binary: &str, args: &[&str], page: &Path) -> String {
    let output = Command::new(binary)
        .args(["--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars"])
        .args(args)
        .arg(format!("file://{}", page.display()))
        .output()
        .expect("run chromium");
    String::from_utf8_lossy(&output.stdout).into_owned()
}

fn probe(binary: &str, report: &Path) -> String {
    let page = std::fs::read_to_string(report).unwrap().replace("</body>", PROBE);
    let probe_page = report.with_file_name("probe.html");
    std::fs::write(&probe_page, page).unwrap();
    let dom = browser(binary, &["--virtual-time-budget=5000", "--dump-dom"], &probe_page);
    let start = dom.find("data-probe=\"").expect("the page's load event never ran") + "data-probe=\"".len();
    dom[start..].split('"').next().unwrap_or_default().to_string()
}

pub fn the_report_of_the_bundled_example_renders_in_chromium() -> Outcome {
    let Some(binary) = chromium() else { return missing(CHROMIUM) };
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("results");
    let example = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fixtures/example");
    let status = Command::new(env!("CARGO_BIN_EXE_ufcsr-analyze"))
        .arg(&example)
        .arg("--out")
        .arg(&out)
        .arg("-q")
        .status()
        .unwrap();
    assert!(status.success());
    let report = out.join("report.html");
    assert!(out.join("heatmap.glb").is_file(), "the example's vehicle.glb should give heatmap.glb");

    // In page order: the scenario map, the frame strip, the three plots
    // (visibility against time and distance, the parts' bars; the quoted
    // measures come first), the contact sheet of the eight views and the
    // heatmap textures (the angular area's, on by default, and the paper-compatible count's, last).
    assert_eq!(probe(binary, &report), "images=11111111;errors=0");
    for figure in ["map.png", "frames-strip.png", "views.png"] {
        let colors = distinct_colors(&out.join(figure));
        assert!(colors > 8, "{figure} is blank ({colors} colours)");
    }
    for plot in ["visibility-time", "visibility-distance", "parts"] {
        let colors = distinct_colors(&out.join(format!("plots/{plot}.png")));
        assert!(colors > 8, "plots/{plot}.png is blank ({colors} colours)");
        // The vector figure the page links to.
        let pdf = std::fs::read(report.with_file_name(format!("plots/{plot}.pdf"))).unwrap();
        assert!(pdf.starts_with(b"%PDF-"), "plots/{plot}.pdf");
    }

    let screenshot = dir.path().join("report.png");
    browser(binary, &["--window-size=1000,1400", &format!("--screenshot={}", screenshot.display())], &report);
    let colors = distinct_colors(&screenshot);
    assert!(colors > 50, "the screenshot is blank ({colors} colours)");

    // The probe bites: without the heatmap image (the angular area's, the
    // next to last; the count's heatmap-count.png is last) it reports it.
    // (Only the image flags: a missing file's error event may fire before
    // the probe's listener exists, so the error count is 0 or 1.)
    std::fs::remove_file(out.join("heatmap.png")).unwrap();
    let probed = probe(binary, &report);
    assert!(probed.starts_with("images=11111101;"), "{probed}");
    Ok(Completion::Completed)
}

/// Distinct pixel values of a PNG (1 for a blank image).
fn distinct_colors(path: &Path) -> usize {
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
    let mut reader = decoder.read_info().unwrap();
    let mut pixels = vec![0; reader.output_buffer_size().unwrap()];
    let frame = reader.next_frame(&mut pixels).unwrap();
    let step = frame.color_type.samples();
    let mut colors: Vec<&[u8]> = pixels[..frame.buffer_size()].chunks(step).collect();
    colors.sort_unstable();
    colors.dedup();
    colors.len()
}

pub fn the_comparison_page_of_two_results_renders_in_chromium() -> Outcome {
    let Some(binary) = chromium() else { return missing(CHROMIUM) };
    let dir = tempfile::tempdir().unwrap();
    let example = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fixtures/example");
    let analyse = |name: &str, dedupe: &str| {
        let out = dir.path().join(name).join("results");
        let status = Command::new(env!("CARGO_BIN_EXE_ufcsr-analyze"))
            .arg(&example)
            .args(["--dedupe", dedupe, "-q", "--out"])
            .arg(&out)
            .status()
            .unwrap();
        assert!(status.success());
        out
    };
    let (per_image, per_frame) = (analyse("per-image", "image"), analyse("per-frame", "frame"));
    let compared = dir.path().join("compared");
    let output = Command::new(env!("CARGO_BIN_EXE_ufcsr-analyze"))
        .arg("report")
        .arg(&per_image)
        .arg(per_frame.join("result.json"))
        .arg("--out")
        .arg(&compared)
        .output()
        .unwrap();
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    let report = compared.join("report.html");
    // The page's content is checked by tests/it/comparison_page.rs; here, that it renders.
    // The two contact sheets, copied beside the page.
    assert_eq!(probe(binary, &report), "images=11;errors=0");
    let screenshot = dir.path().join("compared.png");
    browser(binary, &["--window-size=1000,1400", &format!("--screenshot={}", screenshot.display())], &report);
    let colors = distinct_colors(&screenshot);
    assert!(colors > 50, "the screenshot is blank ({colors} colours)");
    Ok(Completion::Completed)
}

/// The placement section (issue 18) on a result's page: a placement of the
/// example's vehicle (hood legible first, then the grill) beside the result;
/// its picture must render with the page's other images.
pub fn the_placement_section_renders_in_chromium() -> Outcome {
    let Some(binary) = chromium() else { return missing(CHROMIUM) };
    let dir = tempfile::tempdir().unwrap();
    let example = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fixtures/example");
    let archive = dir.path().join("archive");
    std::fs::create_dir_all(archive.join("results")).unwrap();
    std::fs::copy(example.join("vehicle.glb"), archive.join("vehicle.glb")).unwrap();
    let mut table = String::from(
        "frame,time_s,eye,distance_m,candidate,kind,solid_angle_sr,visible_fraction,view_angle_deg,\
         angular_height_deg,frame_s\n",
    );
    for frame in 0..10 {
        for (part, legible) in [("hood", frame < 7), ("grill", frame >= 7)] {
            let fraction = if legible { 1 } else { 0 };
            table += &format!(
                "{frame},{},left,{},{part},part,1e-3,{fraction},10,1,0.1\n",
                f64::from(frame) / 10.0,
                30 - frame
            );
        }
    }
    std::fs::write(archive.join("results/placement-frames.csv"), table).unwrap();
    let out = dir.path().join("results");
    let run = |args: &[&std::ffi::OsStr]| {
        let status = Command::new(env!("CARGO_BIN_EXE_ufcsr-analyze")).args(args).status().unwrap();
        assert!(status.success());
    };
    let placement = out.join("placement");
    run(&["placement".as_ref(), archive.as_os_str(), "-q".as_ref(), "--out".as_ref(), placement.as_os_str()]);
    run(&[example.as_os_str(), "-q".as_ref(), "--out".as_ref(), out.as_os_str()]);
    // The page's eight images (map, frame strip, views, the two heatmaps, three plots) and the placement picture.
    assert_eq!(probe(binary, &out.join("report.html")), "images=111111111;errors=0");
    Ok(Completion::Completed)
}
