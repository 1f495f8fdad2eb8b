//! A study and an observer grid build their set-up (unwrap, PIdT, the
//! archive's files, the renderer) once and hand it to every capture (issue
//! 22 item 5): each setting's and each observer's folder must hold, byte for
//! byte, what a capture of that setting alone writes. The study's outputs are
//! moved aside and the same settings captured one by one into the same paths
//! (results name their archive folder), then the two trees are compared,
//! only the wall times (`results/timings.json`, the report's
//! time of writing) left out. A set-up refuses a capture of another vehicle
//! or palette, whose numbers it would get wrong. `--views-scale`, which a
//! study may lower to save time, changes the views and nothing else.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use ufcsr::Dedupe;
use ufcsr_capture::{
    CaptureOptions, CaptureSetup, FrameSelection, Gpu, Scene, capture_counted, read_rgb_png,
    run_observer_study, run_study, scene::ValueOrTrack, study::ObserverOptions, study::StudyMeasure,
    study::StudyOptions,
};

use crate::study_accuracy::gpu;

/// Every file under `dir` (relative path → bytes), wall times left out:
/// `timings.json`, and the minute `report.html` says it was written in.
fn files_under(dir: &Path) -> BTreeMap<PathBuf, Vec<u8>> {
    let mut files = BTreeMap::new();
    let mut folders = vec![dir.to_path_buf()];
    while let Some(folder) = folders.pop() {
        for entry in std::fs::read_dir(&folder).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                folders.push(path);
            } else if path.file_name().unwrap() != "timings.json" {
                let mut bytes = std::fs::read(&path).unwrap();
                if path.file_name().unwrap() == "report.html" {
                    let page = String::from_utf8(bytes).unwrap();
                    let lines: Vec<&str> =
                        page.lines().filter(|line| !line.contains("class=\"provenance\"")).collect();
                    bytes = lines.join("\n").into_bytes();
                }
                files.insert(path.strip_prefix(dir).unwrap().to_path_buf(), bytes);
            }
        }
    }
    files
}

/// The files of `shared` and `alone` are the same, byte for byte.
fn assert_same_files(shared: &Path, alone: &Path) {
    let (shared_files, alone_files) = (files_under(shared), files_under(alone));
    let names = |files: &BTreeMap<PathBuf, Vec<u8>>| files.keys().cloned().collect::<Vec<_>>();
    assert_eq!(names(&shared_files), names(&alone_files), "{}", alone.display());
    for (name, bytes) in &shared_files {
        assert!(bytes == &alone_files[name], "{} differs from a capture alone", alone.join(name).display());
    }
    assert!(shared_files.contains_key(Path::new("results/result.json")));
    assert!(shared_files.contains_key(Path::new("results/frames.csv")));
}

/// The demo, 3 frames of scenario A, a 256² palette (the smallest the truck covers texels of): quick, with occluders.
fn base_options(out: &Path) -> CaptureOptions {
    CaptureOptions { out: out.to_path_buf(), palette: [256, 256], ..CaptureOptions::default() }
}

/// Moves the folder `out` a study wrote aside, captures each `(folder,
/// scene, frame step)` alone into the same place, and compares the two.
fn assert_each_alone_is_the_same(gpu: &Gpu, out: &Path, captures: &[(String, Scene, u32)]) {
    let shared = out.with_extension("shared");
    std::fs::rename(out, &shared).unwrap();
    for (folder, scene, step) in captures {
        let scenario = scene.scenario("A").unwrap();
        // `--frames all/STEP`: the frames a study keeps of the scenario at that step.
        let options =
            CaptureOptions { frames: FrameSelection::every(*step), ..base_options(&out.join(folder)) };
        capture_counted(&gpu.device, &gpu.queue, scene, scenario, &options, Dedupe::Frame).unwrap();
        assert_same_files(&shared.join(folder), &out.join(folder));
    }
}

#[test]
fn a_studys_settings_are_byte_for_byte_the_captures_of_each_setting_alone() {
    let gpu = gpu();
    let scene = Scene::demo();
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("study");
    let options = StudyOptions {
        // Two resolutions: the second setting gets other tile sizes from the shared renderer.
        ppds: vec![3.0, 2.0],
        frame_steps: vec![90],
        exact_sample: None,
        capture: base_options(&out),
        scenario: "A".into(),
        measure: StudyMeasure::AngularArea,
        dedupe: Dedupe::Frame,
        tolerance_pp: 1.0,
    };
    let study = run_study(&gpu.device, &gpu.queue, &scene, &options).unwrap();
    assert_eq!(study.rows.len(), 2);
    assert!(study.setup_seconds > 0.0);
    let settings: Vec<(String, Scene, u32)> = study
        .rows
        .iter()
        .map(|row| {
            let mut setting = scene.clone();
            setting.rig.set_pixels_per_degree(row.ppd).unwrap();
            (format!("ppd{}-step{}", row.ppd, row.frame_step), setting, row.frame_step)
        })
        .collect();
    assert_each_alone_is_the_same(&gpu, &out, &settings);
}

#[test]
fn a_study_run_twice_costs_and_recommends_alike_by_pixels_rendered() {
    // The pick is by pixels rendered, not by measured seconds: two runs of one study give the
    // same costs, front and pick, and the pick is the cheapest within the tolerance. Without
    // the exact measure every setting is held to its precision; 100 pp lets every one through.
    let gpu = gpu();
    let scene = Scene::demo();
    let dir = tempfile::tempdir().unwrap();
    let run = |name: &str| {
        let options = StudyOptions {
            ppds: vec![4.0, 3.0, 2.0],
            frame_steps: vec![30, 90],
            exact_sample: None,
            capture: CaptureOptions { views_scale: 1, ..base_options(&dir.path().join(name)) },
            scenario: "A".into(),
            measure: StudyMeasure::AngularArea,
            dedupe: Dedupe::Frame,
            tolerance_pp: 100.0,
        };
        run_study(&gpu.device, &gpu.queue, &scene, &options).unwrap()
    };
    let (first, second) = (run("first"), run("second"));
    let costs = |s: &ufcsr_capture::study::Study| -> Vec<(f64, u32, u64, bool)> {
        s.rows.iter().map(|r| (r.ppd, r.frame_step, r.pixels_rendered, r.pareto)).collect()
    };
    assert_eq!(costs(&first), costs(&second));
    let pick = first.recommended.clone().unwrap();
    assert_eq!(Some((pick.ppd, pick.frame_step)), second.recommended.map(|p| (p.ppd, p.frame_step)));
    let cheapest = first.rows.iter().map(|r| r.pixels_rendered).min().unwrap();
    assert_eq!((pick.ppd, pick.frame_step, pick.pixels_rendered), (2.0, 90, cheapest));
    // The cost follows the model: about ppd² × eye-frames (whole tiles, culled tiles out).
    for row in &first.rows {
        assert!(row.pixels_rendered > 0, "{}", row.label());
        let model = row.ppd * row.ppd * f64::from(row.frames);
        let per = row.pixels_rendered as f64 / model;
        let base = cheapest as f64 / (4.0 * f64::from(first.rows.last().unwrap().frames));
        assert!((per / base - 1.0).abs() < 0.5, "{}: {per} vs {base}", row.label());
    }
}

#[test]
fn each_observer_is_byte_for_byte_the_capture_of_that_observer_alone() {
    let gpu = gpu();
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("observers");
    let options = ObserverOptions {
        scenario: "A".into(),
        // Two pedestrians 3.5 m apart, every 30th frame (the buildings hide part of the truck in
        // some): the occluders are placed relative to each one's head, and a renderer that kept the
        // first one's placement fails here.
        population: ufcsr::format::ObserverPopulation::us_adults(ufcsr::format::ObserverPlace::Kerb {
            from: [-9.5, -4.5],
            to: [-4.5, -9.5],
        }),
        sampling: ufcsr::format::ObserverSampling::Grid {
            positions: 2,
            heights: 1,
            eye_heights_m: [1.5, 1.9],
        },
        resolution_check: ufcsr::format::ResolutionCheck::None,
        ppd: 2.0,
        frame_step: 30,
        capture: base_options(&out),
    };
    let scene = Scene::demo();
    let study = run_observer_study(&gpu.device, &gpu.queue, &scene, &options).unwrap();
    assert_eq!(study.observers.len(), 2);
    assert!(study.setup_seconds > 0.0);
    let observers: Vec<(String, Scene, u32)> = study
        .observers
        .iter()
        .enumerate()
        .map(|(index, observer)| {
            let mut alone = scene.clone();
            alone.rig.pedestrian = ValueOrTrack::Fixed(observer.position);
            alone.rig.eye_height_m = observer.eye_height_m;
            alone.rig.set_pixels_per_degree(options.ppd).unwrap();
            (format!("observer-{index:03}"), alone, options.frame_step)
        })
        .collect();
    assert_each_alone_is_the_same(&gpu, &out, &observers);
}

#[test]
fn the_views_scale_changes_only_the_views_of_a_counted_capture() {
    let gpu = gpu();
    let mut scene = Scene::demo();
    scene.rig.set_pixels_per_degree(2.0).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("A");
    let scenario = scene.scenario("A").unwrap();
    let capture = |views_scale: u32| {
        let options =
            CaptureOptions { frames: "0-180/90".parse().unwrap(), views_scale, ..base_options(&out) };
        capture_counted(&gpu.device, &gpu.queue, &scene, scenario, &options, Dedupe::Frame)
    };
    capture(1).unwrap();
    let small = out.with_extension("small");
    std::fs::rename(&out, &small).unwrap();
    capture(2).unwrap();
    // The views, their contact sheet and its PDF (views.png, views.pdf).
    let is_view = |name: &Path| {
        name.starts_with("results/views")
            || name.parent() == Some(Path::new("results"))
                && name.file_name().is_some_and(|n| n.to_string_lossy().starts_with("views."))
    };
    let without_views = |dir: &Path| {
        let mut files = files_under(dir);
        files.retain(|name, _| !is_view(name));
        files
    };
    assert!(without_views(&small) == without_views(&out), "the views scale changed more than the views");
    // The contact sheet is four views wide (each view alone is written with `--figures all` only).
    let sheet_width = |dir: &Path| read_rgb_png(&dir.join("results/views.png")).unwrap().0[0];
    assert_eq!((sheet_width(&small), sheet_width(&out)), (4 * 400, 4 * 800));
    let message = capture(9).err().unwrap().to_string();
    assert!(message.contains("--views-scale"), "{message}");
}

#[test]
fn a_capture_set_up_refuses_another_vehicle_or_palette_instead_of_counting_wrongly() {
    let gpu = gpu();
    let mut scene = Scene::demo();
    scene.rig.set_pixels_per_degree(2.0).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let options = base_options(&dir.path().join("first"));
    let mut setup = CaptureSetup::new(&gpu.device, &gpu.queue, &scene, &options).unwrap();
    let scenario = scene.scenario("A").unwrap().clone();
    let mut refused = |scene: &Scene, options: &CaptureOptions| {
        let counted =
            setup.capture_counted(&gpu.device, &gpu.queue, scene, &scenario, options, Dedupe::Frame);
        counted.err().expect("refused").to_string()
    };
    let other_palette = CaptureOptions { palette: [512, 256], ..base_options(&dir.path().join("second")) };
    assert!(refused(&scene, &other_palette).contains("same palette"));
    let mut other_vehicle = scene.clone();
    other_vehicle.vehicle.parts[0] = "renamed".into();
    assert!(refused(&other_vehicle, &base_options(&dir.path().join("second"))).contains("same vehicle"));
    // Nothing was written for the refused captures.
    assert!(!dir.path().join("second").exists());
}
