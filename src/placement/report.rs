//! The placement files: `placement.json` (schema `ufcsr-placement/1`,
//! `docs/schemas/placement.schema.json`), `placement.csv` (one row per
//! candidate, best first) and `placement-combinations.csv` (one row per
//! chosen set), and the console summary. Every number says what it is in
//! its name and unit; `docs/placement.md` defines them.

use std::collections::BTreeMap;
use std::io::Write;
use std::path::{Path, PathBuf};

use serde::Serialize;
use serde_json::json;

use crate::error::{Error, Result};
use crate::files::write_atomically;
use crate::placement::PlacementOptions;
use crate::placement::footprints::PatchFootprint;
use crate::placement::legibility::{
    ANGULAR_HEIGHT_SOURCE, ArchiveTimelines, DECISION_WINDOW_SOURCE, Exposure, VIEW_ANGLE_SOURCE,
    VISIBLE_FRACTION_SOURCE,
};
use crate::placement::picture::{WrittenPicture, pictured_sets, write_placement_picture};
use crate::placement::search::{Combination, Objective};

/// The `schema` field of placement.json.
pub const PLACEMENT_SCHEMA: &str = "ufcsr-placement/1";

/// One candidate over all archives.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CandidateSummary {
    pub name: String,
    pub kind: &'static str,
    /// Mean over the archives of the seconds it is legible.
    pub legible_s: f64,
    /// Mean over the archives of the seconds it is visible at all.
    pub visible_s: f64,
    /// The latest first legible sighting over the archives, s (null when it
    /// is never legible in some archive).
    pub first_legible_s: Option<f64>,
    /// The smallest distance at first legible sighting over the archives, m.
    pub first_legible_distance_m: Option<f64>,
    /// Mean over the archives of the seconds legible in the decision window.
    pub decision_window_legible_s: f64,
    /// The smallest legible seconds of any archive.
    pub worst_case_legible_s: f64,
    /// Per archive, in input order.
    pub per_archive: Vec<Exposure>,
}

/// Everything `ufcsr-analyze placement` found.
#[derive(Debug, Clone)]
pub struct Placement {
    pub document: serde_json::Value,
    pub candidates: Vec<CandidateSummary>,
    pub combinations: Vec<Combination>,
    /// The patches' footprints the capture recorded, by name.
    pub footprints: BTreeMap<String, PatchFootprint>,
    /// The vehicle model the picture is drawn on, when one is known.
    pub vehicle_model: Option<PathBuf>,
}

fn candidate_summaries(archives: &[ArchiveTimelines]) -> Vec<CandidateSummary> {
    let mut per_name: BTreeMap<String, (&'static str, Vec<Exposure>)> = BTreeMap::new();
    for archive in archives {
        for timeline in &archive.timelines {
            per_name.entry(timeline.name.clone()).or_insert((timeline.kind.name(), Vec::new()));
        }
    }
    let never = Exposure {
        legible_s: 0.0,
        visible_s: 0.0,
        first_legible_s: None,
        first_legible_distance_m: None,
        decision_window_legible_s: 0.0,
    };
    for archive in archives {
        let mut seen: BTreeMap<&str, Exposure> = BTreeMap::new();
        for timeline in &archive.timelines {
            seen.insert(&timeline.name, archive.exposure(timeline));
        }
        for (name, (_, exposures)) in per_name.iter_mut() {
            exposures.push(seen.get(name.as_str()).copied().unwrap_or(never));
        }
    }
    let n = archives.len().max(1) as f64;
    let mut out: Vec<CandidateSummary> = per_name
        .into_iter()
        .map(|(name, (kind, per_archive))| {
            let sum = |f: fn(&Exposure) -> f64| per_archive.iter().map(f).sum::<f64>() / n;
            let all_legible = per_archive.iter().all(|e| e.first_legible_s.is_some());
            CandidateSummary {
                name,
                kind,
                legible_s: sum(|e| e.legible_s),
                visible_s: sum(|e| e.visible_s),
                first_legible_s: all_legible
                    .then(|| per_archive.iter().filter_map(|e| e.first_legible_s).fold(f64::MIN, f64::max)),
                first_legible_distance_m: all_legible.then(|| {
                    per_archive.iter().filter_map(|e| e.first_legible_distance_m).fold(f64::MAX, f64::min)
                }),
                decision_window_legible_s: sum(|e| e.decision_window_legible_s),
                worst_case_legible_s: per_archive.iter().map(|e| e.legible_s).fold(f64::MAX, f64::min),
                per_archive,
            }
        })
        .collect();
    out.sort_by(|a, b| b.legible_s.total_cmp(&a.legible_s).then_with(|| a.name.cmp(&b.name)));
    out
}

fn archive_records(archives: &[ArchiveTimelines], window_s: f64) -> Vec<serde_json::Value> {
    archives
        .iter()
        .map(|a| {
            json!({
                "table": a.table.path.display().to_string(),
                "frames": a.table.frames.len(),
                "eyes": a.table.eyes,
                "seconds_per_frame": a.table.frame_s,
                "duration_s": a.duration_s(),
                "arrival_s": a.arrival_s,
                "decision_window_s": [a.arrival_s - window_s, a.arrival_s],
            })
        })
        .collect()
}

/// The report from the scored archives and the chosen sets.
pub fn assemble(
    options: &PlacementOptions,
    archives: Vec<ArchiveTimelines>,
    combinations: Vec<Combination>,
) -> Placement {
    let t = &options.thresholds;
    let candidates = candidate_summaries(&archives);
    let document = json!({
        "schema": PLACEMENT_SCHEMA,
        "archives": archive_records(&archives, t.decision_window_s),
        "thresholds": {
            "min_angular_height_arcmin": t.min_angular_height_arcmin,
            "min_visible_fraction": t.min_visible_fraction,
            "max_view_angle_deg": t.max_view_angle_deg,
            "decision_window_s": t.decision_window_s,
            "eyes": t.eyes.name(),
            "min_solid_angle_sr": t.min_solid_angle_sr,
            "symmetric": options.symmetric,
            "sources": {
                "min_angular_height_arcmin": ANGULAR_HEIGHT_SOURCE,
                "min_visible_fraction": VISIBLE_FRACTION_SOURCE,
                "max_view_angle_deg": VIEW_ANGLE_SOURCE,
                "decision_window_s": DECISION_WINDOW_SOURCE,
            },
        },
        "candidates": candidates,
        "combinations": combinations,
        "notes": [
            "legible_s, visible_s and decision_window_legible_s are means over the archives of seconds \
             (legible frames x seconds per frame); a frame is legible when the candidate is legible to the eyes \
             the 'eyes' threshold names; first_legible_s is the latest first legible sighting over the archives",
            "combinations: the set of k candidates of one kind maximizing the objective (mean over the archives, \
             or the worst archive) of the seconds at least one is legible; upper_bound_s bounds every k-set's \
             objective (equal to it when exhaustive), gap_s = upper_bound_s - the set's objective",
        ],
    });
    Placement { document, candidates, combinations, footprints: BTreeMap::new(), vehicle_model: None }
}

/// The files written.
#[derive(Debug, Clone)]
pub struct WrittenPlacement {
    pub json: PathBuf,
    pub csv: PathBuf,
    pub combinations_csv: PathBuf,
    /// `placement.png` and `placement-views/`, when a vehicle model is known.
    pub picture: Option<WrittenPicture>,
}

/// Writes the three files into `out` (created if missing), and the
/// picture of the chosen sets when a vehicle model is known.
pub fn write_placement(placement: &Placement, out: &Path) -> Result<WrittenPlacement> {
    std::fs::create_dir_all(out).map_err(|e| Error::io(out, e))?;
    let written = WrittenPlacement {
        json: out.join("placement.json"),
        csv: out.join("placement.csv"),
        combinations_csv: out.join("placement-combinations.csv"),
        picture: None,
    };
    let text = serde_json::to_string_pretty(&placement.document)
        .map_err(|e| Error::bad_file(&written.json, format!("cannot write JSON: {e}")))?;
    write_atomically(&written.json, |w| writeln!(w, "{text}"))?;
    write_atomically(&written.csv, |w| write_candidates(w, &placement.candidates))?;
    write_atomically(&written.combinations_csv, |w| write_combinations(w, &placement.combinations))?;
    let picture = match &placement.vehicle_model {
        Some(path) => {
            let model = crate::archive::VehicleModel::read(path)?;
            let sets = pictured_sets(&placement.combinations, &placement.footprints);
            Some(write_placement_picture(&model, &sets, out)?)
        }
        None => None,
    };
    Ok(WrittenPlacement { picture, ..written })
}

fn optional(value: Option<f64>) -> String {
    value.map(|v| v.to_string()).unwrap_or_default()
}

fn write_candidates(w: &mut impl Write, candidates: &[CandidateSummary]) -> std::io::Result<()> {
    writeln!(
        w,
        "rank,candidate,kind,legible_s,visible_s,first_legible_s,first_legible_distance_m,\
         decision_window_legible_s,worst_case_legible_s"
    )?;
    for (rank, c) in candidates.iter().enumerate() {
        writeln!(
            w,
            "{},{},{},{},{},{},{},{},{}",
            rank + 1,
            crate::output::csv_field(&c.name),
            c.kind,
            c.legible_s,
            c.visible_s,
            optional(c.first_legible_s),
            optional(c.first_legible_distance_m),
            c.decision_window_legible_s,
            c.worst_case_legible_s
        )?;
    }
    Ok(())
}

fn write_combinations(w: &mut impl Write, combinations: &[Combination]) -> std::io::Result<()> {
    writeln!(
        w,
        "k,kind,objective,method,candidates,legible_s,share_of_time,worst_case_s,upper_bound_s,gap_s"
    )?;
    for c in combinations {
        writeln!(
            w,
            "{},{},{},{},{},{},{},{},{},{}",
            c.k,
            c.kind,
            objective_name(c.objective),
            if c.method == crate::placement::Method::Exhaustive { "exhaustive" } else { "greedy" },
            crate::output::csv_field(&c.candidates.join(" + ")),
            c.legible_s,
            c.share_of_time,
            c.worst_case_s,
            c.upper_bound_s,
            c.gap_s
        )?;
    }
    Ok(())
}

fn objective_name(objective: Objective) -> &'static str {
    match objective {
        Objective::Mean => "mean",
        Objective::WorstCase => "worst_case",
    }
}

/// The console summary: the `top` best candidates and every chosen set.
pub fn format_placement(placement: &Placement, top: usize) -> String {
    let mut out = String::from(
        "candidate                                  kind   legible s  visible s  first legible s  (mean over archives)\n",
    );
    for c in placement.candidates.iter().take(top) {
        let first = c.first_legible_s.map_or("never".to_string(), |s| format!("{s:.3}"));
        out += &format!(
            "{:<42} {:<6} {:>9.3}  {:>9.3}  {:>15}\n",
            c.name, c.kind, c.legible_s, c.visible_s, first
        );
    }
    out += "\nbest sets (seconds at least one is legible; share of the archive's time; bound on any k-set)\n";
    for c in &placement.combinations {
        out += &format!(
            "k={} {:<5} {:<10} {:<10} {:>8.3} s  {:>5.1} %  worst {:>7.3} s  bound {:>7.3} s  {}\n",
            c.k,
            c.kind,
            objective_name(c.objective),
            if c.method == crate::placement::Method::Exhaustive { "exhaustive" } else { "greedy" },
            c.legible_s,
            100.0 * c.share_of_time,
            c.worst_case_s,
            c.upper_bound_s,
            c.candidates.join(" + ")
        );
    }
    out
}
