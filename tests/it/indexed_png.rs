//! Indexed (palette) PNGs: valid ones count like RGB; an index beyond the
//! PLTE's entries is corrupt data and fails the file (reported, the batch
//! goes on), instead of decoding as black and counting texel 0.

use crate::common;

use std::path::Path;

/// An indexed PNG of `width`×`height` with `palette` entries (RGB) and
/// `indices` at `depth` bits per pixel.
fn indexed_png(path: &Path, width: u32, height: u32, depth: png::BitDepth, palette: &[u32], indices: &[u8]) {
    std::fs::create_dir_all(path.parent().unwrap()).unwrap();
    let file = std::fs::File::create(path).unwrap();
    let mut encoder = png::Encoder::new(std::io::BufWriter::new(file), width, height);
    encoder.set_color(png::ColorType::Indexed);
    encoder.set_depth(depth);
    encoder.set_palette(
        palette.iter().flat_map(|c| [(c >> 16) as u8, (c >> 8) as u8, *c as u8]).collect::<Vec<_>>(),
    );
    let bits = depth as usize;
    let line = (width as usize * bits).div_ceil(8);
    let mut data = vec![0u8; line * height as usize];
    for (i, &index) in indices.iter().enumerate() {
        let (y, x) = (i / width as usize, i % width as usize);
        let bit = x * bits;
        data[y * line + bit / 8] |= index << (8 - bits - bit % 8);
    }
    let mut writer = encoder.write_header().unwrap();
    writer.write_image_data(&data).unwrap();
}

#[test]
fn an_index_beyond_the_palette_fails_the_file_and_valid_indexed_tiles_count() {
    let dir = tempfile::tempdir().unwrap();
    let archive = common::known_archive(dir.path());
    // Valid, 4 bits per pixel: texels 1 and 2 and the background.
    indexed_png(&archive.join("e.png"), 3, 1, png::BitDepth::Four, &[1, 2, common::BG], &[0, 1, 2]);
    // Corrupt: index 5 of a 3-entry palette (would decode as black = texel 0).
    indexed_png(&archive.join("f.png"), 2, 1, png::BitDepth::Eight, &[1, 2, 3], &[0, 5]);
    let options = common::known_options(dir.path());
    let analysis = ufcsr::analyze(&options, None).expect("the batch goes on");
    let result = &analysis.result;
    assert_eq!(result.images.failed, 1);
    let failure = &result.failures[0];
    assert!(failure.file.ends_with("f.png"), "{failure:?}");
    assert!(
        failure.error.contains("palette index 5") && failure.error.contains("3 entries"),
        "{}",
        failure.error
    );
    // The known archive's counts (t1 = 2, t2 = 2) plus e.png's texels 1 and 2; texel 0 never.
    assert_eq!(analysis.texel_counts[0], 0);
    assert_eq!(analysis.texel_counts[1], 3);
    assert_eq!(analysis.texel_counts[2], 3);
}
