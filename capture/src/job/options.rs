//! What a capture is asked to do ([`CaptureOptions`]) and what it reports
//! ([`Summary`]). Validated once by the binary, then handed to the capture.

use std::path::PathBuf;
use std::sync::Arc;

use crate::error::{CaptureError, Result};
use crate::texture::pidt::own::OwnLabelFiles;

/// PNG compression of tiles.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Compression {
    Fastest,
    /// The default: much faster to encode than `balanced`, for somewhat larger files.
    #[default]
    Fast,
    Balanced,
    High,
}

impl Compression {
    pub(crate) fn png(self) -> png::Compression {
        match self {
            Compression::Fastest => png::Compression::Fastest,
            Compression::Fast => png::Compression::Fast,
            Compression::Balanced => png::Compression::Balanced,
            Compression::High => png::Compression::High,
        }
    }
}

/// The PNG row filter of tiles. The analyzer unfilters Up rows in about half
/// the time of the Paeth rows an adaptive encoder picks (issue 22; figures in
/// `docs/performance.md`), so tiles are Up-filtered unless asked otherwise.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum TileFilter {
    /// Every row Up-filtered: fast to decode, a little larger.
    #[default]
    Up,
    /// The png crate's per-row choice (mostly Paeth): smaller, slower to decode.
    Adaptive,
}

impl TileFilter {
    pub(crate) fn png(self) -> png::Filter {
        match self {
            TileFilter::Up => png::Filter::Up,
            TileFilter::Adaptive => png::Filter::Adaptive,
        }
    }
}

/// Most frames a `--frames` list may name (a day at 100 frames/s is 8.6 million).
pub const MAX_SELECTED_FRAMES: u64 = 10_000_000;

/// Which frames to capture: all, every Nth (`all/N`), or a list such as
/// `0,30,60-90/10`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FrameSelection {
    /// The frames named, or `None`: every `every`-th frame from 0.
    list: Option<Vec<u32>>,
    every: u32,
}

impl Default for FrameSelection {
    fn default() -> FrameSelection {
        FrameSelection::all()
    }
}

impl FrameSelection {
    /// Every frame.
    pub fn all() -> FrameSelection {
        FrameSelection { list: None, every: 1 }
    }

    /// Every `step`-th frame of whatever length the scenario has, the middle
    /// of each `step` frames, as [`stepped_frames`] keeps them; `step` 0 counts as 1.
    pub fn every(step: u32) -> FrameSelection {
        FrameSelection { list: None, every: step.max(1) }
    }

    /// The frames of a scenario with `count` frames.
    pub fn frames(&self, count: u32) -> Vec<u32> {
        match &self.list {
            None => stepped_frames(count, self.every, step_phase(self.every)),
            Some(list) => list.iter().copied().filter(|&f| f < count).collect(),
        }
    }
}

/// Every `step`-th frame of a scenario of `count` frames from frame `phase`:
/// the one definition every command that picks frames by a step uses
/// (`--frames all/N`, `--preview`, `study` and its frame offsets, `observers`,
/// `batch plan`, `design run`), with `phase` [`step_phase`] but for a study's
/// other offsets.
///
/// A kept frame stands for `step` frames of every time total (`step / fps`
/// seconds: [`crate::exact::seconds_per_frame`], the analyzer's `FrameClock`):
/// the `step` frames centred on it, `[f − ⌊step/2⌋, f − ⌊step/2⌋ + step)`. A
/// frame is kept while more than half of those lie in the scenario's `count`
/// frames. At the default phase the kept frames are the middles of the blocks
/// `[0, step)`, `[step, 2·step)`, …, so they stand for the scenario's time to
/// within half a step, for its duration exactly when `step` divides its frame
/// intervals (`count − 1`), and sample it by the midpoint rule. Keeping frames
/// 0, step, … up to the last frame instead made the final frame stand for a
/// whole step past the scenario's end (every 30th frame of 2 s read 2.5 s);
/// keeping them only while their step lay inside sampled every block at its
/// start, and an approaching vehicle's angular area, which grows fastest at
/// the end, came out twice as far from the exact measure's shares (demo A,
/// every 30th frame: 6.3 pp where the middles give 1.0). With no frame kept (a
/// step over twice the scenario) the one at `phase`, or the scenario's middle
/// frame if that comes first, is kept: it stands for one frame (1/fps).
pub(crate) fn stepped_frames(count: u32, step: u32, phase: u32) -> Vec<u32> {
    let (count, step) = (u64::from(count), u64::from(step.max(1)));
    let half = step / 2;
    let inside = |f: u64| (f + step - half).min(count).saturating_sub(f.saturating_sub(half));
    let kept: Vec<u32> = (u64::from(phase)..count)
        .step_by(step as usize)
        .filter(|&f| 2 * inside(f) > step)
        .filter_map(|f| u32::try_from(f).ok())
        .collect();
    match u32::try_from(count) {
        Ok(count) if kept.is_empty() && count > 0 => vec![phase.min((count - 1) / 2)],
        _ => kept,
    }
}

/// The longest step whose every-`step`-th frame keeps at least two of `count`
/// frames ([`FrameSelection::every`]); `None` below two frames. Searched with
/// the one rule rather than solved beside it, so a message that names it
/// cannot drift from what is kept; only a refusal asks.
pub(crate) fn longest_step_keeping_two(count: u32) -> Option<u32> {
    (1..count).rev().find(|&step| FrameSelection::every(step).frames(count).len() >= 2)
}

/// The phase of every `step`-th frame: the middle of the first `step` frames.
pub(crate) fn step_phase(step: u32) -> u32 {
    step.max(1) / 2
}

impl std::str::FromStr for FrameSelection {
    type Err = CaptureError;

    /// Parses `all`, `all/N` (every Nth frame) or comma-separated frames and
    /// inclusive ranges `a-b`, optionally with a step `a-b/s`.
    fn from_str(text: &str) -> Result<FrameSelection> {
        if text.trim().eq_ignore_ascii_case("all") {
            return Ok(FrameSelection::all());
        }
        if let Some((all, step)) = text.split_once('/')
            && all.trim().eq_ignore_ascii_case("all")
        {
            return match step.trim().parse::<u32>() {
                Ok(step) if step > 0 => Ok(FrameSelection::every(step)),
                _ => Err(CaptureError::BadOptions(format!(
                    "frames all/N needs a whole number N ≥ 1 (every Nth frame), not {text:?}"
                ))),
            };
        }
        let bad = || {
            CaptureError::BadOptions(format!(
                "frames must look like 0,30,60-90/10, all or all/N, not {text:?}"
            ))
        };
        let mut frames = Vec::new();
        for item in text.split(',') {
            let (range, step) = match item.split_once('/') {
                Some((range, step)) => (range, step.trim().parse::<u32>().map_err(|_| bad())?),
                None => (item, 1),
            };
            let (a, b) = match range.split_once('-') {
                Some((a, b)) => {
                    (a.trim().parse::<u32>().map_err(|_| bad())?, b.trim().parse::<u32>().map_err(|_| bad())?)
                }
                None => {
                    let a = range.trim().parse::<u32>().map_err(|_| bad())?;
                    (a, a)
                }
            };
            if step == 0 || b < a {
                return Err(bad());
            }
            // A selection is expanded into a list: bound it before it is.
            let selected = u64::from(b - a) / u64::from(step) + 1;
            if frames.len() as u64 + selected > MAX_SELECTED_FRAMES {
                return Err(CaptureError::BadOptions(format!(
                    "--frames {text:?} selects more than {MAX_SELECTED_FRAMES} frames"
                )));
            }
            frames.extend((a..=b).step_by(step as usize));
        }
        frames.sort_unstable();
        frames.dedup();
        Ok(FrameSelection { list: Some(frames), every: 1 })
    }
}

/// How to capture.
#[derive(Debug, Clone)]
pub struct CaptureOptions {
    pub out: PathBuf,
    /// Size of the canonical palette (ignored with `palette_file`).
    pub palette: [u32; 2],
    /// An external palette PNG instead of the canonical palette.
    pub palette_file: Option<PathBuf>,
    pub keep_uvs: bool,
    /// A PIdT and legend painted for the kept UVs, used as is (see [`crate::texture::pidt::own`]).
    pub own_labels: Option<OwnLabelFiles>,
    pub frames: FrameSelection,
    pub compression: Compression,
    /// The tiles' PNG row filter.
    pub tile_filter: TileFilter,
    pub resume: bool,
    pub keep_background_tiles: bool,
    /// Render every tile, even those the vehicle's bounds do not touch
    /// (for benchmarks and checks of the culling).
    pub no_cull: bool,
    /// Render whole tiles: no scissor to the vehicle's projected bounds and
    /// no skipping of tiles where occluders hide the vehicle (for benchmarks
    /// and checks that both give the same tiles).
    pub no_scissor: bool,
    /// Told of every rendered tile (the binary draws a bar); none by default.
    pub progress: CaptureProgress,
    /// PNG encoder threads (0: as many as cores).
    pub encoder_threads: usize,
    /// Render only this shard of the selected frames (see [`crate::job::capture_shard`]).
    pub shard: Option<ufcsr::Shard>,
    /// Each heatmap view in a counted capture's results is 400×300 pixels
    /// times this, 1–8 (the analyzer's `--views-scale`).
    pub views_scale: u32,
}

impl Default for CaptureOptions {
    fn default() -> CaptureOptions {
        CaptureOptions {
            out: PathBuf::from("archive"),
            palette: [4096, 4096],
            palette_file: None,
            keep_uvs: false,
            own_labels: None,
            frames: FrameSelection::all(),
            compression: Compression::Fast,
            tile_filter: TileFilter::Up,
            resume: false,
            keep_background_tiles: false,
            no_cull: false,
            no_scissor: false,
            progress: CaptureProgress::default(),
            encoder_threads: 0,
            shard: None,
            views_scale: ufcsr::output::DEFAULT_VIEWS_SCALE,
        }
    }
}

/// Where a capture reports its progress: each scenario `start`s with its
/// number of tiles, `advance`s by one per tile rendered (or culled, hidden,
/// resumed) and `finish`es. The library draws nothing itself.
#[derive(Clone, Default)]
pub struct CaptureProgress(Option<Arc<dyn ufcsr::Progress + Send>>);

impl CaptureProgress {
    /// Progress reported to `progress`.
    pub fn to(progress: Arc<dyn ufcsr::Progress + Send>) -> CaptureProgress {
        CaptureProgress(Some(progress))
    }

    pub(crate) fn start(&self, total: u64) {
        if let Some(progress) = &self.0 {
            progress.start(total);
        }
    }

    pub(crate) fn advance(&self, done: u64) {
        if let Some(progress) = &self.0 {
            progress.advance(done);
        }
    }

    pub(crate) fn finish(&self) {
        if let Some(progress) = &self.0 {
            progress.finish();
        }
    }
}

impl std::fmt::Debug for CaptureProgress {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(if self.0.is_some() { "CaptureProgress(reported)" } else { "CaptureProgress(none)" })
    }
}

/// What the frame loop did with the tiles of a capture.
///
/// Every tile of every eye-frame is exactly one of `culled`, `hidden`,
/// `resumed` and `rendered` ([`TileTally::accounted`] is their sum);
/// `background` and `written` count among the rendered ones (with
/// `--keep-background-tiles`, `written` also takes the culled-by-slack and
/// hidden tiles, written as background).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct TileTally {
    /// Rendered by the GPU.
    pub rendered: u64,
    /// Handed to the sink (PNGs written, or tiles counted).
    pub written: u64,
    /// Already on disk (`--resume`).
    pub resumed: u64,
    /// Not rendered: outside the vehicle's projected bounds.
    pub culled: u64,
    /// Rendered but pure background (left out).
    pub background: u64,
    /// Pixels of rendered tiles outside the scissor rectangle: neither
    /// rendered nor read back, filled with the background.
    pub pixels_scissored: u64,
    /// Tiles the vehicle's bounds touch but occluders hide: not rendered.
    pub hidden: u64,
}

impl TileTally {
    /// Tiles in one of the four disjoint kinds (culled, hidden, resumed,
    /// rendered): the capture's whole tile count.
    pub fn accounted(&self) -> u64 {
        self.culled + self.hidden + self.resumed + self.rendered
    }

    pub fn add(&mut self, other: TileTally) {
        self.rendered += other.rendered;
        self.written += other.written;
        self.resumed += other.resumed;
        self.culled += other.culled;
        self.background += other.background;
        self.pixels_scissored += other.pixels_scissored;
        self.hidden += other.hidden;
    }
}

/// What a capture did.
#[derive(Debug, Clone, Default)]
pub struct Summary {
    pub out: PathBuf,
    pub scenario: String,
    pub frames: u32,
    pub tiles: u64,
    /// What the frame loop did with them.
    pub tally: TileTally,
    /// Pixels of the tiles the vehicle's bounds touch (not culled): the
    /// share the scissor left out is against this.
    pub pixels: u64,
    pub seconds: f64,
    /// Of which unwrap, PIdT and pipeline setup.
    pub setup_seconds: f64,
    pub texels_per_m2: f64,
    pub palette_share: f64,
    pub parts: usize,
    pub triangles: usize,
    /// What did not fit but did not stop the capture (own PIdT texels).
    pub warnings: Vec<String>,
}

impl Summary {
    /// Frames per second of the frame loop (both eyes, rendering, readback
    /// and PNG encoding; setup excluded).
    pub fn frames_per_second(&self) -> f64 {
        let seconds = self.seconds - self.setup_seconds;
        if seconds > 0.0 { f64::from(self.frames) / seconds } else { 0.0 }
    }
}
