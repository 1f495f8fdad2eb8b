//! The CSV files of a result set: `parts.csv` (one row per legend part, two
//! more columns when the result has measures) and `frames.csv` (one row per
//! eye-frame and part), and the field quoting both use.

use std::io::Write;
use std::path::Path;

use crate::count::part_lookup::FrameLabel;
use crate::error::Result;
use crate::files::write_atomically;
use crate::result::frames::{FRAMES_HEADER, FrameTable};
use crate::result::measures::Measures;
use crate::result::part_stats::PartStats;

/// Writes `parts.csv` with the original tool's columns plus `coverage`.
pub fn write_parts_csv(path: &Path, parts: &[PartStats]) -> Result<()> {
    write_parts_table(path, parts, None)
}

/// Writes `parts.csv`; with `measures`, two more columns,
/// `angular_area_deg2_s` and `exposure_s` (empty where the manifest lacks fps
/// or pixels per degree).
pub(crate) fn write_parts_table(path: &Path, parts: &[PartStats], measures: Option<&Measures>) -> Result<()> {
    write_atomically(path, |writer| {
        write!(
            writer,
            "part_name,pixel_count,part_total_value,highest_value,average_value,total_percentage,coverage"
        )?;
        if measures.is_some() {
            write!(writer, ",angular_area_deg2_s,exposure_s")?;
        }
        writeln!(writer)?;
        for part in parts {
            write!(
                writer,
                "{},{},{},{},{},{},{}",
                csv_field(&part.name),
                part.texels,
                part.total,
                part.peak,
                part.average,
                part.share,
                part.coverage
            )?;
            if let Some(measures) = measures {
                let measure = measures.part(&part.name);
                write!(
                    writer,
                    ",{},{}",
                    optional(measure.and_then(|m| m.angular_area_deg2_s)),
                    optional(measure.and_then(|m| m.exposure_s)),
                )?;
            }
            writeln!(writer)?;
        }
        Ok(())
    })
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
pub fn write_frames_csv(path: &Path, table: &FrameTable) -> Result<()> {
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
        let legend = crate::input::labels::Legend::parse(Path::new("p.csv"), written.into_bytes()).unwrap();
        assert_eq!(legend.parts[0].name, odd);
    }
}
