//! What an analysis is asked to do and what it measures about itself: the
//! options ([`AnalyzeOptions`], [`Dedupe`], [`PaletteChoice`]), progress
//! reporting, and per-stage [`Timings`]. Its own module so that the job
//! (`analyze`) and the report layer (`report`) both depend on it and not on
//! each other.

use std::path::PathBuf;

use crate::archive::shard::Shard;
use crate::color::Color;
use crate::error::{Error, Result};

/// Which palette to use.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum PaletteChoice {
    /// The canonical W×H palette.
    Canonical { width: u32, height: u32 },
    /// A palette image with unique colours.
    Image(PathBuf),
}

pub use crate::format::result::Dedupe;

impl Dedupe {
    /// Its name, as `--dedupe` takes it.
    pub fn name(self) -> &'static str {
        match self {
            Dedupe::Image => "image",
            Dedupe::Frame => "frame",
            Dedupe::EyePair => "eye-pair",
        }
    }

    /// True when counts are per eye-frame or per frame (needs a manifest).
    pub fn per_frame(self) -> bool {
        self != Dedupe::Image
    }
}

impl std::str::FromStr for Dedupe {
    type Err = Error;
    fn from_str(text: &str) -> Result<Dedupe> {
        match text {
            "image" => Ok(Dedupe::Image),
            "frame" => Ok(Dedupe::Frame),
            "eye-pair" => Ok(Dedupe::EyePair),
            other => {
                Err(Error::BadOptions(format!("unknown --dedupe {other:?}: use image, frame or eye-pair")))
            }
        }
    }
}

/// Receives progress while images are counted (the binary draws a bar).
pub trait Progress: Sync {
    /// Counting starts; `total` images will be reported.
    fn start(&self, total: u64);
    /// `done` more images are finished.
    fn advance(&self, done: u64);
    /// Counting is over.
    fn finish(&self);
}

/// Everything [`crate::analyze()`] needs. `None` fields fall back to the archive's
/// manifest, then to the defaults.
#[derive(Debug, Clone)]
pub struct AnalyzeOptions {
    /// The archive folder.
    pub archive: PathBuf,
    pub palette: Option<PaletteChoice>,
    pub pidt: Option<PathBuf>,
    pub legend: Option<PathBuf>,
    pub background: Option<Vec<Color>>,
    pub dedupe: Dedupe,
    pub trim: TrimMode,
    /// Heatmap settings, recorded in the result.
    pub heatmap: HeatmapOptions,
    /// The angular area (deg²·s per texel) shown as the top of the colour
    /// scale of `heatmap.png` (angular area), `heatmap.glb` and the views (`--area-max`;
    /// larger texels clamp), so several scenarios share one scale; `None` =
    /// the largest texel's. Recorded in the result. [`HeatmapOptions::max`]
    /// is the paper count heatmap's.
    pub area_max: Option<f64>,
    /// Stop at the first failed image.
    pub strict: bool,
    /// Files or folders never taken as images (e.g. the output folder).
    pub exclude: Vec<PathBuf>,
    /// Ignore `manifest.json` even if present.
    pub ignore_manifest: bool,
    /// Count only this shard of the archive (see [`crate::archive::shard`]).
    pub shard: Option<Shard>,
    /// The vehicle as unwrapped (glTF with the palette UVs), for `heatmap.glb`;
    /// default: the manifest's `vehicle`.
    pub mesh: Option<PathBuf>,
    /// Tally pixels and texels per eye-frame and part (`frames.csv`) and the
    /// resolution-independent measures (`measures` in `result.json`). Off by
    /// default in the library; the binary turns it on unless `--frames-csv
    /// off`. The capture's `--count` tallies them itself
    /// ([`crate::TileCounter::tally_parts`]).
    pub frames: bool,
    /// Also sum the solid angle each texel subtends (`heatmap-area.png`,
    /// `texel-area.f32`, and the views and `heatmap.glb` in deg²·s instead of
    /// the count); needs `frames` and the eyes' projection. On by default
    /// (the binary's `--texel-area off` keeps the paper's count): the
    /// counting kernel sums each run's solid angle as it finds the run
    /// (docs/performance.md#per-texel-angular-area).
    pub texel_area: bool,
    /// The legend and PIdT the analysis would read (from the options or the
    /// manifest), already loaded by the caller: used instead of reading them
    /// again (the files must still be there; the identity digests them).
    pub loaded_labels: Option<crate::archive::labels::LoadedLabels>,
}

/// The smallest `--area-max` taken (deg²·s): the smallest normal `f32`.
pub(crate) const AREA_MAX_FLOOR: f64 = f32::MIN_POSITIVE as f64;

impl Default for AnalyzeOptions {
    /// Every field empty, off or its type's default, except
    /// [`AnalyzeOptions::texel_area`], which is on.
    fn default() -> AnalyzeOptions {
        AnalyzeOptions {
            archive: PathBuf::new(),
            palette: None,
            pidt: None,
            legend: None,
            background: None,
            dedupe: Dedupe::default(),
            trim: TrimMode::default(),
            heatmap: HeatmapOptions::default(),
            area_max: None,
            strict: false,
            exclude: Vec::new(),
            ignore_manifest: false,
            shard: None,
            mesh: None,
            frames: false,
            texel_area: true,
            loaded_labels: None,
        }
    }
}

pub use crate::format::timings::Timings;

pub use crate::format::result::Scale;

impl std::str::FromStr for Scale {
    type Err = Error;
    fn from_str(text: &str) -> Result<Scale> {
        match text {
            "linear" => Ok(Scale::Linear),
            "log" => Ok(Scale::Log),
            other => Err(Error::BadOptions(format!("unknown heatmap scale {other:?}: use linear or log"))),
        }
    }
}

impl AnalyzeOptions {
    /// [`AnalyzeOptions::area_max`] is a finite number of deg²·s from
    /// [`AREA_MAX_FLOOR`] (the smallest normal `f32`, the type of
    /// `texel-area.f32`'s values) to `f32::MAX`: 0, a negative, NaN or an
    /// infinity would paint nothing meaningful, and a value below the floor
    /// (`1e-300`) rounds to 0 as an `f32`, which painted every texel "never
    /// seen".
    pub fn check_area_max(&self) -> Result<(), Error> {
        match self.area_max {
            Some(max) if !(max.is_finite() && max >= AREA_MAX_FLOOR && max <= f64::from(f32::MAX)) => {
                Err(Error::BadOptions(format!(
                    "--area-max {max}: give the top of the angular-area scale as a positive number of deg²·s"
                )))
            }
            _ => Ok(()),
        }
    }
}

/// Heatmap settings.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct HeatmapOptions {
    pub scale: Scale,
    /// The count shown as the top of the colormap; `None` = the largest count.
    /// Fixing it lets two scenarios share one colour scale (larger counts clamp).
    pub max: Option<u32>,
}

/// How to find empty tiles.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum TrimMode {
    /// Every file size that repeats within one tile size is a candidate.
    #[default]
    Auto,
    /// Every file of at most this many bytes is a candidate (the paper: 30,381).
    Bytes(u64),
    /// Decode everything.
    Off,
}

impl std::str::FromStr for TrimMode {
    type Err = Error;
    fn from_str(text: &str) -> Result<TrimMode, Error> {
        match text {
            "auto" => Ok(TrimMode::Auto),
            "off" => Ok(TrimMode::Off),
            number => number.replace(['_', ','], "").parse().map(TrimMode::Bytes).map_err(|_| {
                Error::BadOptions(format!("invalid --trim {text:?}: use auto, off or a size in bytes"))
            }),
        }
    }
}

impl std::fmt::Display for TrimMode {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            TrimMode::Auto => write!(f, "auto"),
            TrimMode::Off => write!(f, "off"),
            TrimMode::Bytes(bytes) => write!(f, "{bytes}"),
        }
    }
}
