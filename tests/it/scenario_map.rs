//! `map.png`, the scenario from above: the vehicle's trajectory lies where
//! the manifest puts the vehicle, in the colour of its time; the analysis
//! writes the map beside the views when the archive has a manifest (and a
//! font for its words), and the report shows it with the scenario and rig.

use std::path::{Path, PathBuf};

fn example() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("fixtures/example")
}

/// The bundled example analysed into a temporary folder.
fn example_results() -> (tempfile::TempDir, ufcsr::Analysis, ufcsr::output::WrittenFiles) {
    let dir = tempfile::tempdir().unwrap();
    let options = ufcsr::AnalyzeOptions { archive: example(), ..Default::default() };
    let mut analysis = ufcsr::analyze(&options, None).unwrap();
    let written = ufcsr::output::write_results(&mut analysis, dir.path()).unwrap();
    (dir, analysis, written)
}

fn rgb(path: &Path) -> (u32, Vec<u8>) {
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
    let mut reader = decoder.read_info().unwrap();
    let mut pixels = vec![0; reader.output_buffer_size().unwrap()];
    let frame = reader.next_frame(&mut pixels).unwrap();
    pixels.truncate(frame.buffer_size());
    (frame.width, pixels)
}

#[test]
fn the_trajectory_is_drawn_where_the_manifest_puts_the_vehicle_in_its_times_color() {
    if !ufcsr::output::plot_font_available() {
        // Without a font the map is not written; the analysis test below checks that.
        return;
    }
    let manifest = ufcsr::Manifest::load_from_dir(&example()).unwrap().unwrap();
    let track = ufcsr::ScenarioTrack::from_manifest(&manifest).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("map.png");
    let scene = Ok(ufcsr::output::SceneShapes { occluders: Vec::new() });
    let content = ufcsr::output::MapContent { track: &track, scene, vehicle: None, title: "A".into() };
    let frame = ufcsr::output::write_scenario_map(&path, &content).unwrap();
    let (width, pixels) = rgb(&path);
    assert_eq!(width, ufcsr::output::MAP_SIZE.0);
    let (start, end) = (track.frames[0].time_s, track.frames.last().unwrap().time_s);
    let mut matching = 0;
    let segments = track.frames.windows(2).count();
    for pair in track.frames.windows(2) {
        let middle = [0, 1].map(|k| (pair[0].vehicle_position[k] + pair[1].vehicle_position[k]) / 2.0);
        let (x, y) = frame.pixel(middle);
        let i = (y as usize * width as usize + x as usize) * 3;
        let share = ((pair[0].time_s + pair[1].time_s) / 2.0 - start) / (end - start);
        if pixels[i..i + 3] == ufcsr::output::time_color(share) {
            matching += 1;
        }
    }
    // Labels of the marked frames may cover a segment's middle.
    assert!(matching * 10 >= segments * 8, "{matching} of {segments} segment middles in their time's colour");
}

#[test]
fn an_analysis_with_a_manifest_writes_the_map() {
    let (dir, _, written) = example_results();
    let map = dir.path().join(ufcsr::output::MAP_FILE);
    assert_eq!(written.map_png.as_deref(), ufcsr::output::plot_font_available().then_some(map.as_path()));
    assert_eq!(map.is_file(), ufcsr::output::plot_font_available());
    // The report shows the scenario (from the manifest) and the map, and
    // the views before the heatmap texture.
    let page = std::fs::read_to_string(dir.path().join("report.html")).unwrap();
    assert!(page.contains("<tr><th>scenario</th><td>A, 3.0 s</td></tr>"), "{page}");
    assert!(
        page.contains("<tr><th>pedestrian</th><td>standing, eyes at (-5.5, -5.5) m, 1.75 m high</td></tr>")
    );
    assert_eq!(page.contains("<img src=\"map.png\""), ufcsr::output::plot_font_available());
    let position = |text: &str| page.find(text).unwrap_or_else(|| panic!("no {text} in the report"));
    assert!(position("<h2>The scenario") < position("<h2>Paper-compatible"));
    assert!(position("<h2>The heatmap on the vehicle") < position("<h2>The heatmap texture"));
}

#[test]
fn the_frame_strip_shows_frames_of_one_eye_in_part_colors() {
    let (dir, analysis, written) = example_results();
    let strip = dir.path().join(ufcsr::output::FRAME_STRIP_FILE);
    assert_eq!(written.frames_strip_png.as_deref(), Some(strip.as_path()));
    let (width, pixels) = rgb(&strip);
    let height = (pixels.len() / 3) as u32 / width;
    // One row of frames, scaled to the strip's height, under a row of labels and above the colour key.
    assert!(height > ufcsr::output::STRIP_FRAME_HEIGHT + 34, "no colour key below the frames: {height} rows");
    let mut allowed: Vec<[u8; 3]> =
        analysis.result.parts.iter().filter_map(|part| part.color).map(|color| color.rgb()).collect();
    allowed.extend([ufcsr::output::STRIP_BACKGROUND, ufcsr::output::STRIP_UNLABELLED, [255, 255, 255]]);
    let frames_end = ((34 + ufcsr::output::STRIP_FRAME_HEIGHT) * width * 3) as usize;
    let below_labels = &pixels[(34 * width * 3) as usize..frames_end];
    let mut parts_shown = std::collections::BTreeSet::new();
    for pixel in below_labels.chunks(3) {
        let color = [pixel[0], pixel[1], pixel[2]];
        assert!(allowed.contains(&color), "{color:?} is no part's colour");
        if color != ufcsr::output::STRIP_BACKGROUND && color != [255, 255, 255] {
            parts_shown.insert(color);
        }
    }
    // Scenario A's frames show the truck's front and right: many parts.
    assert!(parts_shown.len() >= 8, "only {} part colours in the strip", parts_shown.len());
    let page = std::fs::read_to_string(dir.path().join("report.html")).unwrap();
    assert!(page.contains("<img src=\"frames-strip.png\""));
}
