//! Figures for a paper (issue 35 item 2), on the bundled example: every
//! plot exists as SVG, PDF and PNG at one and two journal columns (with
//! `--figures all`; PNG and PDF at two by default); the SVG printed at its
//! stated width (181.9 mm or 88.9 mm) has no text under 7 pt;
//! the series use the Okabe–Ito palette; no figure names the archive's
//! folder; every axis title says "quantity (unit)".

use std::path::{Path, PathBuf};

/// The example's result set with every figure variant (`--figures all`).
fn example_results(dir: &Path) -> PathBuf {
    let example = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("fixtures/example");
    let options = ufcsr::AnalyzeOptions { archive: example, frames: true, ..Default::default() };
    let mut analysis = ufcsr::analyze(&options, None).unwrap();
    let out = dir.join("results");
    let set = ufcsr::output::ResultSetOptions {
        figures: ufcsr::output::Figures::WithVariants,
        ..Default::default()
    };
    ufcsr::output::write_results_with(&mut analysis, &out, &set).unwrap();
    out
}

/// The value of attribute `name` in the first tag of `svg` that has it.
fn attribute<'a>(tag: &'a str, name: &str) -> Option<&'a str> {
    let start = tag.find(&format!(" {name}=\""))? + name.len() + 3;
    tag[start..].split('"').next()
}

/// Every `<text>` element's font size, in points, when the SVG is printed
/// at the width its root states (in millimetres).
fn printed_font_sizes_pt(svg: &str) -> (f64, Vec<f64>) {
    let root = &svg[svg.find("<svg").unwrap()..];
    let root = &root[..root.find('>').unwrap()];
    let width_mm: f64 =
        attribute(root, "width").unwrap().strip_suffix("mm").expect("width in mm").parse().unwrap();
    let view_box: Vec<f64> =
        attribute(root, "viewBox").unwrap().split(' ').map(|v| v.parse().unwrap()).collect();
    let mm_per_unit = width_mm / view_box[2];
    let sizes = svg
        .split("<text")
        .skip(1)
        .map(|tag| {
            let size: f64 = attribute(&tag[..tag.find('>').unwrap()], "font-size").unwrap().parse().unwrap();
            size * mm_per_unit / ufcsr::output::MM_PER_PT
        })
        .collect();
    (width_mm, sizes)
}

#[test]
fn every_plot_is_svg_pdf_and_png_at_both_column_widths_with_text_of_at_least_7_pt() {
    if !ufcsr::output::plot_font_available() {
        eprintln!("skipped: no TrueType font (UFCSR_FONT or DejaVu Sans) to draw labels with");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let out = example_results(dir.path());
    if let Some(keep) = std::env::var_os("UFCSR_KEEP_FIGURES") {
        let _ = std::process::Command::new("cp").arg("-r").arg(&out).arg(keep).status();
    }
    for plot in ["visibility-time", "visibility-distance", "parts"] {
        // IEEE's text and column widths, inside Elsevier's 190 and 90 mm.
        for (suffix, width) in [("", 181.9), ("-1col", 88.9)] {
            let stem = out.join("plots").join(format!("{plot}{suffix}"));
            let svg = std::fs::read_to_string(stem.with_extension("svg")).unwrap();
            let (width_mm, sizes) = printed_font_sizes_pt(&svg);
            assert_eq!(width_mm, width, "{plot}{suffix}.svg");
            assert!(sizes.len() > 5, "{plot}{suffix}.svg has {} texts", sizes.len());
            let smallest = sizes.iter().copied().fold(f64::MAX, f64::min);
            assert!(
                smallest >= ufcsr::output::MIN_TEXT_PT - 1e-6,
                "{plot}{suffix}.svg: {smallest:.2} pt at {width} mm"
            );
            let pdf = std::fs::read(stem.with_extension("pdf")).unwrap();
            let pdf = String::from_utf8_lossy(&pdf);
            assert!(pdf.starts_with("%PDF-") && pdf.trim_end().ends_with("%%EOF"));
            assert!(pdf.contains("TJ"), "{plot}{suffix}.pdf has no real text");
            // The font the text was measured with, embedded as a subset (issue 44 §1).
            assert!(pdf.contains("/FontFile2") && pdf.contains("/CIDFontType2"), "{plot}{suffix}.pdf");
            assert!(!pdf.contains("Helvetica") && !pdf.contains("/Type1"), "{plot}{suffix}.pdf");
            let media = pdf.split("/MediaBox [").nth(1).unwrap().split(']').next().unwrap();
            let page_width: f64 = media.split_whitespace().nth(2).unwrap().parse().unwrap();
            let expected = (width / 25.4 * 300.0_f64).floor() * 72.0 / 300.0;
            assert!((page_width - expected).abs() < 0.01, "{plot}{suffix}.pdf is {media}");
            assert!(page_width <= width / 25.4 * 72.0, "{plot}{suffix}.pdf is wider than {width} mm");
            // 300 dpi in the PNG's pHYs chunk (11811 pixels per metre).
            let decoder = png::Decoder::new(std::io::BufReader::new(
                std::fs::File::open(stem.with_extension("png")).unwrap(),
            ));
            let dims = decoder.read_info().unwrap().info().pixel_dims.expect("pHYs");
            assert_eq!((dims.xppu, dims.unit), (11811, png::Unit::Meter), "{plot}{suffix}.png");
            let png = image_size(&stem.with_extension("png"));
            assert_eq!(
                png[0],
                (width / 25.4 * 300.0_f64).floor() as u32,
                "{plot}{suffix}.png is not 300 dpi"
            );
            assert!(!svg.contains("example"), "{plot}{suffix}.svg names the archive's folder");
        }
    }
}

fn image_size(path: &Path) -> [u32; 2] {
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
    let reader = decoder.read_info().unwrap();
    [reader.info().width, reader.info().height]
}

#[test]
fn the_series_are_okabe_ito_colors_and_every_axis_says_quantity_and_unit() {
    if !ufcsr::output::plot_font_available() {
        eprintln!("skipped: no TrueType font (UFCSR_FONT or DejaVu Sans) to draw labels with");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let out = example_results(dir.path());
    let svg = std::fs::read_to_string(out.join("plots/visibility-time.svg")).unwrap();
    let hex = |c: &[u8; 3]| format!("#{:02X}{:02X}{:02X}", c[0], c[1], c[2]);
    let used: Vec<String> =
        ufcsr::output::OKABE_ITO.iter().map(hex).filter(|c| svg.contains(c.as_str())).collect();
    assert!(used.len() >= 3, "the series use {used:?} of the Okabe–Ito palette");
    // matplotlib's default cycle (tab10) is gone.
    for old in ["#1F77B4", "#FF7F0E", "#2CA02C"] {
        assert!(!svg.contains(old), "{old} of the old cycle is still drawn");
    }
    for plot in ["visibility-time", "visibility-distance", "parts"] {
        let svg = std::fs::read_to_string(out.join("plots").join(format!("{plot}.svg"))).unwrap();
        let texts: Vec<&str> = svg
            .split("<text")
            .skip(1)
            .map(|t| t[t.find('>').unwrap() + 1..].split('<').next().unwrap().trim())
            .collect();
        let axis_titles: Vec<&&str> = texts.iter().filter(|t| t.contains('(') && t.ends_with(')')).collect();
        assert!(axis_titles.len() >= 2, "{plot}.svg: no \"quantity (unit)\" axis titles in {texts:?}");
        assert!(
            !texts.iter().any(|t| t.contains(", s") || t.contains(", m") || t.contains(", deg")),
            "{texts:?}"
        );
    }
}

#[test]
fn the_report_leads_with_the_quoted_measures_and_says_it_needs_its_folder() {
    let dir = tempfile::tempdir().unwrap();
    let out = example_results(dir.path());
    let page = std::fs::read_to_string(out.join("report.html")).unwrap();
    let first_table = page.find("<table").unwrap();
    let heading = page.find(ufcsr::output::QUOTED_HEADING).expect("no table of the quoted measures");
    assert!(heading < first_table, "the first table is not the quoted measures");
    let table = &page[first_table..page[first_table..].find("</table>").unwrap() + first_table];
    assert!(table.contains("angular area (deg²·s)") && table.contains("exposure (s)"), "{table}");
    // Largest angular area first: the example's windshield (the time plot's top curve).
    let first_row = table.split("<tr><td>").nth(1).unwrap();
    assert!(first_row.starts_with("windshield<"), "{first_row}");
    // The paper's count is kept, labelled as such, below.
    let paper =
        page.find("Paper-compatible: the per-texel count per part").expect("no paper-compatible table");
    assert!(paper > first_table);
    // Pictures are linked, not embedded: the page says it needs its folder.
    assert!(page.find(ufcsr::output::NEEDS_ITS_FOLDER).unwrap() < first_table);
    assert!(page.contains("src=\"views.png\"") || page.contains("src=\"heatmap.png\""));
    assert!(!page.contains("src=\"data:"));
}

/// The default heatmap and the views show per-texel angular area (issue 35
/// item 2): its texels, summed over each part, give that part's
/// `angular_area_deg2_s` in result.json (the same pixel solid angles, summed
/// per texel instead of per part); the paper's count is in heatmap-count.png.
#[test]
fn per_texel_angular_area_adds_up_to_each_parts_angular_area() {
    let example = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("fixtures/example");
    let options =
        ufcsr::AnalyzeOptions { archive: example, frames: true, texel_area: true, ..Default::default() };
    let mut analysis = ufcsr::analyze(&options, None).unwrap();
    let area = analysis.texel_angular_area.clone().expect("no per-texel angular area");
    let labels = analysis.labels.clone().expect("the example has labels");
    assert_eq!(area.len(), analysis.texel_counts.len());
    let measures = analysis.result.measures.clone().unwrap();
    let mut checked = 0;
    for (index, part) in labels.legend.parts.iter().enumerate() {
        let sum: f64 = area
            .iter()
            .zip(&labels.pidt.part_of_texel)
            .filter(|&(_, &p)| usize::from(p) == index)
            .map(|(&a, _)| f64::from(a))
            .sum();
        let expected = measures.part(&part.name).and_then(|m| m.angular_area_deg2_s).unwrap();
        assert!((sum - expected).abs() <= 1e-5 * expected.max(1e-9), "{}: {sum} vs {expected}", part.name);
        checked += usize::from(expected > 0.0);
    }
    assert!(checked >= 3, "only {checked} parts were seen");
    // A texel is seen (count > 0) exactly where it has angular area.
    for (&count, &a) in analysis.texel_counts.iter().zip(&area) {
        assert_eq!(count > 0, a > 0.0);
    }
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("results");
    ufcsr::output::write_results(&mut analysis, &out).unwrap();
    assert_eq!(image_size(&out.join("heatmap-count.png")), image_size(&out.join("heatmap.png")));
    let page = std::fs::read_to_string(out.join("report.html")).unwrap();
    let area_section =
        page.find("The heatmap on the vehicle: angular area per texel").expect("views not area");
    assert!(area_section < page.find("The heatmap texture (paper-compatible count)").unwrap());
    assert!(page.contains("src=\"heatmap.png\"") && page.contains("src=\"heatmap-count.png\""));
}

/// `--area-max` puts the top of the angular-area heatmap where it is told
/// (shared across scenarios): at twice the largest texel, that texel is
/// plasma's middle; it is recorded in result.json, and the values
/// themselves are kept exactly in texel-area.f32. An unusable top is refused.
#[test]
fn area_max_sets_the_top_of_the_area_heatmap_and_the_values_are_kept() {
    let example = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("fixtures/example");
    let options = ufcsr::AnalyzeOptions {
        archive: example.clone(),
        frames: true,
        texel_area: true,
        ..Default::default()
    };
    let area = ufcsr::analyze(&options, None).unwrap().texel_angular_area.unwrap();
    let (at, largest) =
        area.iter().enumerate().fold((0, 0f32), |best, (i, &v)| if v > best.1 { (i, v) } else { best });
    let options = ufcsr::AnalyzeOptions { area_max: Some(2.0 * f64::from(largest)), ..options };
    let mut analysis = ufcsr::analyze(&options, None).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("results");
    ufcsr::output::write_results(&mut analysis, &out).unwrap();
    let decoder =
        png::Decoder::new(std::io::BufReader::new(std::fs::File::open(out.join("heatmap.png")).unwrap()));
    let mut reader = decoder.read_info().unwrap();
    let mut rgb = vec![0; reader.output_buffer_size().unwrap()];
    reader.next_frame(&mut rgb).unwrap();
    assert_eq!(&rgb[at * 3..at * 3 + 3], &ufcsr::output::plasma(0.5), "the largest texel at half the scale");
    assert!(!rgb.chunks_exact(3).any(|p| p == ufcsr::output::plasma(1.0)), "nothing reaches the top");
    let json = std::fs::read_to_string(out.join("result.json")).unwrap();
    assert!(json.contains("\"heatmap_area_max\""));
    let palette = &analysis.result.settings.palette;
    let kept =
        ufcsr::read_texel_area(&out.join(ufcsr::TEXEL_AREA_FILE), palette.width, palette.height).unwrap();
    assert_eq!(kept, area, "texel-area.f32 holds the analysis' values exactly");
    // 1e-300 rounds to 0 as an f32 (texel-area.f32's type): it painted every texel "never seen".
    for bad in [0.0, -1.0, f64::NAN, f64::INFINITY, 1e-300, 1e-39] {
        let options = ufcsr::AnalyzeOptions { area_max: Some(bad), ..options.clone() };
        let error = ufcsr::analyze(&options, None).err().expect("an unusable --area-max is refused");
        assert!(error.to_string().contains("--area-max"), "{error}");
    }
}

/// The per-texel angular area is on by default (the kernels sum it as they
/// count, docs/performance.md#per-texel-angular-area) wherever frames are
/// tallied and the eyes' projection is known; `texel_area: false` (the
/// binary's `--texel-area off`) keeps the paper's count alone.
#[test]
fn per_texel_angular_area_is_on_by_default_and_off_when_asked() {
    let example = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("fixtures/example");
    let options = ufcsr::AnalyzeOptions { archive: example, frames: true, ..Default::default() };
    assert!(ufcsr::analyze(&options, None).unwrap().texel_angular_area.is_some(), "on by default");
    let options = ufcsr::AnalyzeOptions { texel_area: false, ..options };
    let mut analysis = ufcsr::analyze(&options, None).unwrap();
    assert!(analysis.texel_angular_area.is_none());
    assert!(analysis.result.measures.is_some(), "the part measures are still there");
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("results");
    ufcsr::output::write_results(&mut analysis, &out).unwrap();
    assert!(!out.join("heatmap-count.png").exists());
    assert!(!out.join(ufcsr::TEXEL_AREA_FILE).exists());
    assert!(out.join("heatmap.png").exists());
}

#[test]
fn figures_off_writes_no_figure_and_the_same_tables() {
    let dir = tempfile::tempdir().unwrap();
    let drawn = example_results(dir.path());
    let example = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("fixtures/example");
    let options = ufcsr::AnalyzeOptions { archive: example, frames: true, ..Default::default() };
    let mut analysis = ufcsr::analyze(&options, None).unwrap();
    let plain = dir.path().join("plain");
    let set = ufcsr::output::ResultSetOptions { figures: ufcsr::output::Figures::None, ..Default::default() };
    let written = ufcsr::output::write_results_with(&mut analysis, &plain, &set).unwrap();
    for figure in ["plots", "views", "views.png", "views.pdf", "map.png", "frames-strip.png"] {
        assert!(!plain.join(figure).exists(), "{figure} was written with the figures off");
    }
    assert!(written.plots.is_empty() && written.views_png.is_none() && written.map_png.is_none());
    assert!(drawn.join("plots").is_dir() && drawn.join("map.png").is_file(), "the example draws figures");
    for table in ["result.json", "parts.csv", "frames.csv", "heatmap.png"] {
        assert_eq!(
            std::fs::read(plain.join(table)).unwrap(),
            std::fs::read(drawn.join(table)).unwrap(),
            "{table}"
        );
    }
    assert!(plain.join("report.html").is_file());
}
