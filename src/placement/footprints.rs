//! Where a display patch lies on the vehicle, so the chosen patches can be
//! drawn: the capture's `placement-patches.csv` (beside
//! `placement-frames.csv`) gives each patch's centre, outward normal, height
//! axis, width and height; tables from captures that did not write it fall
//! back to the centre in the patch's name (`PART@xX.XXyY.YYzZ.ZZ`), drawn
//! as a disc. A bad table is an error naming the file, the line and the
//! problem.
//!
//! A patch's name carries its display size and centre
//! (`PART@0.40x0.15@x1.20y-0.45z0.80`), so runs with different sizes are
//! never scored as one candidate; `table::label_sizes` puts the size into the
//! names of older tables from their footprints.

use std::collections::BTreeMap;
use std::path::Path;

use crate::error::{Error, Result};
use crate::files::{SMALL_INPUT_LIMIT, read_limited};
use crate::optics::vector::dot;

use crate::format::placement::CandidateKind;
use crate::format::placement_csv::parse_covers;
pub use crate::format::placement_csv::{PLACEMENT_PATCHES_COLUMNS, PLACEMENT_PATCHES_FILE, covers_field};

/// The columns read: all but `mirror` (and `covers`, when there).
const READ_COLUMNS: usize = 12;
/// `covers`' place in [`PLACEMENT_PATCHES_COLUMNS`] (the last; tables written before it lack it).
const COVERS_COLUMN: usize = 13;

/// A display patch's rectangle on the surface (vehicle frame, metres), and
/// the parts it covers.
#[derive(Debug, Clone, PartialEq)]
pub struct PatchFootprint {
    pub centre: [f64; 3],
    /// Outward unit normal.
    pub normal: [f64; 3],
    /// Unit vector along the display's height.
    pub up: [f64; 3],
    /// Width and height, m.
    pub size_m: [f64; 2],
    /// The parts the display covers (`covers`); empty in tables written
    /// before the column, whose patches are judged by their own part.
    pub covers: Vec<String>,
}

impl PatchFootprint {
    /// Whether the surface point `p` is on the patch: the capture's rule
    /// (within W/2 across, H/2 along the height axis and H/2 off the plane).
    pub fn contains(&self, p: [f64; 3]) -> bool {
        let d = [p[0] - self.centre[0], p[1] - self.centre[1], p[2] - self.centre[2]];
        let (n, u) = (self.normal, self.up);
        let across = [u[1] * n[2] - u[2] * n[1], u[2] * n[0] - u[0] * n[2], u[0] * n[1] - u[1] * n[0]];
        let [w, h] = self.size_m;
        dot(d, across).abs() <= w / 2.0 && dot(d, u).abs() <= h / 2.0 && dot(d, n).abs() <= h / 2.0
    }
}

/// The display size a patch's name carries (`PART@0.40x0.15@x1.20y-0.45z0.80`:
/// width x height, m), if any.
pub(crate) fn size_in_name(name: &str) -> Option<[f64; 2]> {
    let mut pieces = name.split('@');
    pieces.next()?;
    let size = pieces.next()?;
    pieces.next()?;
    let (w, h) = size.split_once('x')?;
    let size = [w.parse().ok()?, h.parse().ok()?];
    size.iter().all(|s: &f64| s.is_finite() && *s > 0.0).then_some(size)
}

/// `PART@xX.XXyY.YYzZ.ZZ` with the display size put in
/// (`PART@0.40x0.15@x…`); names that already carry one are kept.
pub(crate) fn name_with_size(name: &str, size: [f64; 2]) -> String {
    if size_in_name(name).is_some() {
        return name.to_string();
    }
    match name.rsplit_once('@') {
        Some((part, place)) => format!("{part}@{:.2}x{:.2}@{place}", size[0], size[1]),
        None => name.to_string(),
    }
}

/// The part a candidate belongs to: a patch's name before its first `@`.
pub(crate) fn part_of(name: &str) -> &str {
    name.split('@').next().unwrap_or(name)
}

/// The centre a patch's name carries (`PART@x1.20y-0.45z0.80`), if any.
pub(crate) fn centre_in_name(name: &str) -> Option<[f64; 3]> {
    let (_, place) = name.rsplit_once('@')?;
    let rest = place.strip_prefix('x')?;
    let (x, rest) = rest.split_once('y')?;
    let (y, z) = rest.split_once('z')?;
    let centre = [x.parse().ok()?, y.parse().ok()?, z.parse().ok()?];
    centre.iter().all(|c: &f64| c.is_finite()).then_some(centre)
}

/// Why `table`'s display patches may not follow today's layout rule, if they
/// may not: a patch with no `covers` (a `placement-patches.csv` written before
/// the column, or none beside the table) was laid out by an older capture, so
/// it may reach over glass or a tyre and is judged by its centre's part alone
/// (`docs/placement.md` §1 item 4). `candidates` are the table's names and
/// kinds, `footprints` its own, named as in the table.
pub(crate) fn layout_warning<'a>(
    candidates: impl Iterator<Item = (&'a str, CandidateKind)>,
    footprints: &BTreeMap<String, PatchFootprint>,
) -> Option<String> {
    let (mut all, mut old) = (0usize, 0usize);
    for (name, _) in candidates.filter(|(_, kind)| *kind == CandidateKind::Patch) {
        all += 1;
        old += usize::from(footprints.get(name).is_none_or(|f| f.covers.is_empty()));
    }
    let why = if footprints.is_empty() {
        format!("there is no {PLACEMENT_PATCHES_FILE} beside it")
    } else {
        format!("its {PLACEMENT_PATCHES_FILE} has no covers column")
    };
    (old > 0).then(|| {
        format!(
            "{old} of its {all} display patches were laid out by an older capture ({why}): such a display may \
             reach over glass or a tyre and is judged by its centre's part alone; capture again for today's \
             layout (docs/placement.md §1 item 4)"
        )
    })
}

/// The footprints in `placement-patches.csv` beside the frames table at
/// `frames_table`, by name; empty when there is no such file.
pub fn read_footprints(frames_table: &Path) -> Result<BTreeMap<String, PatchFootprint>> {
    let path = frames_table.with_file_name(PLACEMENT_PATCHES_FILE);
    if !path.exists() {
        return Ok(BTreeMap::new());
    }
    let bytes = read_limited(&path, SMALL_INPUT_LIMIT)?;
    let mut reader = csv::ReaderBuilder::new().has_headers(true).from_reader(&bytes[..]);
    let header = reader.headers().map_err(|e| Error::bad_file(&path, format!("header: {e}")))?.clone();
    let mut positions = Vec::with_capacity(READ_COLUMNS);
    for column in &PLACEMENT_PATCHES_COLUMNS[..READ_COLUMNS] {
        let found = header.iter().position(|h| h == *column);
        positions.push(found.ok_or_else(|| Error::bad_file(&path, format!("no column {column:?}")))?);
    }
    let covers = header.iter().position(|h| h == PLACEMENT_PATCHES_COLUMNS[COVERS_COLUMN]);
    let mut footprints = BTreeMap::new();
    for (index, record) in reader.records().enumerate() {
        let line = index + 2;
        let record = record.map_err(|e| Error::bad_file(&path, format!("line {line}: {e}")))?;
        let mut footprint = parse_footprint(&record, &positions)
            .map_err(|problem| Error::bad_file(&path, format!("line {line}: {problem}")))?;
        if let Some(field) = covers.and_then(|column| record.get(column)) {
            footprint.covers = parse_covers(field)
                .map_err(|problem| Error::bad_file(&path, format!("line {line}: {problem}")))?;
        }
        let name = record.get(positions[0]).unwrap_or("").trim();
        if name.is_empty() {
            return Err(Error::bad_file(&path, format!("line {line}: candidate is empty")));
        }
        if footprints.insert(name.to_string(), footprint).is_some() {
            return Err(Error::bad_file(&path, format!("line {line}: candidate {name:?} is listed twice")));
        }
    }
    Ok(footprints)
}

fn parse_footprint(
    record: &csv::StringRecord,
    positions: &[usize],
) -> std::result::Result<PatchFootprint, String> {
    let mut numbers = [0.0f64; 11];
    for (slot, (&position, column)) in
        numbers.iter_mut().zip(positions[1..].iter().zip(&PLACEMENT_PATCHES_COLUMNS[1..]))
    {
        let text = record.get(position).unwrap_or("");
        *slot = text
            .trim()
            .parse::<f64>()
            .ok()
            .filter(|v| v.is_finite() && v.abs() <= crate::files::MAX_COORDINATE_M)
            .ok_or_else(|| format!("{column} {text:?} is not a finite number"))?;
    }
    let vector = |i: usize| [numbers[i], numbers[i + 1], numbers[i + 2]];
    let footprint = PatchFootprint {
        centre: vector(0),
        normal: vector(3),
        up: vector(6),
        size_m: [numbers[9], numbers[10]],
        covers: Vec::new(),
    };
    for (name, v) in [("normal", footprint.normal), ("up", footprint.up)] {
        if (dot(v, v).sqrt() - 1.0).abs() > 1e-3 {
            return Err(format!("the {name} axis is not a unit vector"));
        }
    }
    // Axes that are not perpendicular give a rectangle of no width (the
    // across axis is their cross product): a degenerate footprint.
    if dot(footprint.normal, footprint.up).abs() > 1e-3 {
        return Err("the normal and up axes are not perpendicular".into());
    }
    if footprint.size_m.iter().any(|&s| s <= 0.0) {
        return Err("width and height must be more than 0".into());
    }
    Ok(footprint)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_patch_name_carries_its_centre() {
        assert_eq!(centre_in_name("windshield@x1.20y-0.45z0.80"), Some([1.2, -0.45, 0.8]));
        assert_eq!(centre_in_name("a@b@x0.00y0.00z1.50"), Some([0.0, 0.0, 1.5]));
        assert_eq!(centre_in_name("windshield"), None);
        assert_eq!(centre_in_name("w@x1y2"), None);
    }

    #[test]
    fn a_footprint_holds_the_points_of_its_rectangle_only() {
        // A 0.40 × 0.15 display facing +x at the origin, height along z.
        let patch = PatchFootprint {
            centre: [0.0; 3],
            normal: [1.0, 0.0, 0.0],
            up: [0.0, 0.0, 1.0],
            size_m: [0.4, 0.15],
            covers: Vec::new(),
        };
        assert!(patch.contains([0.0, 0.19, 0.07]));
        assert!(!patch.contains([0.0, 0.21, 0.0]));
        assert!(!patch.contains([0.0, 0.0, 0.08]));
        assert!(!patch.contains([0.1, 0.0, 0.0]), "off the plane by more than H/2");
    }

    #[test]
    fn a_bad_footprint_table_names_the_file_line_and_problem() {
        let dir = tempfile::tempdir().unwrap();
        let frames = dir.path().join("placement-frames.csv");
        assert!(read_footprints(&frames).unwrap().is_empty(), "no table: no footprints");
        let header = PLACEMENT_PATCHES_COLUMNS.join(",") + "\n";
        let table = dir.path().join(PLACEMENT_PATCHES_FILE);
        std::fs::write(&table, header.clone() + "p@x0y0z0,0,0,0,1,0,0,0,0,1,0.4,0.15,,\"p,grill\"\n")
            .unwrap();
        let read = read_footprints(&frames).unwrap();
        assert_eq!(read["p@x0y0z0"].size_m, [0.4, 0.15]);
        assert_eq!(read["p@x0y0z0"].covers, ["p", "grill"]);
        // A table written before `covers`: no parts named.
        let before = PLACEMENT_PATCHES_COLUMNS[..13].join(",") + "\n";
        std::fs::write(&table, before + "p@x0y0z0,0,0,0,1,0,0,0,0,1,0.4,0.15,\n").unwrap();
        assert!(read_footprints(&frames).unwrap()["p@x0y0z0"].covers.is_empty());
        for (row, problem) in [
            ("p,0,0,0,2,0,0,0,0,1,0.4,0.15,,p", "line 2: the normal axis is not a unit vector"),
            ("p,0,0,NaN,1,0,0,0,0,1,0.4,0.15,,p", "line 2: centre_z_m \"NaN\" is not a finite number"),
            ("p,0,0,0,1,0,0,0,0,1,0,0.15,,p", "line 2: width and height must be more than 0"),
            ("p,0,0,0,1,0,0,1,0,0,0.4,0.15,,p", "line 2: the normal and up axes are not perpendicular"),
            ("p,0,0,0,1,0,0,0,0,1,0.4,0.15,,\"p,,grill\"", "line 2: covers \"p,,grill\" names an empty part"),
            (
                "p,0,0,0,1,0,0,0,0,1,0.4,0.15,,p\np,0,0,0,1,0,0,0,0,1,0.4,0.15,,p",
                "line 3: candidate \"p\" is listed twice",
            ),
        ] {
            std::fs::write(&table, header.clone() + row + "\n").unwrap();
            let message = read_footprints(&frames).unwrap_err().to_string();
            assert!(message.contains(PLACEMENT_PATCHES_FILE) && message.contains(problem), "{message}");
        }
    }
}
