//! `ufcsr manifest` (`ufcsr manifest`): the command line of
//! describing externally rendered frames (Unity, Blender) as an archive
//! ([`ufcsr::describe`]), beside the other commands and sharing their
//! `--quiet`/`--json`/`-j` words and exit codes. Paths given here are relative to the working
//! directory; those written into the manifest are relative to it.

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;
use serde_json::json;

use super::run::{Done, finish};
use crate::console::{Completion, Console, shown};
use crate::options::LabelArgs;

/// Options of `ufcsr manifest`.
#[derive(Args)]
pub(crate) struct ManifestArgs {
    /// Folder of rendered frames: PNG tiles, or one image per eye and frame (searched recursively).
    pub dir: PathBuf,

    /// How file names give frame, eye, row and col: a regex with named groups, e.g.
    /// '(?P<eye>Left|Right)_(?P<frame>\d+)_(?P<row>\d+)_(?P<col>\d+)\.png$', or a template,
    /// e.g. '{eye}_{frame}_{row}_{col}.png' (`*` any text). Only frame is required: no eye is one
    /// eye "left", no row/col an untiled image. Default: ufcsr capture's f0012_left_r2_c3.png.
    #[arg(long, value_name = "REGEX|TEMPLATE")]
    pub pattern: Option<String>,

    /// Palette, PIdT, legend and background the frames were rendered with (each file inside the
    /// manifest's folder).
    #[command(flatten)]
    pub labels: LabelArgs,

    /// Frames per second of the rendered sequence (frame N is at N / F seconds).
    #[arg(long, value_name = "F")]
    pub fps: Option<f64>,

    /// Pixels per degree at the image centre (without --fov: no per-pixel solid angle).
    #[arg(long, value_name = "P", conflicts_with = "fov")]
    pub pixels_per_degree: Option<f64>,

    /// Field of view of each eye image in degrees, horizontal (107) or HxV (107x119.37, checked
    /// against square pixels).
    #[arg(long, value_name = "H_DEG[xV_DEG]")]
    pub fov: Option<String>,

    /// JSON file of rig fields (docs/scene-file.md#rig: fps, horizontal_fov_deg, ipd_m, …), a scene
    /// file's {"rig": …} or a manifest's rig; --fps and --fov win over it.
    #[arg(long, value_name = "FILE.json")]
    pub rig: Option<PathBuf>,

    /// CSV with a header naming frame, time_s and optionally distance_m: each frame's time (instead
    /// of frame / fps) and the vehicle's distance from the pedestrian in metres.
    #[arg(long, value_name = "FILE.csv")]
    pub frame_times: Option<PathBuf>,

    /// A tile missing from an eye-frame's grid showed only background and was not written (as
    /// ufcsr capture leaves such tiles out): list it as empty instead of refusing the folder.
    #[arg(long)]
    pub missing_tiles_empty: bool,

    /// Tiles of each eye image, columns × rows (e.g. 5x5): needed with --missing-tiles-empty when
    /// tiles are missing (the tiles present cannot tell it); wins over --rig's "tiles".
    #[arg(long, value_name = "COLUMNSxROWS", value_parser = parse_grid)]
    pub grid: Option<[u32; 2]>,

    /// Unity Perception SOLO output (sequence.N/stepK.frame_data.json, read without --fps/--fov): only
    /// this camera's RGB captures are frames (sensor id; twice for two eyes). Default: every RGB camera.
    #[arg(long, value_name = "ID")]
    pub solo_camera: Vec<String>,

    /// Read frames by their file names (--pattern) even where SOLO frame files are present.
    #[arg(long, conflicts_with = "solo_camera")]
    pub ignore_solo: bool,

    /// The manifest to write (default DIR/manifest.json; a folder: FOLDER/manifest.json). It must lie
    /// in DIR or above it; the analyzer reads ARCHIVE/manifest.json.
    #[arg(long, short, value_name = "FILE")]
    pub out: Option<PathBuf>,
}

/// `--grid 5x5`: columns and rows, each at least 1.
fn parse_grid(text: &str) -> std::result::Result<[u32; 2], String> {
    let parsed = text.split_once(['x', 'X']).and_then(|(columns, rows)| {
        let (columns, rows) = (columns.trim().parse::<u32>().ok()?, rows.trim().parse::<u32>().ok()?);
        (columns > 0 && rows > 0 && columns.checked_mul(rows).is_some()).then_some([columns, rows])
    });
    parsed.ok_or_else(|| format!("{text:?}: expected COLUMNSxROWS, each at least 1 (e.g. 5x5)"))
}

/// Writes the manifest and says what it holds and what it lacks.
pub(crate) fn run_manifest(args: ManifestArgs, console: &Console) -> Result<Completion> {
    let palette = args.labels.palette()?;
    let background = args.labels.background_colors()?;
    let options = ufcsr::DescribeOptions {
        dir: args.dir.clone(),
        pattern: args.pattern.clone(),
        out: args.out.clone(),
        palette,
        pidt: args.labels.pidt.clone(),
        legend: args.labels.legend.clone(),
        background,
        fps: args.fps,
        pixels_per_degree: args.pixels_per_degree,
        fov: args.fov.as_deref().map(ufcsr::parse_fov).transpose()?,
        rig: args.rig.clone(),
        frame_times: args.frame_times.clone(),
        missing_tiles_empty: args.missing_tiles_empty,
        grid: args.grid,
        solo_cameras: args.solo_camera.clone(),
        ignore_solo: args.ignore_solo,
    };
    let described = ufcsr::describe(&options)?;
    for note in &described.notes {
        eprintln!("note: {note}");
    }
    Ok(finish(
        console,
        Done {
            completion: Completion::Done,
            written: vec![described.manifest_path.clone()],
            text: summary(&described),
            facts: facts(&described),
        },
    ))
}

fn summary(d: &ufcsr::Described) -> String {
    let optional =
        |value: Option<f64>, unit: &str| value.map_or("unknown".to_string(), |v| format!("{v}{unit}"));
    let solo = d.solo.as_ref().map_or(String::new(), solo_summary);
    solo + &format!(
        "wrote {}: {} tiles ({} listed empty) in {} eye-frames ({} frames, eyes {}); {} × {} tiles (columns × rows) \
         of {}×{} px, \
         eye images {}×{} px\nframes per second: {}; horizontal field of view: {}; pixels per degree: {}; \
         frame times from: {}; distances: {}",
        d.manifest_path.display(),
        d.manifest.tiles.len(),
        d.manifest.tiles.iter().filter(|t| t.empty).count(),
        d.eye_frames,
        d.frames,
        d.eyes.join(", "),
        d.grid[0],
        d.grid[1],
        d.tile_pixels[0],
        d.tile_pixels[1],
        d.eye_pixels[0],
        d.eye_pixels[1],
        optional(d.fps, ""),
        optional(d.horizontal_fov_deg, "°"),
        d.pixels_per_degree.map_or("unknown".to_string(), |v| format!("{v:.6}")),
        d.times_from.unwrap_or("none"),
        if d.distances { "--frame-times" } else { "none" },
    )
}

/// The SOLO line: where the frames came from and what was skipped.
fn solo_summary(solo: &ufcsr::SoloSummary) -> String {
    let cameras: Vec<String> = solo.cameras.iter().map(|(id, eye)| format!("{id} → {eye}")).collect();
    let skipped: Vec<String> = solo.skipped.iter().map(|(kind, n)| format!("{n} {kind}")).collect();
    format!(
        "Unity Perception SOLO: {} frame files in {}{}; cameras {}; eye poses {}; skipped (not FCSP frames): {}\n",
        solo.frame_files,
        solo.folder.display(),
        solo.sequence.map_or(String::new(), |s| format!(" (sequence {s})")),
        cameras.join(", "),
        if solo.poses { "written to frames" } else { "not recorded" },
        if skipped.is_empty() { "none".to_string() } else { skipped.join(", ") },
    )
}

fn facts(d: &ufcsr::Described) -> serde_json::Value {
    json!({
        "manifest": shown(&d.manifest_path),
        "tiles": d.manifest.tiles.len(),
        "empty_tiles": d.manifest.tiles.iter().filter(|t| t.empty).count(),
        "eye_frames": d.eye_frames,
        "frames": d.frames,
        "eyes": d.eyes,
        "grid_columns_rows": d.grid,
        "tile_pixels": d.tile_pixels,
        "eye_pixels": d.eye_pixels,
        "fps": d.fps,
        "horizontal_fov_deg": d.horizontal_fov_deg,
        "pixels_per_degree": d.pixels_per_degree,
        "times_from": d.times_from,
        "distances": d.distances,
        "notes": d.notes,
        "solo": d.solo.as_ref().map(|solo| json!({
            "folder": shown(&solo.folder),
            "frame_files": solo.frame_files,
            "sequence": solo.sequence,
            "cameras": solo.cameras,
            "skipped": solo.skipped,
            "skipped_total": solo.skipped.values().sum::<usize>(),
            "poses": solo.poses,
        })),
    })
}
