//! Finding the frames: every PNG below the folder, named by the pattern,
//! with its size from the PNG header alone (33 bytes, so a capture of
//! thousands of tiles is described in moments), and the checks that make the
//! tiles one capture — each tile once, one tile size, a full grid in every
//! eye-frame, at most two eyes.

use std::collections::{BTreeMap, BTreeSet};
use std::io::Read;
use std::path::{Path, PathBuf};

use crate::describe::names::{NamePattern, TileName};
use crate::error::{Error, Result};

/// One file of the capture.
#[derive(Debug, Clone)]
pub(crate) struct FoundTile {
    /// The file as found below the folder.
    pub path: PathBuf,
    pub name: TileName,
    /// `[width, height]` from the PNG header.
    pub pixels: [u32; 2],
}

/// The capture's files and their layout.
#[derive(Debug, Clone)]
pub(crate) struct Capture {
    /// Sorted by frame, eye, row, column.
    pub tiles: Vec<FoundTile>,
    /// Tiles per eye image, `[columns, rows]`.
    pub grid: [u32; 2],
    /// Pixels of one tile, `[width, height]`.
    pub tile_pixels: [u32; 2],
    /// Distinct frame numbers, ascending.
    pub frames: Vec<u32>,
    /// Distinct eye names, sorted.
    pub eyes: Vec<String>,
    /// Grid positions no file fills, when they may be empty: listed as empty tiles.
    pub missing: Vec<TileName>,
}

impl Capture {
    /// Pixels of one eye image, `[width, height]`.
    pub(crate) fn eye_pixels(&self) -> [u32; 2] {
        [self.grid[0] * self.tile_pixels[0], self.grid[1] * self.tile_pixels[1]]
    }
}

/// The PNGs below `dir` (by name, `excluded` and result folders — those
/// holding a `result.json` — left out), read by `pattern` and checked; a
/// tile missing from a grid is an error unless `missing_empty`.
pub(crate) fn find_capture(
    dir: &Path,
    pattern: &NamePattern,
    excluded: &BTreeSet<PathBuf>,
    grid: Grid,
) -> Result<Capture> {
    let mut tiles = Vec::new();
    let mut unmatched = Vec::new();
    let walk =
        walkdir::WalkDir::new(dir).follow_links(true).sort_by_file_name().into_iter().filter_entry(|entry| {
            !(entry.depth() > 0 && entry.file_type().is_dir() && entry.path().join("result.json").is_file())
        });
    for entry in walk {
        let entry = entry.map_err(|error| {
            let path = error.path().unwrap_or(dir).to_path_buf();
            Error::io(&path, error.into())
        })?;
        let path = entry.path();
        let is_png = path.extension().is_some_and(|e| e.eq_ignore_ascii_case("png"));
        if !entry.file_type().is_file() || !is_png || excluded.contains(&canonical(path)?) {
            continue;
        }
        let relative = slash_path(path.strip_prefix(dir).unwrap_or(path));
        match pattern.read(&relative) {
            Ok(Some(name)) => {
                tiles.push(FoundTile { path: path.to_path_buf(), name, pixels: png_size(path)? })
            }
            Ok(None) => unmatched.push(relative),
            Err(problem) => return Err(Error::bad_file(path, problem)),
        }
    }
    if let Some(first) = unmatched.first() {
        return Err(Error::bad_file(
            dir,
            format!(
                "{} PNG file(s) do not match --pattern {:?}, e.g. {first} (nothing written; \
                 move them out or give a pattern that matches every frame)",
                unmatched.len(),
                pattern.text
            ),
        ));
    }
    if tiles.is_empty() {
        return Err(Error::NoImages { path: dir.to_path_buf() });
    }
    tiles.sort_by(|a, b| key(&a.name).cmp(&key(&b.name)));
    check_capture(tiles, grid)
}

/// How the grid of each eye image is known.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Grid {
    /// `[columns, rows]` as the rig says; else the largest column and row seen.
    pub given: Option<[u32; 2]>,
    /// Positions no file fills are empty tiles, not an error.
    pub missing_empty: bool,
}

fn key(name: &TileName) -> (u32, &str, u32, u32) {
    (name.frame, name.eye.as_str(), name.row, name.col)
}

/// `a/b.png` whatever the platform's separator.
pub(crate) fn slash_path(path: &Path) -> String {
    path.components().map(|c| c.as_os_str().to_string_lossy()).collect::<Vec<_>>().join("/")
}

/// The path with links resolved, or an error naming it.
pub(crate) fn canonical(path: &Path) -> Result<PathBuf> {
    std::fs::canonicalize(path).map_err(|error| Error::io(path, error))
}

/// Each tile once, one size, at most two eyes, every grid position in every eye-frame.
pub(crate) fn check_capture(tiles: Vec<FoundTile>, layout: Grid) -> Result<Capture> {
    let first = &tiles[0];
    for pair in tiles.windows(2) {
        if key(&pair[0].name) == key(&pair[1].name) {
            let TileName { frame, eye, row, col } = &pair[1].name;
            return Err(Error::bad_file(
                &pair[1].path,
                format!(
                    "is frame {frame}, eye {eye}, row {row}, col {col} by its name, like {}: each tile must be one file",
                    pair[0].path.display()
                ),
            ));
        }
    }
    if let Some(other) = tiles.iter().find(|t| t.pixels != first.pixels) {
        return Err(Error::bad_file(
            &other.path,
            format!(
                "is {}×{} pixels, but {} is {}×{}: every tile of a capture must have the same size",
                other.pixels[0],
                other.pixels[1],
                first.path.display(),
                first.pixels[0],
                first.pixels[1]
            ),
        ));
    }
    let eyes: BTreeSet<&str> = tiles.iter().map(|t| t.name.eye.as_str()).collect();
    if eyes.len() > 2 {
        return Err(Error::BadOptions(format!(
            "the file names give {} eyes ({}): a pedestrian has two; check --pattern's eye group",
            eyes.len(),
            eyes.into_iter().collect::<Vec<_>>().join(", ")
        )));
    }
    let seen = [
        tiles.iter().map(|t| t.name.col).max().unwrap_or(0) + 1,
        tiles.iter().map(|t| t.name.row).max().unwrap_or(0) + 1,
    ];
    let grid = layout.given.unwrap_or(seen);
    if let Some(outside) = tiles.iter().find(|t| t.name.col >= grid[0] || t.name.row >= grid[1]) {
        return Err(Error::bad_file(
            &outside.path,
            format!(
                "row {}, col {} lies outside the rig's tiles [{}, {}] ([columns, rows])",
                outside.name.row, outside.name.col, grid[0], grid[1]
            ),
        ));
    }
    let missing = check_grid(&tiles, grid, layout.missing_empty)?;
    let frames: BTreeSet<u32> = tiles.iter().map(|t| t.name.frame).collect();
    Ok(Capture {
        grid,
        tile_pixels: first.pixels,
        frames: frames.into_iter().collect(),
        eyes: eyes.into_iter().map(str::to_string).collect(),
        tiles,
        missing,
    })
}

/// Every eye-frame has all `grid` positions (tiles are sorted and unique),
/// or with `missing_empty` the positions it lacks.
fn check_grid(tiles: &[FoundTile], [columns, rows]: [u32; 2], missing_empty: bool) -> Result<Vec<TileName>> {
    let mut per_eye_frame: BTreeMap<(u32, &str), Vec<&FoundTile>> = BTreeMap::new();
    for tile in tiles {
        per_eye_frame.entry((tile.name.frame, tile.name.eye.as_str())).or_default().push(tile);
    }
    let mut missing = Vec::new();
    for ((frame, eye), found) in per_eye_frame {
        if found.len() == (columns * rows) as usize {
            continue;
        }
        let have: BTreeSet<(u32, u32)> = found.iter().map(|t| (t.name.row, t.name.col)).collect();
        let mut lacking = (0..rows)
            .flat_map(|row| (0..columns).map(move |col| (row, col)))
            .filter(|position| !have.contains(position));
        if missing_empty {
            missing.extend(lacking.map(|(row, col)| TileName { frame, eye: eye.to_string(), row, col }));
            continue;
        }
        let (row, col) = lacking.next().unwrap_or_default();
        let folder = found[0].path.parent().unwrap_or(Path::new("."));
        return Err(Error::bad_file(
            folder,
            format!(
                "frame {frame}, eye {eye} has no tile at row {row}, col {col} ({} of {} tiles; \
                 the other tiles make a grid of {rows} rows × {columns} columns, e.g. {}); if missing \
                 tiles showed only background and were not written, give --missing-tiles-empty",
                found.len(),
                columns * rows,
                found[0].path.display()
            ),
        ));
    }
    Ok(missing)
}

/// `[width, height]` from the PNG signature and IHDR chunk (its CRC checked).
pub(crate) fn png_size(path: &Path) -> Result<[u32; 2]> {
    let mut head = [0u8; 33];
    let mut file = crate::files::open_regular(path)?;
    let read = read_up_to(&mut file, &mut head).map_err(|error| Error::io(path, error))?;
    let bad = |message: &str| Error::Png { path: path.to_path_buf(), message: message.to_string() };
    if read < 8 || head[..8] != *b"\x89PNG\r\n\x1a\n" {
        return Err(bad("no PNG signature (is it a PNG?)"));
    }
    if read < 33 || head[8..12] != [0, 0, 0, 13] || head[12..16] != *b"IHDR" {
        return Err(bad("the header (IHDR chunk) is missing or truncated"));
    }
    if crc32fast::hash(&head[12..29]) != u32::from_be_bytes([head[29], head[30], head[31], head[32]]) {
        return Err(bad("the header (IHDR chunk) is damaged: its CRC does not match"));
    }
    let width = u32::from_be_bytes([head[16], head[17], head[18], head[19]]);
    let height = u32::from_be_bytes([head[20], head[21], head[22], head[23]]);
    if width == 0 || height == 0 {
        return Err(bad(&format!("the header says {width}×{height} pixels")));
    }
    Ok([width, height])
}

fn read_up_to(file: &mut std::fs::File, buffer: &mut [u8]) -> std::io::Result<usize> {
    let mut filled = 0;
    while filled < buffer.len() {
        match file.read(&mut buffer[filled..])? {
            0 => break,
            n => filled += n,
        }
    }
    Ok(filled)
}

#[cfg(test)]
mod tests {
    #[test]
    fn crc_of_a_known_ihdr_matches_the_png_specification() {
        // IHDR of a 1×1 8-bit RGB PNG: CRC 0x907753DE.
        let ihdr = [b'I', b'H', b'D', b'R', 0, 0, 0, 1, 0, 0, 0, 1, 8, 2, 0, 0, 0];
        assert_eq!(crc32fast::hash(&ihdr), 0x9077_53DE);
    }
}
