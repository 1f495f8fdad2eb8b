//! One archive's texel-sample bracket on each candidate's legible seconds
//! (`src/placement/texel_sample.rs`) holds against a known answer: the
//! placement of demo A measured on every texel. The same scene is measured
//! again on a quarter of the texels with many seeds, `ufcsr::placement` is
//! run on each archive, and the test counts how often each candidate's
//! bracket `[low, high]` contains its legible seconds at every texel. Parts
//! only (display patches are laid out from each seed's own sample, so their
//! names differ between seeds). A candidate never legible in the answer
//! and with a bracket of `[0, 0]` is a trivial case and left out of the
//! count (it would cover by construction).

use ufcsr::{PlacementOptions, placement, placement::CandidateKind};
use ufcsr_capture::{CaptureOptions, MeasureOptions, PlacementCandidates, Scene, measure_unobstructed};

use crate::study_accuracy::gpu;

/// Seeds of the sampled measures.
const SEEDS: u64 = 24;
const SAMPLE: f64 = 0.25;

/// Per part, its legible seconds and texel-sample bracket, from the demo A
/// archive measured at `sample` with `seed` (every 3rd frame, 256² palette).
fn measured(sample: f64, seed: u64) -> Vec<(String, f64, Option<[f64; 2]>)> {
    let gpu = gpu();
    let scene = Scene::demo();
    let scenario = scene.scenario("A").unwrap();
    let dir = tempfile::tempdir().unwrap();
    let capture = CaptureOptions {
        out: dir.path().to_path_buf(),
        palette: [256, 256],
        views_scale: 1,
        frames: "0-180/3".parse().unwrap(),
        ..CaptureOptions::default()
    };
    let measure = MeasureOptions {
        sample,
        seed,
        placement: Some(PlacementCandidates::default()),
        ..MeasureOptions::default()
    };
    measure_unobstructed(&gpu.device, &gpu.queue, &scene, scenario, &capture, &measure).unwrap();
    let answer = placement(&PlacementOptions::new(vec![dir.path().to_path_buf()])).unwrap();
    answer
        .document
        .candidates
        .iter()
        .filter(|c| c.kind == CandidateKind::Part)
        .map(|c| (c.name.clone(), c.legible_s, c.texel_sample_interval_s))
        .collect()
}

#[test]
fn one_archives_texel_sample_bracket_covers_the_legible_seconds_of_every_texel() {
    let truth = measured(1.0, 1);
    // With every texel the bracket is the point.
    for (name, legible_s, bracket) in &truth {
        assert_eq!(*bracket, Some([*legible_s, *legible_s]), "{name}");
    }
    let (mut covered, mut cases, mut width) = (0u32, 0u32, 0.0);
    let mut missed = Vec::new();
    for seed in 1..=SEEDS {
        for (name, legible_s, bracket) in measured(SAMPLE, seed) {
            let [low, high] = bracket.expect("a bracket for every part");
            assert!(low <= legible_s + 1e-9 && legible_s <= high + 1e-9, "{name}: {legible_s} {low} {high}");
            let Some((_, true_s, _)) = truth.iter().find(|(n, _, _)| *n == name) else { continue };
            if *true_s == 0.0 && high == 0.0 {
                continue;
            }
            cases += 1;
            width += high - low;
            if low - 1e-9 <= *true_s && *true_s <= high + 1e-9 {
                covered += 1;
            } else {
                missed.push(format!("seed {seed} {name}: {true_s:.2} s not in {low:.2}–{high:.2}"));
            }
        }
    }
    let coverage = f64::from(covered) / f64::from(cases);
    eprintln!(
        "texel-sample bracket at sample {SAMPLE}: {covered} of {cases} cover ({:.1} %), mean width {:.3} s; \
         missed: {missed:?}",
        100.0 * coverage,
        width / f64::from(cases)
    );
    assert!(cases >= 50, "{cases} non-trivial cases");
    assert!((0.90..=0.99).contains(&coverage), "coverage {coverage}");
}
