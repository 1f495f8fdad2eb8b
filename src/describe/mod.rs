//! `ufcsr manifest`: describes a folder of frames rendered outside
//! ufcsr (Unity, Blender, a third party) as an archive manifest, so that
//! `ufcsr analyze DIR` reads it alone — eye-frames for `--dedupe frame`, the
//! palette, PIdT, legend and background, and the metadata a capture would
//! have written (fps, field of view or pixels per degree, rig, frame times
//! and distances) so exposure, deg²·s and the resolution diagnostics work.
//!
//! Paths given here are relative to the working directory; paths written
//! into the manifest are relative to the manifest's folder, which must hold
//! every file it names (the analyzer refuses paths that leave it).

pub(crate) mod metadata;
pub(crate) mod names;
pub(crate) mod scan;
pub(crate) mod solo;
pub(crate) mod solo_camera;

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

use crate::archive::{MANIFEST_FILE, MANIFEST_SCHEMA, Manifest, PaletteChoice, PaletteRecord, TileEntry};
use crate::color::Color;
use crate::error::{Error, Result};
use crate::format::manifest::{EyePose, FrameEntry, RigRecord, RigSettings};

pub(crate) use metadata::FrameTime;
pub use metadata::parse_fov;
pub use names::DEFAULT_PATTERN;
pub(crate) use names::NamePattern;
use scan::{Capture, Grid, canonical, check_capture, find_capture, png_size, slash_path};
use solo::Solo;

/// What to describe and what is known about it.
#[derive(Debug, Clone, Default)]
pub struct DescribeOptions {
    /// The folder of frames (searched recursively).
    pub dir: PathBuf,
    /// A regex with named groups or a `{frame}` template; default [`DEFAULT_PATTERN`].
    pub pattern: Option<String>,
    /// The manifest to write (default `DIR/manifest.json`; a folder: `FOLDER/manifest.json`).
    pub out: Option<PathBuf>,
    pub palette: Option<PaletteChoice>,
    pub pidt: Option<PathBuf>,
    pub legend: Option<PathBuf>,
    pub background: Vec<Color>,
    pub fps: Option<f64>,
    pub pixels_per_degree: Option<f64>,
    /// Horizontal and, to check it, vertical field of view in degrees.
    pub fov: Option<(f64, Option<f64>)>,
    /// A JSON file of rig fields ([`metadata::RIG_FIELDS`]).
    pub rig: Option<PathBuf>,
    /// A CSV `frame,time_s[,distance_m]`.
    pub frame_times: Option<PathBuf>,
    /// List grid positions no file fills as empty tiles (all background, not written) instead of refusing.
    pub missing_tiles_empty: bool,
    /// `[columns, rows]` of each eye image's tiles (`--grid`); wins over the rig file's `tiles`.
    pub grid: Option<[u32; 2]>,
    /// Unity Perception SOLO output: only these sensor ids' RGB captures are frames (empty: every RGB camera).
    pub solo_cameras: Vec<String>,
    /// Read frames by their names even where SOLO frame files are present.
    pub ignore_solo: bool,
}

/// What was written.
#[derive(Debug, Clone)]
pub struct Described {
    pub manifest_path: PathBuf,
    pub manifest: Manifest,
    pub eye_frames: usize,
    pub frames: usize,
    pub eyes: Vec<String>,
    /// Tiles per eye image, `[columns, rows]`.
    pub grid: [u32; 2],
    pub tile_pixels: [u32; 2],
    pub eye_pixels: [u32; 2],
    pub fps: Option<f64>,
    pub horizontal_fov_deg: Option<f64>,
    pub pixels_per_degree: Option<f64>,
    /// Where the frames' times came from: `--frame-times`, `--fps` (frame / fps), or nowhere.
    pub times_from: Option<&'static str>,
    pub distances: bool,
    /// What the manifest still lacks and what stays empty because of it.
    pub notes: Vec<String>,
    /// What Unity Perception's SOLO frame files gave, when the folder had them.
    pub solo: Option<SoloSummary>,
}

/// What was read from a SOLO sequence and what was skipped.
#[derive(Debug, Clone)]
pub struct SoloSummary {
    /// The sequence folder.
    pub folder: PathBuf,
    pub frame_files: usize,
    pub sequence: Option<u64>,
    /// Sensor id → eye name.
    pub cameras: BTreeMap<String, String>,
    /// Files that are not FCSP frames, by kind → count.
    pub skipped: BTreeMap<String, usize>,
    /// Whether each frame's eye poses went into the manifest's `frames`.
    pub poses: bool,
}

/// Reads the folder, checks it and writes the manifest (atomically; nothing on error).
pub fn describe(options: &DescribeOptions) -> Result<Described> {
    let (manifest_path, base) = manifest_place(options)?;
    let pattern = NamePattern::new(options.pattern.as_deref().unwrap_or(DEFAULT_PATTERN))?;
    let Labels { pidt, legend, palette, excluded } = labels(options, &base)?;
    let rig = match &options.rig {
        Some(path) => metadata::read_rig(path)?,
        None => RigSettings::default(),
    };
    // With empty tiles left out, the largest row and column seen may fall short of the grid.
    let given = options.grid.or(rig.tiles.filter(|_| options.missing_tiles_empty));
    let grid = Grid { given, missing_empty: options.missing_tiles_empty };
    let solo = read_solo(options)?;
    let capture = match &solo {
        Some(solo) => check_capture(solo.tiles.clone(), grid)?,
        None => find_capture(&options.dir, &pattern, &excluded, grid)?,
    };
    if given.is_none() {
        refuse_a_guessed_grid(&options.dir, &capture)?;
    }
    let dir = canonical(&options.dir)?;
    let mut notes = layout_notes(options, &manifest_path, given.is_some(), capture.grid);
    let mut rig = rig;
    if let Some(solo) = &solo {
        solo_settings(&mut rig, solo, options.rig.is_some(), &mut notes);
    }
    let settings = settings(options, rig, &capture, &mut notes)?;
    let (times, times_from) = frame_times(options, solo.as_ref(), &capture)?;
    let fps = settings.fps;
    let tiles = tile_entries(&capture, [&options.dir, &dir], &base, times.as_ref(), fps)?;
    let rig = rig_with_ppd(&settings, capture.tile_pixels, options.pixels_per_degree);
    let pixels_per_degree = rig.pixels_per_degree;
    let poses = solo.as_ref().map(|solo| &solo.poses).filter(|poses| !poses.is_empty());
    let poses_written = poses.is_some();
    let frames = frame_entries(times.as_ref(), poses);
    let distances =
        times.as_ref().is_some_and(|t| !t.is_empty() && t.values().all(|t| t.distance_m.is_some()));
    let manifest = Manifest {
        schema: Some(MANIFEST_SCHEMA.to_string()),
        palette,
        pidt,
        parts: legend,
        background: (!options.background.is_empty()).then(|| options.background.clone()),
        tiles,
        frames,
        generator: Some(format!("ufcsr manifest {}", env!("CARGO_PKG_VERSION"))),
        rig: Some(rig),
        ..Manifest::default()
    };
    let times_from = times_from.or(fps.map(|_| "--fps"));
    lacking(&manifest, fps, pixels_per_degree, distances, &mut notes);
    write_checked(&manifest, &manifest_path)?;
    Ok(Described {
        manifest_path,
        eye_frames: manifest.tiles.len() / (capture.grid[0] * capture.grid[1]) as usize,
        frames: capture.frames.len(),
        eyes: capture.eyes.clone(),
        grid: capture.grid,
        tile_pixels: capture.tile_pixels,
        eye_pixels: capture.eye_pixels(),
        fps,
        horizontal_fov_deg: settings.horizontal_fov_deg,
        pixels_per_degree,
        times_from,
        distances,
        notes,
        manifest,
        solo: solo.map(|solo| solo_summary(solo, poses_written)),
    })
}

fn solo_summary(solo: Solo, poses: bool) -> SoloSummary {
    SoloSummary {
        folder: solo.folder,
        frame_files: solo.frame_files,
        sequence: solo.sequence,
        cameras: solo.cameras,
        skipped: solo.skipped,
        poses,
    }
}

/// The SOLO sequence below the folder, unless `--ignore-solo`; its notes go
/// out with the manifest's. `--pattern` and SOLO frame files exclude each other.
fn read_solo(options: &DescribeOptions) -> Result<Option<Solo>> {
    if options.ignore_solo {
        return Ok(None);
    }
    let Some((folder, files)) = solo::find(&options.dir)? else {
        if !options.solo_cameras.is_empty() {
            return Err(Error::bad_file(&options.dir, "--solo-camera: the folder holds no SOLO frame files"));
        }
        return Ok(None);
    };
    if let Some(pattern) = &options.pattern {
        return Err(Error::BadOptions(format!(
            "--pattern {pattern:?}: {} holds Unity Perception SOLO frame files ({} in {}), which name the frames              themselves; leave --pattern out, or give --ignore-solo to read the frames by their names",
            options.dir.display(),
            files.len(),
            folder.display()
        )));
    }
    solo::read(&folder, &files, &options.solo_cameras).map(Some)
}

/// The fps and field of view SOLO gives, into the rig settings: they win
/// over a rig file's (with a note), and --fps/--fov win over them.
fn solo_settings(rig: &mut RigSettings, solo: &Solo, rig_file: bool, notes: &mut Vec<String>) {
    notes.extend(solo.notes.iter().cloned());
    let found = [
        (solo.fps, &mut rig.fps, "fps"),
        (solo.horizontal_fov_deg, &mut rig.horizontal_fov_deg, "horizontal_fov_deg"),
    ];
    for (value, setting, key) in found {
        let Some(value) = value else { continue };
        if rig_file && let Some(old) = setting.filter(|old| (old - value).abs() > 1e-9 * value) {
            notes.push(format!("the SOLO data's {key} {value} replaces the rig file's {old}"));
        }
        *setting = Some(value);
    }
}

/// Frame number → its time (and distance).
type FrameTimes = BTreeMap<u32, FrameTime>;

/// Each frame's time: `--frame-times`, else SOLO's timestamps, else none.
fn frame_times(
    options: &DescribeOptions,
    solo: Option<&Solo>,
    capture: &Capture,
) -> Result<(Option<FrameTimes>, Option<&'static str>)> {
    if let Some(path) = &options.frame_times {
        return Ok((Some(times_of_frames(path, &capture.frames)?), Some("--frame-times")));
    }
    match solo.filter(|solo| !solo.times.is_empty()) {
        Some(solo) => {
            let times =
                solo.times.iter().map(|(&frame, &time_s)| (frame, FrameTime { time_s, distance_m: None }));
            Ok((Some(times.collect()), Some("SOLO timestamps")))
        }
        None => Ok((None, None)),
    }
}

/// The label files as the manifest names them, and their paths (not frames).
struct Labels {
    pidt: Option<PathBuf>,
    legend: Option<PathBuf>,
    palette: Option<PaletteRecord>,
    excluded: BTreeSet<PathBuf>,
}

fn labels(options: &DescribeOptions, base: &Path) -> Result<Labels> {
    let mut excluded = BTreeSet::new();
    let mut inside = |path: &Path, what: &str| -> Result<PathBuf> {
        let full = canonical(path)?;
        excluded.insert(full.clone());
        relative_to(&full, base, path, what)
    };
    let pidt = options.pidt.as_deref().map(|p| inside(p, "--pidt")).transpose()?;
    check_pidt_size(options)?;
    let legend = options.legend.as_deref().map(|p| inside(p, "--legend")).transpose()?;
    let palette = match &options.palette {
        Some(PaletteChoice::Image(path)) => Some(PaletteRecord::File(inside(path, "--fcsp")?)),
        Some(PaletteChoice::Canonical { width, height }) => {
            Some(PaletteRecord::Canonical { canonical: [*width, *height] })
        }
        None => None,
    };
    Ok(Labels { pidt, legend, palette, excluded })
}

/// With tiles missing (`--missing-tiles-empty`) and no grid given, the grid
/// is a guess: the largest column and row seen fall short of it when whole
/// border columns or rows showed only background in every eye-frame (the
/// bundled capture renamed without its empty tiles spans 4 × 3 of its 5 × 5,
/// and analysed so it measured 8 px/° for 10 and the windshield's angular
/// area 33 % short). Refused, naming a missing tile and what to give.
fn refuse_a_guessed_grid(dir: &Path, capture: &Capture) -> Result<()> {
    let Some(example) = capture.missing.first() else { return Ok(()) };
    Err(Error::bad_file(
        dir,
        format!(
            "--missing-tiles-empty: {} tiles are missing (e.g. frame {}, eye {}, row {}, col {}), so the tile \
             grid cannot be told from the tiles present: the largest column and row seen make {} columns × {} \
             rows, but border columns or rows that showed only background in every frame would not be seen, \
             and a short grid gives a wrong pixels per degree and angular areas; give the renderer's grid with \
             --grid COLUMNSxROWS (or --rig with \"tiles\": [columns, rows])",
            capture.missing.len(),
            example.frame,
            example.eye,
            example.row,
            example.col,
            capture.grid[0],
            capture.grid[1]
        ),
    ))
}

/// The PIdT must be the palette's size (the default 4096² without
/// `--palette-size`/`--fcsp`): checked here, naming the file, rather than one
/// command later by the analysis.
fn check_pidt_size(options: &DescribeOptions) -> Result<()> {
    let Some(pidt) = &options.pidt else { return Ok(()) };
    let side = crate::archive::palette::DEFAULT_PALETTE_SIDE;
    let (palette, what) = match &options.palette {
        Some(PaletteChoice::Image(path)) => (png_size(path)?, format!("the palette {}", path.display())),
        Some(PaletteChoice::Canonical { width, height }) => ([*width, *height], "--palette-size".to_string()),
        None => ([side, side], "the default palette (without --palette-size or --fcsp)".to_string()),
    };
    let found = png_size(pidt)?;
    if found == palette {
        return Ok(());
    }
    Err(Error::bad_file(
        pidt,
        format!(
            "the PIdT is {}×{} texels, but {what} is {}×{}: a PIdT labels the palette's texels one for one; give \
             the palette it was made for (e.g. --palette-size {}x{})",
            found[0], found[1], palette[0], palette[1], found[0], found[1]
        ),
    ))
}

/// What the reader should know about the manifest's name and the tile grid.
fn layout_notes(
    options: &DescribeOptions,
    manifest_path: &Path,
    grid_given: bool,
    grid: [u32; 2],
) -> Vec<String> {
    let mut notes = Vec::new();
    if manifest_path.file_name().is_some_and(|name| name != MANIFEST_FILE) {
        notes.push(format!(
            "the analyzer reads only {MANIFEST_FILE}: rename {} before analysing",
            manifest_path.display()
        ));
    }
    if options.missing_tiles_empty && !grid_given {
        notes.push(format!(
            "the grid, {} columns × {} rows, is the largest column and row seen: if whole border columns or rows \
             were left out, give the rig's tiles (--rig with \"tiles\": [columns, rows])",
            grid[0], grid[1]
        ));
    }
    notes
}

/// The manifest's `rig`, with `--pixels-per-degree` where the settings give none.
fn rig_with_ppd(settings: &RigSettings, tile_pixels: [u32; 2], pixels_per_degree: Option<f64>) -> RigRecord {
    let mut rig = metadata::rig_record(settings, tile_pixels);
    if let Some(ppd) = pixels_per_degree {
        rig.pixels_per_degree.get_or_insert(ppd);
    }
    rig
}

/// The `frames` records: each frame's eye poses where SOLO gave them (with
/// its time and distance where known), else each frame's time and distance
/// when every frame has its distance.
fn frame_entries(
    times: Option<&BTreeMap<u32, FrameTime>>,
    poses: Option<&BTreeMap<u32, BTreeMap<String, EyePose>>>,
) -> Option<Vec<FrameEntry>> {
    let entry = |frame: u32, time: Option<&FrameTime>, eyes: Option<BTreeMap<String, EyePose>>| FrameEntry {
        distance_m: time.and_then(|t| t.distance_m),
        eyes,
        frame,
        occluders: None,
        pedestrian: None,
        tiles_with_vehicle: None,
        time_s: time.map(|t| t.time_s),
        vehicle: None,
    };
    if let Some(poses) = poses {
        let time = |frame: &u32| times.and_then(|t| t.get(frame));
        return Some(
            poses.iter().map(|(frame, eyes)| entry(*frame, time(frame), Some(eyes.clone()))).collect(),
        );
    }
    let times = times.filter(|t| t.values().all(|t| t.distance_m.is_some()))?;
    Some(times.iter().map(|(&frame, time)| entry(frame, Some(time), None)).collect())
}

/// The manifest's path and its folder with links resolved; the folder of
/// frames must lie in it, since the manifest's paths may not leave it.
fn manifest_place(options: &DescribeOptions) -> Result<(PathBuf, PathBuf)> {
    if !options.dir.is_dir() {
        return Err(Error::bad_file(&options.dir, "not a folder (give the folder of rendered frames)"));
    }
    let path = match &options.out {
        Some(out) if out.is_dir() || out.as_os_str().to_string_lossy().ends_with(['/', '\\']) => {
            out.join(MANIFEST_FILE)
        }
        Some(out) => out.clone(),
        None => options.dir.join(MANIFEST_FILE),
    };
    let parent = match path.parent() {
        Some(parent) if !parent.as_os_str().is_empty() => parent,
        _ => Path::new("."),
    };
    let base = canonical(parent)?;
    let dir = canonical(&options.dir)?;
    if !dir.starts_with(&base) {
        return Err(Error::BadOptions(format!(
            "--out {}: the manifest must lie in {} or a folder above it (its paths are relative to its \
             folder and may not leave it)",
            path.display(),
            options.dir.display()
        )));
    }
    Ok((path, base))
}

/// `full` (canonical) relative to `base`, or an error naming `given`.
fn relative_to(full: &Path, base: &Path, given: &Path, what: &str) -> Result<PathBuf> {
    match full.strip_prefix(base) {
        Ok(relative) => Ok(PathBuf::from(slash_path(relative))),
        Err(_) => Err(Error::bad_file(
            given,
            format!(
                "{what}: lies outside the manifest's folder {}; the manifest can only name files inside it \
                 (copy the file there)",
                base.display()
            ),
        )),
    }
}

/// The rig settings: the rig file's, then the command line's (which win),
/// then the image size and tiling found, checked against each other.
fn settings(
    options: &DescribeOptions,
    mut settings: RigSettings,
    capture: &Capture,
    notes: &mut Vec<String>,
) -> Result<RigSettings> {
    let rig_name = options.rig.as_deref().unwrap_or(Path::new("--rig"));
    let eye = capture.eye_pixels();
    if let Some([width, height]) = settings.eye_pixels.filter(|given| *given != eye) {
        return Err(Error::bad_file(
            rig_name,
            format!(
                "eye_pixels [{width},{height}] disagrees with the frames: their eye images are {}×{} pixels",
                eye[0], eye[1]
            ),
        ));
    }
    if let Some([columns, rows]) = settings.tiles.filter(|given| *given != capture.grid) {
        notes.push(format!(
            "the rig's tiles [{columns},{rows}] replaced by the frames' grid [{}, {}] ([columns, rows])",
            capture.grid[0], capture.grid[1]
        ));
    }
    settings.eye_pixels = Some(eye);
    settings.tiles = Some(capture.grid);
    let given = [(options.fps, "--fps", "fps"), (options.fov.map(|f| f.0), "--fov", "horizontal_fov_deg")];
    for ((given, flag, key), setting) in
        given.into_iter().zip([&mut settings.fps, &mut settings.horizontal_fov_deg])
    {
        let Some(given) = given else { continue };
        if !(given.is_finite() && given > 0.0) {
            return Err(Error::BadOptions(format!("{flag} {given}: must be a number above 0")));
        }
        if let Some(old) = setting.filter(|old| *old != given) {
            notes.push(format!("{flag} {given} replaces the {key} {old} of the rig file or SOLO data"));
        }
        *setting = Some(given);
    }
    if let Some(ppd) = options.pixels_per_degree.filter(|ppd| !(ppd.is_finite() && *ppd > 0.0)) {
        return Err(Error::BadOptions(format!("--pixels-per-degree {ppd}: must be a number above 0")));
    }
    check_optics(options, &settings, eye)?;
    Ok(settings)
}

/// `--fov HxV` and `--pixels-per-degree` must agree with square pixels over the eye image.
fn check_optics(options: &DescribeOptions, settings: &RigSettings, eye: [u32; 2]) -> Result<()> {
    let Some(fov) = settings.horizontal_fov_deg else { return Ok(()) };
    let vertical = metadata::vertical_fov_deg(fov, eye);
    if let Some((_, Some(given))) = options.fov
        && (given - vertical).abs() > 0.1
    {
        return Err(Error::BadOptions(format!(
            "--fov {fov}x{given}: eye images of {}×{} pixels with square pixels and {fov}° across have a \
             vertical field of view of {vertical:.3}°, not {given}° (ufcsr's eye is a centred pinhole with \
             square pixels)",
            eye[0], eye[1]
        )));
    }
    let derived = f64::from(eye[0]) / fov;
    if let Some(ppd) = options.pixels_per_degree
        && (ppd - derived).abs() > 1e-3 * derived
    {
        return Err(Error::BadOptions(format!(
            "--pixels-per-degree {ppd} disagrees with the rig's field of view: {} pixels over {fov}° is {derived:.6}",
            eye[0]
        )));
    }
    Ok(())
}

/// `--frame-times` for the captured frames: each must be listed.
fn times_of_frames(path: &Path, frames: &[u32]) -> Result<BTreeMap<u32, FrameTime>> {
    let mut all = metadata::read_frame_times(path)?;
    if let Some(missing) = frames.iter().find(|frame| !all.contains_key(frame)) {
        return Err(Error::bad_file(
            path,
            format!(
                "has no row for frame {missing}, which the file names give (every captured frame needs its time)"
            ),
        ));
    }
    all.retain(|frame, _| frames.binary_search(frame).is_ok());
    Ok(all)
}

/// The manifest's tiles (found below `given`, which is `dir` with links resolved), their files relative to `base`, each with its frame's time and distance.
fn tile_entries(
    capture: &Capture,
    [given, dir]: [&Path; 2],
    base: &Path,
    times: Option<&BTreeMap<u32, FrameTime>>,
    fps: Option<f64>,
) -> Result<Vec<TileEntry>> {
    let mut tiles = Vec::with_capacity(capture.tiles.len() + capture.missing.len());
    let found = capture.tiles.iter().map(|tile| (&tile.name, Some(tile.path.as_path())));
    for (name, path) in found.chain(capture.missing.iter().map(|name| (name, None))) {
        let file = match path {
            Some(path) => {
                let below = path.strip_prefix(given).unwrap_or(path);
                // A link inside the folder that leads out of it: the analysis
                // refuses such a tile (`inside_archive`), so the manifest never names it.
                let real = canonical(path)?;
                if !real.starts_with(base) {
                    return Err(Error::bad_file(
                        path,
                        format!(
                            "a frame: is a link leading outside the manifest's folder {} (to {}), which the \
                             analysis refuses; copy the file there",
                            base.display(),
                            real.display()
                        ),
                    ));
                }
                Some(relative_to(&dir.join(below), base, path, "a frame")?)
            }
            None => None,
        };
        let frame = name.frame;
        let (time_s, distance_m) = match times.and_then(|times| times.get(&frame)) {
            Some(time) => (Some(time.time_s), time.distance_m),
            None => (fps.map(|fps| f64::from(frame) / fps), None),
        };
        let empty = file.is_none();
        tiles.push(TileEntry {
            file,
            frame,
            eye: name.eye.clone(),
            row: name.row,
            col: name.col,
            empty,
            distance_m,
            time_s,
        });
    }
    tiles.sort_by(|a, b| (a.frame, &a.eye, a.row, a.col).cmp(&(b.frame, &b.eye, b.row, b.col)));
    Ok(tiles)
}

/// Notes on what stays empty because the manifest lacks it.
fn lacking(
    manifest: &Manifest,
    fps: Option<f64>,
    ppd: Option<f64>,
    distances: bool,
    notes: &mut Vec<String>,
) {
    if fps.is_none() {
        notes.push("no fps (--fps or the rig's fps): exposure_s and angular_area_deg2_s stay empty".into());
    }
    if ppd.is_none() {
        notes.push(
            "no field of view (--fov, or --pixels-per-degree): angular_area_deg2_s, frames.csv's solid_angle_sr \
             and the resolution diagnostics stay empty"
                .into(),
        );
    } else if manifest.rig_settings().and_then(|settings| settings.horizontal_fov_deg).is_none() {
        notes.push("no field of view (--fov): frames.csv's solid_angle_sr stays empty".into());
    }
    if !distances {
        notes.push(
            "no distances (--frame-times with a distance_m column): the distance plots stay empty".into(),
        );
    }
    if manifest.pidt.is_none() {
        notes.push("no --pidt/--legend: counts per texel only, no parts".into());
    }
}

/// Checks the manifest as the analyzer will read it, then writes it atomically.
fn write_checked(manifest: &Manifest, path: &Path) -> Result<()> {
    let bytes = serde_json::to_vec_pretty(manifest)
        .map_err(|error| Error::bad_file(path, format!("could not write the manifest: {error}")))?;
    Manifest::parse(path, &bytes)?;
    crate::files::write_atomically(path, |writer| {
        std::io::Write::write_all(writer, &bytes)?;
        std::io::Write::write_all(writer, b"\n")
    })
}
