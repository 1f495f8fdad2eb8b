//! A researcher's own model, labelled their own way: a glTF written here
//! whose UVs overlap (two doors mirrored onto the same texels, a duplicate
//! face) and a part-map texture painted over those UVs. Known answers:
//! `inspect` takes the parts from the texture (not from the one node name
//! the file has), and without the part map says where the own UVs overlap,
//! by parts and triangles, telling the duplicate face apart.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use crate::common::rgb_png;

/// `data:` URI of bytes (base64).
fn data_uri(bytes: &[u8]) -> String {
    const TABLE: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut text = String::from("data:application/octet-stream;base64,");
    for chunk in bytes.chunks(3) {
        let n = chunk.iter().enumerate().fold(0u32, |n, (i, b)| n | u32::from(*b) << (16 - 8 * i));
        for k in 0..4 {
            if k <= chunk.len() {
                text.push(TABLE[(n >> (18 - 6 * k) & 63) as usize] as char);
            } else {
                text.push('=');
            }
        }
    }
    text
}

/// A triangle's corners and their own UVs.
type UvTriangle = ([[f32; 3]; 3], [[f32; 2]; 3]);

/// A glTF of one node "body": triangles with their own UVs (glTF axes: +Y up, front +Z).
fn write_gltf(path: &Path, triangles: &[UvTriangle]) {
    let mut bytes: Vec<u8> =
        triangles.iter().flat_map(|(p, _)| p.iter().flatten()).flat_map(|v| v.to_le_bytes()).collect();
    let uv_offset = bytes.len();
    bytes.extend(triangles.iter().flat_map(|(_, uv)| uv.iter().flatten()).flat_map(|v| v.to_le_bytes()));
    let count = triangles.len() * 3;
    let (min, max) =
        triangles.iter().flat_map(|(p, _)| p.iter()).fold(([f32::MAX; 3], [f32::MIN; 3]), |(lo, hi), p| {
            ([0, 1, 2].map(|k| lo[k].min(p[k])), [0, 1, 2].map(|k| hi[k].max(p[k])))
        });
    let gltf = serde_json::json!({
        "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0, "name": "body"}],
        "meshes": [{"name": "body", "primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}}]}],
        "buffers": [{"uri": data_uri(&bytes), "byteLength": bytes.len()}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": uv_offset},
            {"buffer": 0, "byteOffset": uv_offset, "byteLength": bytes.len() - uv_offset}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": count, "type": "VEC3", "min": min, "max": max},
            {"bufferView": 1, "componentType": 5126, "count": count, "type": "VEC2"}]
    });
    std::fs::write(path, serde_json::to_vec(&gltf).unwrap()).unwrap();
}

/// A 4 m × 1.5 m "vehicle side" as two quads (front door, rear door), the
/// rear door's UVs mirrored onto the front door's texels (the left half of
/// the texture), a licence plate quad on the right half, and the front
/// door's first triangle once more (a duplicate face). Side walls at x = ±0.9
/// (glTF x is the vehicle's left).
fn model(dir: &Path) -> PathBuf {
    let quad = |z0: f32, z1: f32, x: f32, y0: f32, y1: f32, [u0, u1]: [f32; 2]| {
        let p = [[x, y0, z0], [x, y0, z1], [x, y1, z1], [x, y1, z0]];
        let uv = [[u0, 1.0], [u1, 1.0], [u1, 0.0], [u0, 0.0]];
        [([p[0], p[1], p[2]], [uv[0], uv[1], uv[2]]), ([p[0], p[2], p[3]], [uv[0], uv[2], uv[3]])]
    };
    let mut triangles = Vec::new();
    triangles.extend(quad(0.0, 2.0, 0.9, 0.3, 1.5, [0.0, 0.5]));
    triangles.extend(quad(-2.0, 0.0, 0.9, 0.3, 1.5, [0.0, 0.5]));
    triangles.extend(quad(-0.3, 0.3, -0.9, 0.3, 0.45, [0.5, 1.0]));
    triangles.push(triangles[0]);
    let path = dir.join("car.gltf");
    write_gltf(&path, &triangles);
    path
}

/// A 64×32 part map: left half red (door), right half blue (plate).
fn part_map(dir: &Path) {
    let colors: Vec<u32> = (0..64 * 32).map(|i| if i % 64 < 32 { 0xFF0000 } else { 0x0000FF }).collect();
    rgb_png(&dir.join("partmap.png"), 64, 32, &colors);
    std::fs::write(dir.join("parts.csv"), "name,color\ndoor,#FF0000\nplate,#0000FF\n").unwrap();
}

fn inspect(scene: &Path, out: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_ufcsr-capture"))
        .args(["inspect", scene.to_str().unwrap(), "--out", out.to_str().unwrap()])
        .output()
        .unwrap()
}

#[test]
fn a_part_map_over_overlapping_own_uvs_names_the_parts() {
    let dir = tempfile::tempdir().unwrap();
    model(dir.path());
    part_map(dir.path());
    let scene = dir.path().join("scene.json");
    let vehicle = r#"{"vehicle": {"mesh": "car.gltf", "parts_from": {"part_map": "partmap.png", "legend": "parts.csv"}}}"#;
    std::fs::write(&scene, vehicle).unwrap();
    let output = inspect(&scene, &dir.path().join("out"));
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(output.status.success(), "{stdout}{}", String::from_utf8_lossy(&output.stderr));
    assert!(
        stdout.contains("parts from the part map") && stdout.contains("0 triangles split between parts"),
        "{stdout}"
    );
    let legend = std::fs::read_to_string(dir.path().join("out/inspect-parts.csv")).unwrap();
    let names: Vec<&str> = legend.lines().skip(1).map(|line| line.split(',').next().unwrap()).collect();
    assert_eq!(names, ["door", "plate"], "from the texture, not the node name body: {legend}");
    // Door: both doors (4 triangles) and the duplicate face; plate: 2.
    let row =
        |name: &str| stdout.lines().find(|l| l.trim_start().starts_with(name) && l.ends_with("m²")).unwrap();
    let (door, plate) = (row("door "), row("plate "));
    assert!(door.contains(" 5 triangles"), "{door}");
    assert!(plate.contains(" 2 triangles"), "{plate}");

    // A part map whose legend misses a colour: counted and reported, not silent.
    std::fs::write(dir.path().join("parts.csv"), "name,color\ndoor,#FF0000\n").unwrap();
    let output = inspect(&scene, &dir.path().join("out2"));
    let text =
        format!("{}{}", String::from_utf8_lossy(&output.stdout), String::from_utf8_lossy(&output.stderr));
    assert!(output.status.success(), "{text}");
    assert!(
        text.contains("#0000FF") && text.contains("does not list") && text.contains("\"unmapped\""),
        "{text}"
    );
}

#[test]
fn inspect_says_where_own_uvs_overlap_by_parts_and_triangles() {
    let dir = tempfile::tempdir().unwrap();
    model(dir.path());
    let scene = dir.path().join("scene.json");
    std::fs::write(&scene, r#"{"vehicle": {"mesh": "car.gltf"}}"#).unwrap();
    let output = inspect(&scene, &dir.path().join("out"));
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(output.status.success(), "{stdout}{}", String::from_utf8_lossy(&output.stderr));
    assert!(stdout.contains("--keep-uvs would refuse them"), "{stdout}");
    assert!(
        stdout.contains("body × body:") && stdout.contains("made by coincident duplicate faces"),
        "{stdout}"
    );
    assert!(stdout.contains("0 & 2"), "the rear door (triangles 2, 3) over the front door (0, 1): {stdout}");
    // The picture: the 1024² palette, red where the doors share texels (the left half), the plate in its colour.
    let picture =
        ufcsr::read_color_image(&dir.path().join("out/inspect-uv-overlaps.png"), |_| Ok(())).unwrap();
    // The palette's 1024 rows, then its legend below them.
    assert_eq!(picture.width, 1024);
    assert!(picture.height > 1024 + 40, "no legend below the palette: {} rows", picture.height);
    let at = |x: usize, y: usize| picture.colors[y * 1024 + x];
    assert_eq!((at(256, 700), at(300, 200)), (0xE60000, 0xE60000), "the doors' shared texels are red");
    assert!(![0xE60000, 0xFFFFFF].contains(&at(800, 500)), "the plate's own texels: {:06X}", at(800, 500));
    // The legend's swatches: red (overlap) and each part's colour, below the palette.
    let legend: std::collections::HashSet<u32> = picture.colors[1024 * 1024..].iter().copied().collect();
    assert!(legend.contains(&0xE60000) && legend.contains(&at(800, 500)), "the legend lacks a swatch");
}

#[test]
fn a_wrong_parts_from_or_a_missing_part_map_is_refused_naming_it() {
    let dir = tempfile::tempdir().unwrap();
    model(dir.path());
    let scene = dir.path().join("scene.json");
    let cases = [
        (r#""colour""#, vec!["scene.json", "parts_from must be", "part_map"]),
        (r#"{"part_map": "partmap.png"}"#, vec!["scene.json", "missing field `legend`"]),
        (r#"{"part_map": "nowhere.png", "legend": "parts.csv"}"#, vec!["parts.csv"]),
    ];
    for (parts_from, expected) in cases {
        std::fs::write(
            &scene,
            format!(r#"{{"vehicle": {{"mesh": "car.gltf", "parts_from": {parts_from}}}}}"#),
        )
        .unwrap();
        let output = inspect(&scene, &dir.path().join("out"));
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(2), "{parts_from}: {stderr}");
        for part in expected {
            assert!(stderr.contains(part), "{parts_from}: expected {part:?} in {stderr}");
        }
    }
    part_map(dir.path());
    std::fs::write(&scene, r#"{"vehicle": {"mesh": "car.gltf", "parts_from": {"part_map": "nowhere.png", "legend": "parts.csv"}}}"#)
        .unwrap();
    let output = inspect(&scene, &dir.path().join("out"));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("nowhere.png"), "{stderr}");
}

#[test]
fn a_capture_of_overlapping_own_uvs_measures_on_its_own_unwrap_with_the_part_maps_parts() {
    let dir = tempfile::tempdir().unwrap();
    model(dir.path());
    part_map(dir.path());
    let scene = serde_json::json!({
        "vehicle": {"mesh": "car.gltf", "parts_from": {"part_map": "partmap.png", "legend": "parts.csv"}},
        "rig": {"pedestrian": [0.0, -4.0, 0.0], "eye_pixels": [80, 100], "look_at_vehicle": [0.0, 0.0, 0.8]},
        "scenarios": {"pass": {"duration_s": 1.0,
            "position": [{"t": 0.0, "value": [-1.0, 0.0, 0.0]}, {"t": 1.0, "value": [1.0, 0.0, 0.0]}],
            "yaw_deg": [{"t": 0.0, "value": 0}]}}
    });
    std::fs::write(dir.path().join("scene.json"), serde_json::to_vec(&scene).unwrap()).unwrap();
    let archive = dir.path().join("archive");
    let output = Command::new(env!("CARGO_BIN_EXE_ufcsr-capture"))
        .args(["scene", dir.path().join("scene.json").to_str().unwrap(), "--out", archive.to_str().unwrap()])
        .args(["--ppd", "1", "--palette-size", "256", "--frames", "0,30", "--count"])
        .output()
        .unwrap();
    let said =
        format!("{}{}", String::from_utf8_lossy(&output.stdout), String::from_utf8_lossy(&output.stderr));
    assert!(output.status.success(), "{said}");
    // The capture's own unwrap (no --keep-uvs), labelled door and plate from the texture.
    let legend = std::fs::read_to_string(archive.join("parts.csv")).unwrap();
    let names: Vec<&str> = legend.lines().skip(1).map(|line| line.split(',').next().unwrap()).collect();
    assert_eq!(names, ["door", "plate"], "{legend}");
    let manifest: serde_json::Value =
        serde_json::from_slice(&std::fs::read(archive.join("manifest.json")).unwrap()).unwrap();
    assert_eq!(manifest["unwrap"]["method"], "islands", "{}", manifest["unwrap"]);
}
