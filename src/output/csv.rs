//! The CSV files of a result set: `parts.csv` (one row per legend part, two
//! more columns when the result has measures; in the report's words and
//! order, or the paper's for old scripts) and `frames.csv` (one row per
//! eye-frame and part), and the field quoting both use.

use std::io::Write;
use std::path::Path;

use crate::count::part_lookup::FrameLabel;
use crate::error::Result;
use crate::files::write_atomically;
use crate::result::frames::{FRAMES_HEADER, FrameTable};
use crate::result::measures::Measures;
use crate::result::part_stats::PartStats;

/// The columns of `parts.csv`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum CsvStyle {
    /// The report's words (`part,texels,total,peak,average,share_percent,
    /// coverage_percent,texels_seen`), the report's precision (3 decimals, 2
    /// for coverage) and its order: by total, highest first, ties in legend order.
    #[default]
    Report,
    /// The paper's (and earlier versions') columns (`part_name,pixel_count,
    /// part_total_value,highest_value,average_value,total_percentage,coverage`),
    /// full precision, legend order: for scripts written against them.
    Paper,
}

impl std::str::FromStr for CsvStyle {
    type Err = crate::error::Error;

    fn from_str(text: &str) -> Result<Self> {
        match text {
            "report" => Ok(Self::Report),
            "paper" => Ok(Self::Paper),
            other => Err(crate::error::Error::BadOptions(format!(
                "--csv-style {other:?}: expected `report` or `paper`"
            ))),
        }
    }
}

/// Writes `parts.csv` in the report's vocabulary ([`CsvStyle::Report`]).
pub fn write_parts_csv(path: &Path, parts: &[PartStats]) -> Result<()> {
    write_parts_table(path, parts, None, CsvStyle::Report)
}

/// Writes `parts.csv` in `style`; with `measures`, two more columns,
/// `angular_area_deg2_s` and `exposure_s` (empty where the manifest lacks fps
/// or pixels per degree).
pub(crate) fn write_parts_table(
    path: &Path,
    parts: &[PartStats],
    measures: Option<&Measures>,
    style: CsvStyle,
) -> Result<()> {
    let order = row_order(parts, style);
    write_atomically(path, |writer| {
        match style {
            CsvStyle::Report => {
                write!(writer, "part,texels,total,peak,average,share_percent,coverage_percent,texels_seen")?
            }
            CsvStyle::Paper => write!(
                writer,
                "part_name,pixel_count,part_total_value,highest_value,average_value,total_percentage,coverage"
            )?,
        }
        if measures.is_some() {
            write!(writer, ",angular_area_deg2_s,exposure_s")?;
        }
        writeln!(writer)?;
        for &index in &order {
            let part = &parts[index];
            write!(writer, "{}", part_row(part, style))?;
            if let Some(measures) = measures {
                let measure = measures.part(&part.name);
                let value = |v: Option<f64>| match style {
                    CsvStyle::Report => v.map(|v| format!("{v:.3}")).unwrap_or_default(),
                    CsvStyle::Paper => optional(v),
                };
                write!(
                    writer,
                    ",{},{}",
                    value(measure.and_then(|m| m.angular_area_deg2_s)),
                    value(measure.and_then(|m| m.exposure_s)),
                )?;
            }
            writeln!(writer)?;
        }
        Ok(())
    })
}

/// The rows' order: the report's (total, highest first; ties in legend
/// order) or, for the paper's style, the legend's.
fn row_order(parts: &[PartStats], style: CsvStyle) -> Vec<usize> {
    let mut order: Vec<usize> = (0..parts.len()).collect();
    if style == CsvStyle::Report {
        order.sort_by(|&a, &b| parts[b].total.cmp(&parts[a].total).then(a.cmp(&b)));
    }
    order
}

/// One part's statistics as CSV fields (without the measures).
fn part_row(part: &PartStats, style: CsvStyle) -> String {
    let name = csv_field(&part.name);
    match style {
        CsvStyle::Report => format!(
            "{name},{},{},{},{:.3},{:.3},{:.2},{}",
            part.texels, part.total, part.peak, part.average, part.share, part.coverage, part.texels_seen
        ),
        CsvStyle::Paper => format!(
            "{name},{},{},{},{},{},{}",
            part.texels, part.total, part.peak, part.average, part.share, part.coverage
        ),
    }
}

/// `text` as one CSV field, quoted when it holds a comma, quote or newline.
pub fn csv_field(text: &str) -> String {
    // CR too: an unquoted CR would end the record for any CSV reader.
    if text.contains([',', '"', '\n', '\r']) || text.trim() != text {
        format!("\"{}\"", text.replace('"', "\"\""))
    } else {
        text.to_string()
    }
}

/// Writes [`crate::result::frames::FRAMES_FILE`] of `table`: one row per eye-frame and part.
pub(crate) fn write_frames_csv(path: &Path, table: &FrameTable) -> Result<()> {
    write_atomically(path, |writer| {
        writeln!(writer, "{FRAMES_HEADER}")?;
        let parts: Vec<String> = table.parts.iter().map(|name| csv_field(name)).collect();
        for record in &table.records {
            let prefix = match &record.label {
                FrameLabel::EyeFrame(eye_frame) => format!(
                    "{},{},{},{}",
                    eye_frame.frame,
                    optional(eye_frame.time_s),
                    csv_field(&eye_frame.eye),
                    optional(eye_frame.distance_m)
                ),
                FrameLabel::Image(position) => format!("{position},,,"),
            };
            for (part, name) in parts.iter().enumerate() {
                let solid = record.solid_angle_sr.as_ref().map(|sr| sr[part].to_string()).unwrap_or_default();
                writeln!(writer, "{prefix},{name},{},{},{solid}", record.pixels[part], record.texels[part])?;
            }
        }
        Ok(())
    })
}

fn optional(value: Option<f64>) -> String {
    value.map(|v| v.to_string()).unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::*;

    #[test]
    fn names_with_newlines_and_quotes_round_trip_through_the_legend_reader() {
        let odd = "Door\r\n\"front\", left";
        let written = format!("name,color\n{},#010203\n", csv_field(odd));
        let legend = crate::archive::labels::Legend::parse(Path::new("p.csv"), written.into_bytes()).unwrap();
        assert_eq!(legend.parts[0].name, odd);
    }
}
