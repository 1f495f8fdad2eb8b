//! Unity Perception's SOLO output as it comes: a folder `sequence.N/` of
//! `stepK.frame_data.json` files (Perception 1.0's name; its schema page
//! writes `step.K.frame.json`, also read), each listing the frame's
//! captures — per camera the image file, its `dimension`, the 3×3 `matrix`,
//! `position` and `rotation` — and the frame's `timestamp`. Read so that
//! `ufcsr manifest` needs neither `--fps` nor `--fov` for Unity
//! output, and so that the other files Perception writes beside the frames
//! (segmentation, depth, normals, instance masks) are skipped by a rule and
//! counted instead of stopping the manifest.
//!
//! The rule: a frame (an FCSP image) is the PNG of an RGB camera capture
//! (`@type` ending in `RGBCamera`; with `--solo-camera`, only those sensor
//! ids). Every other file a frame file names (annotations, other sensors,
//! other cameras) and every PNG no frame file names is skipped, counted by
//! kind. One sequence per manifest: each sequence is one run of the scenario.
//!
//! The JSON is read by typed serde records with the fields ufcsr uses (the
//! rest of SOLO's record is ignored), through [`crate::files::read_limited`].

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Component, Path, PathBuf};

use serde::Deserialize;

use crate::describe::names::{DEFAULT_EYE, TileName};
use crate::describe::scan::{FoundTile, png_size, slash_path};
use crate::describe::solo_camera::{eye_pose, horizontal_fov_deg};
use crate::error::{Error, Result};
use crate::format::manifest::EyePose;

/// The endings of a SOLO frame file (Perception 1.0's, then the schema page's).
pub(crate) const FRAME_FILE_ENDINGS: [&str; 2] = [".frame_data.json", ".frame.json"];

/// One frame file: the fields ufcsr reads.
#[derive(Debug, Clone, Deserialize)]
pub(crate) struct SoloFrame {
    /// The sequence (scenario iteration) the frame belongs to.
    #[serde(default)]
    pub sequence: Option<u64>,
    /// Index of the data-producing frame in its sequence: ufcsr's frame number.
    pub step: u32,
    /// Simulation time since the sequence started. Perception 1.0 writes its
    /// `SequenceTime` (the sum of Unity's `Time.deltaTime`: seconds), though
    /// SoloSchema.md says milliseconds; read as seconds.
    #[serde(default)]
    pub timestamp: Option<f64>,
    #[serde(default)]
    pub captures: Vec<SoloCapture>,
}

/// One sensor's capture in a frame.
#[derive(Debug, Clone, Deserialize)]
pub(crate) struct SoloCapture {
    /// e.g. `type.unity.com/unity.solo.RGBCamera`.
    #[serde(rename = "@type", default)]
    pub kind: String,
    /// The sensor's id (the camera's name in Unity).
    #[serde(default)]
    pub id: String,
    /// Unity world metres.
    #[serde(default)]
    pub position: Option<[f64; 3]>,
    /// Unit quaternion x, y, z, w.
    #[serde(default)]
    pub rotation: Option<Vec<f64>>,
    /// The image, relative to the sequence folder.
    #[serde(default)]
    pub filename: Option<String>,
    /// Width and height in pixels.
    #[serde(default)]
    pub dimension: Option<[f64; 2]>,
    /// `Perspective` (or `Orthographic`/`Isometric`).
    #[serde(default)]
    pub projection: Option<String>,
    /// 3×3, column-major ([`horizontal_fov_deg`]).
    #[serde(default)]
    pub matrix: Option<Vec<f64>>,
    #[serde(default)]
    pub annotations: Vec<SoloAnnotation>,
}

/// An annotation of a capture; those with a file are skipped frames' kin.
#[derive(Debug, Clone, Deserialize)]
pub(crate) struct SoloAnnotation {
    #[serde(rename = "@type", default)]
    pub kind: String,
    #[serde(default)]
    pub filename: Option<String>,
}

/// What a SOLO sequence says, ready for the manifest.
#[derive(Debug, Clone, Default)]
pub(crate) struct Solo {
    /// The sequence folder, as found below the described folder.
    pub folder: PathBuf,
    pub frame_files: usize,
    pub sequence: Option<u64>,
    /// The FCSP frames: one untiled image per camera and step.
    pub tiles: Vec<FoundTile>,
    /// Step → seconds.
    pub times: BTreeMap<u32, f64>,
    /// Steps per second: the median over consecutive frames of Δstep / Δtime.
    pub fps: Option<f64>,
    /// Degrees across each image, from the captures' matrices.
    pub horizontal_fov_deg: Option<f64>,
    /// Step → eye → pose in ufcsr's world.
    pub poses: BTreeMap<u32, BTreeMap<String, EyePose>>,
    /// Sensor id → eye name.
    pub cameras: BTreeMap<String, String>,
    /// What was skipped, by kind → files.
    pub skipped: BTreeMap<String, usize>,
    pub notes: Vec<String>,
}

/// The SOLO frame files below `dir` (in `dir` itself or in its
/// `sequence.N` folders), or `None` where there are none. More than one
/// sequence is refused: describe one sequence folder at a time.
pub(crate) fn find(dir: &Path) -> Result<Option<(PathBuf, Vec<PathBuf>)>> {
    let mut by_folder: BTreeMap<PathBuf, Vec<PathBuf>> = BTreeMap::new();
    let walk = walkdir::WalkDir::new(dir).max_depth(2).follow_links(true).sort_by_file_name();
    for entry in walk {
        let entry = entry.map_err(|error| {
            let path = error.path().unwrap_or(dir).to_path_buf();
            Error::io(&path, error.into())
        })?;
        let name = entry.file_name().to_string_lossy();
        let is_frame = name.starts_with("step") && FRAME_FILE_ENDINGS.iter().any(|end| name.ends_with(end));
        let parent = entry.path().parent().unwrap_or(dir);
        let in_sequence = entry.depth() == 1
            || parent.file_name().is_some_and(|n| n.to_string_lossy().starts_with("sequence."));
        if is_frame && in_sequence {
            // A frame file that is a FIFO, a device or a folder is refused by name: skipping it
            // without a word left frames out (issue 41 §3).
            if !entry.file_type().is_file() {
                return Err(Error::bad_file(
                    entry.path(),
                    "is a SOLO frame file name but not a regular file (a FIFO, device, socket or folder): \
                     nothing written",
                ));
            }
            by_folder.entry(parent.to_path_buf()).or_default().push(entry.path().to_path_buf());
        }
    }
    if by_folder.len() > 1 {
        let folders: Vec<String> = by_folder.keys().map(|f| f.display().to_string()).collect();
        return Err(Error::bad_file(
            dir,
            format!(
                "holds {} Unity Perception SOLO sequences ({}): each sequence is one run of the scenario and \
                 one archive; describe one sequence folder at a time (nothing written)",
                folders.len(),
                folders.join(", ")
            ),
        ));
    }
    Ok(by_folder.into_iter().next())
}

/// One RGB capture taken as a frame.
struct Shot {
    step: u32,
    camera: String,
    path: PathBuf,
    dimension: Option<[f64; 2]>,
    fov: Option<f64>,
    pose: Option<EyePose>,
}

/// Reads the sequence's frame files; `cameras` (sensor ids) limits which
/// RGB cameras are frames (empty: all, at most two).
pub(crate) fn read(folder: &Path, files: &[PathBuf], cameras: &[String]) -> Result<Solo> {
    let mut solo = Solo { folder: folder.to_path_buf(), frame_files: files.len(), ..Solo::default() };
    let mut named = BTreeSet::new();
    let mut shots = Vec::new();
    let mut steps = BTreeMap::new();
    for file in files {
        let bytes = crate::files::read_limited(file, crate::files::SMALL_INPUT_LIMIT)?;
        let frame: SoloFrame = crate::format::parse_json(file, &bytes, "Unity Perception SOLO frame file")?;
        if let Some(other) = steps.insert(frame.step, file.clone()) {
            return Err(Error::bad_file(
                file,
                format!("is step {}, like {}: each step is one frame file", frame.step, other.display()),
            ));
        }
        check_sequence(&mut solo, &frame, file)?;
        if let Some(time) = frame.timestamp {
            if !(time.is_finite() && time >= 0.0) {
                return Err(Error::bad_file(file, format!("timestamp {time} is not a time of 0 or more")));
            }
            solo.times.insert(frame.step, time);
        }
        for capture in &frame.captures {
            take_capture(&mut solo, &mut shots, &mut named, (file, frame.step), capture, cameras)?;
        }
    }
    if solo.times.len() != steps.len() {
        solo.times.clear();
        solo.notes.push("not every SOLO frame file has a timestamp: no frame times from SOLO".into());
    }
    skip_unnamed(&mut solo, &named)?;
    assemble(&mut solo, shots)?;
    if solo.times.is_empty() && solo.fps.is_none() {
        solo.fps = sensor_rate(&mut solo)?;
    }
    Ok(solo)
}

/// `sensor_definitions.json`, where Perception before 1.0 (frame files
/// without `timestamp`) keeps the capture rate: the fields ufcsr reads.
#[derive(Debug, Deserialize)]
struct SensorDefinitions {
    #[serde(rename = "sensorDefinitions", default)]
    sensors: Vec<SensorDefinition>,
}

#[derive(Debug, Deserialize)]
struct SensorDefinition {
    #[serde(default)]
    id: String,
    /// Seconds per simulation frame while capturing.
    #[serde(rename = "simulationDeltaTime", default)]
    simulation_delta_time: Option<f64>,
    /// Simulation frames skipped between two captures.
    #[serde(rename = "framesBetweenCaptures", default)]
    frames_between_captures: Option<f64>,
}

/// The file beside the sequence folders (or in the sequence folder).
pub(crate) const SENSOR_DEFINITIONS_FILE: &str = "sensor_definitions.json";

/// Captures per second of the chosen cameras from `sensor_definitions.json`
/// (in the sequence folder or the dataset folder above it):
/// `1 / (simulationDeltaTime × (framesBetweenCaptures + 1))`. `None` where
/// there is no such file or it does not say; cameras that disagree are refused.
fn sensor_rate(solo: &mut Solo) -> Result<Option<f64>> {
    let candidates = [Some(solo.folder.as_path()), solo.folder.parent()];
    let Some(path) =
        candidates.into_iter().flatten().map(|dir| dir.join(SENSOR_DEFINITIONS_FILE)).find(|p| p.exists())
    else {
        return Ok(None);
    };
    let bytes = crate::files::read_limited(&path, crate::files::SMALL_INPUT_LIMIT)?;
    let definitions: SensorDefinitions =
        crate::format::parse_json(&path, &bytes, "Unity Perception SOLO sensor_definitions.json")?;
    let mut rates = Vec::new();
    for sensor in definitions.sensors.iter().filter(|s| solo.cameras.contains_key(&s.id)) {
        let (Some(delta), Some(between)) = (sensor.simulation_delta_time, sensor.frames_between_captures)
        else {
            continue;
        };
        if !(delta.is_finite()
            && delta > 0.0
            && between.is_finite()
            && between >= 0.0
            && between.fract() == 0.0)
        {
            return Err(Error::bad_file(
                &path,
                format!(
                    "sensor {:?}: simulationDeltaTime {delta} and framesBetweenCaptures {between} are not a \
                     capture rate (a time above 0 and a whole number of 0 or more)",
                    sensor.id
                ),
            ));
        }
        rates.push((sensor.id.clone(), 1.0 / (delta * (between + 1.0))));
    }
    let Some((first_id, first)) = rates.first().cloned() else { return Ok(None) };
    if let Some((id, rate)) = rates.iter().find(|(_, rate)| (rate - first).abs() > 1e-9 * first) {
        return Err(Error::bad_file(
            &path,
            format!(
                "cameras {first_id:?} and {id:?} capture at {first} and {rate} per second: one rate per archive"
            ),
        ));
    }
    solo.notes.push(format!(
        "no SOLO timestamps: {first:.6} frames per second from {SENSOR_DEFINITIONS_FILE} (simulationDeltaTime × \
         (framesBetweenCaptures + 1) per capture)"
    ));
    Ok(Some(first))
}

/// Every frame file of one sequence.
fn check_sequence(solo: &mut Solo, frame: &SoloFrame, file: &Path) -> Result<()> {
    match (solo.sequence, frame.sequence) {
        (Some(first), Some(this)) if first != this => Err(Error::bad_file(
            file,
            format!(
                "is of sequence {this}, the folder's other frame files of sequence {first}: one sequence per archive"
            ),
        )),
        (None, Some(this)) => {
            solo.sequence = Some(this);
            Ok(())
        }
        _ => Ok(()),
    }
}

/// The short name of a SOLO `@type` (`…unity.solo.DepthAnnotation` → `DepthAnnotation`).
fn kind_name(kind: &str) -> String {
    let short = kind.rsplit(['.', '/']).next().unwrap_or(kind);
    if short.is_empty() { "untyped".to_string() } else { short.to_string() }
}

/// A capture: a frame when it is an RGB camera chosen, else its files are skipped.
fn take_capture(
    solo: &mut Solo,
    shots: &mut Vec<Shot>,
    named: &mut BTreeSet<String>,
    (file, step): (&Path, u32),
    capture: &SoloCapture,
    cameras: &[String],
) -> Result<()> {
    for annotation in &capture.annotations {
        if let Some(name) = &annotation.filename {
            named.insert(inside(file, name)?);
            *solo.skipped.entry(kind_name(&annotation.kind)).or_default() += 1;
        }
    }
    let Some(name) = &capture.filename else { return Ok(()) };
    let relative = inside(file, name)?;
    named.insert(relative.clone());
    let is_rgb = capture.kind.ends_with("RGBCamera");
    if !is_rgb || !(cameras.is_empty() || cameras.contains(&capture.id)) {
        let kind = if is_rgb {
            format!("camera {} (not --solo-camera)", capture.id)
        } else {
            kind_name(&capture.kind)
        };
        *solo.skipped.entry(kind).or_default() += 1;
        return Ok(());
    }
    let path = solo.folder.join(&relative);
    if !path.extension().is_some_and(|e| e.eq_ignore_ascii_case("png")) {
        return Err(Error::bad_file(
            file,
            format!(
                "camera {:?} at step {step} wrote {name:?}, not a PNG: FCSP frames must be lossless (set the \
                 Perception camera's image format to PNG)",
                capture.id
            ),
        ));
    }
    if let Some(projection) = capture.projection.as_deref().filter(|p| !p.eq_ignore_ascii_case("perspective"))
    {
        return Err(Error::bad_file(
            file,
            format!(
                "camera {:?} has a {projection} projection: ufcsr's eye is a perspective pinhole",
                capture.id
            ),
        ));
    }
    let problem =
        |what: String| Error::bad_file(file, format!("camera {:?} at step {step}: {what}", capture.id));
    let fov = match (&capture.matrix, capture.dimension) {
        (Some(matrix), Some(dimension)) => Some(horizontal_fov_deg(matrix, dimension).map_err(problem)?),
        _ => None,
    };
    let pose = match (capture.position, &capture.rotation) {
        (Some(position), Some(rotation)) => Some(eye_pose(position, rotation).map_err(problem)?),
        _ => None,
    };
    shots.push(Shot { step, camera: capture.id.clone(), path, dimension: capture.dimension, fov, pose });
    Ok(())
}

/// `name` (relative to the sequence folder, as SOLO writes it) as a `/`
/// path that stays inside the folder.
fn inside(file: &Path, name: &str) -> Result<String> {
    let path = Path::new(name);
    if name.is_empty() || !path.components().all(|c| matches!(c, Component::Normal(_))) {
        return Err(Error::bad_file(
            file,
            format!("names the file {name:?}, which does not lie inside its sequence folder"),
        ));
    }
    Ok(slash_path(path))
}

/// PNGs in the sequence folder that no frame file names: skipped, counted.
fn skip_unnamed(solo: &mut Solo, named: &BTreeSet<String>) -> Result<()> {
    // Links are not followed: a link in the dataset may lead anywhere (issue 41 §3); a linked
    // PNG is not walked into, and a linked folder's PNGs are not looked at.
    let walk = walkdir::WalkDir::new(&solo.folder).follow_links(false).sort_by_file_name();
    let mut first = None;
    for entry in walk {
        let entry = entry.map_err(|error| {
            let path = error.path().unwrap_or(&solo.folder).to_path_buf();
            Error::io(&path, error.into())
        })?;
        let path = entry.path();
        let relative = slash_path(path.strip_prefix(&solo.folder).unwrap_or(path));
        if entry.path_is_symlink() && entry.depth() > 0 && !named.contains(&relative) {
            *solo.skipped.entry("link named by no frame file (not followed)".into()).or_default() += 1;
            continue;
        }
        if !entry.file_type().is_file() || !path.extension().is_some_and(|e| e.eq_ignore_ascii_case("png")) {
            continue;
        }
        if !named.contains(&relative) {
            first.get_or_insert(relative);
            *solo.skipped.entry("PNG named by no frame file".into()).or_default() += 1;
        }
    }
    if let Some(first) = first {
        solo.notes.push(format!("PNGs that no SOLO frame file names are not frames (e.g. {first})"));
    }
    Ok(())
}

/// The frames as tiles, each camera an eye, and the rig the captures share.
fn assemble(solo: &mut Solo, shots: Vec<Shot>) -> Result<()> {
    let ids: BTreeSet<&str> = shots.iter().map(|s| s.camera.as_str()).collect();
    solo.cameras = eye_names(&solo.folder, &ids)?;
    let mut fovs: Vec<(f64, &Shot)> = Vec::new();
    for shot in &shots {
        let pixels = png_size(&shot.path)?;
        if let Some([w, h]) = shot.dimension.filter(|d| *d != [f64::from(pixels[0]), f64::from(pixels[1])]) {
            return Err(Error::bad_file(
                &shot.path,
                format!("is {}×{} pixels, but its frame file's dimension says {w}×{h}", pixels[0], pixels[1]),
            ));
        }
        let eye = solo.cameras[&shot.camera].clone();
        if let Some(pose) = shot.pose {
            solo.poses.entry(shot.step).or_default().insert(eye.clone(), pose);
        }
        fovs.extend(shot.fov.map(|fov| (fov, shot)));
        let name = TileName { frame: shot.step, eye, row: 0, col: 0 };
        solo.tiles.push(FoundTile { path: shot.path.clone(), name, pixels });
    }
    solo.horizontal_fov_deg = one_fov(&fovs)?;
    if fovs.len() < shots.len() {
        solo.horizontal_fov_deg = None;
        solo.notes.push(
            "not every SOLO camera capture has a matrix and dimension: no field of view from SOLO".into(),
        );
    }
    if solo.poses.values().map(BTreeMap::len).sum::<usize>() < shots.len() {
        solo.poses.clear();
    }
    solo.fps = steps_per_second(&solo.times, &mut solo.notes)?;
    Ok(())
}

/// One camera: `left`. Two: `left` and `right` where their ids say so, else
/// their ids in lower case. More: refused (choose with `--solo-camera`).
fn eye_names(folder: &Path, ids: &BTreeSet<&str>) -> Result<BTreeMap<String, String>> {
    let lower = |id: &str| id.to_lowercase();
    let names: Vec<String> = match ids.len() {
        0 => {
            return Err(Error::bad_file(
                folder,
                "its SOLO frame files list no RGB camera capture (no frames)",
            ));
        }
        1 => vec![DEFAULT_EYE.to_string()],
        2 => {
            let sided: Vec<&str> = ids
                .iter()
                .map(|id| {
                    if lower(id).contains("left") {
                        "left"
                    } else if lower(id).contains("right") {
                        "right"
                    } else {
                        ""
                    }
                })
                .collect();
            if sided == ["left", "right"] || sided == ["right", "left"] {
                sided.into_iter().map(str::to_string).collect()
            } else {
                ids.iter().map(|id| lower(id)).collect()
            }
        }
        n => {
            return Err(Error::bad_file(
                folder,
                format!(
                    "its SOLO frame files list {n} RGB cameras ({}): a pedestrian has two eyes; choose the FCSP \
                     cameras with --solo-camera ID",
                    ids.iter().copied().collect::<Vec<_>>().join(", ")
                ),
            ));
        }
    };
    if names
        .iter()
        .any(|n| n.is_empty() || !n.chars().all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-'))
    {
        return Err(Error::bad_file(
            folder,
            format!("camera ids {ids:?} do not make eye names (letters, digits, _ and - only)"),
        ));
    }
    Ok(ids.iter().map(|id| id.to_string()).zip(names).collect())
}

/// The one field of view every capture shares (within 1e-4°).
fn one_fov(fovs: &[(f64, &Shot)]) -> Result<Option<f64>> {
    let Some(&(first, _)) = fovs.first() else { return Ok(None) };
    if let Some((other, shot)) = fovs.iter().find(|(fov, _)| (fov - first).abs() > 1e-4) {
        return Err(Error::bad_file(
            &shot.path,
            format!(
                "camera {:?} at step {} has a field of view of {other:.6}°, others {first:.6}°: ufcsr's eyes keep \
                 one lens",
                shot.camera, shot.step
            ),
        ));
    }
    Ok(Some(first))
}

/// Steps per second: the median of Δstep / Δtime over consecutive frames,
/// with a note when the frames are unevenly spaced (over 1 %) or the rate
/// suggests milliseconds.
fn steps_per_second(times: &BTreeMap<u32, f64>, notes: &mut Vec<String>) -> Result<Option<f64>> {
    let mut rates = Vec::new();
    for ((a, ta), (b, tb)) in times.iter().zip(times.iter().skip(1)) {
        if tb <= ta {
            return Err(Error::BadOptions(format!(
                "SOLO timestamps do not increase: step {a} at {ta}, step {b} at {tb}"
            )));
        }
        rates.push(f64::from(b - a) / (tb - ta));
    }
    if rates.is_empty() {
        if !times.is_empty() {
            notes.push("one SOLO frame: no frame rate from its timestamps".into());
        }
        return Ok(None);
    }
    rates.sort_by(f64::total_cmp);
    let median = rates[rates.len() / 2];
    let spread = rates.iter().map(|r| (r - median).abs() / median).fold(0.0, f64::max);
    if spread > 0.01 {
        notes.push(format!(
            "SOLO frames are unevenly spaced (rates differ by up to {:.1} %): fps is the median, {median:.6}; each \
             frame keeps its own time",
            spread * 100.0
        ));
    }
    if median < 1.0 {
        notes.push(format!(
            "SOLO timestamps read as seconds give {median:.6} frames per second; if they are milliseconds, give --fps"
        ));
    }
    Ok(Some(median))
}
