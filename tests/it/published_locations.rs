//! The places published eHMI studies tested, scored as named candidates
//! (issue 42 §7, `src/placement/literature.rs`), on two synthetic
//! `placement-frames.csv` tables with known answers: each place takes its
//! best front part (never the rear bumper, however legible), the
//! windshield top its upper patches only, the interval is Student's t over
//! the two archives, tied candidates share a rank, a place the vehicle
//! lacks is listed with none, and `published-locations.csv` holds one row
//! per place and kind.

use std::path::{Path, PathBuf};

use ufcsr::{
    placement, placement::PUBLISHED_LOCATIONS, placement::published_locations,
    placement::write_published_locations,
};

const HEADER: &str = "frame,time_s,eye,distance_m,candidate,kind,solid_angle_sr,visible_fraction,\
                      view_angle_deg,angular_height_deg,frame_s";

/// A table of 10 frames at 10 per second, one eye: each candidate (name,
/// kind) legible in frames `0..n` and not visible after.
fn table(dir: &Path, name: &str, candidates: &[(&str, &str, u32)]) -> PathBuf {
    let mut text = format!("{HEADER}\n");
    for frame in 0..10u32 {
        for &(candidate, kind, n) in candidates {
            let seen = frame < n;
            text += &format!(
                "{frame},{},left,{},{candidate},{kind},{},{},10,1,0.1\n",
                f64::from(frame) / 10.0,
                30.0 - f64::from(frame),
                if seen { 1e-3 } else { 0.0 },
                if seen { 1.0 } else { 0.0 },
            );
        }
    }
    let path = dir.join(name);
    std::fs::create_dir_all(&path).unwrap();
    std::fs::write(path.join("placement-frames.csv"), text).unwrap();
    path.join("placement-frames.csv")
}

const LOW: &str = "windshield@0.40x0.15@x1.50y0.00z1.20";
const TOP: &str = "windshield@0.40x0.15@x1.30y0.00z1.50";

/// One archive's table. Without `patches` the parts are scored whole (a
/// table without display patches); with them a part is legible only through
/// a patch that fits on it (placement.md), so the windshield's two patches
/// are added alone.
fn archive(dir: &Path, name: &str, front_bumper: u32, patches: bool) -> PathBuf {
    let parts = [
        ("roof", "part", 0),
        ("front_bumper", "part", front_bumper),
        ("rear_bumper", "part", 10),
        ("grill", "part", 3),
        ("front_fender_left", "part", 3),
        ("windshield", "part", 7),
    ];
    if patches {
        table(dir, name, &[("windshield", "part", 7), (LOW, "patch", 10), (TOP, "patch", 4)])
    } else {
        table(dir, name, &parts)
    }
}

#[test]
fn each_published_place_takes_its_best_named_candidate_with_the_interval_over_archives() {
    let dir = tempfile::tempdir().unwrap();
    let tables = vec![archive(dir.path(), "a", 5, false), archive(dir.path(), "b", 3, false)];
    let answer = placement(&crate::placement::options(tables.clone())).unwrap();
    let scores = published_locations(&answer);
    assert_eq!(scores.len(), PUBLISHED_LOCATIONS.len());
    let place = |name: &str| scores.iter().find(|s| s.location.name == name).unwrap();

    // The bumper is the front one: 0.5 and 0.3 s, mean 0.4, t(1) interval 0.4 ± 12.706 · 0.1.
    let bumper = place("bumper").best_part.clone().unwrap();
    assert_eq!(bumper.candidate, "front_bumper");
    assert!((bumper.legible_s - 0.4).abs() < 1e-9, "{bumper:?}");
    let [low, high] = bumper.interval_s.unwrap();
    assert!(low == 0.0 && (high - (0.4 + 1.2706)).abs() < 1e-9, "{bumper:?}");
    // Parts by legible s: rear bumper 1.0, windshield 0.7, front bumper 0.4, grill and fender 0.3 (tied), roof 0.
    assert_eq!((bumper.rank, bumper.of), (3, 6));
    let grille = place("grille").best_part.clone().unwrap();
    let fender = place("above the front wheels (front fenders)").best_part.clone().unwrap();
    assert_eq!((grille.rank, fender.rank), (4, 4), "tied candidates share a rank");
    assert_eq!((grille.tied_with, grille.rank_text()), (1, "4-5 (a tie of 2)".to_string()), "and say so");
    assert_eq!((bumper.tied_with, bumper.rank_text()), (0, "3".to_string()));
    assert_eq!(place("roof").best_part.as_ref().map(|p| (p.legible_s, p.rank)), Some((0.0, 6)));

    // The windshield top: the part and the upper patch only, though the lower one is more legible.
    let with_patches = vec![archive(dir.path(), "pa", 5, true), archive(dir.path(), "pb", 3, true)];
    let patched = published_locations(&placement(&crate::placement::options(with_patches)).unwrap());
    let top = patched.iter().find(|s| s.location.name == "windshield top").unwrap();
    assert_eq!((top.parts, top.patches), (1, 1));
    let patch = top.best_patch.clone().unwrap();
    assert_eq!(patch.candidate, TOP);
    assert!((patch.legible_s - 0.4).abs() < 1e-9 && !patch.mountable, "{patch:?}");
    assert_eq!(top.best_part.as_ref().unwrap().candidate, "windshield");

    // Places this vehicle has no candidate for are listed with none.
    let mirrors = place("side mirrors");
    assert!(mirrors.best_part.is_none() && mirrors.best_patch.is_none() && mirrors.parts == 0);

    let out = dir.path().join("out");
    std::fs::create_dir_all(&out).unwrap();
    let csv = write_published_locations(&scores, &out, &answer.inputs).unwrap();
    let text = std::fs::read_to_string(csv).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 1 + 2 * PUBLISHED_LOCATIONS.len(), "{text}");
    assert!(
        lines.iter().any(|l| l.starts_with("bumper,") && l.contains(",part,1,front_bumper,0.4")),
        "{text}"
    );
    assert!(lines.iter().any(|l| l.starts_with("side mirrors,") && l.contains(",part,0,,")), "{text}");
    let console = ufcsr::placement::format_published_locations(&scores, 2);
    assert!(console.contains("published locations") && console.contains("none on this vehicle"), "{console}");
    assert!(console.contains("rank 4-5 (a tie of 2) of 6"), "a tie is printed as a tie: {console}");
    // An input is never replaced.
    let input_dir = tables[0].parent().unwrap();
    let clash = input_dir.join(ufcsr::placement::PUBLISHED_LOCATIONS_FILE);
    std::fs::write(&clash, "mine").unwrap();
    let inputs = vec![clash.clone()];
    assert!(write_published_locations(&scores, input_dir, &inputs).is_err());
    assert_eq!(std::fs::read_to_string(clash).unwrap(), "mine");
}

#[test]
fn a_best_set_legible_for_no_time_names_no_candidate_anywhere_it_is_printed() {
    let dir = tempfile::tempdir().unwrap();
    let never = [("roof", "part", 0), ("grill", "part", 0)];
    let tables = vec![table(dir.path(), "a", &never), table(dir.path(), "b", &never)];
    let answer = placement(&crate::placement::options(tables)).unwrap();
    let console = ufcsr::format_placement(&answer, 10);
    let best: Vec<&str> = console.lines().filter(|l| l.starts_with("k=")).collect();
    assert!(!best.is_empty(), "{console}");
    for line in best {
        assert!(
            line.ends_with(ufcsr::placement::NO_SET_LEGIBLE)
                && !line.contains("roof")
                && !line.contains("grill"),
            "{line}"
        );
    }
    let scores = published_locations(&answer);
    let roof = scores.iter().find(|s| s.location.name == "roof").unwrap().best_part.clone().unwrap();
    assert_eq!(roof.rank_text(), "1-2 (a tie of 2)", "{roof:?}");
}
