//! `ufcsr placement` (issue 18) on synthetic `placement-frames.csv`
//! tables with known answers: the legibility distance of a facing plate,
//! the threshold and eye rules, the decision window, symmetric pairs, the
//! exhaustive search against brute force, the greedy bound, the schema of
//! placement.json and the errors of bad tables.

use std::path::{Path, PathBuf};

use ufcsr::{
    PlacementOptions, placement, placement::CharacterHeight, placement::EyeRule, placement::Method,
    placement::Objective, placement::Resampling, placement::Thresholds, placement::brute_force_best,
};

use crate::schemas::validator;

const HEADER: &str = "frame,time_s,eye,distance_m,candidate,kind,solid_angle_sr,visible_fraction,\
                      view_angle_deg,angular_height_deg,frame_s";

/// One row: (frame, eye, distance, candidate, kind, solid angle, fraction, angle, height deg).
struct Row<'a> {
    frame: u32,
    eye: &'a str,
    distance_m: f64,
    candidate: &'a str,
    kind: &'a str,
    fraction: f64,
    angle_deg: f64,
    height_deg: f64,
}

/// A table at 10 frames per second.
fn write_table(dir: &Path, name: &str, rows: &[Row]) -> PathBuf {
    let mut text = format!("{HEADER}\n");
    for r in rows {
        text += &format!(
            "{},{},{},{},{},{},{},{},{},{},0.1\n",
            r.frame,
            f64::from(r.frame) / 10.0,
            r.eye,
            r.distance_m,
            r.candidate,
            r.kind,
            if r.fraction > 0.0 { 1e-3 } else { 0.0 },
            r.fraction,
            r.angle_deg,
            r.height_deg
        );
    }
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

/// The rule these tests were written for: characters as tall as the
/// candidate, no width check, every legible frame counts (no dwell).
pub fn plain() -> Thresholds {
    Thresholds {
        character_height: CharacterHeight::Fraction(1.0),
        min_characters: 0,
        min_dwell_s: 0.0,
        ..Thresholds::default()
    }
}

/// `paths` under [`plain`], with a small bootstrap.
pub fn options(paths: Vec<PathBuf>) -> PlacementOptions {
    PlacementOptions {
        thresholds: plain(),
        resampling: Resampling { replicates: 50, ..Resampling::default() },
        ..PlacementOptions::new(paths)
    }
}

fn row<'a>(frame: u32, candidate: &'a str, legible: bool) -> Row<'a> {
    Row {
        frame,
        eye: "left",
        distance_m: 50.0 - f64::from(frame),
        candidate,
        kind: "part",
        fraction: if legible { 1.0 } else { 0.0 },
        angle_deg: 10.0,
        height_deg: 1.0,
    }
}

#[test]
fn a_facing_plate_becomes_legible_at_the_distance_the_threshold_implies() {
    // A 0.15 m high plate facing the eye, the eye approaching 0.5 m per frame
    // from 60 m; its angular height is 2·atan(h / 2d). At 16 arcmin it
    // becomes legible at d* = h / (2·tan 8′) = 32.23 m.
    let dir = tempfile::tempdir().unwrap();
    let h = 0.15;
    let rows: Vec<Row> = (0..100)
        .map(|frame| {
            let d = 60.0 - 0.5 * f64::from(frame);
            Row {
                frame,
                eye: "left",
                distance_m: d,
                candidate: "plate",
                kind: "patch",
                fraction: 1.0,
                angle_deg: 0.0,
                height_deg: (2.0 * (h / (2.0 * d)).atan()).to_degrees(),
            }
        })
        .collect();
    let table = write_table(dir.path(), "plate.csv", &rows);
    let found = placement(&options(vec![table])).unwrap();
    let plate = &found.document.candidates[0];
    let threshold = Thresholds::default().min_character_height_arcmin;
    let implied = h / (2.0 * (threshold / 2.0 / 60.0).to_radians().tan());
    assert!((implied - 32.23).abs() < 0.01, "{implied}");
    let first = plate.first_legible_distance_m.expect("legible at last");
    // The first frame at or inside d*: d* − 0.5 m < first ≤ d*.
    assert!(first <= implied && first > implied - 0.5, "first legible at {first} m, d* = {implied} m");
    // Frames from 32.0 m (frame 56) to 10.5 m (frame 99): 44 frames of 0.1 s.
    assert_eq!(first, 32.0);
    assert!((plate.legible_s - 4.4).abs() < 1e-9, "{}", plate.legible_s);
    assert!((plate.visible_s - 10.0).abs() < 1e-9);
    assert_eq!(plate.first_legible_s, Some(5.6));
}

#[test]
fn a_frame_is_legible_only_when_height_share_and_angle_all_pass_and_the_eye_rule_holds() {
    let dir = tempfile::tempdir().unwrap();
    let mut rows = Vec::new();
    // Frame 0: all pass. 1: too small. 2: too hidden. 3: too oblique.
    // 4: legible to the left eye only.
    for (frame, height, fraction, angle) in
        [(0, 1.0, 1.0, 10.0), (1, 0.2, 1.0, 10.0), (2, 1.0, 0.5, 10.0), (3, 1.0, 1.0, 70.0)]
    {
        for eye in ["left", "right"] {
            rows.push(Row {
                height_deg: height,
                fraction,
                angle_deg: angle,
                eye,
                ..row(frame, "door", true)
            });
        }
    }
    rows.push(Row { eye: "left", ..row(4, "door", true) });
    rows.push(Row { eye: "right", height_deg: 0.1, ..row(4, "door", true) });
    let table = write_table(dir.path(), "t.csv", &rows);
    let any = placement(&options(vec![table.clone()])).unwrap();
    assert!((any.document.candidates[0].legible_s - 0.2).abs() < 1e-9, "frames 0 and 4");
    assert!((any.document.candidates[0].visible_s - 0.5).abs() < 1e-9, "frames 0 to 4");
    let mut options = options(vec![table]);
    options.thresholds.eyes = EyeRule::Both;
    let both = placement(&options).unwrap();
    assert!((both.document.candidates[0].legible_s - 0.1).abs() < 1e-9, "frame 0 only");
}

#[test]
fn the_decision_window_counts_only_the_seconds_before_the_nearest_frame() {
    // 50 frames, nearest at frame 49 (t = 4.9 s); a 1 s window holds
    // frames 39..=49. "early" is legible in frames 0-19, "late" in 40-49.
    let dir = tempfile::tempdir().unwrap();
    let mut rows = Vec::new();
    for frame in 0..50 {
        rows.push(row(frame, "early", frame < 20));
        rows.push(row(frame, "late", frame >= 40));
    }
    let table = write_table(dir.path(), "t.csv", &rows);
    let mut options = options(vec![table]);
    options.thresholds.decision_window_s = 1.0;
    let found = placement(&options).unwrap();
    let by_name = |name: &str| found.document.candidates.iter().find(|c| c.name == name).unwrap().clone();
    assert!((by_name("early").legible_s - 2.0).abs() < 1e-9);
    assert_eq!(by_name("early").decision_window_legible_s, 0.0);
    assert!((by_name("late").decision_window_legible_s - 1.0).abs() < 1e-9);
    assert_eq!(found.document.archives[0].arrival_s, 4.9);
}

#[test]
fn a_symmetric_pair_is_one_choice_and_covers_both_sides() {
    // Left fender legible in frames 0-9, right in 10-19, hood in 0-14:
    // alone the hood wins k = 1; symmetric, the pair covers all 20 frames.
    let dir = tempfile::tempdir().unwrap();
    let mut rows = Vec::new();
    for frame in 0..20 {
        rows.push(row(frame, "front_fender_left", frame < 10));
        rows.push(row(frame, "front_fender_right", frame >= 10));
        rows.push(row(frame, "hood", frame < 15));
    }
    let table = write_table(dir.path(), "t.csv", &rows);
    let single = placement(&options(vec![table.clone()])).unwrap();
    let best1 = single.document.combinations.iter().find(|c| c.k == 1).unwrap();
    assert_eq!(best1.candidates(), ["hood"]);
    let paired = placement(&PlacementOptions { symmetric: true, ..options(vec![table]) }).unwrap();
    // k counts physical displays: the pair is two, so one display is still the hood.
    let best1 = paired.document.combinations.iter().find(|c| c.k == 1).unwrap();
    assert_eq!((best1.candidates(), best1.displays), (vec!["hood".to_string()], 1));
    let best2 = paired.document.combinations.iter().find(|c| c.k == 2).unwrap();
    assert_eq!(best2.candidates(), ["front_fender_left", "front_fender_right"]);
    assert_eq!((best2.displays, best2.members.len()), (2, 1), "one choice, two displays");
    assert!((best2.legible_s - 2.0).abs() < 1e-9 && (best2.share_of_time - 1.0).abs() < 1e-12);
}

/// A deterministic pseudo-random instance: `archives` tables of `frames`
/// frames, `n` candidates each legible with a candidate-dependent chance.
fn random_instance(
    dir: &Path,
    seed: u64,
    archives: usize,
    n: usize,
    frames: u32,
) -> (Vec<PathBuf>, Vec<Vec<Vec<bool>>>) {
    let mut state = seed;
    let mut next = move || {
        state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (state >> 33) as f64 / (1u64 << 31) as f64
    };
    let names: Vec<String> = (0..n).map(|c| format!("c{c:02}")).collect();
    let mut paths = Vec::new();
    let mut flags = Vec::new();
    for a in 0..archives {
        let mut rows = Vec::new();
        let mut archive_flags = vec![vec![false; frames as usize]; n];
        for frame in 0..frames {
            for (c, name) in names.iter().enumerate() {
                let legible = next() < 0.1 + 0.4 * (c as f64 / n as f64);
                archive_flags[c][frame as usize] = legible;
                rows.push(row(frame, name, legible));
            }
        }
        paths.push(write_table(dir, &format!("a{a}.csv"), &rows));
        flags.push(archive_flags);
    }
    (paths, flags)
}

#[test]
fn the_exhaustive_search_equals_brute_force_for_one_two_and_three() {
    let dir = tempfile::tempdir().unwrap();
    for seed in 1..=4 {
        let (paths, flags) = random_instance(dir.path(), seed, 3, 9, 40);
        let found = placement(&options(paths)).unwrap();
        for c in &found.document.combinations {
            assert_eq!(c.method, Method::Exhaustive);
            let objective_value = match c.objective {
                Objective::Mean => c.legible_s,
                Objective::WorstCase => c.worst_case_s,
            };
            let brute = brute_force_best(&flags, &[0.1, 0.1, 0.1], c.k, c.objective);
            assert!(
                (objective_value - brute).abs() < 1e-9,
                "seed {seed} k {} {:?}: {objective_value} vs {brute}",
                c.k,
                c.objective
            );
            assert_eq!(c.gap_s, 0.0);
        }
    }
}

#[test]
fn the_greedy_bound_holds_and_greedy_is_within_one_minus_one_over_e() {
    let dir = tempfile::tempdir().unwrap();
    for seed in 11..=16 {
        let (paths, flags) = random_instance(dir.path(), seed, 2, 10, 30);
        let options = PlacementOptions { exhaustive_limit: 0, ..options(paths) };
        let found = placement(&options).unwrap();
        for c in &found.document.combinations {
            assert_eq!(c.method, Method::Greedy);
            let value = match c.objective {
                Objective::Mean => c.legible_s,
                Objective::WorstCase => c.worst_case_s,
            };
            let optimum = brute_force_best(&flags, &[0.1, 0.1], c.k, c.objective);
            assert!(value <= optimum + 1e-9, "greedy above the optimum");
            assert!(
                optimum <= c.upper_bound_s + 1e-9,
                "seed {seed} k {}: optimum {optimum} above the bound {}",
                c.k,
                c.upper_bound_s
            );
            assert!((c.gap_s - (c.upper_bound_s - value)).abs() < 1e-9);
            if c.objective == Objective::Mean {
                assert!(value >= (1.0 - (-1.0f64).exp()) * optimum - 1e-9);
            }
        }
    }
}

#[test]
fn placement_json_matches_its_schema_which_is_its_types_schema() {
    // docs/schemas/placement.schema.json is generated from the type placement.json is written
    // through (ufcsr::format::SCHEMAS; schemas::committed_schemas_equal_the_generated_ones holds it).
    let file = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("docs/schemas/placement.schema.json");
    let entry = ufcsr::format::SCHEMAS.iter().find(|f| f.schema_file == "placement.schema.json").unwrap();
    assert_eq!(std::fs::read_to_string(&file).unwrap(), entry.text());
    let dir = tempfile::tempdir().unwrap();
    let (paths, _) = random_instance(dir.path(), 7, 2, 5, 20);
    let found = placement(&PlacementOptions { symmetric: true, ..options(paths) }).unwrap();
    let out = dir.path().join("out");
    let written = ufcsr::write_placement(&found, &out).unwrap();
    let schema = validator::Schema::load(&file);
    let document = validator::read_json(&written.json);
    schema.assert_valid(&document, "placement.json");
    assert_eq!(document["schema"], "ufcsr-placement/2");
    let read: ufcsr::format::PlacementDocument = serde_json::from_value(document.clone()).unwrap();
    assert_eq!(read, found.document, "placement.json reads back to what was written");
    let csv = std::fs::read_to_string(&written.csv).unwrap();
    assert!(csv.starts_with("rank,candidate,kind,legible_s"));
    assert_eq!(csv.lines().count(), 6, "a header and five candidates");
    // A renamed field fails the closed schema.
    let mut renamed = document.clone();
    renamed["candidates"][0]["legible"] = renamed["candidates"][0]["legible_s"].take();
    renamed["candidates"][0].as_object_mut().unwrap().remove("legible_s");
    assert!(schema.check(&renamed).is_err());
}

#[test]
fn bad_tables_are_errors_naming_the_file_line_and_problem() {
    let dir = tempfile::tempdir().unwrap();
    let good = write_table(dir.path(), "good.csv", &[row(0, "hood", true), row(1, "hood", true)]);
    let text = std::fs::read_to_string(&good).unwrap();
    let cases = [
        ("no-kind.csv", text.replace(",kind,", ",sort,"), "lacks column \"kind\""),
        ("bad-kind.csv", text.replace(",part,", ",wheel,"), "line 2: kind \"wheel\""),
        ("fraction.csv", text.replacen(",1,10,1,", ",1.5,10,1,", 1), "line 2: visible_fraction 1.5"),
        ("twice.csv", format!("{text}{}", text.lines().nth(1).unwrap()), "two rows for frame 0"),
        ("nan.csv", text.replacen(",10,1,", ",NaN,1,", 1), "view_angle_deg \"NaN\" is not finite"),
        ("empty.csv", format!("{HEADER}\n"), "has no rows"),
    ];
    for (name, content, expected) in cases {
        let path = dir.path().join(name);
        std::fs::write(&path, content).unwrap();
        let error = placement(&options(vec![path.clone()])).unwrap_err().to_string();
        assert!(error.contains(name) && error.contains(expected), "{name}: {error}");
    }
    let missing = placement(&options(vec![dir.path().join("nowhere")])).unwrap_err().to_string();
    assert!(missing.contains("no placement-frames.csv"), "{missing}");
    let options = PlacementOptions { k: 0, ..options(vec![good]) };
    assert!(placement(&options).unwrap_err().to_string().contains("--k 0"));
}

/// A rendered `frames.csv` (the analyzer's or `--count`'s) with per part
/// and eye-frame the solid angles of `solid_angle_sr(frame, part)`.
fn rendered_frames_csv(dir: &Path, parts: &[&str], solid_angle_sr: impl Fn(u32, usize) -> f64) -> PathBuf {
    let mut text = String::from("frame,time_s,eye,distance_m,part,pixels,texels,solid_angle_sr\n");
    for frame in 0..10 {
        for eye in ["left", "right"] {
            for (index, part) in parts.iter().enumerate() {
                let sr = solid_angle_sr(frame, index);
                let pixels = if sr > 0.0 { 40 } else { 0 };
                text += &format!(
                    "{frame},{},{eye},{},{part},{pixels},{pixels},{sr}\n",
                    f64::from(frame) / 10.0,
                    50 - frame
                );
            }
            text += &format!("{frame},{},{eye},{},(unlabelled),0,0,0\n", f64::from(frame) / 10.0, 50 - frame);
        }
    }
    let path = dir.join("frames.csv");
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn a_rendered_frames_table_scored_by_solid_angle_chooses_what_the_exact_table_does() {
    // hood: 2e-4 sr in frames 0-5, then 1e-5; grill: 1e-5, then 2e-4 from frame 6 on. With
    // the rule at 5e-5 sr the hood is legible 0.6 s, the grill 0.4 s, the pair all 1.0 s; the
    // exact table with the same solid angles (and any fraction, angle, height) agrees.
    let dir = tempfile::tempdir().unwrap();
    let parts = ["hood", "grill"];
    let sr = |frame: u32, part: usize| if (frame < 6) == (part == 0) { 2e-4 } else { 1e-5 };
    let rendered = rendered_frames_csv(dir.path(), &parts, sr);
    let mut exact_rows = Vec::new();
    for frame in 0..10 {
        for (index, part) in parts.iter().enumerate() {
            exact_rows.push(Row {
                fraction: 0.5,
                angle_deg: 80.0,
                height_deg: 0.01,
                ..row(frame, part, true)
            });
            let _ = sr(frame, index);
        }
    }
    let exact = write_table(dir.path(), "exact.csv", &exact_rows);
    // write_table gives every row 1e-3 sr: rewrite the solid angles to the rendered ones.
    let text: String = std::fs::read_to_string(&exact)
        .unwrap()
        .lines()
        .enumerate()
        .map(|(line, text)| {
            if line == 0 {
                return format!("{text}\n");
            }
            let (frame, part) = (((line - 1) / 2) as u32, (line - 1) % 2);
            format!("{}\n", text.replacen(",0.001,", &format!(",{},", sr(frame, part)), 1))
        })
        .collect();
    std::fs::write(&exact, text).unwrap();
    let rule = Thresholds { min_solid_angle_sr: Some(5e-5), ..plain() };
    let score = |path: &Path| {
        let options = PlacementOptions { thresholds: rule, k: 2, ..options(vec![path.to_path_buf()]) };
        placement(&options).unwrap()
    };
    let (from_rendered, from_exact) = (score(&rendered), score(&exact));
    for found in [&from_rendered, &from_exact] {
        let legible: Vec<(&str, f64)> =
            found.document.candidates.iter().map(|c| (c.name.as_str(), c.legible_s)).collect();
        assert_eq!(legible.len(), 2);
        assert!((legible[0].1 - 0.6).abs() < 1e-9 && legible[0].0 == "hood", "{legible:?}");
        assert!((legible[1].1 - 0.4).abs() < 1e-9 && legible[1].0 == "grill", "{legible:?}");
    }
    let sets = |found: &ufcsr::Placement| -> Vec<(Vec<String>, f64)> {
        found.document.combinations.iter().map(|c| (c.candidates(), c.legible_s)).collect()
    };
    // The same sets, covering the same seconds (the rendered table's frame length is its time step).
    for (a, b) in sets(&from_rendered).iter().zip(sets(&from_exact)) {
        assert!(a.0 == b.0 && (a.1 - b.1).abs() < 1e-9, "{a:?} against {b:?}");
    }
    assert_eq!(sets(&from_exact)[1].0, ["grill", "hood"]);
    assert!((sets(&from_exact)[1].1 - 1.0).abs() < 1e-9);
    // Without the rule, a rendered table cannot be scored: it has no heights or angles.
    let error = placement(&options(vec![rendered.clone()])).unwrap_err().to_string();
    assert!(error.contains("frames.csv") && error.contains("--min-solid-angle-sr"), "{error}");
}

/// Issue 42 §1: a display must fit where it is said to be legible. A thin rail (no 0.40 × 0.15 m
/// patch fits on it) is legible as a surface in every frame, but has no legible time and is never
/// the best part; the bumper, wider than the display, is legible exactly as long as its best
/// fitting patch (15 frames, not its own 5); the rail is listed as left out, with the reason.
#[test]
fn a_part_narrower_than_the_display_is_never_best_and_a_wider_one_scores_its_best_patch() {
    let dir = tempfile::tempdir().unwrap();
    let patch = "front_bumper@0.40x0.15@x2.90y0.00z0.45";
    let mut rows = Vec::new();
    for frame in 0..20 {
        rows.push(row(frame, "windshield_rail_left", true));
        rows.push(row(frame, "front_bumper", frame < 5));
        if frame < 15 {
            rows.push(Row { kind: "patch", ..row(frame, patch, true) });
        }
    }
    let table = write_table(dir.path(), "placement-frames.csv", &rows);
    let found = placement(&options(vec![table])).unwrap();
    let document = &found.document;
    let candidate = |name: &str| document.candidates.iter().find(|c| c.name == name).unwrap();
    assert_eq!(candidate("windshield_rail_left").legible_s, 0.0);
    assert!((candidate("windshield_rail_left").visible_s - 2.0).abs() < 1e-9, "exposure is kept");
    assert!((candidate("front_bumper").legible_s - 1.5).abs() < 1e-9);
    assert_eq!(candidate("front_bumper").legible_through.as_deref(), Some(patch));
    let best_part = document
        .combinations
        .iter()
        .find(|c| {
            c.kind == ufcsr::placement::CandidateKind::Part && c.k == 1 && c.objective == Objective::Mean
        })
        .unwrap();
    assert_eq!(best_part.candidates(), vec!["front_bumper".to_string()]);
    assert!(
        document.combinations.iter().all(|c| !c.candidates().contains(&"windshield_rail_left".to_string()))
    );
    let rail = document.excluded.iter().find(|e| e.candidate == "windshield_rail_left").unwrap();
    assert_eq!(rail.reason, ufcsr::format::ExclusionReason::NoDisplayFits);
    let console = ufcsr::format_placement(&found, 10);
    assert!(console.contains("no display fits (exposure only): windshield_rail_left"), "{console}");
    // One archive: no P(best), said.
    assert_eq!(best_part.p_best_note.as_deref(), Some("n/a: one unit"));
}
