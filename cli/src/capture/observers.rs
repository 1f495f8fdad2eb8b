//! `ufcsr observers` (`ufcsr-capture observers`): its arguments and [`run_observers`], which
//! captures a scenario from a grid of pedestrians (positions along a kerb ×
//! eye heights) and prints each part's mean, interval and spread.

use std::path::PathBuf;

use anyhow::Context;
use clap::Args;
use ufcsr_capture::{CaptureOptions, Gpu, parse_palette_size};

use super::study::{load_scene, scenario_name};
use crate::choices::Backend;

use crate::console::{Console, say};

/// Uncertainty over the observer (see `ufcsr_capture::run_observer_study`).
#[derive(Args)]
pub struct ObserversArgs {
    /// `demo`, or a scene JSON file.
    scene: String,
    /// Scenario name (default: the first, A for the demo).
    #[arg(long)]
    scenario: Option<String>,
    /// The kerb segment the pedestrians stand on, world metres: X0,Y0:X1,Y1 (default: the
    /// rig's pedestrian only).
    #[arg(long, value_parser = parse_kerb, allow_hyphen_values = true)]
    kerb: Option<[[f64; 2]; 2]>,
    /// Positions along the kerb, each at the middle of an equal piece.
    #[arg(long, default_value_t = 1)]
    positions: u32,
    /// Eye heights LOW:HIGH, metres.
    #[arg(long, value_parser = parse_range, default_value = "1.50:1.90")]
    eye_heights: [f64; 2],
    /// Eye heights over the range, each at the middle of an equal piece.
    #[arg(long, default_value_t = 5)]
    heights: u32,
    /// Pixels per degree of every observer's capture.
    #[arg(long, default_value_t = 10.0)]
    ppd: f64,
    /// Every n-th frame.
    #[arg(long, default_value_t = 3)]
    frame_step: u32,
    /// Canonical palette size, W or WxH.
    #[arg(long, value_name = "W|WxH", default_value = "1024")]
    palette_size: String,
    /// Study folder: observers.json, observers.csv, observer-parts.csv and one folder per observer.
    #[arg(long, default_value = "observers")]
    out: PathBuf,
    /// GPU backend.
    #[arg(long, value_enum, default_value_t = Backend::Auto)]
    backend: Backend,
    /// Size of the heatmap views in each observer's results, each 400×300 pixels times this (1–8):
    /// 1 draws a quarter of the pixels, for a quicker grid; the numbers do not change.
    #[arg(long, value_name = "N", default_value_t = ufcsr::DEFAULT_VIEWS_SCALE,
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

pub fn run_observers(args: ObserversArgs, console: &Console) -> anyhow::Result<()> {
    let scene = load_scene(&args.scene)?;
    let options = ufcsr_capture::ObserverOptions {
        scenario: scenario_name(&scene, args.scenario.as_deref())?,
        kerb: args.kerb,
        positions: args.positions,
        eye_heights_m: args.eye_heights,
        heights: args.heights,
        ppd: args.ppd,
        frame_step: args.frame_step,
        capture: CaptureOptions {
            out: args.out.clone(),
            palette: parse_palette_size(&args.palette_size)?,
            views_scale: args.views_scale,
            ..CaptureOptions::default()
        },
    };
    let gpu = Gpu::create(args.backend.into()).context("creating the GPU device")?;
    eprintln!("adapter: {}", gpu.describe());
    let study = ufcsr_capture::run_observer_study(&gpu.device, &gpu.queue, &scene, &options)?;
    print_observers(&study, console);
    for file in ufcsr_capture::write_observer_study(&study, &args.out)? {
        console.wrote(&file);
        say!(console, "wrote {}", file.display());
    }
    console.fact("observers", study.observers.len());
    console.fact("parts", &study.summary);
    Ok(())
}

fn print_observers(study: &ufcsr_capture::ObserverStudy, console: &Console) {
    let n = study.observers.len();
    say!(
        console,
        "scenario {}, {n} observers at {} px/°, every {} frame(s), eye heights {}–{} m, in {:.1} s ({:.2} s of \
         shared set-up, then {:.2} s per observer)",
        study.scenario,
        study.ppd,
        study.frame_step,
        study.eye_heights_m[0],
        study.eye_heights_m[1],
        study.seconds,
        study.setup_seconds,
        (study.seconds - study.setup_seconds) / n as f64
    );
    say!(
        console,
        "per part over the observers: mean [95 % interval of the mean] (2.5–97.5 % of observers); top-5 = share of \
         observers with the part among the five largest angular areas"
    );
    say!(
        console,
        "{:<24} {:>34} {:>34} {:>6}",
        "part",
        "angular area, deg²·s",
        "share of angular area, %",
        "top-5"
    );
    for part in study.summary.iter().take(15) {
        let (a, s) = (&part.angular_area_deg2_s, &part.angular_area_share_percent);
        say!(
            console,
            "{:<24} {:>34} {:>34} {:>6.2}",
            part.part,
            format!(
                "{:.3} [{:.3}–{:.3}] ({:.3}–{:.3})",
                a.mean, a.mean_ci95[0], a.mean_ci95[1], a.p2_5, a.p97_5
            ),
            format!(
                "{:.2} [{:.2}–{:.2}] ({:.2}–{:.2})",
                s.mean, s.mean_ci95[0], s.mean_ci95[1], s.p2_5, s.p97_5
            ),
            part.top5_frequency
        );
    }
    if study.summary.len() > 15 {
        say!(console, "… {} more parts in observer-parts.csv", study.summary.len() - 15);
    }
}
