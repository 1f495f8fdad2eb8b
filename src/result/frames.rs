//! Per-eye-frame visibility: for every eye-frame (or, without a manifest,
//! every image) and every part, the pixels showing the part and the distinct
//! texels of the part seen in it — the table behind `frames.csv`, read back
//! for merging shards. Counting fills it through
//! [`crate::count::part_lookup`]; [`crate::output::csv`] writes it; the
//! resolution-independent measures ([`crate::result::measures`]) are sums
//! over its rows.

use std::path::Path;

use crate::archive::capture_facts::EyeFrame;
use crate::count::part_lookup::{FrameLabel, FrameRecord};
use crate::error::{Error, Result};

/// Name of the per-eye-frame table beside `result.json`.
pub(crate) const FRAMES_FILE: &str = "frames.csv";

/// Header of [`FRAMES_FILE`]. `solid_angle_sr` is the solid angle the
/// part's pixels subtend in the eye's projection (empty when the manifest
/// gives no projection), written to round-trip exactly.
pub(crate) const FRAMES_HEADER: &str = "frame,time_s,eye,distance_m,part,pixels,texels,solid_angle_sr";

/// The header before `solid_angle_sr` (read back, without solid angles).
pub(crate) const FRAMES_HEADER_V1: &str = "frame,time_s,eye,distance_m,part,pixels,texels";

/// Every eye-frame's tallies, in eye-frame order: the content of [`FRAMES_FILE`].
#[derive(Debug, Clone, PartialEq, Default)]
pub struct FrameTable {
    /// Part names, one column block per part.
    pub parts: Vec<String>,
    pub records: Vec<FrameRecord>,
}

/// One row of a [`FRAMES_FILE`] being read, with its row number (the
/// header is row 1) for messages.
struct FramesRow<'a> {
    path: &'a Path,
    fields: csv::StringRecord,
    number: usize,
}

impl FramesRow<'_> {
    /// An error naming the file and this row.
    fn bad(&self, message: String) -> Error {
        Error::bad_file(self.path, format!("row {}: {message}", self.number))
    }

    fn field(&self, index: usize) -> &str {
        self.fields.get(index).unwrap_or_default()
    }

    /// A number, or `None` for an empty field.
    fn number(&self, index: usize) -> Result<Option<f64>> {
        let text = self.field(index);
        if text.is_empty() {
            return Ok(None);
        }
        text.parse().map(Some).map_err(|_| self.bad(format!("{text:?} is not a number")))
    }

    fn count(&self, index: usize) -> Result<u64> {
        self.field(index).parse().map_err(|_| self.bad(format!("{:?} is not a count", self.field(index))))
    }

    /// The eye-frame the row belongs to, or without time, eye and distance
    /// the image at the position in the frame column.
    fn label(&self) -> Result<FrameLabel> {
        let frame: u64 = self.field(0).parse().map_err(|_| self.bad("no frame number".into()))?;
        if self.field(2).is_empty() && self.field(1).is_empty() && self.field(3).is_empty() {
            return Ok(FrameLabel::Image(frame as usize));
        }
        let frame = u32::try_from(frame).map_err(|_| self.bad("frame too large".into()))?;
        Ok(FrameLabel::EyeFrame(EyeFrame {
            frame,
            eye: self.field(2).to_string(),
            time_s: self.number(1)?,
            distance_m: self.number(3)?,
        }))
    }
}

impl FrameTable {
    /// Reads a [`FRAMES_FILE`] back (for merging shards).
    pub fn read_csv(path: &Path) -> Result<FrameTable> {
        let bad = |message: String| Error::bad_file(path, message);
        let bytes = crate::files::read_limited(path, crate::files::IMAGE_LIMIT)?;
        let mut reader = csv::ReaderBuilder::new().has_headers(true).from_reader(bytes.as_slice());
        let header = reader.headers().map_err(|e| bad(e.to_string()))?.iter().collect::<Vec<_>>().join(",");
        if header != FRAMES_HEADER && header != FRAMES_HEADER_V1 {
            return Err(bad(format!(
                "not a {FRAMES_FILE}: the header is {header:?}, expected {FRAMES_HEADER:?} (or, from older \
                 versions, {FRAMES_HEADER_V1:?})"
            )));
        }
        let mut table = FrameTable::default();
        let mut part = 0;
        for (line, record) in reader.records().enumerate() {
            let row = FramesRow { path, fields: record.map_err(|e| bad(e.to_string()))?, number: line + 2 };
            table.push_row(&row, &mut part)?;
        }
        if table.records.iter().any(|record| record.pixels.len() != table.parts.len()) {
            return Err(bad("an eye-frame lacks some parts' rows".into()));
        }
        Ok(table)
    }

    /// Adds one row: a new eye-frame when its label differs from the last
    /// row's, then the `part`-th part's pixels, texels and solid angle (the
    /// parts in the first eye-frame's order).
    fn push_row(&mut self, row: &FramesRow, part: &mut usize) -> Result<()> {
        let label = row.label()?;
        let name = row.field(4);
        if self.records.last().is_none_or(|last: &FrameRecord| last.label != label) {
            *part = 0;
            self.records.push(FrameRecord {
                label,
                pixels: Vec::new(),
                texels: Vec::new(),
                solid_angle_sr: Some(Vec::new()),
            });
        }
        if self.records.len() == 1 {
            self.parts.push(name.to_string());
        } else if self.parts.get(*part).map(String::as_str) != Some(name) {
            return Err(row.bad(format!("part {name:?} out of the order of the first eye-frame")));
        }
        let record = self.records.last_mut().expect("pushed above");
        record.pixels.push(row.count(5)?);
        record.texels.push(row.count(6)?);
        match (row.number(7)?, record.solid_angle_sr.as_mut()) {
            (Some(sr), Some(solid)) if sr.is_finite() && sr >= 0.0 => solid.push(sr),
            (Some(sr), Some(_)) => return Err(row.bad(format!("solid angle {sr} is not a solid angle"))),
            (Some(_), None) => return Err(row.bad("a solid angle where the eye-frame has none".into())),
            (None, _) => record.solid_angle_sr = None,
        }
        *part += 1;
        Ok(())
    }

    /// The tables of shards that together hold every eye-frame once, as one
    /// table in eye-frame order: what the whole archive's analysis gives.
    pub fn merged(shards: Vec<FrameTable>) -> Option<FrameTable> {
        let mut shards = shards.into_iter();
        let mut merged = shards.next()?;
        for shard in shards {
            merged.records.extend(shard.records);
        }
        let key = |label: &FrameLabel| match label {
            FrameLabel::EyeFrame(e) => (u64::from(e.frame), e.eye.clone()),
            FrameLabel::Image(position) => (*position as u64, String::new()),
        };
        merged.records.sort_by_key(|record| key(&record.label));
        Some(merged)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(text: &str) -> Result<FrameTable> {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join(FRAMES_FILE);
        std::fs::write(&path, text).unwrap();
        FrameTable::read_csv(&path)
    }

    #[test]
    fn solid_angles_round_trip_and_older_tables_read_without_them() {
        let sr = 1.0f64 / 3.0 * 1e-4;
        let new = format!("{FRAMES_HEADER}\n0,0,left,5,a,4,2,{sr}\n0,0,left,5,b,0,0,0\n");
        let table = read(&new).unwrap();
        assert_eq!(table.records[0].solid_angle_sr, Some(vec![sr, 0.0]));
        let old = format!("{FRAMES_HEADER_V1}\n0,0,left,5,a,4,2\n0,0,left,5,b,0,0\n");
        let table = read(&old).unwrap();
        assert_eq!(
            (table.records[0].pixels.clone(), table.records[0].solid_angle_sr.clone()),
            (vec![4, 0], None)
        );
        let wrong = read("frame,eye,pixels\n0,left,3\n").unwrap_err().to_string();
        assert!(wrong.contains("frames.csv") && wrong.contains("expected"), "{wrong}");
        let negative = read(&format!("{FRAMES_HEADER}\n0,0,left,5,a,4,2,-1\n")).unwrap_err().to_string();
        assert!(negative.contains("row 2") && negative.contains("not a solid angle"), "{negative}");
    }
}
