//! Trimming safety: only files byte-identical to a verified all-background
//! tile are skipped; everything else is decoded, whatever its size.

use crate::common;

use common::*;
use ufcsr::{AnalyzeOptions, PaletteChoice, TrimMode, analyze};

fn options(archive: &std::path::Path, trim: TrimMode) -> AnalyzeOptions {
    AnalyzeOptions {
        archive: archive.to_path_buf(),
        palette: Some(PaletteChoice::Canonical { width: 64, height: 64 }),
        trim,
        ..Default::default()
    }
}

#[test]
fn auto_trims_verified_empty_tiles_only() {
    let dir = tempfile::tempdir().unwrap();
    for k in 0..5 {
        rgb_png(&dir.path().join(format!("empty{k}.png")), 16, 16, &[BG; 256]);
    }
    // Same size as the empty tiles but one pixel shows texel 7: same byte
    // count is possible, bytes differ, so it must be decoded.
    let mut sliver = vec![BG; 256];
    sliver[255] = 7;
    rgb_png(&dir.path().join("sliver.png"), 16, 16, &sliver);
    // Two identical non-empty tiles share a size: verification must refuse.
    rgb_png(&dir.path().join("twin1.png"), 4, 4, &[9; 16]);
    rgb_png(&dir.path().join("twin2.png"), 4, 4, &[9; 16]);

    let analysis = analyze(&options(dir.path(), TrimMode::Auto), None).unwrap();
    let images = &analysis.result.images;
    assert_eq!((images.found, images.trimmed, images.decoded), (8, 5, 3));
    assert_eq!(analysis.texel_counts[7], 1);
    assert_eq!(analysis.texel_counts[9], 2);
    let empty = &analysis.result.settings.trim.empty_tiles;
    let verified: Vec<_> = empty.iter().filter(|e| e.verified).collect();
    assert_eq!(verified.len(), 1);
    assert_eq!((verified[0].width, verified[0].height, verified[0].candidates), (16, 16, 5));
    assert!(empty.iter().any(|e| !e.verified && e.width == 4), "twins were a candidate but not verified");
}

#[test]
fn a_byte_threshold_never_loses_small_tiles_with_content() {
    let dir = tempfile::tempdir().unwrap();
    rgb_png(&dir.path().join("empty0.png"), 16, 16, &[BG; 256]);
    rgb_png(&dir.path().join("empty1.png"), 16, 16, &[BG; 256]);
    let mut sliver = vec![BG; 256];
    sliver[0] = 3;
    rgb_png(&dir.path().join("sliver.png"), 16, 16, &sliver);
    // A threshold far above every file size: all are candidates.
    let analysis = analyze(&options(dir.path(), TrimMode::Bytes(1_000_000)), None).unwrap();
    assert_eq!(analysis.texel_counts[3], 1, "the sliver below the threshold was decoded");
    assert_eq!((analysis.result.images.trimmed, analysis.result.images.decoded), (2, 1));

    let off = analyze(&options(dir.path(), TrimMode::Off), None).unwrap();
    assert_eq!((off.result.images.trimmed, off.result.images.decoded), (0, 3));
    assert_eq!(off.texel_counts, analysis.texel_counts, "trimming never changes counts");
}

#[test]
fn empty_tiles_with_stray_pixels_are_not_trimmed() {
    let dir = tempfile::tempdir().unwrap();
    let mut damaged = vec![BG; 64];
    damaged[10] = 0xFEFEFE; // not a palette colour of a 64×64 palette
    rgb_png(&dir.path().join("a.png"), 8, 8, &damaged);
    rgb_png(&dir.path().join("b.png"), 8, 8, &damaged);
    let analysis = analyze(&options(dir.path(), TrimMode::Auto), None).unwrap();
    assert_eq!(analysis.result.images.trimmed, 0);
    assert_eq!(analysis.result.stray_pixels, 2, "stray pixels are counted, not trimmed away");
}
