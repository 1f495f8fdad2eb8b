//! Resolving the inputs: the options against the archive's manifest, and
//! every input loaded once (palette, backgrounds, labels, the archive's
//! images, the vehicle model) into [`Inputs`], before anything is counted.

use std::path::PathBuf;

use crate::archive::archive_reader::Archive;
use crate::archive::capture_facts::{
    CaptureGeometry, EyeFrame, EyeOptics, FrameClock, eye_frames, manifest_spacing_warning,
};
use crate::archive::identity::archive_identity;
use crate::archive::labels::{Legend, LoadedLabels, Pidt};
use crate::archive::manifest::{MANIFEST_FILE, Manifest, PaletteRecord, inside_archive};
use crate::archive::options::{AnalyzeOptions, Dedupe, PaletteChoice};
use crate::archive::palette::{DEFAULT_PALETTE_SIDE, Fcsp};
use crate::color::Color;
use crate::error::{Error, Result};
use crate::format::manifest::TexelIds;

/// The legend and the PIdT, each with the file it was read from.
pub(crate) struct LabelFiles {
    pub legend_path: PathBuf,
    pub legend: Legend,
    pub pidt_path: PathBuf,
    pub pidt: std::sync::Arc<Pidt>,
}

impl LabelFiles {
    /// The legend and PIdT, shared (the PIdT is not copied).
    pub(crate) fn loaded(&self) -> LoadedLabels {
        LoadedLabels { legend: self.legend.clone(), pidt: self.pidt.clone() }
    }
}

/// Options resolved against the manifest: the fully built inputs.
pub(crate) struct Inputs {
    pub palette: Fcsp,
    /// How the tiles' pixels name texels (the manifest's `texel_ids`).
    pub texel_ids: TexelIds,
    pub backgrounds: Vec<Color>,
    /// The legend and PIdT, when the analysis has them.
    pub parts: Option<LabelFiles>,
    pub archive: Archive,
    pub dedupe: Dedupe,
    /// The palette image, when the palette is not the canonical one.
    pub palette_file: Option<PathBuf>,
    /// `--mesh`, or the manifest's `vehicle` when it is there.
    pub vehicle_model: Option<PathBuf>,
    /// What resolving found wrong but not fatal (a missing vehicle model).
    pub warnings: Vec<String>,
    /// Resolution and texel size from the capture's manifest.
    pub geometry: CaptureGeometry,
    /// False for a capture counted while rendering (`--count`): its manifest
    /// names tiles that were never written.
    pub tiles_written: bool,
    /// The manifest's eye-frames, by eye-frame group (empty without one).
    pub eye_frames: Vec<EyeFrame>,
    /// Seconds per captured frame, eyes and pixels per degree.
    pub clock: FrameClock,
    /// What the counts depend on, digested ([`crate::archive::identity`]).
    pub identity: String,
    /// The eyes' projection and tiling (for each pixel's solid angle).
    pub optics: Option<EyeOptics>,
}

/// Whether an archive must hold images to be resolved.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Images {
    /// Counting reads them: none is an error.
    Required,
    /// The counts were measured another way ([`crate::analyze_texel_counts`]).
    Optional,
}

/// Resolves options against the manifest and loads every input once.
pub(crate) fn resolve_inputs(options: &AnalyzeOptions) -> Result<Inputs> {
    resolve_inputs_with(options, Images::Required)
}

/// [`resolve_inputs`], saying whether the archive must hold images.
pub(crate) fn resolve_inputs_with(options: &AnalyzeOptions, images: Images) -> Result<Inputs> {
    let root = &options.archive;
    if !root.is_dir() {
        return Err(Error::bad_file(root, "not a folder (expected an archive folder of PNG tiles)"));
    }
    // A capture interrupted in place left part of itself and no manifest (issue 41).
    crate::files::refuse_unfinished(root)?;
    let manifest = if options.ignore_manifest { None } else { Manifest::load_from_dir(root)? };
    let palette_choice = palette_choice(options, manifest.as_ref())?;
    let texel_ids = manifest.as_ref().map(Manifest::texel_ids).unwrap_or_default();
    let palette = load_palette(root, &palette_choice, texel_ids)?;
    let backgrounds = options
        .background
        .clone()
        .or_else(|| manifest.as_ref().and_then(|m| m.background.clone()))
        .unwrap_or_else(|| vec![Color::DEFAULT_BACKGROUND]);
    let parts = load_labels(options, manifest.as_ref(), &palette)?;
    let archive = read_archive(options, manifest.as_ref(), &palette_choice, &palette)?;
    if archive.found() == 0 && images == Images::Required {
        return Err(Error::NoImages { path: root.to_path_buf() });
    }
    check_dedupe(options, &archive)?;
    let palette_file = match palette_choice {
        PaletteChoice::Image(path) => Some(path),
        PaletteChoice::Canonical { .. } => None,
    };
    let mut warnings = capture_warnings(manifest.as_ref());
    warnings.extend(manifest.as_ref().and_then(manifest_spacing_warning));
    warnings.extend(left_out_file_warnings(&archive, root));
    let vehicle_model = vehicle_model(options, manifest.as_ref(), &mut warnings)?;
    let mut files: Vec<&std::path::Path> = palette_file.iter().map(PathBuf::as_path).collect();
    if let Some(labels) = &parts {
        files.extend([labels.pidt_path.as_path(), labels.legend_path.as_path()]);
    }
    let manifest_path = root.join(crate::archive::manifest::MANIFEST_FILE);
    let identity = archive_identity(manifest.as_ref().map(|_| manifest_path.as_path()), &archive, &files);
    Ok(Inputs {
        identity,
        palette,
        texel_ids,
        backgrounds,
        parts,
        archive,
        dedupe: options.dedupe,
        tiles_written: tiles_written(manifest.as_ref()),
        geometry: manifest.as_ref().map(CaptureGeometry::from_manifest).unwrap_or_default(),
        palette_file,
        vehicle_model,
        warnings,
        eye_frames: manifest.as_ref().map(eye_frames).unwrap_or_default(),
        clock: manifest.as_ref().map(FrameClock::from_manifest).unwrap_or_default(),
        optics: manifest.as_ref().and_then(EyeOptics::from_manifest),
    })
}

/// The palette asked for: the option, else the manifest's, else the
/// canonical palette of the default size.
fn palette_choice(options: &AnalyzeOptions, manifest: Option<&Manifest>) -> Result<PaletteChoice> {
    Ok(match (&options.palette, manifest.and_then(|m| m.palette.as_ref())) {
        (Some(choice), _) => choice.clone(),
        (None, Some(PaletteRecord::Canonical { canonical: [width, height] })) => {
            PaletteChoice::Canonical { width: *width, height: *height }
        }
        (None, Some(PaletteRecord::File(file))) => {
            PaletteChoice::Image(inside_archive(&options.archive, "palette", file)?)
        }
        (None, None) => {
            PaletteChoice::Canonical { width: DEFAULT_PALETTE_SIDE, height: DEFAULT_PALETTE_SIDE }
        }
    })
}

/// The palette of `choice`, for tiles whose pixels name texels by
/// `texel_ids`: 32-bit ids take only the canonical palette, of at most
/// [`crate::archive::palette::MAX_RGBA32_TEXELS`] texels; a larger one is
/// refused naming the manifest and its `palette` before anything per texel
/// is allocated.
fn load_palette(root: &std::path::Path, choice: &PaletteChoice, texel_ids: TexelIds) -> Result<Fcsp> {
    let manifest = || root.join(MANIFEST_FILE);
    match (choice, texel_ids) {
        (PaletteChoice::Canonical { width, height }, TexelIds::Rgb24) => Fcsp::canonical([*width, *height]),
        (PaletteChoice::Image(path), TexelIds::Rgb24) => Fcsp::from_png(path),
        (PaletteChoice::Canonical { width, height }, TexelIds::Rgba32) => {
            Fcsp::canonical_rgba32([*width, *height]).map_err(|error| match error {
                Error::BadOptions(message) => Error::bad_file(&manifest(), format!("palette: {message}")),
                other => other,
            })
        }
        (PaletteChoice::Image(path), TexelIds::Rgba32) => Err(Error::bad_file(
            &manifest(),
            format!(
                "palette: texel_ids \"rgba32\" takes the canonical palette, not the image {}",
                path.display()
            ),
        )),
    }
}

/// The legend and PIdT (options first, then the manifest's), loaded against
/// the palette's size; one without the other is an error.
fn load_labels(
    options: &AnalyzeOptions,
    manifest: Option<&Manifest>,
    palette: &Fcsp,
) -> Result<Option<LabelFiles>> {
    let from_manifest = |field: &str, path: &Option<PathBuf>| {
        path.as_ref().map(|p| inside_archive(&options.archive, field, p)).transpose()
    };
    let pidt_path = match &options.pidt {
        Some(path) => Some(path.clone()),
        None => manifest.map(|m| from_manifest("pidt", &m.pidt)).transpose()?.flatten(),
    };
    let legend_path = match &options.legend {
        Some(path) => Some(path.clone()),
        None => manifest.map(|m| from_manifest("parts", &m.parts)).transpose()?.flatten(),
    };
    match (pidt_path, legend_path) {
        (Some(pidt_path), Some(legend_path)) => {
            if let Some(loaded) = &options.loaded_labels {
                return loaded_labels(loaded, legend_path, pidt_path, palette).map(Some);
            }
            let legend = Legend::load(&legend_path)?;
            let pidt = Pidt::load(&pidt_path, &legend, [palette.width(), palette.height()])?;
            Ok(Some(LabelFiles { legend_path, legend, pidt_path, pidt: pidt.into() }))
        }
        (Some(pidt_path), None) => Err(Error::BadOptions(format!(
            "the PIdT {} needs its legend: add --parts parts.csv",
            pidt_path.display()
        ))),
        (None, Some(legend_path)) => Err(Error::BadOptions(format!(
            "the legend {} needs its PIdT: add --pidt pidt.png",
            legend_path.display()
        ))),
        (None, None) if options.loaded_labels.is_some() => Err(Error::BadOptions(format!(
            "labels were given already loaded, but {} names no PIdT and legend",
            options.archive.display()
        ))),
        (None, None) => Ok(None),
    }
}

/// The caller's [`LoadedLabels`] for the files at these paths, refused when
/// the PIdT is not the palette's size.
fn loaded_labels(
    loaded: &LoadedLabels,
    legend_path: PathBuf,
    pidt_path: PathBuf,
    palette: &Fcsp,
) -> Result<LabelFiles> {
    let size = [loaded.pidt.width, loaded.pidt.height];
    if size != [palette.width(), palette.height()] {
        return Err(Error::bad_file(
            &pidt_path,
            format!(
                "was loaded at {}×{}, the palette is {}×{}",
                size[0],
                size[1],
                palette.width(),
                palette.height()
            ),
        ));
    }
    Ok(LabelFiles { legend_path, legend: loaded.legend.clone(), pidt_path, pidt: loaded.pidt.clone() })
}

/// The archive's images: those the manifest lists, or without one every PNG
/// in the folder except the outputs, the PIdT and the palette image.
fn read_archive(
    options: &AnalyzeOptions,
    manifest: Option<&Manifest>,
    palette_choice: &PaletteChoice,
    palette: &Fcsp,
) -> Result<Archive> {
    let root = &options.archive;
    match manifest {
        Some(manifest) => Archive::from_manifest(root, manifest),
        None => {
            let mut exclude = options.exclude.clone();
            exclude.extend(options.pidt.iter().cloned());
            if let PaletteChoice::Image(path) = palette_choice {
                exclude.push(path.clone());
            }
            Archive::scan_folder(root, &exclude, [palette.width(), palette.height()])
        }
    }
}

/// Refuses a per-frame dedupe rule the archive cannot follow.
fn check_dedupe(options: &AnalyzeOptions, archive: &Archive) -> Result<()> {
    if options.dedupe.per_frame() && archive.frame_groups == 0 {
        return Err(Error::BadOptions(format!(
            "--dedupe {} needs {}/manifest.json to know which tiles form one eye-frame",
            options.dedupe.name(),
            options.archive.display()
        )));
    }
    if options.dedupe == Dedupe::EyePair && options.shard.is_some() {
        // Shards hold whole eye-frames, and the two eyes of a frame may fall
        // in different shards, where a texel would count once in each.
        return Err(Error::BadOptions(
            "--dedupe eye-pair cannot be sharded yet (a frame's two eyes may fall in different shards)"
                .into(),
        ));
    }
    Ok(())
}

/// False for a capture counted while rendering (`--count`), whose manifest
/// says its tiles were never written.
fn tiles_written(manifest: Option<&Manifest>) -> bool {
    manifest.is_none_or(Manifest::tiles_written)
}

/// The first five names, comma-separated, with "…" when there are more.
fn first_five(names: &[String]) -> String {
    let listed = names.iter().take(5).cloned().collect::<Vec<_>>().join(", ");
    if names.len() > 5 { format!("{listed}, …") } else { listed }
}

/// One warning per kind of PNG the archive reader left out: textures,
/// earlier results or staging folders, and files reached twice through links.
fn left_out_file_warnings(archive: &Archive, root: &std::path::Path) -> Vec<String> {
    let mut warnings = Vec::new();
    if !archive.skipped.is_empty() {
        warnings.push(format!(
            "{} PNGs in {} {SKIPPED_FILES_WARNING}: palette- or PIdT-sized textures, or the palette/PIdT a \
             manifest below names ({}); without a manifest every other PNG is counted",
            archive.skipped.len(),
            root.display(),
            first_five(&archive.skipped)
        ));
    }
    if !archive.result_folders.is_empty() {
        warnings.push(format!(
            "{} folders in {} ({} PNGs) {SKIPPED_FILES_WARNING}: they hold an earlier run's results (a \
             result.json) or are a staging folder ({})",
            archive.result_folders.len(),
            root.display(),
            archive.result_folder_pngs,
            first_five(&archive.result_folders)
        ));
    }
    if !archive.aliases.is_empty() {
        warnings.push(format!(
            "{} PNGs in {} {SKIPPED_FILES_WARNING}: they are files already counted, reached again through a \
             folder link ({})",
            archive.aliases.len(),
            root.display(),
            first_five(&archive.aliases)
        ));
    }
    warnings
}

/// The vehicle model: `--mesh` (missing is an error now, not after
/// counting), else the manifest's `vehicle` (only the pictures need it, so a
/// missing or unreadable one is a warning and counting goes on without).
fn vehicle_model(
    options: &AnalyzeOptions,
    manifest: Option<&Manifest>,
    warnings: &mut Vec<String>,
) -> Result<Option<PathBuf>> {
    if let Some(mesh) = &options.mesh {
        crate::files::open_regular(mesh)?;
        return Ok(Some(mesh.clone()));
    }
    let named = manifest
        .and_then(|m| m.vehicle.as_deref())
        .map(|file| inside_archive(&options.archive, "vehicle", file))
        .transpose()?;
    Ok(named.and_then(|path| match crate::files::open_regular(&path) {
        Ok(_) => Some(path),
        Err(Error::Io { cause, .. }) if cause.kind() == std::io::ErrorKind::NotFound => {
            warnings
                .push(format!("{}: {MISSING_VEHICLE_WARNING} (give the mesh with --mesh)", path.display()));
            None
        }
        // Say what it is (a FIFO, a folder, ...), not that it is missing.
        Err(error) => {
            warnings.push(format!("{error}: {UNREADABLE_VEHICLE_WARNING} (give the mesh with --mesh)"));
            None
        }
    }))
}

/// Warnings about the inputs (found while resolving them, the same for every
/// shard of an archive): merge carries them over from the first shard.
pub(crate) const SKIPPED_FILES_WARNING: &str = "were left out as not frames";

pub(crate) const MISSING_VEHICLE_WARNING: &str =
    "the vehicle the manifest names is missing, so there is no heatmap.glb and no views";

pub(crate) const UNREADABLE_VEHICLE_WARNING: &str =
    "the vehicle the manifest names cannot be read, so there is no heatmap.glb and no views";

/// What the capture warned about (the manifest's `warnings`), carried into the result.
pub(crate) const CAPTURE_WARNING: &str = "the capture warned: ";

fn capture_warnings(manifest: Option<&Manifest>) -> Vec<String> {
    let listed = manifest.map(|m| m.warnings.as_slice()).unwrap_or_default();
    listed.iter().map(|warning| format!("{CAPTURE_WARNING}{warning}")).collect()
}
