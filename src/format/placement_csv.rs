//! The placement tables the exact measure writes and `ufcsr analyze
//! placement` reads: `placement-frames.csv` (one row per candidate and
//! eye-frame, [`PlacementFrameRow`]) and `placement-patches.csv` (each
//! display patch's rectangle). Their names and columns are defined here
//! once, for the writer (the capture) and the reader (the analyzer); what
//! the columns mean is in `docs/placement.md`.

use std::borrow::Cow;

use serde::{Deserialize, Serialize};

/// The file name the capture writes into an archive's results folder.
pub const PLACEMENT_FRAMES_FILE: &str = "placement-frames.csv";

/// The columns every `placement-frames.csv` must have, in the capture's
/// order; the capture writes [`PLACEMENT_FRAMES_OPTIONAL`] after them.
pub const PLACEMENT_FRAMES_COLUMNS: [&str; 10] = [
    "frame",
    "time_s",
    "eye",
    "distance_m",
    "candidate",
    "kind",
    "solid_angle_sr",
    "visible_fraction",
    "view_angle_deg",
    "angular_height_deg",
];

/// The most bytes a `placement-frames.csv` may have: `placement` reads no
/// larger table, and the capture refuses to write one (it stops, naming the
/// options that shrink it), so the two agree on what is readable.
pub const PLACEMENT_TABLE_LIMIT: u64 = crate::files::SMALL_INPUT_LIMIT;

/// The columns a reader takes when they are there: the seconds one frame
/// stands for and the candidate's left/right mirror image.
pub const PLACEMENT_FRAMES_OPTIONAL: [&str; 2] = ["frame_s", "mirror"];

/// One row of `placement-frames.csv`: what one eye saw of one candidate in
/// one frame (the fields in column order).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PlacementFrameRow<'a> {
    pub frame: u64,
    pub time_s: f64,
    pub eye: Cow<'a, str>,
    pub distance_m: f64,
    pub candidate: Cow<'a, str>,
    /// `part` or `patch`.
    pub kind: Cow<'a, str>,
    pub solid_angle_sr: f64,
    pub visible_fraction: f64,
    pub view_angle_deg: f64,
    pub angular_height_deg: f64,
    pub frame_s: f64,
    /// The mirror image's name; empty when it has none.
    pub mirror: Cow<'a, str>,
}

/// The file the capture writes beside `placement-frames.csv`.
pub const PLACEMENT_PATCHES_FILE: &str = "placement-patches.csv";

/// The columns of `placement-patches.csv`, in the capture's order; all but
/// `mirror` (the mirror image's name, may be empty) are read, and `covers`
/// (the parts the display covers, [`covers_field`]) when it is there: tables
/// written before it judge a patch by its own part.
pub const PLACEMENT_PATCHES_COLUMNS: [&str; 14] = [
    "candidate",
    "centre_x_m",
    "centre_y_m",
    "centre_z_m",
    "normal_x",
    "normal_y",
    "normal_z",
    "up_x",
    "up_y",
    "up_z",
    "width_m",
    "height_m",
    "mirror",
    "covers",
];

/// A patch's `covers` field: the part names as one CSV record (`bumper,grill`;
/// a name holding a comma or a quote is quoted), so any part name reads back.
pub fn covers_field(parts: &[String]) -> String {
    let mut writer =
        csv::WriterBuilder::new().terminator(csv::Terminator::Any(b'\n')).from_writer(Vec::new());
    if parts.is_empty() || writer.write_record(parts).is_err() {
        return String::new();
    }
    let bytes = writer.into_inner().unwrap_or_default();
    let text = String::from_utf8_lossy(&bytes);
    text.strip_suffix('\n').unwrap_or(&text).to_string()
}

/// The part names of a `covers` field ([`covers_field`]); `Err` names the problem.
pub(crate) fn parse_covers(field: &str) -> Result<Vec<String>, String> {
    if field.trim().is_empty() {
        return Ok(Vec::new());
    }
    let mut reader = csv::ReaderBuilder::new().has_headers(false).from_reader(field.as_bytes());
    let mut records = reader.records();
    let record = records
        .next()
        .ok_or("covers is empty")?
        .map_err(|e| format!("covers {field:?} is not a list of part names: {e}"))?;
    if records.next().is_some() {
        return Err(format!("covers {field:?} holds a line break outside quotes"));
    }
    let parts: Vec<String> = record.iter().map(|p| p.trim().to_string()).collect();
    if parts.iter().any(String::is_empty) {
        return Err(format!("covers {field:?} names an empty part"));
    }
    Ok(parts)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_row_type_writes_the_published_columns_in_order() {
        let row = PlacementFrameRow {
            frame: 20,
            time_s: 0.5,
            eye: "left".into(),
            distance_m: 12.0,
            candidate: "grille".into(),
            kind: "part".into(),
            solid_angle_sr: 0.01,
            visible_fraction: 0.5,
            view_angle_deg: 30.0,
            angular_height_deg: 2.0,
            frame_s: 0.25,
            mirror: "".into(),
        };
        let mut writer = csv::Writer::from_writer(Vec::new());
        writer.serialize(&row).unwrap();
        let text = String::from_utf8(writer.into_inner().unwrap()).unwrap();
        let header = text.lines().next().unwrap();
        let expected: Vec<&str> =
            PLACEMENT_FRAMES_COLUMNS.iter().chain(&PLACEMENT_FRAMES_OPTIONAL).copied().collect();
        assert_eq!(header, expected.join(","));
        let mut reader = csv::Reader::from_reader(text.as_bytes());
        let back: PlacementFrameRow = reader.deserialize().next().unwrap().unwrap();
        assert_eq!(back, row);
    }

    #[test]
    fn a_covers_field_reads_back_any_part_names() {
        for parts in [
            vec![],
            vec!["grill".to_string()],
            vec!["bumper".into(), "grill".into()],
            vec!["a,b".into(), "say \"hi\"".into(), "line\nbreak".into()],
        ] {
            let field = covers_field(&parts);
            assert_eq!(parse_covers(&field).unwrap(), parts, "{field:?}");
        }
        assert_eq!(covers_field(&["bumper".into(), "grill".into()]), "bumper,grill");
        assert!(parse_covers("grill,,bumper").unwrap_err().contains("empty part"));
    }
}
