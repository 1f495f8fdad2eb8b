//! Planning a design: read and check the file, name its cells and tasks.
//!
//! Every refusal happens here, before anything is measured, and names the
//! factor and level at fault (`vehicles[1] "bus": unknown body "buss"…`), so
//! a Slurm array never starts on a design that would fail in task 37. The
//! design hash (FNV-1a 64 of the file's canonical JSON) ties every task
//! file to the design it was run for: merge refuses any other.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

use ufcsr::{
    format::CellLevels, format::Crossing, format::DESIGN_SCHEMA, format::Design, format::ScenarioLevel,
    format::ScenarioSource, format::TrafficKind, format::TrafficLevel,
};

use crate::error::{CaptureError, Result};
use crate::scene::family::BodyType;
use crate::scene::street::{MAX_OTHER_VEHICLES, POSITIONS, StreetOptions, other_positions};

/// The most tasks one design may plan (a Slurm array's usual ceiling is far above; this bounds a typo).
pub const MAX_TASKS: usize = 100_000;
/// The most observers per task.
pub(crate) const MAX_OBSERVERS_PER_TASK: u32 = 1000;

/// One independent task: a cell and a replicate.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PlannedTask {
    pub index: u32,
    pub cell: CellLevels,
    pub replicate: u32,
}

/// A checked design and its tasks.
#[derive(Debug, Clone)]
pub struct Plan {
    pub design: Design,
    /// The design file (model and scene paths are relative to its folder).
    pub path: PathBuf,
    pub hash: String,
    pub cells: Vec<CellLevels>,
    pub tasks: Vec<PlannedTask>,
}

impl Plan {
    /// The folder the design's relative paths start from.
    pub fn base(&self) -> &Path {
        self.path.parent().unwrap_or(Path::new("."))
    }
}

/// FNV-1a, 64 bits, as 16 hex digits: a fingerprint, not a security measure.
pub(crate) fn fnv1a_hex(bytes: &[u8]) -> String {
    let mut hash: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in bytes {
        hash ^= u64::from(b);
        hash = hash.wrapping_mul(0x0000_0100_0000_01b3);
    }
    format!("{hash:016x}")
}

/// Reads, checks and plans the design file `path`.
pub fn plan_design(path: &Path) -> Result<Plan> {
    let bytes = ufcsr::files::read_limited(path, ufcsr::files::SMALL_INPUT_LIMIT)?;
    let design: Design = ufcsr::format::parse_json(path, &bytes, "design")?;
    ufcsr::format::check_version(path, &design.schema, DESIGN_SCHEMA)?;
    plan_checked(design, path)
}

/// Plans a parsed design (`path` names it in messages and roots its relative paths).
pub fn plan_checked(design: Design, path: &Path) -> Result<Plan> {
    let bad = |message: String| CaptureError::bad_file(path, message);
    check_levels(&design).map_err(bad)?;
    // Counted before any cell is listed: a small file may name a vast crossing.
    let count = cell_count(&design);
    let replicates = design.replicates;
    let tasks = count.saturating_mul(u128::from(replicates));
    if tasks > MAX_TASKS as u128 {
        return Err(bad(format!(
            "{count} cells × {replicates} replicates = {tasks} tasks: more than {MAX_TASKS}"
        )));
    }
    let cells = cells_of(&design).map_err(bad)?;
    let mut tasks = Vec::with_capacity(cells.len() * replicates as usize);
    for cell in &cells {
        for replicate in 0..replicates {
            tasks.push(PlannedTask { index: tasks.len() as u32, cell: cell.clone(), replicate });
        }
    }
    let canonical = serde_json::to_vec(&design).map_err(|e| bad(e.to_string()))?;
    Ok(Plan { hash: fnv1a_hex(&canonical), design, path: path.to_path_buf(), cells, tasks })
}

/// The cells of the crossing, counted from the levels' kinds without listing them (a full
/// crossing keeps the scenario × traffic pairs whose kinds go together, [`kinds_fit`]).
pub(crate) fn cell_count(design: &Design) -> u128 {
    if let Crossing::Cells(cells) = &design.crossing {
        return cells.len() as u128;
    }
    let mut scenarios: Vec<(&ScenarioSource, u128)> = Vec::new();
    for s in &design.scenarios {
        match scenarios
            .iter_mut()
            .find(|(k, _)| std::mem::discriminant(*k) == std::mem::discriminant(&s.source))
        {
            Some((_, n)) => *n += 1,
            None => scenarios.push((&s.source, 1)),
        }
    }
    let mut traffic: Vec<(&TrafficKind, u128)> = Vec::new();
    for t in &design.traffic {
        match traffic.iter_mut().find(|(k, _)| std::mem::discriminant(*k) == std::mem::discriminant(&t.kind))
        {
            Some((_, n)) => *n += 1,
            None => traffic.push((&t.kind, 1)),
        }
    }
    let pairs: u128 = scenarios
        .iter()
        .flat_map(|(s, ns)| traffic.iter().filter(|(t, _)| kinds_fit(s, t)).map(move |(_, nt)| ns * nt))
        .sum();
    pairs * design.vehicles.len() as u128
}

/// Names unique and present in every factor.
fn check_names<'a>(factor: &str, names: impl Iterator<Item = &'a String>) -> std::result::Result<(), String> {
    let mut seen = BTreeSet::new();
    for (i, name) in names.enumerate() {
        if name.trim().is_empty() || !seen.insert(name.as_str()) {
            return Err(format!("{factor}[{i}] {name:?}: each level needs its own, non-empty name"));
        }
        if let Some(c) = name.chars().find(|c| c.is_control()) {
            return Err(format!(
                "{factor}[{i}] {name:?}: a control character ({c:?}) in a name would forge lines in the \
                 terminal, design.csv and the plan"
            ));
        }
    }
    if seen.is_empty() {
        return Err(format!("{factor}: the factor needs at least one level"));
    }
    Ok(())
}

fn check_vehicles(design: &Design) -> std::result::Result<(), String> {
    check_names("vehicles", design.vehicles.iter().map(|v| &v.name))?;
    for (i, v) in design.vehicles.iter().enumerate() {
        let at = format!("vehicles[{i}] {:?}", v.name);
        match (&v.model, &v.body) {
            (Some(_), None) if v.dims.is_some() => {
                return Err(format!("{at}: dims go with a body, not a model"));
            }
            (Some(_), None) => {}
            (None, Some(body)) if BodyType::parse(body).is_none() => {
                let names: Vec<&str> = BodyType::ALL.iter().map(|b| b.name()).collect();
                return Err(format!("{at}: unknown body {body:?} (one of {})", names.join(", ")));
            }
            (None, Some(_)) => {}
            _ => return Err(format!("{at}: give exactly one of \"model\" and \"body\"")),
        }
        let dims = v.dims.unwrap_or_default();
        let given = [dims.length_m, dims.width_m, dims.height_m, dims.bonnet_length_m, dims.bonnet_height_m]
            .into_iter()
            .chain([dims.wheelbase_m])
            .flatten();
        if given.into_iter().any(|d| !(d.is_finite() && d > 0.0 && d < 30.0)) {
            return Err(format!("{at}: every dimension must be more than 0 and under 30 m"));
        }
        if let Some(rake) = dims.windshield_rake_deg
            && !(rake.is_finite() && (0.0..90.0).contains(&rake))
        {
            return Err(format!("{at}: windshield_rake_deg {rake} must be 0 to 90"));
        }
        if let Some([w, h]) = v.display_m
            && !(w.is_finite() && h.is_finite() && w > 0.0 && h > 0.0 && w <= 20.0 && h <= 20.0)
        {
            return Err(format!("{at}: display_m [{w}, {h}] must be more than 0 and at most 20 m"));
        }
    }
    Ok(())
}

fn check_scenarios(design: &Design) -> std::result::Result<(), String> {
    check_names("scenarios", design.scenarios.iter().map(|s| &s.name))?;
    for (i, s) in design.scenarios.iter().enumerate() {
        let at = format!("scenarios[{i}] {:?}", s.name);
        match &s.source {
            ScenarioSource::Demo { scenario } if crate::scene::demo::scenario(scenario).is_none() => {
                return Err(format!("{at}: the demo has scenarios A, B, C and D, not {scenario:?}"));
            }
            ScenarioSource::Street(street) => {
                if !(1..=POSITIONS).contains(&street.position) || !(1..=3).contains(&street.pedestrian) {
                    return Err(format!("{at}: position must be 1 to {POSITIONS} and pedestrian 1 to 3"));
                }
                if !(street.speed_mps.is_finite() && (0.0..=40.0).contains(&street.speed_mps)) {
                    return Err(format!("{at}: speed_mps {} must be 0 to 40", street.speed_mps));
                }
            }
            _ => {}
        }
    }
    Ok(())
}

fn check_traffic(design: &Design) -> std::result::Result<(), String> {
    check_names("traffic", design.traffic.iter().map(|t| &t.name))?;
    for (i, t) in design.traffic.iter().enumerate() {
        if let TrafficKind::Generated { vehicles } = t.kind
            && vehicles > MAX_OTHER_VEHICLES
        {
            return Err(format!(
                "traffic[{i}] {:?}: at most {MAX_OTHER_VEHICLES} generated vehicles",
                t.name
            ));
        }
    }
    Ok(())
}

/// Every level of every factor, and the measure.
fn check_levels(design: &Design) -> std::result::Result<(), String> {
    if let Some(c) = design.name.chars().find(|c| c.is_control()) {
        return Err(format!("name {:?}: a control character ({c:?}) in the design's name", design.name));
    }
    check_vehicles(design)?;
    check_scenarios(design)?;
    check_traffic(design)?;
    let m = &design.measure;
    if !(m.sample > 0.0 && m.sample <= 1.0) {
        return Err(format!("measure.sample {}: must be in (0, 1]", m.sample));
    }
    if !(16..=8192).contains(&m.palette) || m.frame_step == 0 {
        return Err("measure: palette must be 16 to 8192 texels and frame_step at least 1".into());
    }
    if m.patch_spacing_m.is_some_and(|s| !(s.is_finite() && s >= 0.01)) {
        return Err("measure.patch_spacing_m: must be at least 0.01 m".into());
    }
    if m.rendered_ppd.is_some() {
        return Err("measure.rendered_ppd: designs run the exact measure only (leave it out)".into());
    }
    if design.replicates == 0 {
        return Err("replicates: at least 1".into());
    }
    if let Some(p) = &design.population
        && !(1..=MAX_OBSERVERS_PER_TASK).contains(&p.observers)
    {
        return Err(format!("population.observers {}: must be 1 to {MAX_OBSERVERS_PER_TASK}", p.observers));
    }
    Ok(())
}

/// Traffic a scenario cannot carry, by name.
fn traffic_fits(
    cell: &CellLevels,
    scenario: &ScenarioLevel,
    traffic: &TrafficLevel,
) -> std::result::Result<(), String> {
    if !kinds_fit(&scenario.source, &traffic.kind) {
        return Err(format!(
            "cell {cell}: traffic level {:?} does not fit scenario level {:?} (adjacent-lane and lead-car go with \
             demo scenarios, generated with street scenarios, scene files carry their own occluders)",
            traffic.name, scenario.name
        ));
    }
    if let (ScenarioSource::Street(street), TrafficKind::Generated { vehicles }) =
        (&scenario.source, &traffic.kind)
    {
        let options = StreetOptions {
            position: street.position,
            pedestrian: street.pedestrian,
            speed_mps: street.speed_mps,
            others: *vehicles,
            seed: 0,
        };
        other_positions(&options).map_err(|e| format!("cell {cell}: {e}"))?;
    }
    Ok(())
}

/// Whether a traffic level's kind goes with a scenario level's (a full crossing leaves out the others).
pub(crate) fn kinds_fit(scenario: &ScenarioSource, traffic: &TrafficKind) -> bool {
    matches!(
        (scenario, traffic),
        (_, TrafficKind::None)
            | (ScenarioSource::Demo { .. }, TrafficKind::AdjacentLane | TrafficKind::LeadCar)
            | (ScenarioSource::Street(_), TrafficKind::Generated { .. })
    )
}

/// Every file in `files` with its FNV-1a 64 fingerprint, by path relative to `base` (the design's
/// folder), read through the file layer as the model loader read it.
pub(crate) fn input_hashes(base: &Path, files: &[PathBuf]) -> Result<BTreeMap<String, String>> {
    let mut hashes = BTreeMap::new();
    for file in files {
        let bytes = ufcsr::files::read_limited(file, ufcsr::files::MODEL_LIMIT)?;
        // `./x.mtl` (an OBJ beside a design in the working folder names its MTL so) is `x.mtl`.
        let relative: PathBuf = file
            .strip_prefix(base)
            .unwrap_or(file)
            .components()
            .filter(|c| !matches!(c, std::path::Component::CurDir))
            .collect();
        let name = relative.to_string_lossy().replace('\\', "/");
        hashes.insert(name, fnv1a_hex(&bytes));
    }
    Ok(hashes)
}

#[cfg(test)]
thread_local! {
    /// Cells listed by [`cells_of`] on this thread: the tests' bound that a refused crossing was
    /// counted, never listed.
    pub static LISTED_CELLS: std::cell::Cell<usize> = const { std::cell::Cell::new(0) };
}

/// The cells of the crossing, each level named in its factor (levels looked up by name in maps:
/// a listed crossing of many cells over many levels stays linear).
fn cells_of(design: &Design) -> std::result::Result<Vec<CellLevels>, String> {
    let vehicles: BTreeSet<&str> = design.vehicles.iter().map(|v| v.name.as_str()).collect();
    let scenarios: BTreeMap<&str, &ScenarioLevel> =
        design.scenarios.iter().map(|s| (s.name.as_str(), s)).collect();
    let traffic: BTreeMap<&str, &TrafficLevel> =
        design.traffic.iter().map(|t| (t.name.as_str(), t)).collect();
    let cells: Vec<CellLevels> = match &design.crossing {
        Crossing::Full => design
            .vehicles
            .iter()
            .flat_map(|v| {
                design.scenarios.iter().flat_map(move |s| {
                    design.traffic.iter().filter(|t| kinds_fit(&s.source, &t.kind)).map(move |t| CellLevels {
                        vehicle: v.name.clone(),
                        scenario: s.name.clone(),
                        traffic: t.name.clone(),
                    })
                })
            })
            .collect(),
        Crossing::Cells(cells) => cells.clone(),
    };
    #[cfg(test)]
    LISTED_CELLS.with(|n| n.set(n.get() + cells.len()));
    let mut seen = BTreeSet::new();
    for (i, cell) in cells.iter().enumerate() {
        let missing = |factor: &str, name: &str| format!("cells[{i}]: no {factor} level {name:?}");
        if !vehicles.contains(cell.vehicle.as_str()) {
            return Err(missing("vehicle", &cell.vehicle));
        }
        let scenario =
            scenarios.get(cell.scenario.as_str()).ok_or_else(|| missing("scenario", &cell.scenario))?;
        let level = traffic.get(cell.traffic.as_str()).ok_or_else(|| missing("traffic", &cell.traffic))?;
        traffic_fits(cell, scenario, level)?;
        if !seen.insert(cell) {
            return Err(format!("cells[{i}]: cell {cell} listed twice"));
        }
    }
    if cells.is_empty() {
        return Err("the crossing has no cell (does any traffic level fit any scenario?)".into());
    }
    Ok(cells)
}
