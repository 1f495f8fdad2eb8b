//! The placement files: `placement.json` (the typed
//! [`PlacementDocument`], schema `ufcsr-placement/2`,
//! `docs/schemas/placement.schema.json`), `placement.csv` (one row per
//! candidate, best first) and `placement-combinations.csv` (one row per
//! chosen set), and the console summary. Every number says what it is in
//! its name and unit; `docs/placement.md` defines them. In every output a
//! set states `k` as physical displays and marks the members that add no
//! legible time.

use std::collections::BTreeMap;
use std::io::Write;
use std::path::{Path, PathBuf};

use crate::error::{Error, Result};
use crate::files::write_atomically;
pub use crate::format::placement::PLACEMENT_SCHEMA;
pub(crate) use crate::format::placement::{
    ArchiveRecord, CandidateKind, CandidateRecord, CombinationRecord, MemberRecord, PlacementDocument,
    SensitivityRecord, Sources, ThresholdsRecord, UncertaintyRecord,
};
use crate::placement::footprints::PatchFootprint;
use crate::placement::legibility::{
    ArchiveTimelines, CHARACTER_ARCMIN_SOURCE, CHARACTER_HEIGHT_SOURCE, CHARACTER_PITCH, CHARACTERS_SOURCE,
    DECISION_WINDOW_SOURCE, DWELL_SOURCE, Exposure, VIEW_ANGLE_SOURCE, VISIBLE_FRACTION_SOURCE,
};
use crate::placement::picture::{WrittenPicture, pictured_sets, write_placement_picture};
use crate::placement::regions::{NOT_MOUNTABLE_SOURCE, REGION_RADIUS_SOURCE};
use crate::placement::search::{Objective, Universe, displays, union_of};
use crate::placement::uncertainty::{CONFIDENCE, assess};
use crate::placement::{PlacementOptions, Scoring, Searched};

/// Everything `ufcsr placement` found.
#[derive(Debug, Clone)]
pub struct Placement {
    pub document: PlacementDocument,
    /// The patches' footprints the capture recorded, by name.
    pub footprints: BTreeMap<String, PatchFootprint>,
    /// The vehicle model the picture is drawn on, when one is known.
    pub vehicle_model: Option<PathBuf>,
    /// Every file the answer was read from (the tables and their
    /// footprints): [`write_placement`] never writes over one.
    pub inputs: Vec<PathBuf>,
}

impl CombinationRecord {
    /// Every candidate of the set (a pair gives both), in member order.
    pub fn candidates(&self) -> Vec<String> {
        self.members.iter().flat_map(|m| m.candidates.clone()).collect()
    }

    /// The members joined by " + ", each that adds no legible time marked;
    /// [`NO_SET_LEGIBLE`] when the set is legible for no time at all (a best of
    /// nothing names no candidate).
    pub fn members_text(&self) -> String {
        if self.legible_s <= 0.0 {
            return NO_SET_LEGIBLE.to_string();
        }
        self.members.iter().map(MemberRecord::label).collect::<Vec<_>>().join(" + ")
    }
}

/// What a best set legible for 0 s prints instead of its (arbitrary) members.
pub const NO_SET_LEGIBLE: &str = "none: no candidate of this kind is legible (0 s)";

impl MemberRecord {
    /// The member's candidates joined by " & ", marked "[adds 0 s]" when it adds no legible time.
    pub fn label(&self) -> String {
        let names = self.candidates.join(" & ");
        if self.adds_no_time { format!("{names} [adds 0 s]") } else { names }
    }
}

fn candidate_records(main: &Scoring) -> Vec<CandidateRecord> {
    let archives = &main.archives;
    let mut per_name: BTreeMap<String, (&crate::placement::legibility::Timeline, Vec<Exposure>)> =
        BTreeMap::new();
    for archive in archives {
        for timeline in &archive.timelines {
            per_name.entry(timeline.name.clone()).or_insert((timeline, Vec::new()));
        }
    }
    let never = Exposure {
        legible_s: 0.0,
        visible_s: 0.0,
        first_legible_s: None,
        first_legible_distance_m: None,
        decision_window_legible_s: 0.0,
        texel_sample_interval_s: None,
    };
    for (index, archive) in archives.iter().enumerate() {
        let brackets = main.brackets.get(index).and_then(Option::as_ref);
        let exposure = |t: &crate::placement::legibility::Timeline| Exposure {
            texel_sample_interval_s: brackets.and_then(|b| b.get(&t.name)).copied(),
            ..archive.exposure(t)
        };
        let seen: BTreeMap<&str, Exposure> =
            archive.timelines.iter().map(|t| (t.name.as_str(), exposure(t))).collect();
        for (name, (_, exposures)) in per_name.iter_mut() {
            exposures.push(seen.get(name.as_str()).copied().unwrap_or(never));
        }
    }
    let mut members: BTreeMap<&str, usize> = BTreeMap::new();
    for representative in main.regions.values() {
        *members.entry(representative).or_default() += 1;
    }
    let n = archives.len().max(1) as f64;
    let not_mountable = crate::placement::eligible::not_mountable(&main.excluded);
    let mut through: BTreeMap<String, String> = BTreeMap::new();
    for timeline in archives.iter().flat_map(|a| &a.timelines) {
        if let crate::placement::eligible::Fit::Through(patch) = &timeline.fit {
            through.entry(timeline.name.clone()).or_insert_with(|| patch.clone());
        }
    }
    let mut out: Vec<CandidateRecord> = per_name
        .into_iter()
        .map(|(name, (timeline, per_archive))| {
            let sum = |f: fn(&Exposure) -> f64| per_archive.iter().map(f).sum::<f64>() / n;
            let all_legible = per_archive.iter().all(|e| e.first_legible_s.is_some());
            let region = main.regions.get(&name).filter(|r| **r != name).cloned();
            let region_members =
                if region.is_some() { 0 } else { members.get(name.as_str()).copied().unwrap_or(1) };
            CandidateRecord {
                kind: timeline.kind,
                display_size_m: timeline.size_m,
                mountable: !not_mountable.contains(name.as_str()),
                region,
                region_members: region_members.max(1),
                legible_s: sum(|e| e.legible_s),
                visible_s: sum(|e| e.visible_s),
                first_legible_s: all_legible
                    .then(|| per_archive.iter().filter_map(|e| e.first_legible_s).fold(f64::MIN, f64::max)),
                first_legible_distance_m: all_legible.then(|| {
                    per_archive.iter().filter_map(|e| e.first_legible_distance_m).fold(f64::MAX, f64::min)
                }),
                decision_window_legible_s: sum(|e| e.decision_window_legible_s),
                worst_case_legible_s: per_archive.iter().map(|e| e.legible_s).fold(f64::MAX, f64::min),
                texel_sample_interval_s: mean_bracket(&per_archive),
                per_archive,
                legible_through: through.get(name.as_str()).cloned(),
                name,
            }
        })
        .collect();
    out.sort_by(|a, b| b.legible_s.total_cmp(&a.legible_s).then_with(|| a.name.cmp(&b.name)));
    out
}

/// The mean of the archives' texel-sample brackets, when every archive has one.
fn mean_bracket(per_archive: &[Exposure]) -> Option<[f64; 2]> {
    let brackets: Option<Vec<[f64; 2]>> = per_archive.iter().map(|e| e.texel_sample_interval_s).collect();
    let brackets = brackets.filter(|b| !b.is_empty())?;
    let n = brackets.len() as f64;
    Some([brackets.iter().map(|b| b[0]).sum::<f64>() / n, brackets.iter().map(|b| b[1]).sum::<f64>() / n])
}

fn archive_records(archives: &[ArchiveTimelines], window_s: f64) -> Vec<ArchiveRecord> {
    archives
        .iter()
        .map(|a| ArchiveRecord {
            table: a.table.path.display().to_string(),
            frames: a.table.frames.len(),
            eyes: a.table.eyes.clone(),
            seconds_per_frame: a.table.frame_s,
            duration_s: a.duration_s(),
            arrival_s: a.arrival_s,
            decision_window_s: [a.arrival_s - window_s, a.arrival_s],
            warning: None,
        })
        .collect()
}

/// A found set as a record: members with what each adds, the scores and,
/// for the mean, the interval, P(best) and runners-up.
pub(crate) fn combination_record(
    universe: &Universe,
    searched: &Searched,
    options: &PlacementOptions,
) -> CombinationRecord {
    let Searched { kind, k, objective, choices, found } = searched;
    let picked = &found.picked;
    let seconds = universe.seconds(&union_of(universe, choices, picked));
    let shares: Vec<f64> =
        seconds.iter().zip(&universe.duration_s).map(|(&s, &d)| if d > 0.0 { s / d } else { 0.0 }).collect();
    let total = universe.mean(&seconds);
    let members = picked
        .iter()
        .map(|&member| {
            let others: Vec<usize> = picked.iter().copied().filter(|&c| c != member).collect();
            let adds_s = total - universe.score(choices, &others, Objective::Mean).0;
            MemberRecord {
                candidates: choices[member].names.clone(),
                displays: choices[member].displays(),
                adds_s,
                adds_no_time: adds_s <= 1e-12,
            }
        })
        .collect();
    let achieved = universe.value(*objective, &seconds).0;
    let upper = found.bound.unwrap_or(achieved).max(achieved);
    let assessment = (*objective == Objective::Mean)
        .then(|| assess(universe, choices, found, *k, options.exhaustive_limit, &options.resampling));
    CombinationRecord {
        k: *k,
        displays: displays(choices, picked),
        kind: *kind,
        objective: *objective,
        method: found.method,
        members,
        legible_s: total,
        interval_s: assessment.as_ref().and_then(|a| a.interval_s),
        p_best: assessment.as_ref().and_then(|a| a.p_best),
        p_within_epsilon: assessment.as_ref().and_then(|a| a.p_within_epsilon),
        share_of_time: universe.mean(&shares),
        worst_case_s: universe.worst(&seconds),
        per_archive_s: seconds,
        upper_bound_s: upper,
        gap_s: upper - achieved,
        tied_with: assessment
            .as_ref()
            .map(|a| {
                a.tied_with
                    .iter()
                    .map(|set| set.iter().flat_map(|&c| choices[c].names.clone()).collect())
                    .collect()
            })
            .unwrap_or_default(),
        p_best_note: assessment.as_ref().and_then(|a| a.note).map(String::from),
        runners_up: assessment.map(|a| a.runners_up).unwrap_or_default(),
    }
}

fn thresholds_record(options: &PlacementOptions) -> ThresholdsRecord {
    let t = &options.thresholds;
    ThresholdsRecord {
        min_character_height_arcmin: t.min_character_height_arcmin,
        character_height: t.character_height,
        min_characters: t.min_characters,
        character_pitch: CHARACTER_PITCH,
        min_visible_fraction: t.min_visible_fraction,
        max_view_angle_deg: t.max_view_angle_deg,
        min_dwell_s: t.min_dwell_s,
        decision_window_s: t.decision_window_s,
        eyes: t.eyes,
        min_solid_angle_sr: t.min_solid_angle_sr,
        symmetric: options.symmetric,
        not_mountable: options.not_mountable.clone(),
        region_radius_m: options.region_radius_m,
        sources: Sources {
            min_character_height_arcmin: CHARACTER_ARCMIN_SOURCE.into(),
            character_height: CHARACTER_HEIGHT_SOURCE.into(),
            min_characters: CHARACTERS_SOURCE.into(),
            min_visible_fraction: VISIBLE_FRACTION_SOURCE.into(),
            max_view_angle_deg: VIEW_ANGLE_SOURCE.into(),
            min_dwell_s: DWELL_SOURCE.into(),
            decision_window_s: DECISION_WINDOW_SOURCE.into(),
            not_mountable: NOT_MOUNTABLE_SOURCE.into(),
            region_radius_m: REGION_RADIUS_SOURCE.into(),
        },
    }
}

/// What placement.json says of the intervals and probabilities.
pub(crate) const UNCERTAINTY_METHOD: &str = "interval_s: Student's t 95 % interval of the mean over the archives of the \
     set's legible seconds (the archives are the random units: scenarios, observers, texel-sample seeds; frames \
     and eyes inside an archive are not); p_best: share of bootstrap replicates over the archives (n drawn with \
     replacement) whose re-run search gives this set; p_within_epsilon: share in which it is at most epsilon_s \
     below the replicate's best; exact ties share P(best) (each of t tied sets 1/t per replicate; tied_with \
     names them); no P(best) with one archive (n/a: one unit) or when the best set is legible 0 s (no candidate \
     legible); runners_up: other sets of at most k displays with legible_s inside the interval (docs/placement.md \
     section 2)";

/// The report from the scored archives and the chosen sets.
pub(crate) fn assemble(
    options: &PlacementOptions,
    main: &Scoring,
    combinations: Vec<CombinationRecord>,
    sensitivity: Vec<SensitivityRecord>,
) -> Placement {
    let document = PlacementDocument {
        schema: PLACEMENT_SCHEMA.to_string(),
        archives: archive_records(&main.archives, options.thresholds.decision_window_s),
        thresholds: thresholds_record(options),
        uncertainty: UncertaintyRecord {
            units: "archives".into(),
            archives: main.archives.len(),
            confidence: CONFIDENCE,
            replicates: options.resampling.replicates,
            seed: options.resampling.seed,
            epsilon_s: options.resampling.epsilon_s,
            method: UNCERTAINTY_METHOD.into(),
        },
        candidates: candidate_records(main),
        combinations,
        sensitivity,
        excluded: main.excluded.clone(),
        notes: vec![
            "legible_s, visible_s and decision_window_legible_s are means over the archives of seconds (legible \
             frames x seconds per frame); a frame is legible when the candidate's characters are legible to the \
             eyes the 'eyes' threshold names, inside a run of at least min_dwell_s; first_legible_s is the latest \
             first legible sighting over the archives"
                .into(),
            "combinations: per kind, the set of at most k physical displays (a symmetric pair is two) of mountable \
             candidates, one per region, maximizing the objective (mean over the archives, or the worst archive) \
             of the seconds at least one is legible; members with adds_no_time add nothing to the others; \
             upper_bound_s bounds every such set's objective (equal to it when exhaustive)"
                .into(),
        ],
    };
    Placement { document, footprints: BTreeMap::new(), vehicle_model: None, inputs: Vec::new() }
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
    let written = WrittenPlacement {
        json: out.join("placement.json"),
        csv: out.join("placement.csv"),
        combinations_csv: out.join("placement-combinations.csv"),
        picture: None,
    };
    // An input table named placement.csv, or a --mesh named placement.json,
    // is refused before anything is written, never replaced.
    let outputs = [
        written.json.clone(),
        written.csv.clone(),
        written.combinations_csv.clone(),
        out.join(crate::placement::PLACEMENT_PICTURE_FILE),
        out.join(crate::placement::picture::PLACEMENT_PDF_FILE),
    ];
    let inputs: Vec<PathBuf> = placement.inputs.iter().chain(&placement.vehicle_model).cloned().collect();
    crate::files::refuse_overwriting_inputs(&outputs, &inputs)?;
    // The vehicle model is read (and a bad --mesh refused) before anything
    // is written (issue 41: the tables used to be written first).
    let model = placement.vehicle_model.as_deref().map(crate::archive::VehicleModel::read).transpose()?;
    crate::files::create_output_dir(out)?;
    let text = serde_json::to_string_pretty(&placement.document)
        .map_err(|e| Error::bad_file(&written.json, format!("cannot write JSON: {e}")))?;
    write_atomically(&written.json, |w| writeln!(w, "{text}"))?;
    write_atomically(&written.csv, |w| write_candidates(w, &placement.document.candidates))?;
    write_atomically(&written.combinations_csv, |w| write_combinations(w, &placement.document.combinations))?;
    // The picture of an earlier run (placement.png, placement-views/) goes:
    // it showed sets this answer may not choose, or a run without a
    // vehicle model would leave it beside the new files.
    let stale_files = [
        crate::placement::PLACEMENT_PICTURE_FILE,
        crate::placement::picture::PLACEMENT_PDF_FILE,
        crate::placement::PLACEMENT_VIEWS_DIR,
    ];
    for stale in stale_files {
        crate::files::remove_inside(out, &out.join(stale))?;
    }
    let picture = match &model {
        Some(model) => {
            let sets = pictured_sets(&placement.document.combinations, &placement.footprints);
            Some(write_placement_picture(model, &sets, out)?)
        }
        None => None,
    };
    Ok(WrittenPlacement { picture, ..written })
}

fn optional(value: Option<f64>) -> String {
    value.map(|v| v.to_string()).unwrap_or_default()
}

fn write_candidates(w: &mut impl Write, candidates: &[CandidateRecord]) -> std::io::Result<()> {
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
            c.kind.name(),
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

fn write_combinations(w: &mut impl Write, combinations: &[CombinationRecord]) -> std::io::Result<()> {
    writeln!(
        w,
        "k,kind,objective,method,candidates,legible_s,share_of_time,worst_case_s,upper_bound_s,gap_s"
    )?;
    for c in combinations {
        writeln!(
            w,
            "{},{},{},{},{},{},{},{},{},{}",
            c.k,
            c.kind.name(),
            c.objective.name(),
            c.method.name(),
            crate::output::csv_field(&c.members_text()),
            c.legible_s,
            c.share_of_time,
            c.worst_case_s,
            c.upper_bound_s,
            c.gap_s
        )?;
    }
    Ok(())
}

fn interval_text(c: &CombinationRecord) -> String {
    let interval = c
        .interval_s
        .map_or("one archive: no interval".to_string(), |[low, high]| format!("95 % {low:.2}-{high:.2} s"));
    let p = match (c.p_best, c.p_within_epsilon, &c.p_best_note) {
        (Some(p), Some(within), _) => format!(", P(best) {p:.2}, P(within eps) {within:.2}"),
        (_, _, Some(note)) => format!(", P(best) {note}"),
        _ => String::new(),
    };
    let tied = if c.tied_with.is_empty() {
        String::new()
    } else {
        let sets: Vec<String> = c.tied_with.iter().map(|s| s.join(" & ")).collect();
        format!("\n    tied (exactly as legible, P(best) shared): {}", sets.join("; "))
    };
    format!("{interval}{p}{tied}")
}

/// The console summary: the `top` best candidates, every chosen set (k in
/// physical displays, members adding nothing marked, the interval and
/// P(best) with the runners-up), and the thresholds whose step changes a set.
pub fn format_placement(placement: &Placement, top: usize) -> String {
    let document = &placement.document;
    let mut out = String::from(
        "candidate                                            kind   legible s  visible s  first legible s  (mean over archives)\n",
    );
    let sampled =
        document.candidates.iter().any(|c| c.texel_sample_interval_s.is_some_and(|[lo, hi]| hi > lo));
    // One line per place: a region's first patch; not-mountable patches only in placement.csv.
    let listed = |c: &&CandidateRecord| c.region.is_none() && (c.mountable || c.kind == CandidateKind::Part);
    for c in document.candidates.iter().filter(listed).take(top) {
        let first = c.first_legible_s.map_or("never".to_string(), |s| format!("{s:.3}"));
        let no_fit = document.excluded.iter().any(|e| {
            e.candidate == c.name && e.reason == crate::placement::eligible::ExclusionReason::NoDisplayFits
        });
        let mut note = match (c.mountable, c.region_members) {
            (false, _) => " (not mountable)".to_string(),
            (true, _) if no_fit => " (no display fits: exposure only)".to_string(),
            (true, n) if n > 1 => format!(" (region of {n})"),
            _ => String::new(),
        };
        if let (true, Some([lo, hi])) = (sampled, c.texel_sample_interval_s) {
            note += &format!(" texel sample {lo:.3}–{hi:.3} s");
        }
        out += &format!(
            "{:<52} {:<6} {:>9.3}  {:>9.3}  {:>15}{note}\n",
            c.name,
            c.kind.name(),
            c.legible_s,
            c.visible_s,
            first
        );
    }
    out += &format!(
        "\nbest sets of at most k physical displays (a symmetric pair is two); seconds at least one is legible, \
         mean over {} archive(s); [adds 0 s]: a member that adds no legible time\n",
        document.archives.len()
    );
    for c in &document.combinations {
        out += &format!(
            "k={} ({} displays) {:<5} {:<10} {:<10} {:>7.3} s  {:>5.1} %  worst {:>6.3} s  bound {:>6.3} s  {}\n",
            c.k,
            c.displays,
            c.kind.name(),
            c.objective.name(),
            c.method.name(),
            c.legible_s,
            100.0 * c.share_of_time,
            c.worst_case_s,
            c.upper_bound_s,
            c.members_text()
        );
        if c.objective == Objective::Mean {
            out += &format!("    {}\n", interval_text(c));
            for r in &c.runners_up {
                let p = r.p_best.map_or(String::new(), |p| format!(", P(best) {p:.2}"));
                out += &format!(
                    "    runner-up {:.3} s ({} displays{p}): {}\n",
                    r.legible_s,
                    r.displays,
                    r.candidates.join(" + ")
                );
            }
        }
    }
    let excluded = crate::placement::eligible::excluded_line(&document.excluded);
    if !excluded.is_empty() {
        out += &format!("\n{excluded}\n");
    }
    for warning in crate::format::placement::warning_lines(&document.archives) {
        out += &format!("\n{warning}\n");
    }
    out += &sensitivity_text(document);
    out
}

fn sensitivity_text(document: &PlacementDocument) -> String {
    let flips: Vec<String> = document
        .sensitivity
        .iter()
        .flat_map(|step| {
            step.sets.iter().filter(|s| !s.same_set).map(move |s| {
                format!(
                    "    {} = {}: best {} of {} changes to {} ({:.3} s; the reported set {:.3} s)\n",
                    step.threshold,
                    step.value,
                    s.kind.name(),
                    s.k,
                    s.candidates.join(" + "),
                    s.legible_s,
                    s.reported_set_legible_s
                )
            })
        })
        .collect();
    let steps = document.sensitivity.len();
    if flips.is_empty() {
        format!(
            "\nsensitivity: with each of {steps} threshold steps (one step down and up) every best set stays\n"
        )
    } else {
        format!(
            "\nsensitivity: {} of the best sets change under one threshold step:\n{}",
            flips.len(),
            flips.concat()
        )
    }
}
