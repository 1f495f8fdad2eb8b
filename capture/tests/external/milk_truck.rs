//! A real vehicle from `../shared/ref/vehicles/` (the Cesium milk truck, see
//! its SOURCE.md): `inspect`, region labelling, the partial-UV message, a tiny
//! capture, and every rendered pixel naming a labelled texel. Ignored with the
//! reason when the model is absent; a failure under `CI`.

use std::path::{Path, PathBuf};

use libtest_mimic::Completion;
use ufcsr_capture::{
    Backend, CaptureOptions, FrameSelection, Gpu, InspectOptions, Scene, UvState, capture, inspect, verify,
};

use crate::need::{Outcome, missing, repository, shared_dir};
use crate::render_check::render_and_check;

/// The milk-truck scene (`fixtures/scenes/milk-truck.json`) rewritten into
/// `work` to name the model in [`shared_dir`]; the skip when it is absent.
fn milk_truck_scene(work: &Path) -> Result<PathBuf, Outcome> {
    let shared = shared_dir();
    let model = shared.join("ref/vehicles/cesium-milk-truck.glb");
    if !model.is_file() {
        return Err(missing(&format!("{} (see shared/ref/vehicles/SOURCE.md)", model.display())));
    }
    let fixture = repository().join("fixtures/scenes/milk-truck.json");
    let text = std::fs::read_to_string(&fixture).unwrap();
    let absolute = shared.canonicalize().unwrap().display().to_string();
    let scene = work.join("milk-truck.json");
    std::fs::write(&scene, text.replace("../../../shared", &absolute)).unwrap();
    Ok(scene)
}

pub fn milk_truck_inspects_and_labels_into_named_parts() -> Outcome {
    let work = tempfile::tempdir().unwrap();
    let scene = match milk_truck_scene(work.path()) {
        Ok(scene) => scene,
        Err(skipped) => return skipped,
    };
    let out = tempfile::tempdir().unwrap();
    let inspection = inspect(&InspectOptions {
        input: scene.clone(),
        out: out.path().to_path_buf(),
        pixels_per_metre: Some(40.0),
    })
    .unwrap();
    // SOURCE.md: about 3.6k triangles (3624), more once the region rules'
    // boundaries cut the body's large triangles. Y up, +Z forward: 4.87 m
    // long, 2.79 m wide, 2.58 m high, standing on the ground under its centre.
    let cut = inspection.regions.cut_triangles;
    assert!(cut > 0 && (3624 + cut..=3624 + 2 * cut).contains(&inspection.triangles), "{cut}");
    let (min, max) = inspection.bounds;
    let size = max - min;
    assert!(
        (size.x - 4.869).abs() < 0.01 && (size.y - 2.792).abs() < 0.01 && (size.z - 2.583).abs() < 0.01,
        "{size}"
    );
    assert!(inspection.ground_centre.length() < 0.01, "{}", inspection.ground_centre);
    // The model has no slivers; cutting along the rules' boundaries near
    // the sharp ends of long triangles leaves a few, below a square centimetre.
    assert_eq!(inspection.quality.degenerate, 0);
    assert!(inspection.quality.sliver_area_m2 < 1e-4, "{:?}", inspection.quality);
    assert!(inspection.warnings.is_empty(), "{:?}", inspection.warnings);
    // The glass and trim primitives have no TEXCOORD_0.
    let UvState::Partial(missing) = &inspection.uvs else { panic!("{:?}", inspection.uvs) };
    assert_eq!(missing.len(), 2);
    assert!(missing[0].contains("\"glass\"") && missing[1].contains("\"window_trim\""), "{missing:?}");

    let mut names: Vec<&str> = inspection.parts.iter().map(|p| p.name.as_str()).collect();
    names.sort_unstable();
    assert_eq!(
        names,
        ["bumper", "cab", "hood", "tank", "wheels_front", "wheels_rear", "window_trim", "windows"]
    );
    for part in &inspection.parts {
        assert!(part.area_m2 > 0.1 && part.triangles > 0, "{part:?}");
    }
    let total: f64 = inspection.parts.iter().map(|p| p.area_m2).sum();
    assert!((total - 64.816).abs() < 0.01, "{total}");
    // The cargo tank is the biggest body part, the cab next.
    let area = |name: &str| inspection.parts.iter().find(|p| p.name == name).map_or(0.0, |p| p.area_m2);
    assert!(area("tank") > area("cab") && area("cab") > area("hood"), "{:?}", inspection.parts);
    for file in ["inspect-side.png", "inspect-top.png", "inspect-front.png", "inspect-parts.csv"] {
        assert!(out.path().join(file).is_file(), "{file}");
    }
    let report = inspection.to_string();
    assert!(report.contains("expect_length_m 5: ok"), "{report}");

    // A wrong scale is caught: the same truck in "centimetres".
    let text = std::fs::read_to_string(&scene).unwrap().replace("\"scale\": 1.0", "\"scale\": 0.01");
    let copy = out.path().join("milk-truck-cm.json");
    std::fs::write(&copy, text).unwrap();
    let wrong = Scene::load(&copy).unwrap();
    assert!(
        wrong.warnings.iter().any(|w| w.contains("expect_length_m") && w.contains("axes.scale")),
        "{:?}",
        wrong.warnings
    );
    Ok(Completion::Completed)
}

pub fn milk_truck_keep_uvs_names_the_primitives_without_uvs_and_a_tiny_capture_verifies() -> Outcome {
    let work = tempfile::tempdir().unwrap();
    let scene_path = match milk_truck_scene(work.path()) {
        Ok(scene) => scene,
        Err(skipped) => return skipped,
    };
    let mut scene = Scene::load(&scene_path).unwrap();
    let error = ufcsr_capture::keep_uvs(&scene.vehicle, [1024, 1024]).unwrap_err().to_string();
    assert!(error.contains("primitive 1 of mesh 1") && error.contains("\"glass\""), "{error}");

    let gpu = Gpu::create(Backend::Auto).unwrap_or_else(|e| panic!("GPU tests need an adapter: {e}"));
    scene.rig.set_pixels_per_degree(2.0).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let options = CaptureOptions {
        out: dir.path().join("truck"),
        palette: [512, 512],
        frames: "0,30,60".parse::<FrameSelection>().unwrap(),
        ..CaptureOptions::default()
    };
    let summary = capture(&gpu.device, &gpu.queue, &scene, &scene.scenarios[0], &options).unwrap();
    assert_eq!(summary.parts, 8);
    assert!(summary.tally.written > 0);
    let (vehicle, stray) = verify(&options.out).unwrap();
    assert!(vehicle > 0);
    assert_eq!(stray, 0);
    let legend = std::fs::read_to_string(options.out.join("parts.csv")).unwrap();
    for part in ["hood", "cab", "tank", "bumper", "windows"] {
        assert!(legend.lines().any(|line| line.starts_with(&format!("{part},"))), "{legend}");
    }
    Ok(Completion::Completed)
}

/// The milk truck at the degenerate-mesh test's ten poses: no stray pixel.
pub fn every_pixel_of_the_milk_truck_names_a_labelled_texel() -> Outcome {
    let work = tempfile::tempdir().unwrap();
    let scene = match milk_truck_scene(work.path()) {
        Ok(scene) => Scene::load(&scene).unwrap(),
        Err(skipped) => return skipped,
    };
    let gpu = Gpu::create(Backend::Auto).unwrap();
    let (vehicle, stray) = render_and_check(&gpu, &scene.vehicle);
    eprintln!("milk truck: {vehicle} vehicle pixels, {stray} stray");
    assert!(vehicle > 10_000, "{vehicle} vehicle pixels");
    assert_eq!(stray, 0);
    Ok(Completion::Completed)
}

/// The milk truck's scene with `vehicle` replaced by `edit` of it (no rename, no region rules).
fn scene_with_vehicle(scene: &Path, work: &Path, name: &str, edit: impl Fn(&mut serde_json::Value)) -> Scene {
    let mut file: serde_json::Value = serde_json::from_slice(&std::fs::read(scene).unwrap()).unwrap();
    let vehicle = file["vehicle"].as_object_mut().unwrap();
    vehicle.remove("rename");
    vehicle.remove("parts");
    edit(&mut file["vehicle"]);
    let path = work.join(name);
    std::fs::write(&path, serde_json::to_vec_pretty(&file).unwrap()).unwrap();
    Scene::load(&path).unwrap()
}

/// A model nobody here made, labelled through its own UVs: a part map
/// painted (here, by the test) with each material's colour over that
/// material's own UV triangles gives every triangle its material back —
/// the truck's own texture atlas, its glass and window trim (no UVs) named
/// by material as `names` says.
pub fn milk_truck_parts_from_a_part_map_over_its_own_uvs_are_its_materials() -> Outcome {
    let work = tempfile::tempdir().unwrap();
    let scene = match milk_truck_scene(work.path()) {
        Ok(scene) => scene,
        Err(skipped) => return skipped,
    };
    let by_material =
        scene_with_vehicle(&scene, work.path(), "materials.json", |v| v["parts_from"] = "material".into());
    let truck = &by_material.vehicle;
    let colors = [0xE69F00u32, 0x56B4E9, 0x009E73, 0xF0E442, 0x0072B2, 0xD55E00];
    assert!(truck.parts.len() <= colors.len(), "{:?}", truck.parts);
    // Paint each triangle's own UV triangle (texel centres inside, or the
    // centroid's texel; the first material to reach a texel keeps it) on a 1024² map.
    let side = 1024usize;
    let mut map = vec![0u32; side * side];
    for (t, triangle) in truck.triangles.iter().enumerate() {
        let uv = triangle.map(|i| truck.own_uvs[i as usize] * side as f32);
        if !uv.iter().all(|p| p.is_finite()) {
            continue;
        }
        let color = colors[truck.triangle_part[t] as usize];
        // A UV triangle too small to hold a texel centre: the texel under its centroid (a brush covers it).
        let centroid = (uv[0] + uv[1] + uv[2]) / 3.0;
        let at =
            |x: i64, y: i64| y.rem_euclid(side as i64) as usize * side + x.rem_euclid(side as i64) as usize;
        let texel = at(centroid.x.floor() as i64, centroid.y.floor() as i64);
        if map[texel] == 0 {
            map[texel] = color;
        }
        let (lo, hi) = (uv[0].min(uv[1]).min(uv[2]), uv[0].max(uv[1]).max(uv[2]));
        let area = (uv[1] - uv[0]).perp_dot(uv[2] - uv[0]);
        for y in (lo.y - 0.5).ceil() as i64..=(hi.y - 0.5).floor() as i64 {
            for x in (lo.x - 0.5).ceil() as i64..=(hi.x - 0.5).floor() as i64 {
                let p = glam::Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
                let inside =
                    (0..3).all(|k| (uv[(k + 1) % 3] - uv[k]).perp_dot(p - uv[k]) * area.signum() >= 0.0);
                let texel = at(x, y);
                if inside && map[texel] == 0 {
                    map[texel] = color;
                }
            }
        }
    }
    let rgb: Vec<u8> = map.iter().flat_map(|&c| ufcsr::Color::from_packed(c).rgb()).collect();
    ufcsr::files::write_rgb_png(
        &work.path().join("partmap.png"),
        [side as u32, side as u32],
        &rgb,
        png::Compression::Fast,
    )
    .unwrap();
    let legend: String = truck
        .parts
        .iter()
        .zip(colors)
        .map(|(name, c)| format!("{name},{}\n", ufcsr::Color::from_packed(c)))
        .collect();
    std::fs::write(work.path().join("parts.csv"), format!("name,color\n{legend}")).unwrap();
    let mapped = scene_with_vehicle(&scene, work.path(), "mapped.json", |v| {
        v["parts_from"] =
            serde_json::json!({"part_map": "partmap.png", "legend": "parts.csv", "names": "material"});
    });
    let name = |mesh: &ufcsr_capture::Mesh, t: usize| mesh.parts[mesh.triangle_part[t] as usize].clone();
    let agree = (0..truck.triangles.len()).filter(|&t| name(truck, t) == name(&mapped.vehicle, t)).count();
    let mut wrong = std::collections::BTreeMap::new();
    for t in (0..truck.triangles.len()).filter(|&t| name(truck, t) != name(&mapped.vehicle, t)) {
        *wrong.entry((name(truck, t), name(&mapped.vehicle, t))).or_insert(0) += 1;
    }
    // Every one of the 3624 triangles: no two materials share texels in the truck's atlas.
    assert_eq!(agree, truck.triangles.len(), "triangles that did not get their material back: {wrong:?}");
    let mut names = mapped.vehicle.parts.clone();
    names.sort_unstable();
    let mut materials = truck.parts.clone();
    materials.sort_unstable();
    assert_eq!(names, materials);
    Ok(Completion::Completed)
}
