//! Parts: the legend, the Part Identification Texture (PIdT), and the join
//! of per-texel counts into per-part statistics.
//!
//! A texel belongs to the legend part whose colour it carries in the PIdT.
//! Texels whose PIdT colour no legend entry names are *unlabelled*: they are
//! counted and reported, never silently dropped.

use std::collections::{BTreeMap, HashMap};
use std::path::Path;

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::color::Color;
use crate::decode::read_color_image;
use crate::error::{Error, Result};

/// One legend entry.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Part {
    pub name: String,
    pub color: Color,
}

/// The legend: part names and the PIdT colours that mark them.
#[derive(Debug, Clone, Default)]
pub struct Legend {
    pub parts: Vec<Part>,
}

impl Legend {
    /// Reads a legend: CSV `name,color` (header optional) or a JSON list of
    /// `{"name", "color"}`.
    pub fn load(path: &Path) -> Result<Legend> {
        let bytes = crate::input_file::read_limited(path, crate::input_file::SMALL_INPUT_LIMIT)?;
        Legend::parse(path, bytes)
    }

    /// Parses a legend's bytes; `path` names it in messages and its
    /// extension (`.json`) picks the format when the text does not.
    pub fn parse(path: &Path, bytes: Vec<u8>) -> Result<Legend> {
        let text = String::from_utf8(bytes).map_err(|_| Error::bad_file(path, "legend is not UTF-8 text"))?;
        let is_json = path.extension().is_some_and(|e| e.eq_ignore_ascii_case("json"))
            || text.trim_start().starts_with('[');
        let parts = if is_json {
            serde_json::from_str::<Vec<Part>>(&text)
                .map_err(|e| Error::bad_file(path, format!("invalid JSON legend: {e}")))?
        } else {
            parse_csv_legend(path, &text)?
        };
        Legend::new(path, parts)
    }

    /// Checks that names and colours are unique and the legend is not empty.
    pub fn new(path: &Path, parts: Vec<Part>) -> Result<Legend> {
        if parts.is_empty() {
            return Err(Error::bad_file(path, "the legend lists no parts"));
        }
        if parts.len() >= usize::from(UNLABELLED) {
            return Err(Error::bad_file(path, format!("too many parts ({}); at most 65534", parts.len())));
        }
        let mut colors = HashMap::new();
        let mut names = HashMap::new();
        for (index, part) in parts.iter().enumerate() {
            if let Some(other) = colors.insert(part.color, index) {
                return Err(Error::bad_file(
                    path,
                    format!(
                        "parts {:?} and {:?} share the colour {}",
                        parts[other].name, part.name, part.color
                    ),
                ));
            }
            if names.insert(part.name.clone(), index).is_some() {
                return Err(Error::bad_file(path, format!("part name {:?} appears twice", part.name)));
            }
        }
        Ok(Legend { parts })
    }
}

/// Splits one CSV line into fields, honouring double quotes.
fn parse_csv_legend(path: &Path, text: &str) -> Result<Vec<Part>> {
    // The csv crate: quoted names with commas, quotes, CR or LF round-trip.
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(false)
        .flexible(true)
        .trim(csv::Trim::All)
        .from_reader(text.trim_start_matches('\u{feff}').as_bytes());
    let mut records = Vec::new();
    for record in reader.records() {
        let record = record.map_err(|e| Error::bad_file(path, format!("invalid CSV legend: {e}")))?;
        let line = record.position().map_or(0, |p| p.line());
        if record.iter().all(str::is_empty) {
            continue;
        }
        records.push((line, record));
    }
    let (mut name_column, mut color_column) = (0, 1);
    let mut rows = records.iter().peekable();
    if let Some((_, first)) = rows.peek() {
        let find = |wanted: &[&str]| first.iter().position(|h| wanted.contains(&h.to_lowercase().as_str()));
        if let (Some(name), Some(color)) = (find(&["name", "part", "part_name"]), find(&["color", "colour"]))
        {
            (name_column, color_column) = (name, color);
            rows.next();
        }
    }
    let mut parts = Vec::new();
    for (line_no, record) in rows {
        let (Some(name), Some(color)) = (record.get(name_column), record.get(color_column)) else {
            return Err(Error::bad_file(path, format!("line {line_no}: expected name,color")));
        };
        let color = color.parse().map_err(|e| Error::bad_file(path, format!("line {line_no}: {e}")))?;
        if name.is_empty() {
            return Err(Error::bad_file(path, format!("line {line_no}: empty part name")));
        }
        parts.push(Part { name: name.to_string(), color });
    }
    Ok(parts)
}

/// Marker for texels whose PIdT colour is in no legend entry.
pub const UNLABELLED: u16 = u16::MAX;

/// The PIdT resolved against a legend: a part number per texel.
pub struct Pidt {
    pub width: u32,
    pub height: u32,
    /// Legend index per texel, or [`UNLABELLED`].
    pub part_of_texel: Vec<u16>,
    /// Texels per legend part.
    pub part_texels: Vec<u64>,
    /// Unlabelled PIdT colours and how many texels carry each.
    pub unlabelled_colors: BTreeMap<Color, u64>,
}

impl Pidt {
    /// Reads the PIdT at `path`, which must be `width`×`height` texels.
    pub fn load(path: &Path, legend: &Legend, width: u32, height: u32) -> Result<Pidt> {
        let image = read_color_image(path, |found_width, found_height| {
            if (found_width, found_height) == (width, height) {
                Ok(())
            } else {
                Err(Error::WrongSize {
                    path: path.to_path_buf(),
                    what: "the PIdT must match the palette".to_string(),
                    expected_width: width,
                    expected_height: height,
                    found_width,
                    found_height,
                })
            }
        })?;
        Ok(Pidt::from_colors(width, height, &image.colors, legend))
    }

    /// Resolves packed PIdT colours (row-major) against a legend.
    pub fn from_colors(width: u32, height: u32, colors: &[u32], legend: &Legend) -> Pidt {
        // A legend holds tens of parts: a sorted list searched only when the
        // colour changes is as fast as a hash map here, with std alone.
        let mut index: Vec<(u32, u16)> =
            legend.parts.iter().enumerate().map(|(i, part)| (part.color.packed(), i as u16)).collect();
        index.sort_unstable();
        let row = width as usize;
        let part_of_texel: Vec<u16> = colors
            .par_chunks(row.max(1))
            .flat_map_iter(|row_colors| {
                let index = &index;
                // PIdT rows are long runs of one colour; remember the last lookup.
                let mut last = (u32::MAX, UNLABELLED);
                row_colors.iter().map(move |&color| {
                    if color != last.0 {
                        let part = index
                            .binary_search_by_key(&color, |&(key, _)| key)
                            .map_or(UNLABELLED, |i| index[i].1);
                        last = (color, part);
                    }
                    last.1
                })
            })
            .collect();
        let mut part_texels = vec![0u64; legend.parts.len()];
        let mut unlabelled_colors = BTreeMap::new();
        for (&part, &color) in part_of_texel.iter().zip(colors) {
            if part == UNLABELLED {
                *unlabelled_colors.entry(Color::from_packed(color)).or_insert(0) += 1;
            } else {
                part_texels[usize::from(part)] += 1;
            }
        }
        Pidt { width, height, part_of_texel, part_texels, unlabelled_colors }
    }
}

/// Statistics of one part (or of the unlabelled texels).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct PartStats {
    pub name: String,
    pub color: Option<Color>,
    /// Texels of this part in the PIdT.
    pub texels: u64,
    /// Sum of the counts of its texels.
    pub total: u64,
    /// Largest count of one of its texels.
    pub peak: u32,
    /// `total / texels`, 0 for a part without texels.
    pub average: f64,
    /// Percentage of the grand total (sum of totals over legend parts).
    pub share: f64,
    /// Percentage of its texels seen at least once.
    pub coverage: f64,
    /// Texels with count ≥ 1.
    pub texels_seen: u64,
}

/// Raw sums gathered per part during the join.
#[derive(Debug, Clone, Copy, Default)]
struct Sums {
    texels: u64,
    total: u64,
    peak: u32,
    seen: u64,
}

impl Sums {
    fn add(&mut self, count: u32) {
        self.texels += 1;
        self.total += u64::from(count);
        self.peak = self.peak.max(count);
        self.seen += u64::from(count > 0);
    }
    fn merge(mut self, other: Sums) -> Sums {
        self.texels += other.texels;
        self.total += other.total;
        self.peak = self.peak.max(other.peak);
        self.seen += other.seen;
        self
    }
}

/// The per-part table and the unlabelled remainder.
#[derive(Debug, Clone, PartialEq)]
pub struct PartTable {
    pub parts: Vec<PartStats>,
    pub unlabelled: PartStats,
    /// Sum of totals over legend parts (the paper's "grand total").
    pub grand_total: u64,
}

/// Joins per-texel counts with the PIdT (in parallel, exact integer sums).
pub fn join_parts(texel_counts: &[u32], pidt: &Pidt, legend: &Legend) -> PartTable {
    let slots = legend.parts.len() + 1; // last slot: unlabelled
    let sums = texel_counts
        .par_chunks(1 << 16)
        .zip(pidt.part_of_texel.par_chunks(1 << 16))
        .fold(
            || vec![Sums::default(); slots],
            |mut sums, (counts, parts)| {
                for (&count, &part) in counts.iter().zip(parts) {
                    let slot = if part == UNLABELLED { slots - 1 } else { usize::from(part) };
                    sums[slot].add(count);
                }
                sums
            },
        )
        .reduce(
            || vec![Sums::default(); slots],
            |a, b| a.into_iter().zip(b).map(|(x, y)| x.merge(y)).collect(),
        );
    let grand_total: u64 = sums[..slots - 1].iter().map(|s| s.total).sum();
    let stats = |name: &str, color: Option<Color>, sums: &Sums| PartStats {
        name: name.to_string(),
        color,
        texels: sums.texels,
        total: sums.total,
        peak: sums.peak,
        average: ratio(sums.total, sums.texels),
        share: 100.0 * ratio(sums.total, grand_total),
        coverage: 100.0 * ratio(sums.seen, sums.texels),
        texels_seen: sums.seen,
    };
    let parts =
        legend.parts.iter().zip(&sums).map(|(part, s)| stats(&part.name, Some(part.color), s)).collect();
    let unlabelled = stats("(unlabelled)", None, &sums[slots - 1]);
    PartTable { parts, unlabelled, grand_total }
}

/// `numerator / denominator`, 0 when the denominator is 0.
pub fn ratio(numerator: u64, denominator: u64) -> f64 {
    if denominator == 0 { 0.0 } else { numerator as f64 / denominator as f64 }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn legend() -> Legend {
        Legend::new(
            Path::new("parts.csv"),
            vec![
                Part { name: "Hood".into(), color: Color::from_packed(0xFF0000) },
                Part { name: "Roof".into(), color: Color::from_packed(0x00FF00) },
                Part { name: "Ghost".into(), color: Color::from_packed(0x0000FF) },
            ],
        )
        .unwrap()
    }

    #[test]
    fn parses_csv_with_header_quotes_and_bom() {
        let parts = parse_csv_legend(
            Path::new("p.csv"),
            "\u{feff}name,color\n\"Door, front left\",#010203\nHood,#ff0000\n\n",
        )
        .unwrap();
        assert_eq!(parts[0].name, "Door, front left");
        assert_eq!(parts[1].color, Color::from_packed(0xFF0000));
        let error = parse_csv_legend(Path::new("p.csv"), "name,color\nHood,red\n").unwrap_err();
        assert!(error.to_string().contains("line 2"), "{error}");
        // Names with CR, LF and quotes round-trip through the writer.
        let odd = "Door\r\n\"front\", left";
        let written = format!("name,color\n{},#010203\n", crate::report::csv_field(odd));
        assert_eq!(parse_csv_legend(Path::new("p.csv"), &written).unwrap()[0].name, odd);
    }

    #[test]
    fn rejects_shared_colours() {
        let parts = vec![
            Part { name: "A".into(), color: Color::from_packed(1) },
            Part { name: "B".into(), color: Color::from_packed(1) },
        ];
        assert!(Legend::new(Path::new("p.csv"), parts).unwrap_err().to_string().contains("share"));
    }

    #[test]
    fn joins_hand_computed_table() {
        let legend = legend();
        // 2×3 PIdT: Hood, Hood, Roof, Roof, unlabelled, unlabelled.
        let pidt =
            Pidt::from_colors(2, 3, &[0xFF0000, 0xFF0000, 0x00FF00, 0x00FF00, 0x0A0000, 0x0A0000], &legend);
        assert_eq!(pidt.part_texels, vec![2, 2, 0]);
        assert_eq!(pidt.unlabelled_colors[&Color::from_packed(0x0A0000)], 2);
        let table = join_parts(&[3, 1, 0, 4, 5, 0], &pidt, &legend);
        assert_eq!(table.grand_total, 8);
        let hood = &table.parts[0];
        assert_eq!((hood.texels, hood.total, hood.peak), (2, 4, 3));
        assert_eq!((hood.average, hood.share, hood.coverage), (2.0, 50.0, 100.0));
        let roof = &table.parts[1];
        assert_eq!((roof.total, roof.peak, roof.coverage), (4, 4, 50.0));
        let ghost = &table.parts[2];
        assert_eq!((ghost.texels, ghost.average, ghost.share), (0, 0.0, 0.0));
        assert_eq!((table.unlabelled.texels, table.unlabelled.total), (2, 5));
    }
}
