//! The eight views of the heatmap on the vehicle: written for an archive with
//! a vehicle model, one scale for all, never-seen texels grey and the
//! background white — and they show what the capture saw: in the bundled
//! example (scenario A, the truck turning towards the pedestrian on its
//! right) the front and right are seen far more than the rear and left; the
//! compass marks the pedestrian on the vehicle's front right; the contact
//! sheet's colour bar has its ticks; and the front-right view matches its
//! reference image (tests/reference/).

use std::path::{Path, PathBuf};

/// Pixels of the vehicle, and those of them showing a count, in a view:
/// everything not white is the vehicle, except the compass in the top-right
/// corner; never-seen grey stays grey (r = g = b) when shaded or outlined,
/// while the plasma scale has no grey.
fn colored_pixels(path: &Path) -> (usize, usize) {
    let (width, _, pixels) = rgb(path);
    let compass = 68 * ufcsr::output::DEFAULT_VIEWS_SCALE as usize;
    let (mut seen, mut vehicle) = (0, 0);
    for (index, p) in pixels.chunks(3).enumerate() {
        let (x, y) = (index % width as usize, index / width as usize);
        if x + compass >= width as usize && y < compass {
            continue;
        }
        if p != [255, 255, 255] {
            vehicle += 1;
            if !(p[0] == p[1] && p[1] == p[2]) {
                seen += 1;
            }
        }
    }
    (seen, vehicle)
}

#[test]
fn eight_views_show_the_heatmap_where_the_pedestrian_looked() {
    let dir = tempfile::tempdir().unwrap();
    let example = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("fixtures/example");
    let options = ufcsr::AnalyzeOptions { archive: example, ..Default::default() };
    let mut analysis = ufcsr::analyze(&options, None).unwrap();
    let written = ufcsr::output::write_results_with(&mut analysis, dir.path(), &with_variants()).unwrap();
    assert_eq!(written.views_png.as_deref(), Some(dir.path().join("views.png").as_path()));
    let share = |name: &str| {
        let (seen, vehicle) = colored_pixels(&dir.path().join(format!("views/{name}.png")));
        assert!(vehicle > 20_000, "{name}: the vehicle covers only {vehicle} pixels");
        seen as f64 / vehicle as f64
    };
    let (front, right, rear, left) = (share("front"), share("right"), share("rear"), share("left"));
    assert!(front > 0.5 && right > 0.3, "front {front:.2}, right {right:.2}");
    assert!(rear < 0.05 && left < 0.1, "rear {rear:.2}, left {left:.2}");
    let (seen, vehicle) = colored_pixels(&dir.path().join("views.png"));
    assert!(seen > 0 && vehicle > seen);
}

/// The bundled example's result set with each view alone too (`views/`), in a temporary folder.
fn example_results() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    let example = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("fixtures/example");
    let options = ufcsr::AnalyzeOptions { archive: example, ..Default::default() };
    let mut analysis = ufcsr::analyze(&options, None).unwrap();
    ufcsr::output::write_results_with(&mut analysis, dir.path(), &with_variants()).unwrap();
    dir
}

/// The result set's options that write the variants, `views/NAME.png` among them (`--figures all`).
fn with_variants() -> ufcsr::output::ResultSetOptions {
    ufcsr::output::ResultSetOptions { figures: ufcsr::output::Figures::WithVariants, ..Default::default() }
}

/// Decoded RGB pixels of a PNG.
fn rgb(path: &Path) -> (u32, u32, Vec<u8>) {
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
    let mut reader = decoder.read_info().unwrap();
    let mut pixels = vec![0; reader.output_buffer_size().unwrap()];
    let frame = reader.next_frame(&mut pixels).unwrap();
    pixels.truncate(frame.buffer_size());
    (frame.width, frame.height, pixels)
}

#[test]
fn the_front_right_view_of_the_example_matches_its_reference_image() {
    // A reference image, tolerant of small differences (a texel at an edge,
    // rounding of a projection on another platform): at most 0.5 % of the
    // pixels may differ.
    let dir = example_results();
    let reference = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/reference/views-front-right.png");
    let (width, height, expected) = rgb(&reference);
    let (w, h, got) = rgb(&dir.path().join("views/front-right.png"));
    assert_eq!((w, h), (width, height));
    let differing = expected.chunks(3).zip(got.chunks(3)).filter(|(a, b)| a != b).count();
    let pixels = (width * height) as usize;
    assert!(
        differing * 200 <= pixels,
        "{differing} of {pixels} pixels differ from tests/reference/views-front-right.png \
         (if the views changed on purpose, replace the reference with the new views/front-right.png)"
    );
}

#[test]
fn the_compass_marks_the_pedestrian_on_the_vehicles_front_right() {
    // Scenario A: the pedestrian stands at the south-west corner and the
    // truck turns east past it, so the pedestrian is ahead and to the right
    // in every frame: green dots in the compass's upper-right quarter only.
    let dir = example_results();
    let (width, height, pixels) = rgb(&dir.path().join("views/rear.png"));
    let scale = ufcsr::output::DEFAULT_VIEWS_SCALE;
    assert_eq!((width, height), (400 * scale, 300 * scale));
    let centre = ((width - 34 * scale) as usize, (34 * scale) as usize);
    let (mut front_right, mut elsewhere) = (0, 0);
    for (index, p) in pixels.chunks(3).enumerate() {
        let (x, y) = (index % width as usize, index / width as usize);
        if p == [0, 150, 60] {
            if x > centre.0 && y < centre.1 { front_right += 1 } else { elsewhere += 1 }
        }
    }
    assert!(
        front_right > 20 && elsewhere == 0,
        "{front_right} green pixels front-right, {elsewhere} elsewhere"
    );
    let (sheet_width, sheet_height, _) = rgb(&dir.path().join("views.png"));
    // Below the views: the colour bar, its numbers and the caption, sized
    // to print at 7 pt or more at 181.9 mm (views.pdf).
    assert_eq!(sheet_width, 4 * 400 * scale);
    assert!(sheet_height > 2 * 300 * scale + 96 * scale, "{sheet_height}");
    let size = ufcsr::output::sheet_text_px(sheet_width);
    let em_pt = size / 1.24 / f64::from(sheet_width) * 181.9 / ufcsr::output::MM_PER_PT;
    assert!(em_pt >= ufcsr::output::MIN_TEXT_PT, "{em_pt} pt");
    let pdf = std::fs::read(dir.path().join("views.pdf")).unwrap();
    assert!(pdf.starts_with(b"%PDF-") && pdf.trim_ascii_end().ends_with(b"%%EOF"));
    let head = String::from_utf8_lossy(&pdf[..pdf.len().min(2000)]).into_owned();
    let media = head.split("/MediaBox [").nth(1).unwrap().split(']').next().unwrap();
    let page_width: f64 = media.split_whitespace().nth(2).unwrap().parse().unwrap();
    assert!((page_width - 515.62).abs() < 0.01, "views.pdf is not 181.9 mm wide: {media}");
}
