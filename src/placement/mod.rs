//! Where should the eHMI go (issue 18): from each archive's
//! `placement-frames.csv` (per candidate placement and eye-frame: visible
//! solid angle, visible fraction, viewing angle, visible angular height;
//! written by the capture's exact measure), which candidates are *legible*
//! for how long, and the best one, two, three … placements across
//! scenarios, with how sure that answer is. `ufcsr placement
//! RESULTS… --out DIR` writes `placement.json` (schema `ufcsr-placement/2`,
//! the type [`crate::format::placement::PlacementDocument`]), `placement.csv` and
//! `placement-combinations.csv`, and with a vehicle model (the archive's
//! `vehicle.glb`, or `--mesh`) `placement.png`, the chosen placements on the
//! vehicle; `docs/placement.md` says what every number means and where the
//! default thresholds come from.
//!
//! The folder: [`table`] reads and checks a table, [`legibility`] the
//! thresholds and per-candidate timelines, [`choices`] what is chosen among
//! (pairs with `--symmetric`), [`eligible`] the one rule of which
//! candidates may be an answer (a display must fit; mountable surfaces),
//! [`regions`] one patch per region of near patches, [`search`]
//! exhaustive and greedy search of at most k physical displays with its
//! bound, [`uncertainty`] the interval, P(best) and runners-up,
//! [`sensitivity`] the answer with each threshold one step off,
//! [`texel_sample`] the bracket one archive's texel sample puts on each
//! candidate's legible seconds, [`report`]
//! the files written, [`footprints`] where each patch lies, [`picture`]
//! the chosen placements drawn on the vehicle and [`literature`] the
//! places published studies tested, scored as named candidates.

pub(crate) mod choices;
pub(crate) mod eligible;
pub(crate) mod footprints;
pub(crate) mod legibility;
pub(crate) mod literature;
pub(crate) mod picture;
pub(crate) mod regions;
pub(crate) mod report;
pub(crate) mod search;
pub(crate) mod sensitivity;
pub(crate) mod table;
pub(crate) mod texel_sample;
pub(crate) mod uncertainty;

pub use eligible::{Fit, default_exclusions, default_not_mountable, excluded_line, exclusions};
pub use legibility::{ArchiveTimelines, Timeline};
pub use literature::{
    LocationScore, PUBLISHED_LOCATIONS, PUBLISHED_LOCATIONS_FILE, PlaceScore, PublishedLocation, Zone,
    format_published_locations, published_locations, write_published_locations,
};
pub use report::{NO_SET_LEGIBLE, WrittenPlacement, format_placement};
pub use uncertainty::{
    BestShares, NO_CANDIDATE_LEGIBLE, ONE_UNIT, best_shares, bootstrap_weights, t_interval,
    t_interval_signed, tied as tied_scores, tied_best_credits,
};

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use crate::error::{Error, Result};
use crate::format::placement::{CombinationRecord, SensitivitySet};
pub use footprints::{
    PLACEMENT_PATCHES_COLUMNS, PLACEMENT_PATCHES_FILE, PatchFootprint, covers_field, read_footprints,
};
pub use legibility::{CharacterHeight, Exposure, EyeRule, Thresholds, parse_character_height, timelines};
pub use picture::{Mark, PLACEMENT_PICTURE_FILE, PLACEMENT_VIEWS_DIR, PicturedSet, render_marked};
pub use regions::{DEFAULT_NOT_MOUNTABLE, DEFAULT_REGION_RADIUS_M, mountable};
pub use report::{PLACEMENT_SCHEMA, Placement, write_placement};
use search::{Choice, Found, Universe};
pub use search::{EXHAUSTIVE_LIMIT, Method, Objective, brute_force_best};
pub use table::{
    CandidateKind, PLACEMENT_FRAMES_COLUMNS, PLACEMENT_FRAMES_FILE, PlacementTable, read_table, resolve_table,
};
pub use uncertainty::{DEFAULT_EPSILON_S, DEFAULT_REPLICATES, Resampling};

/// The most physical displays in one set (`--k`).
pub const MAX_K: usize = 8;

/// What `ufcsr placement` is asked.
#[derive(Debug, Clone)]
pub struct PlacementOptions {
    /// Tables, or folders holding `placement-frames.csv` (or `results/` of one).
    pub inputs: Vec<PathBuf>,
    pub thresholds: Thresholds,
    /// Sets of at most 1 to k physical displays are searched.
    pub k: usize,
    /// A left/right pair is chosen together (two displays).
    pub symmetric: bool,
    /// At most this many sets are searched exhaustively, beyond it greedy
    /// with a bound ([`EXHAUSTIVE_LIMIT`]; 0 forces greedy).
    pub exhaustive_limit: u128,
    /// Head nouns of surfaces where no display is mounted ([`regions`]).
    pub not_mountable: Vec<String>,
    /// Patches of one part within this many metres are one region (0: off).
    pub region_radius_m: f64,
    /// The bootstrap behind P(best).
    pub resampling: Resampling,
    /// The vehicle model for the picture; `None`: the archive's `vehicle.glb`
    /// when there is one.
    pub mesh: Option<PathBuf>,
}

impl PlacementOptions {
    /// `inputs` with the default thresholds and rules, k = 3, no symmetry.
    pub fn new(inputs: Vec<PathBuf>) -> PlacementOptions {
        PlacementOptions {
            inputs,
            thresholds: Thresholds::default(),
            k: 3,
            symmetric: false,
            exhaustive_limit: EXHAUSTIVE_LIMIT,
            not_mountable: DEFAULT_NOT_MOUNTABLE.iter().map(|s| s.to_string()).collect(),
            region_radius_m: DEFAULT_REGION_RADIUS_M,
            resampling: Resampling::default(),
            mesh: None,
        }
    }

    fn pairing(&self) -> choices::Pairing {
        if self.symmetric { choices::Pairing::Symmetric } else { choices::Pairing::Single }
    }

    /// The options' own errors (bad thresholds, k, radius, resampling), before
    /// any table is read: `ufcsr where` asks before it measures.
    pub fn check(&self) -> Result<()> {
        self.thresholds.check()?;
        if !(1..=MAX_K).contains(&self.k) {
            return Err(Error::BadOptions(format!("--k {}: must be 1 to {MAX_K} displays", self.k)));
        }
        if self.inputs.is_empty() {
            return Err(Error::BadOptions("placement needs at least one result folder or table".into()));
        }
        if !(self.region_radius_m.is_finite() && (0.0..=10.0).contains(&self.region_radius_m)) {
            return Err(Error::BadOptions(format!(
                "--region-radius-m {}: must be 0 to 10",
                self.region_radius_m
            )));
        }
        if !(self.resampling.epsilon_s.is_finite() && self.resampling.epsilon_s >= 0.0)
            || self.resampling.replicates > 100_000
        {
            return Err(Error::BadOptions(
                "--epsilon-s must be 0 or more and --replicates at most 100000".into(),
            ));
        }
        Ok(())
    }
}

/// One search: its kind, k and objective, what it chose among and found.
pub(crate) struct Searched {
    pub kind: CandidateKind,
    pub k: usize,
    pub objective: Objective,
    /// Shared by the searches of one kind (each k and objective): one copy.
    pub choices: Arc<[Choice]>,
    pub found: Found,
}

/// The tables scored under one set of thresholds and searched.
pub(crate) struct Scoring {
    pub archives: Vec<ArchiveTimelines>,
    pub universe: Universe,
    /// Per mountable candidate, its region's ([`regions::representatives`]).
    pub regions: BTreeMap<String, String>,
    pub searched: Vec<Searched>,
    /// Per archive, each candidate's texel-sample bracket of its legible
    /// seconds ([`texel_sample`]); filled for the reported scoring only.
    pub brackets: Vec<Option<BTreeMap<String, [f64; 2]>>>,
    /// The candidates no answer may hold, and why ([`eligible::exclusions`]).
    pub excluded: Vec<eligible::ExcludedRecord>,
}

/// Mean legible seconds per candidate over the archives.
fn mean_legible(archives: &[ArchiveTimelines]) -> BTreeMap<&str, (CandidateKind, f64)> {
    let mut out: BTreeMap<&str, (CandidateKind, f64)> = BTreeMap::new();
    for archive in archives {
        for t in &archive.timelines {
            let seconds = t.legible.len() as f64 * archive.table.frame_s;
            out.entry(&t.name).or_insert((t.kind, 0.0)).1 += seconds / archives.len() as f64;
        }
    }
    out
}

fn score_and_search(
    tables: &[Arc<PlacementTable>],
    thresholds: &Thresholds,
    options: &PlacementOptions,
    footprints: &BTreeMap<String, PatchFootprint>,
    unfit: &std::collections::BTreeSet<String>,
    objectives: &[Objective],
) -> Scoring {
    let archives: Vec<ArchiveTimelines> =
        tables.iter().map(|t| legibility::timelines_with(t.clone(), thresholds, unfit)).collect();
    let universe = Universe::of(&archives);
    let legible = mean_legible(&archives);
    let scored: Vec<regions::Scored> = legible
        .iter()
        .map(|(name, (kind, legible_s))| regions::Scored { name, kind: *kind, legible_s: *legible_s })
        .collect();
    let excluded = eligible::exclusions(
        archives.iter().flat_map(|a| a.timelines.iter().map(|t| (t.name.as_str(), t.kind))),
        footprints,
        &options.not_mountable,
    );
    let left_out = excluded.iter().map(|e| e.candidate.clone()).collect();
    let regions = regions::representatives(&scored, footprints, &left_out, options.region_radius_m);
    let mut searched = Vec::new();
    for kind in [CandidateKind::Part, CandidateKind::Patch] {
        let choices: Arc<[Choice]> =
            choices::choices(&archives, &universe, kind, options.pairing(), &regions).into();
        for k in 1..=options.k {
            for &objective in objectives {
                if let Some(found) =
                    search::best_set(&universe, &choices, k, objective, options.exhaustive_limit)
                {
                    searched.push(Searched { kind, k, objective, choices: Arc::clone(&choices), found });
                }
            }
        }
    }
    Scoring { archives, universe, regions, searched, brackets: Vec::new(), excluded }
}

/// Reads every table, scores every candidate, searches the best sets and
/// says how sure each is (interval, P(best), runners-up, sensitivity).
pub fn placement(options: &PlacementOptions) -> Result<Placement> {
    options.check()?;
    let mut tables = Vec::with_capacity(options.inputs.len());
    let mut footprints = BTreeMap::new();
    let mut vehicle_model = options.mesh.clone();
    let mut seen: Vec<(PathBuf, &PathBuf)> = Vec::with_capacity(options.inputs.len());
    let mut inputs = Vec::with_capacity(2 * options.inputs.len());
    let mut counts = Vec::with_capacity(options.inputs.len());
    let mut warnings = Vec::with_capacity(options.inputs.len());
    for input in &options.inputs {
        let path = resolve_table(input)?;
        refuse_table_twice(&path, input, &mut seen)?;
        let mut own = read_footprints(&path)?;
        inputs.push(path.clone());
        inputs.push(path.with_file_name(PLACEMENT_PATCHES_FILE));
        vehicle_model = vehicle_model.or_else(|| vehicle_beside(&path));
        counts.push(texel_sample::read_sample_counts(&path)?);
        inputs.push(path.with_file_name(texel_sample::UNOBSTRUCTED_PARTS_FILE));
        let mut table = read_table(&path)?;
        table::label_sizes(&mut table, &mut own);
        warnings.push(footprints::layout_warning(
            table.candidates.values().map(|c| (c.name.as_str(), c.kind)),
            &own,
        ));
        footprints.extend(own);
        if table.rendered && options.thresholds.min_solid_angle_sr.is_none() {
            return Err(Error::bad_file(
                &path,
                "a rendered frames.csv holds solid angles only (no visible fraction, view angle or angular \
                 height): score it with --min-solid-angle-sr (docs/placement.md §5)",
            ));
        }
        tables.push(Arc::new(table));
    }
    let objectives: &[Objective] =
        if tables.len() > 1 { &[Objective::Mean, Objective::WorstCase] } else { &[Objective::Mean] };
    // Which patches stand for no part depends on the tables and the list, not the thresholds: once.
    let unfit = eligible::unfit_patches(
        tables.iter().flat_map(|t| t.candidates.values().map(|c| (c.name.as_str(), c.kind))),
        &footprints,
        &options.not_mountable,
    );
    let mut main = score_and_search(&tables, &options.thresholds, options, &footprints, &unfit, objectives);
    main.brackets = tables
        .iter()
        .zip(&counts)
        .map(|(table, counts)| {
            counts.as_ref().map(|c| texel_sample::legible_brackets(table, c, &options.thresholds, &unfit))
        })
        .collect();
    let combinations: Vec<CombinationRecord> =
        main.searched.iter().map(|s| report::combination_record(&main.universe, s, options)).collect();
    let mut sensitivity = Vec::new();
    for step in sensitivity::steps(&options.thresholds) {
        let moved =
            score_and_search(&tables, &step.thresholds, options, &footprints, &unfit, &[Objective::Mean]);
        sensitivity.push(sensitivity::record(&step, moved_sets(&main, &moved)));
    }
    let mut placement = report::assemble(options, &main, combinations, sensitivity);
    for (record, warning) in placement.document.archives.iter_mut().zip(warnings) {
        record.warning = warning;
    }
    placement.footprints = footprints;
    placement.vehicle_model = vehicle_model;
    placement.inputs = inputs;
    Ok(placement)
}

/// Errors, naming both inputs, when `input`'s table `path` is one already
/// read (the same path twice, a link to it, or `A` and `A/results`): one
/// archive scored as two would weight it twice in the mean and could flip
/// the ranking.
fn refuse_table_twice<'a>(
    path: &Path,
    input: &'a PathBuf,
    seen: &mut Vec<(PathBuf, &'a PathBuf)>,
) -> Result<()> {
    let real = crate::files::resolved(path).unwrap_or_else(|| path.to_path_buf());
    if let Some((_, first)) = seen.iter().find(|(known, _)| *known == real) {
        return Err(Error::bad_file(
            path,
            format!(
                "is given twice ({} and {} are one table): each archive counts once",
                first.display(),
                input.display()
            ),
        ));
    }
    seen.push((real, input));
    Ok(())
}

/// The best sets by the mean under moved thresholds against the reported.
fn moved_sets(main: &Scoring, moved: &Scoring) -> Vec<SensitivitySet> {
    let place = |name: &String| main.regions.get(name).unwrap_or(name).clone();
    let places = |names: &[String]| {
        let mut p: Vec<String> = names.iter().map(place).collect();
        p.sort();
        p.dedup();
        p
    };
    let names = |s: &Searched| -> Vec<String> {
        s.found.picked.iter().flat_map(|&c| s.choices[c].names.clone()).collect()
    };
    moved
        .searched
        .iter()
        .filter_map(|m| {
            let reported = main
                .searched
                .iter()
                .find(|r| r.kind == m.kind && r.k == m.k && r.objective == Objective::Mean)?;
            let candidates = names(m);
            let reported_names = names(reported);
            Some(SensitivitySet {
                kind: m.kind,
                k: m.k,
                same_set: places(&candidates) == places(&reported_names),
                legible_s: m.universe_value(&moved.universe),
                reported_set_legible_s: seconds_of(moved, &reported_names),
                candidates,
            })
        })
        .collect()
}

impl Searched {
    /// The mean legible seconds of the set found.
    pub(crate) fn universe_value(&self, universe: &Universe) -> f64 {
        universe.score(&self.choices, &self.found.picked, Objective::Mean).0
    }
}

/// The mean seconds at least one of `names` is legible in `scoring`.
fn seconds_of(scoring: &Scoring, names: &[String]) -> f64 {
    let frames = |archive: &ArchiveTimelines| -> Vec<usize> {
        let mut any: Vec<usize> = archive
            .timelines
            .iter()
            .filter(|t| names.contains(&t.name))
            .flat_map(|t| t.legible.iter().copied())
            .collect();
        any.sort_unstable();
        any.dedup();
        any
    };
    let all: Vec<Vec<usize>> = scoring.archives.iter().map(frames).collect();
    let bits = scoring.universe.bits(all.iter().map(|f| Some(f.as_slice())));
    scoring.universe.mean(&scoring.universe.seconds(&bits))
}

/// The capture's `vehicle.glb` of the archive whose table is `table`: beside
/// it or in the folder above (`ARCHIVE/results/placement-frames.csv`).
fn vehicle_beside(table: &Path) -> Option<PathBuf> {
    let folder = table.parent()?;
    [Some(folder), folder.parent()]
        .into_iter()
        .flatten()
        .map(|dir| dir.join("vehicle.glb"))
        .find(|p| p.is_file())
}
