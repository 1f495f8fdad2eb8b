//! `ufcsr observers` (`ufcsr observers`): its arguments and [`run_observers`], which
//! draws pedestrians from a declared population (or, with `--sampling
//! grid`, the old grid), captures a scenario from each and prints each
//! part's population mean, its 95 % interval and the spread over people;
//! with `--display WxH`, the same for every candidate display's (and
//! part's) legible seconds, from an exact measure of each observer.

use std::path::PathBuf;

use anyhow::Context;
use clap::{Args, ValueEnum};
use ufcsr::{
    format::ObserverPlace, format::ObserverPopulation, format::ObserverSampling, format::ResolutionCheck,
    format::StatureGroup,
};
use ufcsr_capture::{CaptureOptions, Gpu, parse_capture_palette_size};

use super::study::scenario_name;
use crate::choices::Backend;

use crate::console::{Console, say};

/// How the observers are chosen.
#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
enum Sampling {
    /// Independent draws from the population: the mean gets a 95 % interval.
    Random,
    /// A grid of `--positions` × `--heights` cell midpoints: no interval is claimed.
    Grid,
}

/// How each observer's own resolution error is bounded.
#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
enum Resolution {
    /// A second capture at half the ppd and twice the frame step; bound = safety factor × difference.
    Coarser,
    /// Not bounded: the intervals leave it out (and say so).
    None,
}

/// Uncertainty over the observer (see `ufcsr_capture::run_observer_study`).
#[derive(Args)]
pub(crate) struct ObserversArgs {
    #[command(flatten)]
    scene: super::source::SourceArgs,
    /// Scenario name (default: the first, A for the demo).
    #[arg(long)]
    scenario: Option<String>,
    /// The population, a JSON file (place, groups, truncate_sd; docs/science.md); instead of
    /// --kerb, --area and --group.
    #[arg(long, value_name = "FILE", conflicts_with_all = ["kerb", "area", "group"])]
    population: Option<PathBuf>,
    /// People stand uniformly along this kerb segment, world metres: X0,Y0:X1,Y1 (default: the
    /// rig's pedestrian, standing or walking).
    #[arg(long, value_parser = parse_kerb, allow_hyphen_values = true, conflicts_with = "area")]
    kerb: Option<[[f64; 2]; 2]>,
    /// People stand uniformly over this axis-aligned rectangle, world metres: X0,Y0:X1,Y1.
    #[arg(long, value_parser = parse_kerb, allow_hyphen_values = true)]
    area: Option<[[f64; 2]; 2]>,
    /// A group of the population, NAME:WEIGHT:STATURE_MEAN_M:STATURE_SD_M[:EYE_OFFSET_M] (offset
    /// default 0.11), repeated for a mixture; replaces the default (US adults ≥ 20 y, women
    /// 1.613 ± 0.071 m and men 1.753 ± 0.076 m in equal weight, CDC/NCHS 2021).
    #[arg(long, value_parser = parse_group)]
    group: Vec<StatureGroup>,
    /// How the observers are chosen.
    #[arg(long, value_enum, default_value_t = Sampling::Random)]
    sampling: Sampling,
    /// Observers drawn (random sampling).
    #[arg(long, default_value_t = 16)]
    observers: u32,
    /// Seed of the draws (random sampling): the same seed gives the same observers.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Grid: positions along the kerb, each at the middle of an equal piece.
    #[arg(long, default_value_t = 1)]
    positions: u32,
    /// Grid: eye heights LOW:HIGH, metres (default: the population's 5th–95th percentile).
    #[arg(long, value_parser = parse_range)]
    eye_heights: Option<[f64; 2]>,
    /// Grid: eye heights over the range, each at the middle of an equal piece.
    #[arg(long, default_value_t = 5)]
    heights: u32,
    /// How each observer's resolution error is bounded and folded into the intervals.
    #[arg(long, value_enum, default_value_t = Resolution::Coarser)]
    resolution_check: Resolution,
    /// Safety factor of the coarser-capture bound (Roache's 3 for two grids).
    #[arg(long, default_value_t = ufcsr_capture::study::DEFAULT_SAFETY_FACTOR)]
    safety_factor: f64,
    /// Pixels per degree of every observer's capture.
    #[arg(long, default_value_t = 10.0)]
    ppd: f64,
    /// Every n-th frame.
    #[arg(long, default_value_t = 3)]
    frame_step: u32,
    /// Canonical palette size, W or WxH; above 2^24 texels (up to 8192x8192) as `capture` draws
    /// and counts them (32-bit texel ids).
    #[arg(long, value_name = "W|WxH", default_value = "1024")]
    palette_size: String,
    /// Study folder: observers.json, observers.csv, observer-parts.csv and one folder per observer.
    #[arg(long, default_value = "observers")]
    out: PathBuf,
    /// GPU backend.
    #[arg(long, value_enum, default_value_t = Backend::Auto)]
    backend: Backend,
    /// Also report per candidate display of this size (width x height in metres, e.g. 0.40x0.15)
    /// and per part the legible seconds under the placement answer's default rule: each observer
    /// is also measured exactly (CPU) with placement candidates at --frame-step, the resolution
    /// check at twice it (writes observer-displays.csv; docs/science.md).
    #[arg(long, value_name = "WxH")]
    display: Option<String>,
    /// With --display: how far apart candidate patch centres are, metres.
    #[arg(long, value_name = "M", default_value_t = ufcsr_capture::DEFAULT_PATCH_SPACING_M, requires = "display")]
    patch_spacing: f64,
    /// With --display: the share of texels each observer's exact measure samples, e.g. 1/16
    /// (below 1 every observer draws its own texels, and the interval covers that noise too).
    #[arg(long, value_name = "FRACTION", default_value = "1", requires = "display")]
    display_sample: String,
    /// Size of the heatmap views in each observer's results, each 400×300 pixels times this (1–8):
    /// 1 draws a quarter of the pixels, for a quicker study; the numbers do not change.
    #[arg(long, value_name = "N", default_value_t = ufcsr::output::DEFAULT_VIEWS_SCALE,
          value_parser = clap::value_parser!(u32).range(1..=8))]
    views_scale: u32,
}

fn parse_pair(text: &str, separator: char, what: &str) -> Result<[f64; 2], String> {
    let (a, b) =
        text.split_once(separator).ok_or_else(|| format!("{what}: expected A{separator}B, got {text:?}"))?;
    let number = |s: &str| s.trim().parse::<f64>().map_err(|e| format!("{what}: {s:?}: {e}"));
    Ok([number(a)?, number(b)?])
}

fn parse_range(text: &str) -> Result<[f64; 2], String> {
    parse_pair(text, ':', "eye heights")
}

fn parse_kerb(text: &str) -> Result<[[f64; 2]; 2], String> {
    let (from, to) =
        text.split_once(':').ok_or_else(|| format!("kerb: expected X0,Y0:X1,Y1, got {text:?}"))?;
    Ok([parse_pair(from, ',', "kerb")?, parse_pair(to, ',', "kerb")?])
}

fn parse_group(text: &str) -> Result<StatureGroup, String> {
    let fields: Vec<&str> = text.split(':').collect();
    if !(4..=5).contains(&fields.len()) || fields[0].is_empty() {
        return Err(format!(
            "group: expected NAME:WEIGHT:STATURE_MEAN_M:STATURE_SD_M[:EYE_OFFSET_M], got {text:?}"
        ));
    }
    let number = |s: &str| s.trim().parse::<f64>().map_err(|e| format!("group {text:?}: {s:?}: {e}"));
    Ok(StatureGroup {
        name: fields[0].into(),
        weight: number(fields[1])?,
        stature_mean_m: number(fields[2])?,
        stature_sd_m: number(fields[3])?,
        eye_offset_m: fields.get(4).map_or(Ok(0.11), |s| number(s))?,
        source: "--group on the command line".into(),
    })
}

/// The population from `--population`, or from `--kerb`/`--area` and `--group` with the defaults.
fn population(args: &ObserversArgs) -> anyhow::Result<ObserverPopulation> {
    if let Some(path) = &args.population {
        // Through the analyzer's reader: a regular file, size-capped, never a FIFO that hangs.
        let bytes = ufcsr::files::read_limited(path, ufcsr::files::SMALL_INPUT_LIMIT)
            .with_context(|| format!("reading the population {}", path.display()))?;
        return serde_json::from_slice(&bytes)
            .with_context(|| format!("{}: not a population", path.display()));
    }
    let place = match (args.kerb, args.area) {
        (Some([from, to]), _) => ObserverPlace::Kerb { from, to },
        (None, Some([corner, opposite])) => ObserverPlace::Area { corner, opposite },
        (None, None) => ObserverPlace::Rig,
    };
    let mut population = ObserverPopulation::us_adults(place);
    if !args.group.is_empty() {
        population.groups = args.group.clone();
    }
    Ok(population)
}

pub(crate) fn run_observers(args: ObserversArgs, console: &Console) -> anyhow::Result<()> {
    let scene = args.scene.source()?.scene()?;
    scene.refuse_fleet("`ufcsr observers`")?;
    let population = population(&args)?;
    ufcsr_capture::study::check_population(&population)?;
    let sampling = match args.sampling {
        Sampling::Random => ObserverSampling::Random { observers: args.observers, seed: args.seed },
        Sampling::Grid => ObserverSampling::Grid {
            positions: args.positions,
            heights: args.heights,
            eye_heights_m: args.eye_heights.unwrap_or_else(|| {
                [0.05, 0.95].map(|q| ufcsr_capture::study::eye_height_quantile(&population, q))
            }),
        },
    };
    let options = ufcsr_capture::study::ObserverOptions {
        scenario: scenario_name(&scene, args.scenario.as_deref())?,
        population,
        sampling,
        resolution_check: match args.resolution_check {
            Resolution::Coarser => ResolutionCheck::Coarser { safety_factor: args.safety_factor },
            Resolution::None => ResolutionCheck::None,
        },
        ppd: args.ppd,
        frame_step: args.frame_step,
        capture: CaptureOptions {
            out: args.out.clone(),
            palette: parse_capture_palette_size(&args.palette_size)?,
            views_scale: args.views_scale,
            ..CaptureOptions::default()
        },
    };
    let displays = match &args.display {
        Some(text) => Some(ufcsr_capture::study::DisplayOptions {
            display_m: ufcsr_capture::parse_display(text)?,
            spacing_m: args.patch_spacing,
            sample: super::captures::parse_fraction(&args.display_sample).map_err(|_| {
                anyhow::anyhow!(
                    "--display-sample {}: must be a fraction in (0, 1], e.g. 1/16",
                    args.display_sample
                )
            })?,
        }),
        None => None,
    };
    // Refused before the observers are captured, not after.
    displays.as_ref().map(ufcsr_capture::study::DisplayOptions::check).transpose()?;
    let gpu = Gpu::create(args.backend.into()).context("creating the GPU device")?;
    eprintln!("adapter: {}", gpu.describe());
    let mut study = ufcsr_capture::run_observer_study(&gpu.device, &gpu.queue, &scene, &options)?;
    print_observers(&study, console);
    // The displays are measured before anything is written, so that
    // observers.json carries them (its `displays`).
    let mut written = Vec::new();
    if let Some(displays) = displays {
        let displays = ufcsr_capture::study::run_observer_displays(
            &gpu.device,
            &gpu.queue,
            &scene,
            &options,
            &displays,
        )?;
        print_displays(&displays, console);
        study.displays = Some(displays.record());
        written.push(ufcsr_capture::study::write_display_study(&displays, &args.out)?);
        console.fact("display_candidates", displays.summary.len());
    }
    // Each observer's folder (its archive, results and coarser capture) is this run's whole.
    crate::capture::captures::record_archives_of(study.observers.iter().map(|o| &o.results), console);
    for file in ufcsr_capture::study::write_observer_study(&study, &args.out)?.into_iter().chain(written) {
        console.wrote(&file);
        say!(console, "wrote {}", file.display());
    }
    console.fact("observers", study.observers.len());
    console.fact("parts", &study.summary);
    Ok(())
}

fn print_displays(study: &ufcsr_capture::study::DisplayStudy, console: &Console) {
    let [w, h] = study.options.display_m;
    say!(
        console,
        "displays {w:.2} × {h:.2} m every {:.2} m, {} texels per observer, in {:.1} s: {}",
        study.options.spacing_m,
        study.options.sample,
        study.seconds,
        study.interval
    );
    say!(
        console,
        "per candidate: legible s, population mean [95 % interval of the mean] (2.5–97.5 % of observers)"
    );
    for candidate in study.summary.iter().take(15) {
        say!(
            console,
            "{:<44} {:<5} {:>34}",
            candidate.candidate,
            candidate.kind,
            value_text(&candidate.legible_s, 2)
        );
    }
    if study.summary.len() > 15 {
        say!(console, "… {} more candidates in observer-displays.csv", study.summary.len() - 15);
    }
    let left_out = ufcsr::placement::excluded_line(&study.excluded);
    if !left_out.is_empty() {
        say!(console, "{left_out}");
    }
}

/// `mean [interval] (spread)`, the interval left out on a grid.
fn value_text(v: &ufcsr::format::PopulationValue, digits: usize) -> String {
    let interval =
        v.mean_ci95.map_or_else(String::new, |[low, high]| format!(" [{low:.digits$}–{high:.digits$}]"));
    format!("{:.digits$}{interval} ({:.digits$}–{:.digits$})", v.mean, v.p2_5, v.p97_5)
}

fn print_observers(study: &ufcsr::format::ObserverStudy, console: &Console) {
    let n = study.observers.len();
    let how = match study.sampling {
        ObserverSampling::Random { seed, .. } => format!("drawn from the population (seed {seed})"),
        ObserverSampling::Grid { eye_heights_m: [low, high], .. } => {
            format!("on a grid (eye heights {low:.3}–{high:.3} m; no interval claimed)")
        }
    };
    say!(
        console,
        "scenario {}, {n} observers {how} at {} px/°, every {} frame(s), in {:.1} s ({:.2} s of shared set-up, then \
         {:.2} s per observer)",
        study.scenario,
        study.ppd,
        study.frame_step,
        study.seconds,
        study.setup_seconds,
        (study.seconds - study.setup_seconds) / n as f64
    );
    for group in &study.population.groups {
        say!(
            console,
            "  group {}: weight {}, stature {} ± {} m, eye height = stature − {} m ({})",
            group.name,
            group.weight,
            group.stature_mean_m,
            group.stature_sd_m,
            group.eye_offset_m,
            group.source
        );
    }
    say!(console, "{}", study.interval);
    say!(
        console,
        "per part: population mean [95 % interval of the mean] (2.5–97.5 % of observers); top-5 = share of observers \
         with the part among the five largest angular areas"
    );
    say!(
        console,
        "{:<24} {:>40} {:>34} {:>6}",
        "part",
        "angular area, deg²·s",
        "share of angular area, %",
        "top-5"
    );
    for part in study.summary.iter().take(15) {
        say!(
            console,
            "{:<24} {:>40} {:>34} {:>6.2}",
            part.part,
            value_text(&part.angular_area_deg2_s, 3),
            value_text(&part.angular_area_share_percent, 2),
            part.top5_frequency
        );
    }
    if study.summary.len() > 15 {
        say!(console, "… {} more parts in observer-parts.csv", study.summary.len() - 15);
    }
}
