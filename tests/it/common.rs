//! Helpers shared by the integration tests: writing small PNGs of every
//! flavour (RGB, RGBA, grey, indexed, 16-bit, interlaced) and building
//! hand-computable archives.

#![allow(dead_code)] // each test module uses its own part

use std::io::Write;
use std::path::{Path, PathBuf};

/// The default background, packed.
pub const BG: u32 = 0x000FFF;

/// Packed colours → RGB bytes.
pub fn rgb_bytes(colors: &[u32]) -> Vec<u8> {
    colors.iter().flat_map(|&c| [(c >> 16) as u8, (c >> 8) as u8, c as u8]).collect()
}

/// Writes a PNG with the given format.
pub fn write_png(
    path: &Path,
    width: u32,
    height: u32,
    color: png::ColorType,
    depth: png::BitDepth,
    data: &[u8],
    palette: Option<&[u8]>,
) {
    if let Some(parent) = path.parent() {
        std::fs::create_dir_all(parent).unwrap();
    }
    let file = std::fs::File::create(path).unwrap();
    let mut encoder = png::Encoder::new(std::io::BufWriter::new(file), width, height);
    encoder.set_color(color);
    encoder.set_depth(depth);
    if let Some(palette) = palette {
        encoder.set_palette(palette.to_vec());
    }
    let mut writer = encoder.write_header().unwrap();
    writer.write_image_data(data).unwrap();
    writer.finish().unwrap();
}

/// Writes an 8-bit RGB PNG of packed colours.
pub fn rgb_png(path: &Path, width: u32, height: u32, colors: &[u32]) {
    assert_eq!(colors.len(), (width * height) as usize);
    write_png(path, width, height, png::ColorType::Rgb, png::BitDepth::Eight, &rgb_bytes(colors), None);
}

/// Writes an Adam7-interlaced 8-bit RGB PNG by hand (the png crate's encoder
/// does not interlace).
pub fn interlaced_rgb_png(path: &Path, width: u32, height: u32, colors: &[u32]) {
    const PASSES: [(u32, u32, u32, u32); 7] =
        [(0, 0, 8, 8), (4, 0, 8, 8), (0, 4, 4, 8), (2, 0, 4, 4), (0, 2, 2, 4), (1, 0, 2, 2), (0, 1, 1, 2)];
    let mut raw = Vec::new();
    for (x0, y0, dx, dy) in PASSES {
        let columns: Vec<u32> = (x0..width).step_by(dx as usize).collect();
        let rows: Vec<u32> = (y0..height).step_by(dy as usize).collect();
        if columns.is_empty() || rows.is_empty() {
            continue;
        }
        for &y in &rows {
            raw.push(0u8); // filter: none
            for &x in &columns {
                raw.extend(rgb_bytes(&[colors[(y * width + x) as usize]]));
            }
        }
    }
    png_from_filtered_rows(path, width, height, &raw, 1, flate2::Compression::default());
}

/// Writes an 8-bit RGB PNG from filtered scanlines (`raw`), deflated at
/// `level`; `interlace` 1 is Adam7.
pub fn png_from_filtered_rows(
    path: &Path,
    width: u32,
    height: u32,
    raw: &[u8],
    interlace: u8,
    level: flate2::Compression,
) {
    let mut zlib = flate2::write::ZlibEncoder::new(Vec::new(), level);
    zlib.write_all(raw).unwrap();
    let compressed = zlib.finish().unwrap();
    let mut header = Vec::new();
    header.extend(width.to_be_bytes());
    header.extend(height.to_be_bytes());
    header.extend([8, 2, 0, 0, interlace]); // 8-bit RGB, deflate, adaptive filtering
    let png = png_from_chunks(&[(b"IHDR", &header), (b"IDAT", &compressed), (b"IEND", &[])]);
    std::fs::write(path, png).unwrap();
}

/// A PNG file's bytes: the signature, then each `(type, body)` chunk with its
/// length and CRC (for tests that build damaged or unusual PNGs by hand).
pub use ufcsr::synthetic::png_from_chunks;

/// Analysis options for the hand-made 4×4-palette archives of the
/// bad-input tests: canonical palette, no trimming.
pub fn small_palette_options(archive: &Path) -> ufcsr::AnalyzeOptions {
    ufcsr::AnalyzeOptions {
        archive: archive.to_path_buf(),
        palette: Some(ufcsr::PaletteChoice::Canonical { width: 4, height: 4 }),
        trim: ufcsr::TrimMode::Off,
        ..Default::default()
    }
}

/// The hand-computable archive used by the known-answer tests.
///
/// Canonical 4×4 palette (texel index = colour), background #000FFF:
/// - `a.png` = [1, 1, 2, bg]          → texels 1, 2 (1 counted once)
/// - `b.png` = [2, 3, 3, 3]           → texels 2, 3
/// - `c.png`, `c2.png` = all bg       → identical bytes: trimmed
/// - `d.png` = [1, #FFFFFF, bg, 5]    → texels 1, 5; one stray pixel
///
/// Counts: t1 = 2, t2 = 2, t3 = 1, t5 = 1, all others 0.
/// PIdT: row 0 (t0–t3) part A #FF0000, row 1 (t4–t7) part B #00FF00,
/// rows 2–3 #0A0000 (unlabelled); legend C #0000FF has no texels.
pub fn known_archive(dir: &Path) -> PathBuf {
    let archive = dir.join("archive");
    rgb_png(&archive.join("a.png"), 2, 2, &[1, 1, 2, BG]);
    rgb_png(&archive.join("b.png"), 2, 2, &[2, 3, 3, 3]);
    rgb_png(&archive.join("c.png"), 2, 2, &[BG; 4]);
    rgb_png(&archive.join("sub/c2.png"), 2, 2, &[BG; 4]);
    rgb_png(&archive.join("d.png"), 2, 2, &[1, 0xFFFFFF, BG, 5]);
    let mut pidt = vec![0xFF0000; 4];
    pidt.extend([0x00FF00; 4]);
    pidt.extend([0x0A0000; 8]);
    rgb_png(&dir.join("pidt.png"), 4, 4, &pidt);
    std::fs::write(dir.join("parts.csv"), "name,color\nA,#FF0000\nB,#00FF00\nC,#0000FF\n").unwrap();
    archive
}

/// Options for the known archive.
pub fn known_options(dir: &Path) -> ufcsr::AnalyzeOptions {
    ufcsr::AnalyzeOptions {
        archive: dir.join("archive"),
        palette: Some(ufcsr::PaletteChoice::Canonical { width: 4, height: 4 }),
        pidt: Some(dir.join("pidt.png")),
        legend: Some(dir.join("parts.csv")),
        ..Default::default()
    }
}

/// The error message of an analysis that must fail.
pub fn failure(options: &ufcsr::AnalyzeOptions) -> String {
    match ufcsr::analyze(options, None) {
        Ok(_) => panic!("expected the analysis of {} to fail", options.archive.display()),
        Err(error) => error.to_string(),
    }
}
