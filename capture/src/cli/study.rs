//! `ufcsr-capture study`: its arguments and [`run_study`], which runs the
//! library's resolution study and prints its table.

use std::path::PathBuf;

use anyhow::Context;
use clap::Args;
use ufcsr_capture::{Backend, CaptureOptions, Gpu, Scene, parse_palette_size};

use super::capture::parse_fraction;

/// A resolution study (see `ufcsr_capture::run_study`).
#[derive(Args)]
pub struct StudyArgs {
    /// `demo`, or a scene JSON file.
    scene: String,
    /// Scenario name (default: the first, A for the demo).
    #[arg(long)]
    scenario: Option<String>,
    /// Pixels per degree to try; the highest is the reference.
    #[arg(long, value_delimiter = ',', default_value = "60,40,30,20,15,10,6")]
    ppd: Vec<f64>,
    /// Every n-th frame to try; the smallest is the reference.
    #[arg(long, value_delimiter = ',', default_value = "1,2,4,6,10")]
    frame_step: Vec<u32>,
    /// Largest acceptable share L1 error against the reference, percentage points.
    #[arg(long, default_value_t = 1.0)]
    tolerance: f64,
    /// What one count means: image (once per tile), frame (once per eye-frame) or eye-pair
    /// (once per frame over both eyes).
    #[arg(long, value_enum, default_value_t = ufcsr::Dedupe::Image)]
    dedupe: ufcsr::Dedupe,
    /// Canonical palette size, W or WxH.
    #[arg(long, default_value = "4096")]
    palette_size: String,
    /// Study folder: study.csv, study.json, study.svg/.png and one folder per setting.
    #[arg(long, default_value = "study")]
    out: PathBuf,
    /// GPU backend.
    #[arg(long, value_enum, default_value_t = Backend::Auto)]
    backend: Backend,
    /// Also compare every setting with the exact unobstructed measure of this share of the
    /// texels, e.g. 1/64 (see --measure unobstructed).
    #[arg(long, value_name = "FRACTION")]
    unobstructed_sample: Option<String>,
}

pub fn run_study(args: StudyArgs) -> anyhow::Result<()> {
    let scene =
        if args.scene == "demo" { Scene::demo() } else { Scene::load(std::path::Path::new(&args.scene))? };
    let scenario = match &args.scenario {
        Some(name) => scene.scenario(name)?.name.clone(),
        None => scene.scenarios.first().map(|s| s.name.clone()).context("the scene has no scenario")?,
    };
    let options = ufcsr_capture::StudyOptions {
        scenario,
        ppds: args.ppd,
        frame_steps: args.frame_step,
        tolerance_pp: args.tolerance,
        dedupe: args.dedupe,
        capture: CaptureOptions {
            out: args.out.clone(),
            palette: parse_palette_size(&args.palette_size)?,
            ..CaptureOptions::default()
        },
        unobstructed_sample: args.unobstructed_sample.as_deref().map(parse_fraction).transpose()?,
    };
    let gpu = Gpu::create(args.backend).context("creating the GPU device")?;
    eprintln!("adapter: {}", gpu.describe());
    let study = ufcsr_capture::run_study(&gpu.device, &gpu.queue, &scene, &options)?;
    println!("scenario {}: reference {}", study.scenario, study.reference);
    println!(
        "{:>6} {:>5} {:>6} {:>9} {:>9} {:>9} {:>7} {:>5} {:>6} {:>12} {:>9}",
        "ppd",
        "step",
        "frames",
        "seconds",
        "L1 pp",
        "max pp",
        "tau",
        "top5",
        "pareto",
        "L1 vs exact",
        "tau exact"
    );
    for row in &study.rows {
        let e = &row.error;
        let exact = row.error_vs_unobstructed.as_ref();
        println!(
            "{:>6} {:>5} {:>6} {:>9.2} {:>9.3} {:>9.3} {:>7.3} {:>5} {:>6} {:>12} {:>9}",
            row.ppd,
            row.frame_step,
            row.frames,
            row.seconds,
            e.share_l1_pp,
            e.share_max_pp,
            e.kendall_tau_total,
            e.top_k_overlap,
            if row.pareto { "*" } else { "" },
            exact.map_or("-".into(), |u| format!("{:.3}", u.share_l1_pp)),
            exact.map_or("-".into(), |u| format!("{:.3}", u.kendall_tau_total)),
        );
    }
    match study.cheapest_within_tolerance {
        Some(index) => {
            let row = &study.rows[index];
            println!(
                "cheapest within {} pp: {} ({:.2} s, share L1 {:.3} pp)",
                study.tolerance_pp,
                row.label(),
                row.seconds,
                row.error.share_l1_pp
            );
        }
        None => println!("no setting is within {} pp of the reference", study.tolerance_pp),
    }
    for file in ufcsr_capture::write_study(&study, &args.out)? {
        println!("wrote {}", file.display());
    }
    Ok(())
}
