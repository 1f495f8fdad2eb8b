//! What the user meant by ARCHIVE, where the folder alone would mislead: the
//! `tiles/` folder of an archive (a manifest.json one level up) or the parent
//! of several archives (`--scenario all` writes one per scenario) would be
//! counted as one manifest-less folder and give a plausible but wrong result.
//! Both stop with exit 2 and a message naming the manifest(s), unless
//! `--no-manifest` says the folder is meant as it is, or `--each` asks for
//! every archive below to be analysed separately. The folder of a capture
//! that measures several vehicles (one archive per vehicle, each naming it
//! in its manifest's `scene.measured`) is analysed as with `--each`
//! ([`fleet_below`]): there is no one archive it could mean.

use std::path::{Path, PathBuf};

use ufcsr::MANIFEST_FILE;

/// How deep below ARCHIVE to look for other archives' manifests
/// (`OUT/A/manifest.json` of `--scenario all` is one level down).
const SEARCH_DEPTH: usize = 3;

/// The folders below `dir` (not `dir` itself) that hold a manifest.json, in
/// name order; tile folders and result folders are not searched.
pub(crate) fn archives_below(dir: &Path) -> Vec<PathBuf> {
    let mut found: Vec<PathBuf> = walkdir::WalkDir::new(dir)
        .min_depth(1)
        .max_depth(SEARCH_DEPTH)
        .sort_by_file_name()
        .into_iter()
        .filter_entry(|entry| {
            !(entry.file_type().is_dir() && matches!(entry.file_name().to_str(), Some("tiles" | "results")))
        })
        .flatten()
        .filter(|entry| entry.file_type().is_file() && entry.file_name() == MANIFEST_FILE)
        .filter_map(|entry| entry.path().parent().map(Path::to_path_buf))
        .filter(|folder| folder != dir)
        .collect();
    found.dedup();
    found
}

/// Why `archive` is probably not what the user meant, or `None`: it has no
/// manifest, but its parent has one, or archives lie below it.
pub(crate) fn misread_archive(archive: &Path) -> Option<String> {
    if archive.join(MANIFEST_FILE).is_file() || !archive.is_dir() {
        return None;
    }
    if let Some(parent) = archive.parent().filter(|p| p.join(MANIFEST_FILE).is_file()) {
        let shown = if parent.as_os_str().is_empty() { Path::new(".") } else { parent };
        return Some(format!(
            "{} has no {MANIFEST_FILE}, but the folder above it is an archive ({}): analyse that \
             (ufcsr analyze {}), or pass --no-manifest to count {} on its own",
            archive.display(),
            shown.join(MANIFEST_FILE).display(),
            shown.display(),
            archive.display()
        ));
    }
    let below = archives_below(archive);
    if below.is_empty() {
        return None;
    }
    let listed: Vec<String> = below.iter().map(|dir| dir.join(MANIFEST_FILE).display().to_string()).collect();
    Some(format!(
        "{} has no {MANIFEST_FILE} but holds {} archive{} ({}): analyse one of them, pass --each to \
         analyse each separately, or --no-manifest to count every PNG below {} as one archive",
        archive.display(),
        below.len(),
        if below.len() == 1 { "" } else { "s" },
        listed.join(", "),
        archive.display()
    ))
}

/// Whether `dir` is the folder of a capture that measured several vehicles
/// (`ufcsr capture scene FILE --out DIR` writes `DIR/NAME` per vehicle): no
/// manifest of its own, and an archive below whose manifest names the
/// vehicle it measures (`scene.measured`).
pub(crate) fn fleet_below(dir: &Path) -> bool {
    if dir.join(MANIFEST_FILE).is_file() {
        return false;
    }
    let measures_a_fleet_vehicle = |archive: &PathBuf| {
        let path = archive.join(MANIFEST_FILE);
        ufcsr::files::read_limited(&path, ufcsr::files::SMALL_INPUT_LIMIT)
            .ok()
            .and_then(|bytes| ufcsr::Manifest::parse(&path, &bytes).ok())
            .is_some_and(|manifest| manifest.scene.is_some_and(|scene| scene.measured.is_some()))
    };
    archives_below(dir).iter().any(measures_a_fleet_vehicle)
}
