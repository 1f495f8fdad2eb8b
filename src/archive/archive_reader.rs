//! The archive: which files are images, and how they group into eye-frames.
//!
//! With a `manifest.json` the manifest's tile list is the truth (tiles it marks
//! empty were never written and count as trimmed). Without one, every `*.png`
//! below the folder is an image, in sorted path order so that reports and
//! results never depend on directory iteration order.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use walkdir::WalkDir;

use crate::archive::manifest::Manifest;
use crate::error::{Error, Result};

/// One image file to analyse.
#[derive(Debug, Clone)]
pub struct ImageSource {
    /// Where to read it.
    pub path: PathBuf,
    /// Its path relative to the archive folder, `/`-separated, for reports.
    pub name: String,
    /// Eye-frame group (index into the sorted `(frame, eye)` pairs), when known.
    pub frame_group: Option<usize>,
    /// The tile's `[row, col]` in its eye image, when a manifest says.
    pub tile: Option<[u32; 2]>,
}

/// The images of an archive.
#[derive(Debug, Clone)]
pub struct Archive {
    pub root: PathBuf,
    pub images: Vec<ImageSource>,
    /// Tiles the manifest lists as empty (no file written).
    pub listed_empty: u64,
    /// Number of distinct `(frame, eye)` groups; 0 without a manifest.
    pub frame_groups: usize,
    /// The eye-frame group of each tile listed as empty (for sharding).
    pub listed_empty_groups: Vec<usize>,
    /// PNGs left out of a folder without a manifest because they are not
    /// frames: textures of the palette's size, and files a manifest further
    /// down names as its palette or PIdT (relative names, for the warning).
    pub skipped: Vec<String>,
    /// Folders left out of a folder without a manifest because they hold
    /// outputs ([`is_output_folder`]): an earlier run's results are not frames.
    pub result_folders: Vec<String>,
    /// PNGs in those folders (not frames, counted in `images.skipped`).
    pub result_folder_pngs: usize,
    /// PNGs reached a second time through a folder link (counted once).
    pub aliases: Vec<String>,
}

impl Archive {
    /// The images a manifest lists. Two entries that are one file (an alias
    /// such as `./tiles/./x.png`, or a path through a folder link) are
    /// refused: the file would be counted twice.
    pub fn from_manifest(root: &Path, manifest: &Manifest) -> Result<Archive> {
        let mut groups = BTreeMap::new();
        for tile in &manifest.tiles {
            let next = groups.len();
            groups.entry((tile.frame, tile.eye.clone())).or_insert(next);
        }
        // Renumber groups in (frame, eye) order so group ids are stable.
        for (number, id) in groups.values_mut().enumerate() {
            *id = number;
        }
        let mut listed_empty = 0;
        let mut listed_empty_groups = Vec::new();
        let mut images = Vec::new();
        let mut resolved: BTreeMap<PathBuf, &Path> = BTreeMap::new();
        for tile in &manifest.tiles {
            let group = groups[&(tile.frame, tile.eye.clone())];
            if let Some(file) = &tile.file {
                let place = format!("tile {}", tile.place());
                crate::archive::manifest::inside_archive(root, &place, file)?;
                // A tile that cannot be resolved (missing) fails when it is read.
                if let Some(real) = crate::files::resolved(&root.join(file))
                    && let Some(first) = resolved.insert(real, file)
                {
                    return Err(Error::bad_file(
                        &root.join(crate::archive::manifest::MANIFEST_FILE),
                        format!(
                            "tiles {} and {} are the same file: it would be counted twice",
                            first.display(),
                            file.display()
                        ),
                    ));
                }
            }
            match &tile.file {
                Some(file) => images.push(ImageSource {
                    path: root.join(file),
                    name: slash_path(file),
                    frame_group: Some(group),
                    tile: Some([tile.row, tile.col]),
                }),
                None => {
                    listed_empty += 1;
                    listed_empty_groups.push(group);
                }
            }
        }
        images.sort_by(|a, b| a.name.cmp(&b.name));
        Ok(Archive {
            root: root.to_path_buf(),
            images,
            listed_empty,
            frame_groups: groups.len(),
            listed_empty_groups,
            skipped: Vec::new(),
            result_folders: Vec::new(),
            result_folder_pngs: 0,
            aliases: Vec::new(),
        })
    }

    /// Every `*.png` below `root` except those in `exclude` (files or folders,
    /// e.g. the PIdT or the output folder when they sit inside the archive),
    /// the palette and PIdT files that manifests below `root` name, and PNGs
    /// of `texture_size` (a palette or PIdT kept beside the frames) when
    /// there are frames of another size: those are listed in `skipped`.
    pub fn scan_folder(root: &Path, exclude: &[PathBuf], texture_size: [u32; 2]) -> Result<Archive> {
        if !root.is_dir() {
            return Err(Error::bad_file(root, "not a folder (expected an archive folder of PNG tiles)"));
        }
        let excluded: Vec<PathBuf> = exclude.iter().filter_map(|p| p.canonicalize().ok()).collect();
        let mut images = Vec::new();
        let mut result_folders = Vec::new();
        let mut aliases = Vec::new();
        let mut seen = std::collections::BTreeSet::new();
        let walker = WalkDir::new(root).follow_links(true).sort_by_file_name().into_iter();
        for entry in walker.filter_entry(|entry| {
            let kept = entry
                .path()
                .canonicalize()
                .map(|p| !excluded.iter().any(|x| p.starts_with(x)))
                .unwrap_or(true);
            if kept && entry.depth() > 0 && is_output_folder(entry.path()) {
                result_folders.push(slash_path(entry.path().strip_prefix(root).unwrap_or(entry.path())));
                return false;
            }
            kept
        }) {
            let entry = entry.map_err(|e| {
                let path = e.path().unwrap_or(root).to_path_buf();
                Error::Io { path, cause: e.into() }
            })?;
            let is_png = entry.path().extension().is_some_and(|e| e.eq_ignore_ascii_case("png"));
            // Anything named *.png that is not a folder is an image: a FIFO,
            // socket or device then fails to open and is reported and counted
            // as failed, never silently skipped (nor opened and waited on).
            if !entry.file_type().is_dir() && is_png {
                let relative = slash_path(entry.path().strip_prefix(root).unwrap_or(entry.path()));
                // One file reached twice (through a folder link) is one image.
                if let Some(real) = crate::files::resolved(entry.path())
                    && !seen.insert(real)
                {
                    aliases.push(relative);
                    continue;
                }
                images.push(ImageSource {
                    path: entry.path().to_path_buf(),
                    name: relative,
                    frame_group: None,
                    tile: None,
                });
            }
        }
        images.sort_by(|a, b| a.name.cmp(&b.name));
        let named = textures_named_by_manifests(root);
        let (textures, frames): (Vec<ImageSource>, Vec<ImageSource>) =
            images.into_iter().partition(|image| {
                named.iter().any(|n| same_file(n, &image.path)) || png_size(&image.path) == Some(texture_size)
            });
        // A folder of nothing but palette-sized PNGs holds frames of that size.
        let (images, textures) = if frames.is_empty() { (textures, Vec::new()) } else { (frames, textures) };
        Ok(Archive {
            root: root.to_path_buf(),
            images,
            listed_empty: 0,
            frame_groups: 0,
            listed_empty_groups: Vec::new(),
            skipped: textures.into_iter().map(|t| t.name).collect(),
            result_folder_pngs: result_folders.iter().map(|folder| count_pngs(&root.join(folder))).sum(),
            result_folders,
            aliases,
        })
    }

    /// Number of tiles found: image files plus tiles listed as empty.
    pub fn found(&self) -> u64 {
        self.images.len() as u64 + self.listed_empty
    }
}

/// A folder of outputs, never frames: one holding a `result.json` (an
/// earlier run's result set, with its `plots/` and `views/`), or a staging
/// folder (`.ufcsr-staging-*`) a killed run left.
pub(crate) fn is_output_folder(dir: &Path) -> bool {
    let staging = dir.file_name().is_some_and(|n| n.to_string_lossy().starts_with(".ufcsr-staging-"));
    staging || std::fs::symlink_metadata(dir.join("result.json")).is_ok_and(|m| m.is_file())
}

/// The `*.png` files below `dir` (links not followed).
fn count_pngs(dir: &Path) -> usize {
    WalkDir::new(dir)
        .into_iter()
        .flatten()
        .filter(|e| {
            !e.file_type().is_dir() && e.path().extension().is_some_and(|x| x.eq_ignore_ascii_case("png"))
        })
        .count()
}

/// Width and height from a PNG's header, if it is a readable regular file.
fn png_size(path: &Path) -> Option<[u32; 2]> {
    use std::io::Read;
    let mut bytes = [0u8; crate::png::rows::HEADER_BYTES];
    crate::files::open_regular(path).ok()?.read_exact(&mut bytes).ok()?;
    let header = crate::png::rows::parse_header(path, &bytes).ok()?;
    Some([header.width, header.height])
}

fn same_file(a: &Path, b: &Path) -> bool {
    match (a.canonicalize(), b.canonicalize()) {
        (Ok(a), Ok(b)) => a == b,
        _ => false,
    }
}

/// The palette and PIdT files of every `manifest.json` below `root` (an
/// `archives/` folder of captures, analysed as one folder): they are not frames.
fn textures_named_by_manifests(root: &Path) -> Vec<PathBuf> {
    let mut named = Vec::new();
    for entry in WalkDir::new(root).follow_links(true).into_iter().flatten() {
        if entry.file_name() != crate::archive::manifest::MANIFEST_FILE || !entry.file_type().is_file() {
            continue;
        }
        let Some(folder) = entry.path().parent() else { continue };
        // An unreadable manifest names nothing; the frames are still counted.
        let Ok(Some(manifest)) = Manifest::load_from_dir(folder) else { continue };
        named.extend(manifest.pidt.iter().map(|p| folder.join(p)));
        if let Some(crate::archive::manifest::PaletteRecord::File(file)) = &manifest.palette {
            named.push(folder.join(file));
        }
    }
    named
}

fn slash_path(path: &Path) -> String {
    path.components().map(|c| c.as_os_str().to_string_lossy()).collect::<Vec<_>>().join("/")
}
