//! The glTF files of an archive (issue 20): `vehicle.glb` stands upright in
//! glTF's axes with the palette as its texture and reads back into the
//! vehicle frame (by the analyzer and by the capture's own mesh loader), and
//! `scene.glb` holds every occluder of the scene at its world place, one
//! node per occluder named after it; the manifest names both.

use std::path::Path;
use std::process::Command;

use ufcsr_capture::{Scene, load_vehicle, scene::Axes, scene::PartSource};

/// A quick demo capture (`--count`: no tiles written) into `out`.
fn demo_archive(out: &Path) {
    let output = Command::new(env!("CARGO_BIN_EXE_ufcsr-capture"))
        .args(["demo", "--scenario", "A", "--ppd", "3", "--palette-size", "256", "--frames", "0-180/90"])
        .args(["--count", "-q", "--out"])
        .arg(out)
        .output()
        .unwrap();
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
}

/// Each node's world bounds: accessor min/max moved by its translation
/// (ufcsr writes no rotation or scale).
fn node_bounds(gltf: &gltf::Gltf) -> Vec<(String, [f64; 3], [f64; 3])> {
    gltf.document
        .nodes()
        .map(|node| {
            let (translation, rotation, scale) = node.transform().decomposed();
            assert_eq!((rotation, scale), ([0.0, 0.0, 0.0, 1.0], [1.0; 3]));
            let bounds = node.mesh().unwrap().primitives().next().unwrap().bounding_box();
            let at = |k: usize, v: [f32; 3]| f64::from(v[k]) + f64::from(translation[k]);
            let min = [0, 1, 2].map(|k| at(k, bounds.min));
            let max = [0, 1, 2].map(|k| at(k, bounds.max));
            (node.name().unwrap_or("").to_string(), min, max)
        })
        .collect()
}

fn close(a: [f64; 3], b: [f64; 3], tolerance: f64) -> bool {
    a.iter().zip(b).all(|(a, b)| (a - b).abs() <= tolerance)
}

#[test]
fn the_demo_truck_stands_upright_in_vehicle_glb_with_the_palette_on_it_and_reads_back_exactly() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("archive");
    demo_archive(&out);
    let path = out.join("vehicle.glb");
    let gltf = gltf::Gltf::open(&path).unwrap();
    // glTF axes: x = the truck's left (±1.24 m), y = up (0..1.90 m), z = forward (−2.95..2.97 m).
    let nodes = node_bounds(&gltf);
    let min = nodes.iter().fold([f64::MAX; 3], |m, n| [0, 1, 2].map(|k| m[k].min(n.1[k])));
    let max = nodes.iter().fold([f64::MIN; 3], |m, n| [0, 1, 2].map(|k| m[k].max(n.2[k])));
    assert!(close(min, [-1.24, 0.0, -2.95], 1e-6) && close(max, [1.24, 1.90, 2.97], 1e-6), "{min:?} {max:?}");
    // Every primitive is textured with the palette: texel (x, y) has colour y·W + x.
    for primitive in gltf.document.meshes().flat_map(|m| m.primitives()) {
        let texture = primitive.material().pbr_metallic_roughness().base_color_texture();
        assert_eq!(texture.map(|t| t.texture().index()), Some(0), "a primitive without the palette");
    }
    let gltf::image::Source::View { view, .. } = gltf.document.images().next().unwrap().source() else {
        panic!("the palette is embedded")
    };
    let blob = gltf.blob.as_ref().unwrap();
    let png = &blob[view.offset()..view.offset() + view.length()];
    let mut reader = png::Decoder::new(std::io::Cursor::new(png)).read_info().unwrap();
    let mut rgb = vec![0; reader.output_buffer_size().unwrap()];
    reader.next_frame(&mut rgb).unwrap();
    assert_eq!((reader.info().width, reader.info().height), (256, 256));
    let texel = |x: usize, y: usize| &rgb[(y * 256 + x) * 3..(y * 256 + x) * 3 + 3];
    assert_eq!((texel(0, 0), texel(255, 0), texel(3, 2)), (&[0, 0, 0][..], &[0, 0, 255][..], &[0, 2, 3][..]));
    // Read back by the analyzer: the vehicle frame, z up.
    let model = ufcsr::VehicleModel::read(&path).unwrap();
    let points: Vec<[f32; 3]> = model.parts.iter().flat_map(|p| p.positions.iter().copied()).collect();
    let lo = [0, 1, 2].map(|k| points.iter().map(|p| f64::from(p[k])).fold(f64::MAX, f64::min));
    let hi = [0, 1, 2].map(|k| points.iter().map(|p| f64::from(p[k])).fold(f64::MIN, f64::max));
    assert!(close(lo, [-2.95, -1.24, 0.0], 1e-6) && close(hi, [2.97, 1.24, 1.90], 1e-6), "{lo:?} {hi:?}");
    // Read back by the capture with the default (glTF) axes: the truck exactly,
    // the axis map being a permutation.
    let mesh = load_vehicle(&path, PartSource::Node, &Axes::default()).unwrap();
    let demo = Scene::demo().vehicle;
    assert_eq!(mesh.bounds(), demo.bounds());
    assert_eq!(mesh.triangles.len(), demo.triangles.len());
    let mut parts = mesh.parts.clone();
    let mut expected = demo.parts.clone();
    parts.sort();
    expected.sort();
    assert_eq!(parts, expected);
}

#[test]
fn scene_glb_has_every_occluder_of_the_demo_at_its_world_place_by_name_and_the_manifest_names_it() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("archive");
    demo_archive(&out);
    let gltf = gltf::Gltf::open(out.join("scene.glb")).unwrap();
    let nodes = node_bounds(&gltf);
    let names: Vec<&str> = nodes.iter().map(|n| n.0.as_str()).collect();
    let mut expected = vec!["ground".to_string()];
    expected.extend((1..=16).map(|k| format!("building {k}")));
    assert_eq!(names, expected);
    // World (x, y, z) is glTF (y, z, x): each node's bounds are its occluder's box.
    let occluders = Scene::demo().occluders;
    assert_eq!(occluders.objects.len(), 17);
    for ((name, min, max), object) in nodes.iter().zip(&occluders.objects) {
        let world = |p: [f64; 3]| [p[2], p[0], p[1]];
        assert!(close(world(*min), object.min.to_array(), 1e-4), "{name}: {min:?} vs {:?}", object.min);
        assert!(close(world(*max), object.max.to_array(), 1e-4), "{name}: {max:?} vs {:?}", object.max);
    }
    // The ground: 400 m square at height 0; the first corner block (−27..−7.5 m both ways) 10 m tall.
    assert!(close(nodes[0].1, [-200.0, 0.0, -200.0], 1e-4) && close(nodes[0].2, [200.0, 0.0, 200.0], 1e-4));
    assert!(close(nodes[1].1, [-27.0, 0.0, -27.0], 1e-4) && close(nodes[1].2, [-7.5, 10.0, -7.5], 1e-4));
    let manifest: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("manifest.json")).unwrap()).unwrap();
    assert_eq!(
        (manifest["vehicle"].as_str(), manifest["occluders"].as_str()),
        (Some("vehicle.glb"), Some("scene.glb"))
    );
}
