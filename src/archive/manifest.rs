//! The archive manifest (`manifest.json`): what a capture wrote and how to read it.
//!
//! `ufcsr-capture` writes it; Unity or Blender users may write it by hand. It
//! names the palette, PIdT, legend and background used for the capture and
//! lists every tile with its frame, eye, row and column, so the analyzer needs
//! no options and can deduplicate texels per eye-frame. Fields it does not know
//! (per-frame time, vehicle pose, rig settings...) are kept in `extra`.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Deserializer, Serialize};
use serde_json::{Map, Value};

use crate::color::Color;
use crate::error::{Error, Result};
use crate::files::write_atomically;

/// File name of the manifest inside an archive folder.
pub const MANIFEST_FILE: &str = "manifest.json";

/// Schema string written by this version.
pub const MANIFEST_SCHEMA: &str = "ufcsr-manifest/1";

/// An archive manifest. Paths are relative to the archive folder.
#[derive(Debug, Clone, Serialize, Deserialize, Default)]
pub struct Manifest {
    /// Schema version, `ufcsr-manifest/1`.
    #[serde(default)]
    pub schema: Option<String>,
    /// The palette the vehicle was rendered with.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub palette: Option<PaletteRecord>,
    /// The Part Identification Texture (relative path).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pidt: Option<PathBuf>,
    /// The legend of the PIdT, CSV or JSON (relative path).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub parts: Option<PathBuf>,
    /// Colours that are not the vehicle.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub background: Option<Vec<Color>>,
    /// Every tile of the capture, written or known to be empty.
    pub tiles: Vec<TileEntry>,
    /// Everything else (rig, scene, per-frame poses...), kept verbatim.
    #[serde(flatten)]
    pub extra: Map<String, Value>,
}

/// Which palette a capture used, as `manifest.json` records it (the
/// palette itself, loaded, is [`crate::Fcsp`]; what an analysis is asked
/// for is [`crate::PaletteChoice`]).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum PaletteRecord {
    /// The canonical palette of the given `[width, height]`.
    Canonical { canonical: [u32; 2] },
    /// A palette image, relative to the archive folder.
    File(PathBuf),
}

/// The one containment rule for every path a manifest names — tiles,
/// `pidt`, `parts`, a palette image, `vehicle`: relative, without `..`, and,
/// with links followed, inside the archive folder `root`. Returns the path
/// to read. A file that does not exist passes here and fails where it is
/// read, naming itself. Paths given on the command line (`--pidt`, `--mesh`,
/// …) are the user's own choice and are not held to it.
pub fn inside_archive(root: &Path, field: &str, file: &Path) -> Result<PathBuf> {
    let manifest = root.join(MANIFEST_FILE);
    if file.is_absolute() || file.components().any(|c| matches!(c, std::path::Component::ParentDir)) {
        return Err(Error::bad_file(
            &manifest,
            format!("{field} {} must be a path inside the archive folder", file.display()),
        ));
    }
    let path = root.join(file);
    if let (Some(real_root), Some(real)) = (crate::files::resolved(root), crate::files::resolved(&path))
        && !real.starts_with(&real_root)
    {
        return Err(Error::bad_file(
            &manifest,
            format!(
                "{field} {} leads outside the archive folder (through a link, to {}): an archive names only its own files",
                file.display(),
                real.display()
            ),
        ));
    }
    Ok(path)
}

/// One tile of one eye of one frame.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct TileEntry {
    /// The PNG (relative path); absent when the tile was not written because
    /// nothing but background could be in it (then `empty` is true).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub file: Option<PathBuf>,
    /// Frame number, starting at 0.
    pub frame: u32,
    /// Which eye, `"left"` or `"right"` (numbers are accepted and kept as text).
    #[serde(deserialize_with = "eye_as_text")]
    pub eye: String,
    /// Tile row, 0 = top.
    pub row: u32,
    /// Tile column, 0 = left.
    pub col: u32,
    /// True when the capture knew the tile is pure background and wrote no file.
    #[serde(default, skip_serializing_if = "is_false")]
    pub empty: bool,
    /// Anything else (`time_s`, `distance_m`...).
    #[serde(flatten)]
    pub extra: Map<String, Value>,
}

impl TileEntry {
    /// Where the tile is, for messages: `(frame 20, eye left, row 2, col 2)`.
    pub fn place(&self) -> String {
        format!("(frame {}, eye {}, row {}, col {})", self.frame, self.eye, self.row, self.col)
    }
}

fn is_false(value: &bool) -> bool {
    !*value
}

fn eye_as_text<'de, D: Deserializer<'de>>(deserializer: D) -> Result<String, D::Error> {
    match Value::deserialize(deserializer)? {
        Value::String(text) => Ok(text),
        Value::Number(number) => Ok(number.to_string()),
        other => Err(serde::de::Error::custom(format!("eye must be a string or a number, not {other}"))),
    }
}

impl Manifest {
    /// Reads `dir/manifest.json` if there is one.
    pub fn load_from_dir(dir: &Path) -> Result<Option<Manifest>> {
        let path = dir.join(MANIFEST_FILE);
        // symlink_metadata: a dangling link is still "a manifest that is there".
        if let Err(error) = std::fs::symlink_metadata(&path) {
            if error.kind() == std::io::ErrorKind::NotFound {
                return Ok(None);
            }
            return Err(Error::io(&path, error));
        }
        let bytes = crate::files::read_limited(&path, crate::files::SMALL_INPUT_LIMIT)?;
        Manifest::parse(&path, &bytes).map(Some)
    }

    /// Parses and checks a manifest's bytes; `path` is only used in messages.
    pub fn parse(path: &Path, bytes: &[u8]) -> Result<Manifest> {
        let manifest: Manifest = serde_json::from_slice(bytes)
            .map_err(|error| Error::bad_file(path, format!("invalid manifest: {error}")))?;
        manifest.check(path)?;
        Ok(manifest)
    }

    /// Rejects manifests that would make the analysis ambiguous.
    fn check(&self, path: &Path) -> Result<()> {
        self.check_schema(path)?;
        self.check_eyes(path)?;
        self.check_tile_places(path)
    }

    /// A schema this version reads (or none).
    fn check_schema(&self, path: &Path) -> Result<()> {
        if let Some(schema) = &self.schema
            && schema != MANIFEST_SCHEMA
        {
            let hint = if schema.starts_with("ufcsr-manifest/") {
                format!("a version this ufcsr does not know (it reads {MANIFEST_SCHEMA}); update ufcsr")
            } else {
                format!("not a ufcsr manifest (expected {MANIFEST_SCHEMA})")
            };
            return Err(Error::bad_file(path, format!("schema {schema:?}: {hint}")));
        }
        Ok(())
    }

    /// Two eyes: numbered 0 and 1, or two names (left/right, L/R...).
    fn check_eyes(&self, path: &Path) -> Result<()> {
        let mut eyes = BTreeSet::new();
        for (number, tile) in self.tiles.iter().enumerate() {
            let numeric = !tile.eye.is_empty()
                && tile.eye.bytes().all(|b| b.is_ascii_digit() || b == b'.' || b == b'-');
            if (numeric && tile.eye != "0" && tile.eye != "1") || tile.eye.is_empty() {
                return Err(Error::bad_file(
                    path,
                    format!(
                        "tiles[{number}]: eye {:?}: a pedestrian has two eyes, 0 and 1 (or left and right)",
                        tile.eye
                    ),
                ));
            }
            eyes.insert(tile.eye.as_str());
            if eyes.len() > 2 {
                return Err(Error::bad_file(
                    path,
                    format!(
                        "tiles[{number}]: a third eye {:?} besides {:?}: a pedestrian has two eyes",
                        tile.eye,
                        eyes.iter().filter(|e| **e != tile.eye).collect::<Vec<_>>()
                    ),
                ));
            }
        }
        Ok(())
    }

    /// Every tile has a file or is marked empty (not both), no place
    /// (frame, eye, row, col) or file is listed twice, and files stay inside
    /// the archive folder.
    fn check_tile_places(&self, path: &Path) -> Result<()> {
        let mut positions = BTreeSet::new();
        let mut files = BTreeSet::new();
        for (number, tile) in self.tiles.iter().enumerate() {
            let place = format!("tiles[{number}] {}", tile.place());
            match (&tile.file, tile.empty) {
                (None, false) => {
                    return Err(Error::bad_file(
                        path,
                        format!("{place} has no file and is not marked empty"),
                    ));
                }
                (Some(_), true) => {
                    return Err(Error::bad_file(path, format!("{place} names a file but is marked empty")));
                }
                _ => {}
            }
            if !positions.insert((tile.frame, tile.eye.clone(), tile.row, tile.col)) {
                return Err(Error::bad_file(path, format!("{place} is listed twice")));
            }
            if let Some(file) = &tile.file {
                Self::check_tile_file(path, &place, file, &mut files)?;
            }
        }
        Ok(())
    }

    /// A tile's file is a relative path inside the archive folder, listed once
    /// (`./tiles/./x.png` is `tiles/x.png`; links are resolved by the archive
    /// reader). `place` names the tile in messages.
    fn check_tile_file(
        path: &Path,
        place: &str,
        file: &Path,
        files: &mut BTreeSet<std::path::PathBuf>,
    ) -> Result<()> {
        if file.is_absolute() || file.components().any(|c| matches!(c, std::path::Component::ParentDir)) {
            return Err(Error::bad_file(
                path,
                format!("{place}: file {} must be a path inside the archive folder", file.display()),
            ));
        }
        let lexical: std::path::PathBuf =
            file.components().filter(|c| !matches!(c, std::path::Component::CurDir)).collect();
        if !files.insert(lexical) {
            return Err(Error::bad_file(path, format!("{place}: file {} is listed twice", file.display())));
        }
        Ok(())
    }

    /// Writes the manifest to `dir/manifest.json` atomically, pretty-printed.
    pub fn write_to_dir(&self, dir: &Path) -> Result<()> {
        let path = dir.join(MANIFEST_FILE);
        write_atomically(&path, |writer| {
            serde_json::to_writer_pretty(&mut *writer, self).map_err(std::io::Error::other)?;
            std::io::Write::write_all(writer, b"\n")
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const EXAMPLE: &str = r##"{
        "schema": "ufcsr-manifest/1",
        "palette": {"canonical": [64, 64]},
        "pidt": "pidt.png",
        "parts": "parts.csv",
        "background": ["#000FFF"],
        "rig": {"eye_height_m": 1.75},
        "tiles": [
            {"file": "tiles/f0000_left_r0_c0.png", "frame": 0, "eye": "left", "row": 0, "col": 0, "time_s": 0.0},
            {"frame": 0, "eye": 1, "row": 0, "col": 0, "empty": true}
        ]
    }"##;

    #[test]
    fn parses_example_and_keeps_extra_fields() {
        let manifest = Manifest::parse(Path::new("m.json"), EXAMPLE.as_bytes()).unwrap();
        assert_eq!(manifest.palette, Some(PaletteRecord::Canonical { canonical: [64, 64] }));
        assert_eq!(manifest.tiles[1].eye, "1");
        assert!(manifest.tiles[1].empty);
        assert!(manifest.extra.contains_key("rig"));
        assert!(manifest.tiles[0].extra.contains_key("time_s"));
        let again = serde_json::to_string(&manifest).unwrap();
        let reparsed = Manifest::parse(Path::new("m.json"), again.as_bytes()).unwrap();
        assert_eq!(reparsed.tiles.len(), 2);
    }

    #[test]
    fn rejects_duplicates_and_escaping_paths() {
        let twice = EXAMPLE.replace(r#""eye": 1"#, r#""eye": "left""#);
        let error = Manifest::parse(Path::new("m.json"), twice.as_bytes()).unwrap_err();
        assert!(error.to_string().contains("listed twice"), "{error}");
        let escaping = EXAMPLE.replace("tiles/f0000", "../f0000");
        let error = Manifest::parse(Path::new("m.json"), escaping.as_bytes()).unwrap_err();
        assert!(error.to_string().contains("inside the archive"), "{error}");
    }

    #[test]
    fn rejects_unknown_schemas_and_eyes_a_pedestrian_does_not_have() {
        let parse = |text: &str| Manifest::parse(Path::new("m.json"), text.as_bytes());
        let newer = EXAMPLE.replace("ufcsr-manifest/1", "ufcsr-manifest/2");
        let error = parse(&newer).unwrap_err().to_string();
        assert!(error.contains("m.json") && error.contains("does not know"), "{error}");
        let foreign = EXAMPLE.replace("ufcsr-manifest/1", "unity-capture/1");
        assert!(parse(&foreign).unwrap_err().to_string().contains("not a ufcsr manifest"));
        let three = EXAMPLE.replace(r#""eye": 1"#, r#""eye": 3"#);
        assert!(parse(&three).unwrap_err().to_string().contains("eye \"3\""));
        let third = EXAMPLE.replace(r#""eye": 1"#, r#""eye": "right""#).replace(
            r#"{"frame": 0, "eye": "right""#,
            r#"{"frame": 1, "eye": "centre", "row": 0, "col": 0, "empty": true}, {"frame": 0, "eye": "right""#,
        );
        assert!(parse(&third).unwrap_err().to_string().contains("a third eye"), "{third}");
        // Without a schema (a hand-written manifest), numbered eyes are fine.
        let plain = EXAMPLE
            .replace(r#""schema": "ufcsr-manifest/1","#, "")
            .replace(r#""eye": "left""#, r#""eye": 0"#);
        assert!(parse(&plain).is_ok());
    }
}
