//! The eight views of the heatmap on the vehicle: written for an archive with
//! a vehicle model, one scale for all, never-seen texels grey and the
//! background white — and they show what the capture saw: in the bundled
//! example (scenario A, the truck turning towards the pedestrian on its
//! right) the front and right are seen far more than the rear and left; and
//! the front-right view matches its reference image (tests/reference/).

use std::path::{Path, PathBuf};

fn coloured_pixels(path: &Path) -> (usize, usize) {
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
    let mut reader = decoder.read_info().unwrap();
    let mut pixels = vec![0; reader.output_buffer_size().unwrap()];
    let frame = reader.next_frame(&mut pixels).unwrap();
    let (mut seen, mut vehicle) = (0, 0);
    for p in pixels[..frame.buffer_size()].chunks(3) {
        let rgb = [p[0], p[1], p[2]];
        if rgb != [255, 255, 255] {
            vehicle += 1;
            if rgb != ufcsr::NEVER_SEEN {
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
    let written = ufcsr::write_results(&mut analysis, dir.path()).unwrap();
    assert_eq!(written.views_png.as_deref(), Some(dir.path().join("views.png").as_path()));
    let share = |name: &str| {
        let (seen, vehicle) = coloured_pixels(&dir.path().join(format!("views/{name}.png")));
        assert!(vehicle > 5_000, "{name}: the vehicle covers only {vehicle} pixels");
        seen as f64 / vehicle as f64
    };
    let (front, right, rear, left) = (share("front"), share("right"), share("rear"), share("left"));
    assert!(front > 0.5 && right > 0.3, "front {front:.2}, right {right:.2}");
    assert!(rear < 0.05 && left < 0.1, "rear {rear:.2}, left {left:.2}");
    let (seen, vehicle) = coloured_pixels(&dir.path().join("views.png"));
    assert!(seen > 0 && vehicle > seen);
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
    let dir = tempfile::tempdir().unwrap();
    let example = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("fixtures/example");
    let options = ufcsr::AnalyzeOptions { archive: example, ..Default::default() };
    let mut analysis = ufcsr::analyze(&options, None).unwrap();
    ufcsr::write_results(&mut analysis, dir.path()).unwrap();
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
