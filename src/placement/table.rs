//! Reading one archive's `placement-frames.csv` (written by `ufcsr capture
//! … --measure unobstructed --placement`) into per-candidate, per-eye-frame
//! numbers, checked so that a bad table is an error naming the file, the
//! line and the problem, never a silent wrong placement.
//!
//! Columns (`docs/placement.md`): `frame,time_s,eye,distance_m,candidate,
//! kind,solid_angle_sr,visible_fraction,view_angle_deg,angular_height_deg`,
//! optionally `frame_s` (seconds one frame stands for) and `mirror` (the
//! candidate's left/right mirror image). A row may be left out where the
//! candidate is not visible at all; the frames are those any row names.
//!
//! A *rendered* `frames.csv` (the analyzer's, or the capture's `--count`:
//! `frame,time_s,distance_m,eye,part,pixels,texels,solid_angle_sr`) is read
//! too, as a table of parts with solid angles only ([`PlacementTable::rendered`]);
//! it can be scored by the solid-angle rule alone (`--min-solid-angle-sr`),
//! which is how the rendered and the exact measure are compared.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use crate::error::{Error, Result};
use crate::files::read_limited;

pub use crate::format::placement_csv::{PLACEMENT_FRAMES_COLUMNS, PLACEMENT_FRAMES_FILE};

pub use crate::format::placement::CandidateKind;

/// What one eye saw of one candidate in one frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sighting {
    pub solid_angle_sr: f64,
    pub visible_fraction: f64,
    pub view_angle_deg: f64,
    pub angular_height_deg: f64,
}

/// One frame of the scenario.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrameInfo {
    pub frame: u64,
    pub time_s: f64,
    pub distance_m: f64,
}

/// One candidate and what it was seen as, per (frame index, eye index).
#[derive(Debug, Clone, PartialEq)]
pub struct CandidateRows {
    pub name: String,
    pub kind: CandidateKind,
    pub mirror: Option<String>,
    /// A display's width and height, m (from its name; `None` for a part).
    pub size_m: Option<[f64; 2]>,
    pub sightings: BTreeMap<(usize, usize), Sighting>,
}

/// One archive's table.
#[derive(Debug, Clone, PartialEq)]
pub struct PlacementTable {
    pub path: PathBuf,
    /// In frame order.
    pub frames: Vec<FrameInfo>,
    /// Eye names, in order of first appearance.
    pub eyes: Vec<String>,
    /// Seconds one frame stands for.
    pub frame_s: f64,
    /// By name.
    pub candidates: BTreeMap<String, CandidateRows>,
    /// Read from a rendered `frames.csv`: solid angles only (visible
    /// fraction, view angle and angular height are not measured there).
    pub rendered: bool,
}

/// The table of `input`: the file itself, or `placement-frames.csv` in the
/// folder or in its `results/`.
/// A FIFO, a device or a socket, given or found there, is refused as not a
/// regular file (issue 41: a FIFO was "no placement-frames.csv here").
pub fn resolve_table(input: &Path) -> Result<PathBuf> {
    let regular = |path: &Path| crate::files::open_regular(path).map(|_| path.to_path_buf());
    match std::fs::metadata(input) {
        Ok(metadata) if !metadata.is_dir() => return regular(input),
        _ => {}
    }
    for candidate in [input.join(PLACEMENT_FRAMES_FILE), input.join("results").join(PLACEMENT_FRAMES_FILE)] {
        if std::fs::metadata(&candidate).is_ok() {
            return regular(&candidate);
        }
    }
    Err(Error::bad_file(
        input,
        format!(
            "no {PLACEMENT_FRAMES_FILE} here nor in its results/: capture with `ufcsr capture … --measure \
             unobstructed --placement` (docs/placement.md)"
        ),
    ))
}

/// One parsed row.
struct Row {
    /// The row's line in the file (the header is line 1), for messages.
    line: usize,
    frame: FrameInfo,
    eye: String,
    candidate: String,
    kind: CandidateKind,
    sighting: Sighting,
    frame_s: Option<f64>,
    mirror: Option<String>,
}

/// Column positions of a table's header.
struct Columns {
    required: [usize; 10],
    frame_s: Option<usize>,
    mirror: Option<usize>,
}

impl Columns {
    fn of(path: &Path, header: &csv::StringRecord) -> Result<Columns> {
        let find = |name: &str| header.iter().position(|h| h.trim() == name);
        let mut required = [0; 10];
        for (slot, name) in required.iter_mut().zip(PLACEMENT_FRAMES_COLUMNS) {
            *slot = find(name).ok_or_else(|| {
                Error::bad_file(
                    path,
                    format!(
                        "line 1: the header lacks column {name:?} (needs {})",
                        PLACEMENT_FRAMES_COLUMNS.join(",")
                    ),
                )
            })?;
        }
        Ok(Columns { required, frame_s: find("frame_s"), mirror: find("mirror") })
    }

    /// A rendered `frames.csv`'s columns in the places [`rendered_row`]
    /// reads: frame, time, eye, distance, part, (unused), solid angle.
    fn rendered(header: &csv::StringRecord) -> Columns {
        let find = |name: &str| header.iter().position(|h| h.trim() == name).unwrap_or(usize::MAX);
        let mut required = [usize::MAX; 10];
        for (slot, name) in
            [(0, "frame"), (1, "time_s"), (2, "eye"), (3, "distance_m"), (4, "part"), (6, "solid_angle_sr")]
        {
            required[slot] = find(name);
        }
        Columns { required, frame_s: None, mirror: None }
    }
}

/// Reads and checks one table (see the module documentation).
pub fn read_table(path: &Path) -> Result<PlacementTable> {
    let bytes = read_limited(path, crate::format::placement_csv::PLACEMENT_TABLE_LIMIT)?;
    let mut reader = csv::ReaderBuilder::new().has_headers(true).from_reader(&bytes[..]);
    let header =
        reader.headers().map_err(|e| Error::bad_file(path, format!("line 1: not CSV: {e}")))?.clone();
    let rendered = RENDERED_COLUMNS.iter().all(|c| header.iter().any(|h| h.trim() == *c))
        && !header.iter().any(|h| h.trim() == "candidate");
    let columns = if rendered { Columns::rendered(&header) } else { Columns::of(path, &header)? };
    let mut rows = Vec::new();
    for (index, record) in reader.records().enumerate() {
        let line = index + 2;
        let record = record.map_err(|e| Error::bad_file(path, format!("line {line}: not CSV: {e}")))?;
        let parsed =
            if rendered { rendered_row(&record, &columns) } else { parse_row(&record, &columns).map(Some) };
        if let Some(mut row) = parsed.map_err(|m| Error::bad_file(path, format!("line {line}: {m}")))? {
            row.line = line;
            rows.push(row);
        }
    }
    if rows.is_empty() {
        return Err(Error::bad_file(path, "has no rows: no candidate was measured in any eye-frame"));
    }
    let mut table = assemble(path, rows)?;
    table.rendered = rendered;
    Ok(table)
}

/// The columns of a rendered `frames.csv` read as a placement table.
const RENDERED_COLUMNS: [&str; 5] = ["frame", "time_s", "distance_m", "eye", "part"];

/// A rendered `frames.csv` row as a part's sighting with its solid angle
/// (visible fraction 1 when seen, view angle and angular height 0: not
/// measured); `None` for the rows of no legend part (`(unlabelled)`,
/// `(all texels)`).
fn rendered_row(record: &csv::StringRecord, columns: &Columns) -> std::result::Result<Option<Row>, String> {
    let field = |at: usize| record.get(at).map(str::trim).unwrap_or("");
    let [frame, time, eye, distance, part, solid] = [0, 1, 2, 3, 4, 6].map(|i| field(columns.required[i]));
    if part.starts_with('(') {
        return Ok(None);
    }
    if solid.is_empty() {
        return Err(
            "solid_angle_sr is empty: the manifest gives no projection (rig.settings), so a rendered \
                    table has no solid angles to score"
                .into(),
        );
    }
    let number = |name: &str, text: &str| -> std::result::Result<f64, String> {
        text.parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .ok_or_else(|| format!("{name} {text:?} is not a finite number"))
    };
    let solid_angle_sr = number("solid_angle_sr", solid)?;
    let sighting = Sighting {
        solid_angle_sr,
        visible_fraction: if solid_angle_sr > 0.0 { 1.0 } else { 0.0 },
        view_angle_deg: 0.0,
        angular_height_deg: 0.0,
    };
    check_sighting(&sighting)?;
    let frame = FrameInfo {
        frame: frame.parse().map_err(|_| format!("frame {frame:?} is not a whole number ≥ 0"))?,
        time_s: number("time_s", time)?,
        distance_m: number("distance_m", distance)?,
    };
    check_frame(&frame)?;
    Ok(Some(Row {
        line: 0,
        frame,
        eye: eye.to_string(),
        candidate: part.to_string(),
        kind: CandidateKind::Part,
        sighting,
        frame_s: None,
        mirror: None,
    }))
}

fn parse_row(record: &csv::StringRecord, columns: &Columns) -> std::result::Result<Row, String> {
    let field = |at: usize| record.get(at).map(str::trim).unwrap_or("");
    let [frame, time, eye, distance, candidate, kind, solid, fraction, angle, height] =
        columns.required.map(field);
    let number = |name: &str, text: &str| -> std::result::Result<f64, String> {
        let value: f64 = text.parse().map_err(|_| format!("{name} {text:?} is not a number"))?;
        if value.is_finite() { Ok(value) } else { Err(format!("{name} {text:?} is not finite")) }
    };
    let frame: u64 = frame.parse().map_err(|_| format!("frame {frame:?} is not a whole number ≥ 0"))?;
    let kind = match kind {
        "part" => CandidateKind::Part,
        "patch" => CandidateKind::Patch,
        other => return Err(format!("kind {other:?} is neither part nor patch")),
    };
    if eye.is_empty() || candidate.is_empty() {
        return Err("eye and candidate must not be empty".into());
    }
    let sighting = Sighting {
        solid_angle_sr: number("solid_angle_sr", solid)?,
        visible_fraction: number("visible_fraction", fraction)?,
        view_angle_deg: number("view_angle_deg", angle)?,
        angular_height_deg: number("angular_height_deg", height)?,
    };
    check_sighting(&sighting)?;
    let frame_s = match columns.frame_s.map(field).filter(|t| !t.is_empty()) {
        Some(text) => {
            let seconds = number("frame_s", text)?;
            if seconds <= 0.0 || seconds > MAX_SECONDS {
                return Err(format!(
                    "frame_s {text:?} must be more than 0 and at most {MAX_SECONDS} seconds"
                ));
            }
            Some(seconds)
        }
        None => None,
    };
    let frame =
        FrameInfo { frame, time_s: number("time_s", time)?, distance_m: number("distance_m", distance)? };
    check_frame(&frame)?;
    Ok(Row {
        line: 0,
        frame,
        eye: eye.to_string(),
        candidate: candidate.to_string(),
        kind,
        sighting,
        frame_s,
        mirror: columns.mirror.map(field).filter(|t| !t.is_empty()).map(str::to_string),
    })
}

/// The longest time a table may name, s: a scenario's duration is at most
/// 10⁶ s (docs/scene-file.md), so a larger time or `frame_s` is no capture's
/// and would overflow the seconds summed over frames.
pub(crate) const MAX_SECONDS: f64 = 1e6;

/// The farthest distance a table may name, m (the tracks' ±10⁶ m bound).
pub(crate) const MAX_DISTANCE_M: f64 = 1e6;

/// A frame's time and distance: a distance from 0 to [`MAX_DISTANCE_M`], a
/// time within ±[`MAX_SECONDS`].
fn check_frame(frame: &FrameInfo) -> std::result::Result<(), String> {
    if !(0.0..=MAX_DISTANCE_M).contains(&frame.distance_m) {
        return Err(format!("distance_m {} must be 0 to {MAX_DISTANCE_M} m", frame.distance_m));
    }
    if frame.time_s.abs() > MAX_SECONDS {
        return Err(format!("time_s {} is beyond ±{MAX_SECONDS} s", frame.time_s));
    }
    Ok(())
}

fn check_sighting(s: &Sighting) -> std::result::Result<(), String> {
    if s.solid_angle_sr < 0.0 {
        return Err(format!("solid_angle_sr {} is negative", s.solid_angle_sr));
    }
    if !(0.0..=1.0 + 1e-9).contains(&s.visible_fraction) {
        return Err(format!("visible_fraction {} is outside 0 to 1", s.visible_fraction));
    }
    if !(0.0..=90.0 + 1e-9).contains(&s.view_angle_deg) {
        return Err(format!("view_angle_deg {} is outside 0 to 90", s.view_angle_deg));
    }
    if !(0.0..=180.0).contains(&s.angular_height_deg) {
        return Err(format!("angular_height_deg {} is outside 0 to 180", s.angular_height_deg));
    }
    Ok(())
}

/// Frames, eyes and candidates from the rows, with the consistency checks.
fn assemble(path: &Path, rows: Vec<Row>) -> Result<PlacementTable> {
    let mut frames: BTreeMap<u64, (FrameInfo, usize)> = BTreeMap::new();
    let mut eyes: Vec<String> = Vec::new();
    let mut frame_s: Option<f64> = None;
    for row in &rows {
        let (known, _) = *frames.entry(row.frame.frame).or_insert((row.frame, row.line));
        if known != row.frame {
            return Err(Error::bad_file(
                path,
                format!(
                    "line {}: frame {} has two times or distances ({:?} and {:?})",
                    row.line, row.frame.frame, known, row.frame
                ),
            ));
        }
        if !eyes.contains(&row.eye) {
            if eyes.len() == 2 {
                return Err(Error::bad_file(
                    path,
                    format!(
                        "line {}: eye {:?} is a third eye (the table already has {:?} and {:?}); an \
                         eye-frame is seen by two eyes at most",
                        row.line, row.eye, eyes[0], eyes[1]
                    ),
                ));
            }
            eyes.push(row.eye.clone());
        }
        if let Some(seconds) = row.frame_s {
            match frame_s {
                Some(known) if (known - seconds).abs() > 1e-9 * known.max(seconds) => {
                    return Err(Error::bad_file(
                        path,
                        format!("line {}: frame_s is both {known} and {seconds}", row.line),
                    ));
                }
                _ => frame_s = Some(seconds),
            }
        }
    }
    refuse_backwards_clock(path, &frames)?;
    let frame_list: Vec<FrameInfo> = frames.values().map(|(frame, _)| *frame).collect();
    let frame_s = match frame_s {
        Some(seconds) => seconds,
        None => smallest_time_step(path, &frame_list)?,
    };
    let index: BTreeMap<u64, usize> = frame_list.iter().enumerate().map(|(i, f)| (f.frame, i)).collect();
    let candidates = candidates_of(path, rows, &index, &eyes)?;
    Ok(PlacementTable {
        path: path.to_path_buf(),
        frames: frame_list,
        eyes,
        frame_s,
        candidates,
        rendered: false,
    })
}

/// Errors, naming the line, when a later frame has an earlier time than the
/// frame before it (a clock that runs backwards would make the legible
/// stretches and dwell times wrong).
fn refuse_backwards_clock(path: &Path, frames: &BTreeMap<u64, (FrameInfo, usize)>) -> Result<()> {
    let ordered: Vec<&(FrameInfo, usize)> = frames.values().collect();
    for pair in ordered.windows(2) {
        let ((before, _), (after, line)) = (pair[0], pair[1]);
        if after.time_s < before.time_s {
            return Err(Error::bad_file(
                path,
                format!(
                    "line {line}: time_s {} of frame {} is before time_s {} of frame {}: the clock runs \
                     backwards",
                    after.time_s, after.frame, before.time_s, before.frame
                ),
            ));
        }
    }
    Ok(())
}

/// Without `frame_s`: the smallest positive step between the frames' times.
fn smallest_time_step(path: &Path, frames: &[FrameInfo]) -> Result<f64> {
    frames
        .windows(2)
        .map(|pair| pair[1].time_s - pair[0].time_s)
        .filter(|&step| step > 0.0)
        .min_by(f64::total_cmp)
        .ok_or_else(|| {
            Error::bad_file(path, "one frame only and no frame_s column: cannot tell how long a frame lasts")
        })
}

fn candidates_of(
    path: &Path,
    rows: Vec<Row>,
    index: &BTreeMap<u64, usize>,
    eyes: &[String],
) -> Result<BTreeMap<String, CandidateRows>> {
    let mut candidates: BTreeMap<String, CandidateRows> = BTreeMap::new();
    for row in rows {
        let entry = candidates.entry(row.candidate.clone()).or_insert_with(|| CandidateRows {
            name: row.candidate.clone(),
            kind: row.kind,
            mirror: row.mirror.clone(),
            size_m: match row.kind {
                CandidateKind::Patch => crate::placement::footprints::size_in_name(&row.candidate),
                CandidateKind::Part => None,
            },
            sightings: BTreeMap::new(),
        });
        if entry.kind != row.kind {
            return Err(Error::bad_file(
                path,
                format!("candidate {:?} is both a part and a patch", row.candidate),
            ));
        }
        match (&entry.mirror, &row.mirror) {
            (Some(known), Some(mirror)) if known != mirror => {
                return Err(Error::bad_file(
                    path,
                    format!(
                        "line {}: mirror of candidate {:?} is both {known:?} and {mirror:?}",
                        row.line, row.candidate
                    ),
                ));
            }
            (None, Some(_)) => entry.mirror = row.mirror.clone(),
            _ => {}
        }
        let key = (index[&row.frame.frame], eyes.iter().position(|e| *e == row.eye).unwrap_or(0));
        if entry.sightings.insert(key, row.sighting).is_some() {
            return Err(Error::bad_file(
                path,
                format!(
                    "candidate {:?} has two rows for frame {} eye {}",
                    row.candidate, row.frame.frame, row.eye
                ),
            ));
        }
    }
    refuse_one_sided_mirrors(path, &candidates)?;
    Ok(candidates)
}

/// Errors when a candidate is its own mirror image, or when its mirror
/// names another mirror (or none): a pair chosen together would then hold
/// one candidate twice, or three candidates would form no pair.
fn refuse_one_sided_mirrors(path: &Path, candidates: &BTreeMap<String, CandidateRows>) -> Result<()> {
    for (name, rows) in candidates {
        let Some(mirror) = &rows.mirror else { continue };
        if mirror == name {
            return Err(Error::bad_file(
                path,
                format!("mirror of candidate {name:?} is the candidate itself"),
            ));
        }
        if let Some(other) = candidates.get(mirror)
            && other.mirror.as_deref() != Some(name.as_str())
        {
            return Err(Error::bad_file(
                path,
                format!(
                    "mirror of candidate {name:?} is {mirror:?}, but the mirror of {mirror:?} is {}: mirrors \
                     must name each other",
                    other.mirror.as_deref().map_or("none".to_string(), |m| format!("{m:?}"))
                ),
            ));
        }
    }
    Ok(())
}

/// Puts the display size into the names of `table`'s patches that lack it
/// (tables from captures before names carried it), from their footprints,
/// and renames the footprints alike, so patches of different sizes are
/// never scored as one candidate. Patches without a footprint keep their
/// name and have no known size.
pub(crate) fn label_sizes(
    table: &mut PlacementTable,
    footprints: &mut BTreeMap<String, crate::placement::footprints::PatchFootprint>,
) {
    let renamed = |name: &str| match footprints.get(name) {
        Some(f) if crate::placement::footprints::size_in_name(name).is_none() => {
            crate::placement::footprints::name_with_size(name, f.size_m)
        }
        _ => name.to_string(),
    };
    let candidates = std::mem::take(&mut table.candidates);
    for (name, mut rows) in candidates {
        let new_name = renamed(&name);
        rows.size_m = rows.size_m.or_else(|| footprints.get(&name).map(|f| f.size_m));
        rows.mirror = rows.mirror.as_deref().map(renamed);
        rows.name = new_name.clone();
        table.candidates.insert(new_name, rows);
    }
    let old = std::mem::take(footprints);
    for (name, footprint) in old {
        let new_name = if crate::placement::footprints::size_in_name(&name).is_none() {
            crate::placement::footprints::name_with_size(&name, footprint.size_m)
        } else {
            name
        };
        footprints.insert(new_name, footprint);
    }
}
