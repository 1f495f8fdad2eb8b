//! Reading and writing an archive's `manifest.json` (its types and checks
//! are the format's, [`crate::format::manifest`]), and the one rule for the
//! paths it names ([`inside_archive`]).

use std::path::{Path, PathBuf};

use crate::error::{Error, Result};
use crate::files::write_atomically;
pub use crate::format::manifest::{MANIFEST_FILE, MANIFEST_SCHEMA, Manifest, PaletteRecord, TileEntry};

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
        "rig": {"settings": {"eye_height_m": 1.75}},
        "tiles": [
            {"file": "tiles/f0000_left_r0_c0.png", "frame": 0, "eye": "left", "row": 0, "col": 0, "time_s": 0.0},
            {"frame": 0, "eye": 1, "row": 0, "col": 0, "empty": true}
        ]
    }"##;

    #[test]
    fn rejects_duplicates_and_escaping_paths() {
        let twice = EXAMPLE.replace(r#""eye": 1"#, r#""eye": "left""#);
        let error = Manifest::parse(Path::new("m.json"), twice.as_bytes()).unwrap_err();
        assert!(error.to_string().contains("listed twice"), "{error}");
        // Twice with both written (neither empty) as well.
        let both_written = twice.replace(r#", "empty": true"#, "");
        assert!(Manifest::parse(Path::new("m.json"), both_written.as_bytes()).is_err());
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
        assert!(parse(&EXAMPLE.replace(r#""eye": 1"#, r#""eye": 2"#)).is_err());
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
