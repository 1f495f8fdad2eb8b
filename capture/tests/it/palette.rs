//! External palettes (read with `textureLoad`): the canonical palette as an
//! image renders exactly like the computed one, and a shuffled palette gives
//! an archive whose pixels still all name labelled texels.

use std::path::Path;

use ufcsr::files::write_rgb_png;
use ufcsr::{Color, Fcsp, Manifest, PaletteRecord};
use ufcsr_capture::{Backend, CaptureOptions, FrameSelection, Gpu, Scene, capture, read_rgb_png, verify};

fn demo_capture(gpu: &Gpu, out: &Path, palette_file: Option<&Path>) {
    let mut scene = Scene::demo();
    scene.rig.set_pixels_per_degree(3.0).unwrap();
    let options = CaptureOptions {
        out: out.to_path_buf(),
        palette: [256, 256],
        palette_file: palette_file.map(Path::to_path_buf),
        frames: "120-180/20".parse::<FrameSelection>().unwrap(),
        ..CaptureOptions::default()
    };
    let scenario = scene.scenario("D").unwrap().clone();
    capture(&gpu.device, &gpu.queue, &scene, &scenario, &options).unwrap();
}

#[test]
fn external_palettes_render_through_texture_load() {
    let gpu = Gpu::create(Backend::Auto).unwrap_or_else(|e| panic!("GPU tests need an adapter: {e}"));
    let dir = tempfile::tempdir().unwrap();

    // The canonical palette as an image: same tiles, byte for byte.
    let canonical = Fcsp::canonical([256, 256]).unwrap();
    let image = dir.path().join("canonical.png");
    write_rgb_png(&image, [256, 256], &canonical.texel_rgb(), png::Compression::Fast).unwrap();
    demo_capture(&gpu, &dir.path().join("computed"), None);
    demo_capture(&gpu, &dir.path().join("loaded"), Some(&image));
    let manifest = Manifest::load_from_dir(&dir.path().join("computed")).unwrap().unwrap();
    let mut compared = 0;
    for tile in manifest.tiles.iter().filter_map(|t| t.file.as_ref()) {
        let a = read_rgb_png(&dir.path().join("computed").join(tile)).unwrap();
        let b = read_rgb_png(&dir.path().join("loaded").join(tile)).unwrap();
        assert!(a == b, "{} differs", tile.display());
        compared += 1;
    }
    assert!(compared > 0);

    // A shuffled palette (a fixed permutation of the canonical colours).
    let mut colors: Vec<u32> = (0..256 * 256).collect();
    let mut state = 0x2545_f491_u64;
    for i in (1..colors.len()).rev() {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        colors.swap(i, (state % (i as u64 + 1)) as usize);
    }
    let rgb: Vec<u8> = colors.iter().flat_map(|&c| Color::from_packed(c).rgb()).collect();
    let shuffled = dir.path().join("shuffled.png");
    write_rgb_png(&shuffled, [256, 256], &rgb, png::Compression::Fast).unwrap();
    let out = dir.path().join("shuffled");
    demo_capture(&gpu, &out, Some(&shuffled));
    let manifest = Manifest::load_from_dir(&out).unwrap().unwrap();
    assert_eq!(manifest.palette, Some(PaletteRecord::File("palette.png".into())));
    let (vehicle, stray) = verify(&out).unwrap();
    assert_eq!(stray, 0);
    assert!(vehicle > 1000, "{vehicle}");
    // The background colour's texel is never part of an island.
    let palette = Fcsp::from_png(&out.join("palette.png")).unwrap();
    let texel = palette.texel_of(Color::DEFAULT_BACKGROUND.packed()).unwrap();
    let (_, pidt) = read_rgb_png(&out.join("pidt.png")).unwrap();
    assert_eq!(&pidt[texel * 3..texel * 3 + 3], &[0, 0, 0]);
}
