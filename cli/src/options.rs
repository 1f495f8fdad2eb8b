//! The options more than one command shares, defined once: the words every
//! command understands ([`Global`]: `--quiet`, `--json`, `--threads/-j`,
//! before or after the command's own arguments), how frames name texels and
//! parts ([`LabelArgs`], for the analysis and `manifest`), and the heatmap's
//! colour scale ([`HeatmapScaleArgs`], for the analysis and `heatmap`).

use std::path::PathBuf;

use anyhow::Context;
use clap::Args;

use crate::choices::Scale;
use crate::console::Style;

/// The words every command understands, anywhere on the command line.
#[derive(Args, Clone, Copy, Debug, Default)]
pub(crate) struct Global {
    /// Nothing on stdout and no progress bar (a command whose result is its output, such as
    /// `completions` or `batch plan`, still prints it); warnings and errors still go to stderr.
    #[arg(long, short, global = true)]
    pub quiet: bool,

    /// One JSON object on stdout instead of the text, whatever the ending (usage errors,
    /// failures, Ctrl-C too): command, exit_code, written (every file written) and the
    /// command's own facts; on an error also error.
    #[arg(long, global = true)]
    pub json: bool,

    /// Worker threads: decoding and counting, PNG encoders, the exact measure's ray casting and
    /// the other parallel work (0: one per core).
    #[arg(long, short = 'j', global = true, default_value_t = 0,
          value_parser = clap::value_parser!(u16).range(0..=1024))]
    pub threads: u16,
}

impl Global {
    /// What goes to stdout.
    pub(crate) fn style(&self) -> Style {
        match (self.json, self.quiet) {
            (true, _) => Style::Json,
            (false, true) => Style::Quiet,
            (false, false) => Style::Text,
        }
    }

    /// Starts the worker threads `--threads` asks for (0: one per core), once
    /// per process: the first and only pool, which every command uses.
    pub(crate) fn start_threads(&self) -> anyhow::Result<()> {
        if self.threads > 0 {
            rayon::ThreadPoolBuilder::new()
                .num_threads(usize::from(self.threads))
                .build_global()
                .context("could not start the worker threads")?;
        }
        Ok(())
    }
}

/// How the frames name texels and parts: the palette they were rendered with,
/// the PIdT and its legend, and the background. One set of options for every
/// command that reads frames (the analysis and `manifest`), parsed once by
/// [`LabelArgs::palette`] and [`LabelArgs::background_colors`]. Relative
/// paths are from the working directory.
#[derive(Args)]
pub(crate) struct LabelArgs {
    /// Part Identification Texture: palette-sized PNG, each texel in its part's colour.
    #[arg(long, value_name = "PNG")]
    pub pidt: Option<PathBuf>,

    /// Legend of the PIdT: CSV `name,color` (#RRGGBB) or JSON [{"name","color"}].
    #[arg(long, visible_alias = "parts", value_name = "CSV|JSON")]
    pub legend: Option<PathBuf>,

    /// Palette image the frames were rendered with: unique colours in any layout (default: the
    /// canonical palette).
    #[arg(long, value_name = "PNG", conflicts_with = "palette_size")]
    pub fcsp: Option<PathBuf>,

    /// Size of the canonical palette the frames were rendered with, W or WxH (default 4096x4096).
    #[arg(long, value_name = "W|WxH")]
    pub palette_size: Option<String>,

    /// Background colour to ignore, #RRGGBB; repeat for several (default #000FFF).
    #[arg(long, value_name = "HEX")]
    pub background: Vec<String>,
}

impl LabelArgs {
    /// `--fcsp` or `--palette-size`, if either is given.
    pub(crate) fn palette(&self) -> anyhow::Result<Option<ufcsr::PaletteChoice>> {
        Ok(match (&self.fcsp, &self.palette_size) {
            (Some(png), _) => Some(ufcsr::PaletteChoice::Image(png.clone())),
            (None, Some(size)) => {
                let [width, height] = ufcsr::parse_palette_size(size)?;
                Some(ufcsr::PaletteChoice::Canonical { width, height })
            }
            (None, None) => None,
        })
    }

    /// Every `--background`, parsed (empty when none is given).
    pub(crate) fn background_colors(&self) -> anyhow::Result<Vec<ufcsr::Color>> {
        self.background
            .iter()
            .map(|text| text.parse::<ufcsr::Color>().with_context(|| format!("--background {text:?}")))
            .collect()
    }
}

/// The heatmap's colour scale.
#[derive(Args)]
pub(crate) struct HeatmapScaleArgs {
    /// Colour scale of the heatmap: `linear` or `log` (default: linear, or the result's own).
    #[arg(long, value_enum)]
    pub scale: Option<Scale>,

    /// Count shown as the top of the colour scale (share one scale across scenarios).
    #[arg(long, value_name = "N")]
    pub max: Option<u32>,
}

impl HeatmapScaleArgs {
    /// The heatmap options: these arguments, else `stored` (a result's own
    /// scale and top), else the defaults.
    pub(crate) fn options(
        &self,
        stored: Option<(ufcsr::Scale, Option<u32>)>,
    ) -> anyhow::Result<ufcsr::HeatmapOptions> {
        let scale = match self.scale {
            Some(scale) => scale.into(),
            None => stored.map(|s| s.0).unwrap_or_default(),
        };
        let max = self.max.or(stored.and_then(|s| s.1));
        anyhow::ensure!(max != Some(0), "--max must be at least 1");
        Ok(ufcsr::HeatmapOptions { scale, max })
    }
}
