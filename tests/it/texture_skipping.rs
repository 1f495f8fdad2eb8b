//! A folder without a manifest: PNGs that are not frames (a palette or PIdT
//! kept beside the tiles, as a Unity project does, or the PIdTs of archives
//! in sub-folders) are left out, counted and named in a warning, instead of
//! being counted as frames.

use crate::common;

use ufcsr::{Shard, analyze, merge_results, output::write_results};

#[test]
fn a_palette_sized_png_beside_the_tiles_is_left_out_and_reported() {
    let dir = tempfile::tempdir().unwrap();
    let archive = common::known_archive(dir.path());
    let options = common::known_options(dir.path());
    let plain = analyze(&options, None).unwrap();
    // The 4×4 palette, saved in the tile folder.
    common::rgb_png(&archive.join("unity/palette.png"), 4, 4, &(0..16).collect::<Vec<u32>>());
    let with_texture = analyze(&options, None).unwrap();
    assert_eq!(with_texture.texel_counts, plain.texel_counts, "the palette was counted as a frame");
    assert_eq!(with_texture.result.images.skipped, 1);
    assert_eq!(with_texture.result.images.found, plain.result.images.found);
    assert!(
        with_texture
            .result
            .warnings
            .iter()
            .any(|w| w.contains("unity/palette.png") && w.contains("not frames")),
        "{:?}",
        with_texture.result.warnings
    );

    // Shards merge to the same bytes, warning included.
    let whole = dir.path().join("whole");
    let mut analysis = with_texture;
    write_results(&mut analysis, &whole).unwrap();
    let shards: Vec<_> = (0..2)
        .map(|index| {
            let options =
                ufcsr::AnalyzeOptions { shard: Some(Shard::new(index, 2).unwrap()), ..options.clone() };
            let out = dir.path().join(format!("shard{index}"));
            write_results(&mut analyze(&options, None).unwrap(), &out).unwrap().result_json
        })
        .collect();
    let merged_out = dir.path().join("merged");
    write_results(&mut merge_results(&shards).unwrap(), &merged_out).unwrap();
    assert!(
        std::fs::read(whole.join("result.json")).unwrap()
            == std::fs::read(merged_out.join("result.json")).unwrap()
    );
}

#[test]
fn the_pidt_a_manifest_below_names_is_not_a_frame_and_a_folder_of_big_tiles_is_counted() {
    let dir = tempfile::tempdir().unwrap();
    let archive = common::known_archive(dir.path());
    let options = common::known_options(dir.path());
    let plain = analyze(&options, None).unwrap();
    // A sub-archive whose manifest names its own 2×2 PIdT (the tiles' size).
    let sub = archive.join("capture-2");
    common::rgb_png(&sub.join("labels.png"), 2, 2, &[0xFF0000; 4]);
    std::fs::write(
        sub.join("manifest.json"),
        r#"{"schema": "ufcsr-manifest/1", "pidt": "labels.png", "parts": "parts.csv", "tiles": []}"#,
    )
    .unwrap();
    let analysis = analyze(&options, None).unwrap();
    assert_eq!(analysis.texel_counts, plain.texel_counts);
    assert_eq!(analysis.result.images.skipped, 1);

    // Nothing but palette-sized PNGs: they are the frames.
    let only = dir.path().join("only");
    common::rgb_png(&only.join("a.png"), 4, 4, &[1; 16]);
    let options = ufcsr::AnalyzeOptions { archive: only, ..common::known_options(dir.path()) };
    let analysis = analyze(&options, None).unwrap();
    assert_eq!(analysis.result.images.decoded, 1);
    assert_eq!(analysis.result.images.skipped, 0);
}
