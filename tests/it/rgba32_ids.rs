//! Archives of 32-bit texel ids (`"texel_ids": "rgba32"`, schema
//! `ufcsr-manifest/2`): a palette of more than 2^24 texels counts every
//! texel exactly, ids that share their RGB but not their alpha are told
//! apart, and the 24-bit archives read as before.

use std::path::{Path, PathBuf};

use crate::common::*;
use ufcsr::{AnalyzeOptions, Dedupe, analyze, rgba32_pixel};

/// 8192 × 2049 = 16 785 408 texels: 8192 more than 24-bit colours name.
const SIZE: [u32; 2] = [8192, 2049];
const TEXELS: u32 = SIZE[0] * SIZE[1];
/// A low texel, and the texel 2^24 above it: the same RGB, another alpha.
const LOW: u32 = 5;
const HIGH: u32 = (1 << 24) + 5;
/// The palette's last texel, and the first id beyond it (a stray).
const LAST: u32 = TEXELS - 1;
const BEYOND: u32 = TEXELS;

fn rgba_png(path: &Path, width: u32, height: u32, ids: &[u32]) {
    let bytes: Vec<u8> = ids.iter().flat_map(|&id| rgba32_pixel(id)).collect();
    write_png(path, width, height, png::ColorType::Rgba, png::BitDepth::Eight, &bytes, None);
}

/// The archive: frame 0 has a left (`a`) and a right (`b`) RGBA tile, frame
/// 1 a left RGB tile (`c`, opaque: 24-bit ids). The PIdT labels the texels
/// below 2^24 (rows 0–2047) part A and row 2048 (ids from 2^24) part B.
///
/// - a = [LOW, LOW, HIGH, bg, LAST, bg, bg, bg]
/// - b = [HIGH, HIGH, HIGH, LAST, BEYOND, bg, LOW, bg]
/// - c = [LOW, bg, bg, bg, 7, 7, bg, bg]
///
/// Once per image: LOW 3, HIGH 2, LAST 2, 7 1 (A 4, B 4); per frame
/// (eye-pair): LOW 2, HIGH 1, LAST 1, 7 1 (A 3, B 2). One stray pixel.
fn rgba32_archive(dir: &Path) -> PathBuf {
    let archive = dir.join("archive");
    rgba_png(&archive.join("tiles/a.png"), 4, 2, &[LOW, LOW, HIGH, BG, LAST, BG, BG, BG]);
    rgba_png(&archive.join("tiles/b.png"), 4, 2, &[HIGH, HIGH, HIGH, LAST, BEYOND, BG, LOW, BG]);
    rgb_png(&archive.join("tiles/c.png"), 4, 2, &[LOW, BG, BG, BG, 7, 7, BG, BG]);
    let row = SIZE[0] as usize * 3;
    let mut pidt = [255u8, 0, 0].repeat(row / 3 * (SIZE[1] as usize - 1));
    pidt.extend([0u8, 255, 0].repeat(row / 3));
    write_png(
        &archive.join("pidt.png"),
        SIZE[0],
        SIZE[1],
        png::ColorType::Rgb,
        png::BitDepth::Eight,
        &pidt,
        None,
    );
    std::fs::write(archive.join("parts.csv"), "name,color\nA,#FF0000\nB,#00FF00\n").unwrap();
    write_manifest(&archive, "ufcsr-manifest/2", r#""texel_ids": "rgba32","#, SIZE);
    archive
}

fn write_manifest(archive: &Path, schema: &str, ids: &str, [width, height]: [u32; 2]) {
    let manifest = format!(
        r#"{{"schema": "{schema}", {ids} "palette": {{"canonical": [{width}, {height}]}},
        "pidt": "pidt.png", "parts": "parts.csv",
        "tiles": [
          {{"file": "tiles/a.png", "frame": 0, "eye": "left", "row": 0, "col": 0}},
          {{"file": "tiles/b.png", "frame": 0, "eye": "right", "row": 0, "col": 0}},
          {{"file": "tiles/c.png", "frame": 1, "eye": "left", "row": 0, "col": 0}}
        ]}}"#
    );
    std::fs::write(archive.join("manifest.json"), manifest).unwrap();
}

/// The non-zero counts, by texel.
fn seen(counts: &[u32]) -> Vec<(u32, u32)> {
    counts.iter().enumerate().filter(|&(_, &c)| c > 0).map(|(t, &c)| (t as u32, c)).collect()
}

#[test]
fn a_palette_above_2_24_texels_counts_every_texel_exactly_from_rgba32_tiles() {
    let dir = tempfile::tempdir().unwrap();
    let archive = rgba32_archive(dir.path());
    let options = AnalyzeOptions { archive: archive.clone(), ..Default::default() };
    let mut analysis = analyze(&options, None).unwrap();
    assert_eq!(analysis.texel_counts.len(), TEXELS as usize, "sized to the palette, not to 2^32");
    assert_eq!(seen(&analysis.texel_counts), [(LOW, 3), (7, 1), (HIGH, 2), (LAST, 2)]);
    let result = &analysis.result;
    assert_eq!((result.images.found, result.images.decoded, result.images.failed), (3, 3, 0));
    assert_eq!((result.pixels.texel, result.pixels.background, result.stray_pixels), (12, 11, 1));
    assert_eq!((result.texels_seen, result.max_count, result.grand_total), (4, 3, 8));
    assert_eq!(result.stray_colors, 1);
    assert_eq!(result.images_with_stray_pixels[0].file, "tiles/b.png");
    let parts: Vec<_> = result.parts.iter().map(|p| (p.name.as_str(), p.texels, p.total, p.peak)).collect();
    assert_eq!(parts, [("A", 1 << 24, 4, 3), ("B", 8192, 4, 2)]);
    assert!(result.notes.iter().any(|n| n.contains("rgba32")), "{:?}", result.notes);
    assert_eq!((result.settings.palette.width, result.settings.palette.height), (SIZE[0], SIZE[1]));

    // Per frame (eye-pair): each frame's distinct texels once.
    let per_frame = analyze(&AnalyzeOptions { dedupe: Dedupe::EyePair, ..options.clone() }, None).unwrap();
    assert_eq!(seen(&per_frame.texel_counts), [(LOW, 2), (7, 1), (HIGH, 1), (LAST, 1)]);
    let totals: Vec<u64> = per_frame.result.parts.iter().map(|p| p.total).collect();
    assert_eq!(totals, [3, 2]);

    // The result set is written, and its result.json reads back with every count.
    let out = dir.path().join("results");
    ufcsr::output::write_results(&mut analysis, &out).unwrap();
    let stored = ufcsr::read_texel_counts(&out.join("result.json")).unwrap();
    assert_eq!(seen(&stored.texel_counts), [(LOW, 3), (7, 1), (HIGH, 2), (LAST, 2)]);
    let heatmap = image_size(&out.join("heatmap.png"));
    assert_eq!(heatmap, SIZE, "one heatmap pixel per texel");
}

fn image_size(path: &Path) -> [u32; 2] {
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
    let info = decoder.read_info().unwrap();
    [info.info().width, info.info().height]
}

#[test]
fn rgba32_manifests_that_disagree_or_ask_for_absurd_palettes_are_refused_naming_the_field() {
    let dir = tempfile::tempdir().unwrap();
    let archive = dir.path().join("archive");
    rgba_png(&archive.join("tiles/a.png"), 4, 2, &[LOW; 8]);
    rgba_png(&archive.join("tiles/b.png"), 4, 2, &[LOW; 8]);
    rgba_png(&archive.join("tiles/c.png"), 4, 2, &[LOW; 8]);
    std::fs::write(archive.join("parts.csv"), "name,color\nA,#FF0000\n").unwrap();
    let options = AnalyzeOptions { archive: archive.clone(), ..Default::default() };
    let refusal = |schema: &str, ids: &str, size: [u32; 2]| {
        write_manifest(&archive, schema, ids, size);
        failure(&options)
    };
    let absurd = refusal("ufcsr-manifest/2", r#""texel_ids": "rgba32","#, [65536, 65536]);
    assert!(
        absurd.contains("manifest.json") && absurd.contains("palette") && absurd.contains("2^26"),
        "{absurd}"
    );
    let old = refusal("ufcsr-manifest/1", r#""texel_ids": "rgba32","#, SIZE);
    assert!(old.contains("manifest.json") && old.contains("ufcsr-manifest/2"), "{old}");
    let missing = refusal("ufcsr-manifest/2", "", SIZE);
    assert!(missing.contains("manifest.json") && missing.contains("texel_ids"), "{missing}");
    let too_big_for_24_bits = refusal("ufcsr-manifest/1", "", SIZE);
    assert!(too_big_for_24_bits.contains("2^24"), "{too_big_for_24_bits}");
}

#[test]
fn rgba_tiles_of_a_24_bit_archive_still_name_texels_by_their_rgb() {
    let dir = tempfile::tempdir().unwrap();
    let archive = dir.path().join("archive");
    // Alpha 254 and 0: a 24-bit archive ignores alpha, as it always did.
    rgba_png(&archive.join("a.png"), 2, 1, &[(1 << 24) + 3, 0xFF00_0005]);
    let analysis = analyze(&small_palette_options(&archive), None).unwrap();
    assert_eq!(seen(&analysis.texel_counts), [(3, 1), (5, 1)]);
    assert!(!analysis.result.notes.iter().any(|n| n.contains("rgba32")));
}

#[test]
fn rgba32_shards_merge_to_the_whole_analysis_counts() {
    let dir = tempfile::tempdir().unwrap();
    let archive = rgba32_archive(dir.path());
    let options = AnalyzeOptions { archive, ..Default::default() };
    let whole = analyze(&options, None).unwrap();
    let shards: Vec<PathBuf> = (0..2)
        .map(|index| {
            let shard = Some(ufcsr::Shard::new(index, 2).unwrap());
            let mut analysis = analyze(&AnalyzeOptions { shard, ..options.clone() }, None).unwrap();
            ufcsr::output::write_results(&mut analysis, &dir.path().join(format!("shard{index}")))
                .unwrap()
                .result_json
        })
        .collect();
    let merged = ufcsr::merge_results(&shards).unwrap();
    assert_eq!(seen(&merged.texel_counts), seen(&whole.texel_counts));
    assert_eq!(merged.result.parts, whole.result.parts);
    assert_eq!(merged.result.stray_pixels, 1);
}

/// Copies the bundled example (24-bit RGB tiles) into `dir`, its manifest
/// declaring 32-bit texel ids: RGB tiles are opaque, so every id is the
/// pixel's 24-bit colour.
fn example_as_rgba32(dir: &Path) -> PathBuf {
    let source = Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/example");
    let archive = dir.join("example");
    std::fs::create_dir_all(archive.join("tiles")).unwrap();
    for entry in walk(&source) {
        let relative = entry.strip_prefix(&source).unwrap();
        std::fs::copy(&entry, archive.join(relative)).unwrap();
    }
    let manifest = std::fs::read_to_string(source.join("manifest.json")).unwrap();
    let manifest =
        manifest.replacen("\"ufcsr-manifest/1\"", "\"ufcsr-manifest/2\", \"texel_ids\": \"rgba32\"", 1);
    std::fs::write(archive.join("manifest.json"), manifest).unwrap();
    archive
}

fn walk(dir: &Path) -> Vec<PathBuf> {
    let mut files = Vec::new();
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() { files.extend(walk(&path)) } else { files.push(path) }
    }
    files
}

#[test]
fn the_example_declared_rgba32_counts_as_the_24_bit_kernels_count_it() {
    let dir = tempfile::tempdir().unwrap();
    let example = Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/example");
    let rgba32 = example_as_rgba32(dir.path());
    for dedupe in [Dedupe::Image, Dedupe::Frame, Dedupe::EyePair] {
        let options = |archive: &Path| AnalyzeOptions {
            archive: archive.to_path_buf(),
            dedupe,
            frames: true,
            texel_area: true,
            ..Default::default()
        };
        let reference = analyze(&options(&example), None).unwrap();
        let wide = analyze(&options(&rgba32), None).unwrap();
        assert_eq!(wide.texel_counts, reference.texel_counts, "{dedupe:?}");
        // The per-texel angular area, summed pixel by pixel as the 24-bit path sums it: to the bit.
        assert!(reference.texel_angular_area.is_some());
        assert!(
            wide.texel_angular_area == reference.texel_angular_area,
            "{dedupe:?}: the angular areas differ"
        );
        // frames.csv and the resolution-independent measures, by part and eye-frame.
        assert!(reference.frames.is_some());
        assert!(wide.frames == reference.frames, "{dedupe:?}: frames.csv differs");
        assert!(wide.result.measures == reference.result.measures, "{dedupe:?}: the measures differ");
        let (a, b) = (&wide.result, &reference.result);
        assert_eq!(a.parts, b.parts, "{dedupe:?}");
        assert_eq!((a.pixels.texel, a.stray_pixels), (b.pixels.texel, b.stray_pixels), "{dedupe:?}");
        // The same empty tiles trimmed (verified by their ids here).
        assert!(b.images.trimmed > 0, "the example has empty tiles");
        assert_eq!(a.images, b.images, "{dedupe:?}");
        assert_eq!(a.pixels, b.pixels, "{dedupe:?}");
        assert_eq!(a.settings.trim, b.settings.trim, "{dedupe:?}");
    }
}

/// The fixture's tiles as the renderer's readback holds them: RGBA rows,
/// `(name, frame, eye, ids)` in capture order (a frame's eyes one after
/// the other; `c`'s RGB PNG is opaque, so its alpha is 255).
const TILES: [(&str, u32, &str, [u32; 8]); 3] = [
    ("tiles/a.png", 0, "left", [LOW, LOW, HIGH, BG, LAST, BG, BG, BG]),
    ("tiles/b.png", 0, "right", [HIGH, HIGH, HIGH, LAST, BEYOND, BG, LOW, BG]),
    ("tiles/c.png", 1, "left", [LOW, BG, BG, BG, 7, 7, BG, BG]),
];

/// The fixture with its eyes' optics (8 × 4 pixels of 2 × 2 tiles, 90°, 60
/// fps), so pixels have solid angles: `b` is the lower right tile of its
/// eye, `c` the upper right. Returns each tile's `[row, col]`.
fn with_optics(archive: &Path) -> [[u32; 2]; 3] {
    let manifest = std::fs::read_to_string(archive.join("manifest.json")).unwrap();
    let manifest = manifest
        .replacen(
            r#""tiles": ["#,
            r#""rig": {"settings": {"horizontal_fov_deg": 90, "eye_pixels": [8, 4], "tiles": [2, 2], "fps": 60}},
            "tiles": ["#,
            1,
        )
        .replacen(r#""eye": "right", "row": 0, "col": 0"#, r#""eye": "right", "row": 1, "col": 1"#, 1)
        .replacen(r#""frame": 1, "eye": "left", "row": 0, "col": 0"#, r#""frame": 1, "eye": "left", "row": 0, "col": 1"#, 1);
    std::fs::write(archive.join("manifest.json"), manifest).unwrap();
    [[0, 0], [1, 1], [0, 1]]
}

#[test]
fn tiles_of_32_bit_ids_counted_in_memory_give_what_their_png_tiles_give() {
    let dir = tempfile::tempdir().unwrap();
    let archive = rgba32_archive(dir.path());
    let places = with_optics(&archive);
    let palette = ufcsr::Fcsp::canonical_rgba32(SIZE).unwrap();
    let legend = ufcsr::Legend::load(&archive.join("parts.csv")).unwrap();
    let pidt = ufcsr::Pidt::load(&archive.join("pidt.png"), &legend, SIZE).unwrap();
    // Each eye-frame is one tile here, so `image` counts as `frame` does.
    for dedupe in [Dedupe::Frame, Dedupe::EyePair] {
        let background = [ufcsr::Color::from_packed(BG)];
        let mut counter = ufcsr::TileCounter::new(&palette, &background, dedupe).unwrap();
        assert!(counter.counts_rgba32());
        let lookup = ufcsr::PartLookup::new(&palette, Some((&legend, &pidt)), &[BG]);
        counter.tally_parts(lookup, ufcsr::EyeProjection::new(90.0, [8, 4]));
        for ((name, frame, eye, ids), [row, col]) in TILES.into_iter().zip(places) {
            let rgba: Vec<u8> = ids.iter().flat_map(|&id| rgba32_pixel(id)).collect();
            let tile = ufcsr::CountedTile { name, frame, eye, size: [4, 2], origin: [col * 4, row * 2] };
            counter.count_tile(&tile, &rgba).unwrap();
        }
        // One shard of one, so both keep the per-texel solid-angle units
        // (eye-pair dedupe is not sharded; the units do not depend on it).
        let shard = (dedupe == Dedupe::Frame).then(|| ufcsr::Shard::new(0, 1).unwrap());
        let options = AnalyzeOptions {
            archive: archive.clone(),
            dedupe,
            trim: ufcsr::TrimMode::Off,
            frames: true,
            texel_area: true,
            shard,
            ..Default::default()
        };
        let counted = ufcsr::analyze_counted(&options, counter).unwrap();
        let png = analyze(&options, None).unwrap();
        // The PNG test's known answers, per eye-frame and per frame.
        let known: &[(u32, u32)] = match dedupe {
            Dedupe::EyePair => &[(LOW, 2), (7, 1), (HIGH, 1), (LAST, 1)],
            _ => &[(LOW, 3), (7, 1), (HIGH, 2), (LAST, 2)],
        };
        assert_eq!(seen(&counted.texel_counts), known, "{dedupe:?}");
        assert!(counted.texel_counts == png.texel_counts, "{dedupe:?}");
        assert!(counted.frames.is_some() && counted.frames == png.frames, "{dedupe:?}: frames.csv differs");
        // The per-texel solid angles: the same integers, for every texel seen.
        assert!(counted.texel_angular_area.is_some() && counted.texel_angular_area == png.texel_angular_area);
        if shard.is_some() {
            let units =
                |analysis: &ufcsr::Analysis| analysis.texel_area_units.as_ref().unwrap().units.clone();
            let (counted_units, png_units) = (units(&counted), units(&png));
            assert!(counted_units == png_units, "the solid-angle units differ");
            assert!([LOW, 7, HIGH, LAST].iter().all(|&t| png_units[t as usize] > 0));
        }
        // All of result.json: pixels, the stray, parts, measures, notes.
        assert_eq!(counted.result, png.result, "{dedupe:?}");
    }
}

#[test]
fn tiles_counted_as_24_bit_colours_are_refused_for_an_rgba32_manifest() {
    let dir = tempfile::tempdir().unwrap();
    let archive = rgba32_archive(dir.path());
    // A 4096² palette's counter counts 24-bit colours.
    let palette = ufcsr::Fcsp::canonical([4096, 4096]).unwrap();
    let counter = ufcsr::TileCounter::new(&palette, &[ufcsr::Color::from_packed(BG)], Dedupe::Image).unwrap();
    assert!(!counter.counts_rgba32());
    let options = AnalyzeOptions { archive, ..Default::default() };
    let error = ufcsr::analyze_counted(&options, counter).err().expect("refused").to_string();
    assert!(error.contains("manifest.json") && error.contains("rgba32"), "{error}");
}

/// Tiles beside the fixture's: `d` and `e` empty RGBA 4×2 tiles (the
/// background, opaque: the same bytes), `f` and `g` 8×2 tiles of the texel
/// 2^24 above the background colour (its RGB, alpha 254: no background,
/// though its RGB is), also the same bytes. Frames 1 right, 2 left and
/// right, 3 left.
fn with_empty_tiles(archive: &Path) {
    let above_bg = BG + (1 << 24);
    let more = [
        ("tiles/d.png", 1, "right", BG, 4),
        ("tiles/e.png", 2, "left", BG, 4),
        ("tiles/f.png", 2, "right", above_bg, 8),
        ("tiles/g.png", 3, "left", above_bg, 8),
    ];
    let entry = |file: &str, frame: u32, eye: &str| {
        format!(r#"{{"file": "{file}", "frame": {frame}, "eye": "{eye}", "row": 0, "col": 0}}"#)
    };
    let mut entries: Vec<String> =
        TILES.iter().map(|&(file, frame, eye, _)| entry(file, frame, eye)).collect();
    for (file, frame, eye, id, width) in more {
        rgba_png(&archive.join(file), width, 2, &vec![id; width as usize * 2]);
        entries.push(entry(file, frame, eye));
    }
    let manifest = format!(
        r#"{{"schema": "ufcsr-manifest/2", "texel_ids": "rgba32",
        "palette": {{"canonical": [{}, {}]}}, "pidt": "pidt.png", "parts": "parts.csv",
        "tiles": [{}]}}"#,
        SIZE[0],
        SIZE[1],
        entries.join(", ")
    );
    std::fs::write(archive.join("manifest.json"), manifest).unwrap();
}

#[test]
fn empty_rgba32_tiles_are_trimmed_and_tiles_that_differ_from_the_background_only_by_alpha_are_not() {
    let dir = tempfile::tempdir().unwrap();
    let archive = rgba32_archive(dir.path());
    with_empty_tiles(&archive);
    let under_bg = BG + (1 << 24);
    let options = AnalyzeOptions { archive, dedupe: Dedupe::Frame, frames: true, ..Default::default() };
    let trimmed = analyze(&options, None).unwrap();
    let whole = analyze(&AnalyzeOptions { trim: ufcsr::TrimMode::Off, ..options.clone() }, None).unwrap();
    let images = &trimmed.result.images;
    assert_eq!((images.found, images.decoded, images.trimmed), (7, 5, 2), "d and e trimmed");
    let empty = &trimmed.result.settings.trim.empty_tiles;
    let verified: Vec<(&str, bool)> = empty.iter().map(|e| (e.reference.as_str(), e.verified)).collect();
    assert_eq!(verified, [("tiles/d.png", true), ("tiles/f.png", false)], "f (alpha 254) is no background");
    // The same counts as decoding every tile: f and g's texel twice (every
    // tile is an eye-frame of its own).
    assert!(trimmed.texel_counts == whole.texel_counts);
    assert_eq!(seen(&trimmed.texel_counts), [(LOW, 3), (7, 1), (HIGH, 2), (under_bg, 2), (LAST, 2)]);
    assert!(trimmed.frames.is_some() && trimmed.frames == whole.frames, "frames.csv differs");
    let (a, b) = (&trimmed.result, &whole.result);
    assert_eq!((&a.parts, a.pixels.texel, a.stray_pixels), (&b.parts, b.pixels.texel, b.stray_pixels));
    assert_eq!(a.pixels.background + 16, b.pixels.background, "two trimmed tiles of 8 pixels");
    assert_eq!(a.pixels.texel, 12 + 32, "f and g decoded");
}
