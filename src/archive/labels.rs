//! Labels: the legend (part names and colours) and the Part Identification
//! Texture (PIdT) that paints each texel with its part's colour.
//!
//! A texel belongs to the legend part whose colour it carries in the PIdT.
//! Texels whose PIdT colour no legend entry names are *unlabelled*: they are
//! counted and reported, never silently dropped (see
//! [`crate::result::part_stats`] for the join).

use std::collections::{BTreeMap, HashMap};
use std::path::Path;

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::color::Color;
use crate::error::{Error, Result};
use crate::png::rows::read_color_image;

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
        let bytes = crate::files::read_limited(path, crate::files::SMALL_INPUT_LIMIT)?;
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

    /// Checks that names are not blank, names and colours are unique and the
    /// legend is not empty.
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
            // The CSV reader trims names; a JSON legend must not sneak in "" or "  " either.
            if part.name.trim().is_empty() {
                return Err(Error::bad_file(
                    path,
                    format!("part {} (colour {}): empty or blank part name", index + 1, part.color),
                ));
            }
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

/// A legend and PIdT already loaded from the files an analysis resolves
/// ([`crate::AnalyzeOptions::loaded_labels`]): a study's settings share one
/// instead of decoding the 4096² PIdT again for each. Whoever builds it
/// vouches that it holds those files' contents.
#[derive(Clone)]
pub struct LoadedLabels {
    pub legend: Legend,
    pub pidt: std::sync::Arc<Pidt>,
}

impl std::fmt::Debug for LoadedLabels {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "LoadedLabels {{ parts: {}, pidt: {}×{} }}",
            self.legend.parts.len(),
            self.pidt.width,
            self.pidt.height
        )
    }
}

/// The PIdT resolved against a legend: a part number per texel (the
/// capture holds the same texture as the image it writes, `PidtImage`).
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
        let row = (width as usize).max(1);
        let mut part_of_texel = vec![UNLABELLED; colors.len()];
        let no_tallies = || (vec![0u64; legend.parts.len()], BTreeMap::new());
        // Row by row on every core: each row's parts, and its tallies.
        let (part_texels, unlabelled_colors) = part_of_texel
            .par_chunks_mut(row)
            .zip(colors.par_chunks(row))
            .fold(no_tallies, |(mut part_texels, mut unlabelled), (parts, row_colors)| {
                // PIdT rows are long runs of one colour: one lookup per run.
                let mut x = 0;
                while x < row_colors.len() {
                    let color = row_colors[x];
                    let run =
                        row_colors[x..].iter().position(|&c| c != color).unwrap_or(row_colors.len() - x);
                    let found = index.binary_search_by_key(&color, |&(key, _)| key);
                    let part = found.map_or(UNLABELLED, |i| index[i].1);
                    parts[x..x + run].fill(part);
                    if part == UNLABELLED {
                        *unlabelled.entry(Color::from_packed(color)).or_insert(0u64) += run as u64;
                    } else {
                        part_texels[usize::from(part)] += run as u64;
                    }
                    x += run;
                }
                (part_texels, unlabelled)
            })
            .reduce(no_tallies, |(mut texels, mut unlabelled), (more_texels, more_unlabelled)| {
                texels.iter_mut().zip(more_texels).for_each(|(sum, more)| *sum += more);
                for (color, count) in more_unlabelled {
                    *unlabelled.entry(color).or_insert(0) += count;
                }
                (texels, unlabelled)
            });
        Pidt { width, height, part_of_texel, part_texels, unlabelled_colors }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pidt_runs_resolve_to_parts_and_tallies_row_by_row() {
        let parts = vec![
            Part { name: "Hood".into(), color: Color::from_packed(0xFF0000) },
            Part { name: "Roof".into(), color: Color::from_packed(0x00FF00) },
        ];
        let legend = Legend::new(Path::new("p.csv"), parts).unwrap();
        let (hood, roof, stray) = (0xFF0000, 0x00FF00, 0x0A0000);
        // 4×3: runs that end at a row's end, an unlabelled run in the
        // middle of a row, a one-texel run.
        let colors = [hood, hood, stray, roof, roof, roof, roof, roof, stray, stray, hood, stray];
        let pidt = Pidt::from_colors(4, 3, &colors, &legend);
        assert_eq!(
            pidt.part_of_texel,
            [0, 0, UNLABELLED, 1, 1, 1, 1, 1, UNLABELLED, UNLABELLED, 0, UNLABELLED]
        );
        assert_eq!(pidt.part_texels, [3, 5]);
        assert_eq!(pidt.unlabelled_colors, BTreeMap::from([(Color::from_packed(stray), 4)]));
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
        // Names with CR, LF and quotes, quoted (as output::csv writes them).
        let written = "name,color\n\"Door\r\n\"\"front\"\", left\",#010203\n";
        assert_eq!(parse_csv_legend(Path::new("p.csv"), written).unwrap()[0].name, "Door\r\n\"front\", left");
    }

    #[test]
    fn rejects_shared_colors() {
        let parts = vec![
            Part { name: "A".into(), color: Color::from_packed(1) },
            Part { name: "B".into(), color: Color::from_packed(1) },
        ];
        assert!(Legend::new(Path::new("p.csv"), parts).unwrap_err().to_string().contains("share"));
    }
}
