//! Where should the eHMI go (issue 18): from each archive's
//! `placement-frames.csv` (per candidate placement and eye-frame: visible
//! solid angle, visible fraction, viewing angle, visible angular height;
//! written by the capture's exact measure), which candidates are *legible*
//! for how long, and the best one, two, three … placements across
//! scenarios. `ufcsr-analyze placement RESULTS… --out DIR` writes
//! `placement.json` (schema `ufcsr-placement/1`), `placement.csv` and
//! `placement-combinations.csv`, and with a vehicle model (the archive's
//! `vehicle.glb`, or `--mesh`) `placement.png`, the chosen placements on the
//! vehicle; `docs/placement.md` says what every number means and where the
//! default thresholds come from.
//!
//! The folder: [`table`] reads and checks a table, [`legibility`] the
//! thresholds and per-candidate timelines, [`choices`] what is chosen among
//! (pairs with `--symmetric`), [`search`] exhaustive and greedy search with
//! its bound, [`report`] the files written, [`footprints`] where each patch
//! lies and [`picture`] the chosen placements drawn on the vehicle.

pub mod choices;
pub mod footprints;
pub mod legibility;
pub mod picture;
pub mod report;
pub mod search;
pub mod table;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use crate::error::{Error, Result};
pub use footprints::{PLACEMENT_PATCHES_COLUMNS, PLACEMENT_PATCHES_FILE, PatchFootprint, read_footprints};
pub use legibility::{Exposure, EyeRule, Thresholds, timelines};
pub use picture::{Mark, PLACEMENT_PICTURE_FILE, PLACEMENT_VIEWS_DIR, PicturedSet, render_marked};
pub use report::{CandidateSummary, PLACEMENT_SCHEMA, Placement, write_placement};
pub use search::{Combination, EXHAUSTIVE_LIMIT, Method, Objective, brute_force_best};
pub use table::{
    CandidateKind, PLACEMENT_FRAMES_COLUMNS, PLACEMENT_FRAMES_FILE, PlacementTable, read_table, resolve_table,
};

/// The most placements in one set (`--k`).
pub const MAX_K: usize = 8;

/// What `ufcsr-analyze placement` is asked.
#[derive(Debug, Clone)]
pub struct PlacementOptions {
    /// Tables, or folders holding `placement-frames.csv` (or `results/` of one).
    pub inputs: Vec<PathBuf>,
    pub thresholds: Thresholds,
    /// Sets of 1 to k placements are searched.
    pub k: usize,
    /// A left/right pair counts as one choice.
    pub symmetric: bool,
    /// At most this many k-sets are searched exhaustively, beyond it greedy
    /// with a bound ([`EXHAUSTIVE_LIMIT`]; 0 forces greedy).
    pub exhaustive_limit: u128,
    /// The vehicle model for the picture; `None`: the archive's `vehicle.glb`
    /// when there is one.
    pub mesh: Option<PathBuf>,
}

impl PlacementOptions {
    /// `inputs` with the default thresholds, k = 3, no symmetry.
    pub fn new(inputs: Vec<PathBuf>) -> PlacementOptions {
        PlacementOptions {
            inputs,
            thresholds: Thresholds::default(),
            k: 3,
            symmetric: false,
            exhaustive_limit: EXHAUSTIVE_LIMIT,
            mesh: None,
        }
    }
}

/// Reads every table, scores every candidate and searches the best sets.
pub fn placement(options: &PlacementOptions) -> Result<Placement> {
    options.thresholds.check()?;
    if !(1..=MAX_K).contains(&options.k) {
        return Err(Error::BadOptions(format!("--k {}: must be 1 to {MAX_K}", options.k)));
    }
    if options.inputs.is_empty() {
        return Err(Error::BadOptions("placement needs at least one result folder or table".into()));
    }
    let mut archives = Vec::with_capacity(options.inputs.len());
    let mut footprints = BTreeMap::new();
    let mut vehicle_model = options.mesh.clone();
    for input in &options.inputs {
        let path = resolve_table(input)?;
        footprints.extend(read_footprints(&path)?);
        vehicle_model = vehicle_model.or_else(|| vehicle_beside(&path));
        let table = read_table(&path)?;
        if table.rendered && options.thresholds.min_solid_angle_sr.is_none() {
            return Err(Error::bad_file(
                &path,
                "a rendered frames.csv holds solid angles only (no visible fraction, view angle or angular \
                 height): score it with --min-solid-angle-sr (docs/placement.md §5)",
            ));
        }
        archives.push(timelines(table, &options.thresholds));
    }
    let universe = search::Universe::of(&archives);
    let mut combinations = Vec::new();
    for kind in [CandidateKind::Part, CandidateKind::Patch] {
        let choices = choices::choices(&archives, &universe, kind, options.symmetric);
        for k in 1..=options.k.min(choices.len()) {
            for objective in [Objective::Mean, Objective::WorstCase] {
                if objective == Objective::WorstCase && archives.len() == 1 {
                    continue;
                }
                combinations.extend(search::best_set(
                    &universe,
                    &choices,
                    k,
                    objective,
                    options.exhaustive_limit,
                ));
            }
        }
    }
    let mut placement = report::assemble(options, archives, combinations);
    placement.footprints = footprints;
    placement.vehicle_model = vehicle_model;
    Ok(placement)
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
