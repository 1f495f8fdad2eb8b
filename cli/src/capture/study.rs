//! `ufcsr study` (`ufcsr study`): its arguments and [`run_study`], which runs the
//! library's resolution study and prints its table.

use std::path::PathBuf;

use anyhow::Context;
use clap::Args;
use ufcsr_capture::{CaptureOptions, Gpu, Scene, parse_capture_palette_size};

use super::captures::parse_fraction;
use crate::choices::{Backend, Dedupe, StudyMeasure};

use crate::console::{Console, say};

/// A resolution study (see `ufcsr_capture::run_study`).
#[derive(Args)]
pub(crate) struct StudyArgs {
    #[command(flatten)]
    scene: super::source::SourceArgs,
    /// Scenario name (default: the first, A for the demo).
    #[arg(long)]
    scenario: Option<String>,
    /// Pixels per degree to try; the highest is the precision reference.
    #[arg(long, value_delimiter = ',', default_value = "60,40,30,20,15,10,6")]
    ppd: Vec<f64>,
    /// Every n-th frame to try; the smallest is the precision reference.
    #[arg(long, value_delimiter = ',', default_value = "1,2,4,6,10")]
    frame_step: Vec<u32>,
    /// Largest acceptable share L1 error against the exact measure of every frame (the upper end
    /// of its 95 % interval over frame offsets), percentage points.
    #[arg(long, default_value_t = 1.0)]
    tolerance: f64,
    /// What is studied: angular-area (solid angle of the pixels ↔ ray-traced solid angle) or
    /// count (texels seen per eye-frame ↔ any-part visibility).
    #[arg(long, value_enum, default_value_t = StudyMeasure::AngularArea)]
    measure: StudyMeasure,
    /// What one count of the settings' results means: frame (once per eye-frame, the default
    /// here, because the exact measure it is compared with counts so), image (once per tile, the
    /// default of `analyze` and `capture --count`, the paper's count) or eye-pair (once per
    /// frame over both eyes).
    #[arg(long, value_enum, default_value_t = Dedupe::Frame)]
    dedupe: Dedupe,
    /// Canonical palette size, W or WxH; above 2^24 texels (up to 8192x8192) as `capture` draws
    /// and counts them (32-bit texel ids).
    #[arg(long, value_name = "W|WxH", default_value = "4096")]
    palette_size: String,
    /// Study folder: study.csv, study.json, study.svg/.png and one folder per setting.
    #[arg(long, default_value = "study")]
    out: PathBuf,
    /// GPU backend.
    #[arg(long, value_enum, default_value_t = Backend::Auto)]
    backend: Backend,
    /// Size of the heatmap views in each setting's results, each 400×300 pixels times this (1–8):
    /// 1 draws a quarter of the pixels, for a quicker study; the numbers do not change.
    #[arg(long, value_name = "N", default_value_t = ufcsr::output::DEFAULT_VIEWS_SCALE,
          value_parser = clap::value_parser!(u32).range(1..=8))]
    views_scale: u32,
    /// Measure the exact reference (on every frame) on this share of the texels, e.g. 1/16
    /// (default: all); its sampling error widens every interval.
    #[arg(long, value_name = "FRACTION", conflicts_with = "no_exact")]
    exact_sample: Option<String>,
    /// Skip the exact reference: compare with the finest setting only (precision).
    #[arg(long)]
    no_exact: bool,
}

/// The scenario asked for, or the scene's first.
pub(crate) fn scenario_name(scene: &Scene, asked: Option<&str>) -> anyhow::Result<String> {
    Ok(match asked {
        Some(name) => scene.scenario(name)?.name.clone(),
        None => scene.scenarios.first().map(|s| s.name.clone()).context("the scene has no scenario")?,
    })
}

pub(crate) fn run_study(args: StudyArgs, console: &Console) -> anyhow::Result<()> {
    let scene = args.scene.source()?.scene()?;
    scene.refuse_fleet("`ufcsr study`")?;
    let options = ufcsr_capture::study::StudyOptions {
        scenario: scenario_name(&scene, args.scenario.as_deref())?,
        ppds: args.ppd,
        frame_steps: args.frame_step,
        tolerance_pp: args.tolerance,
        dedupe: args.dedupe.into(),
        measure: args.measure.into(),
        capture: CaptureOptions {
            out: args.out.clone(),
            palette: parse_capture_palette_size(&args.palette_size)?,
            views_scale: args.views_scale,
            ..CaptureOptions::default()
        },
        exact_sample: match (args.no_exact, args.exact_sample.as_deref()) {
            (true, _) => None,
            (false, None) => Some(1.0),
            (false, Some(text)) => Some(parse_fraction(text)?),
        },
    };
    let gpu = Gpu::create(args.backend.into()).context("creating the GPU device")?;
    eprintln!("adapter: {}", gpu.describe());
    let study = ufcsr_capture::run_study(&gpu.device, &gpu.queue, &scene, &options)?;
    print_study(&study, console);
    // Each setting's archive (and the exact reference's) is this run's whole.
    let archives = study.rows.iter().map(|row| &row.results).chain(study.exact.as_ref().map(|e| &e.results));
    crate::capture::captures::record_archives_of(archives, console);
    for file in ufcsr_capture::study::write_study(&study, &args.out)? {
        console.wrote(&file);
        say!(console, "wrote {}", file.display());
    }
    console.fact("recommended", &study.recommended);
    console.fact("closest", &study.closest);
    Ok(())
}

fn print_study(study: &ufcsr_capture::study::Study, console: &Console) {
    say!(
        console,
        "scenario {}, measure {}: error = share L1 (pp) of the setting against the exact measure of every \
         frame; 95 % = over the step's frame offsets; step pp = the frame step alone (at offset 0 and \
         over offsets); precision = against the finest setting ({}); Mpixels = pixels rendered, the cost the pick and \
         the front (*) rank by (seconds are measured, reported only)",
        study.scenario,
        study.measure,
        study.reference
    );
    if let Some(exact) = &study.exact {
        say!(
            console,
            "exact reference: {} of {} texels (sample {}), {} eye-frames, {:.1} s",
            exact.sampled_texels,
            exact.labelled_texels,
            exact.sample,
            exact.eye_frames,
            exact.seconds
        );
    }
    say!(
        console,
        "set-up shared by the settings (unwrap, PIdT, archive files, renderer): {:.2} s, once; \
         seconds below are each setting's own",
        study.setup_seconds
    );
    say!(
        console,
        "{:>6} {:>5} {:>6} {:>9} {:>10} {:>10} {:>17} {:>7} {:>5} {:>10} {:>15} {:>12} {:>6}",
        "ppd",
        "step",
        "frames",
        "seconds",
        "Mpixels",
        "error pp",
        "95 % pp",
        "tau",
        "top5",
        "step pp",
        "step range pp",
        "precision pp",
        "pareto"
    );
    for row in &study.rows {
        let exact = row.error_vs_exact.as_ref();
        say!(
            console,
            "{:>6} {:>5} {:>6} {:>9.2} {:>10.2} {:>10} {:>17} {:>7} {:>5} {:>10} {:>15} {:>12.3} {:>6}",
            row.ppd,
            row.frame_step,
            row.frames,
            row.seconds,
            row.pixels_rendered as f64 / 1e6,
            exact.map_or("-".into(), |e| format!("{:.3}", e.error.share_l1_pp)),
            exact.map_or("-".into(), |e| format!("{:.3}–{:.3}", e.ci95_pp[0], e.ci95_pp[1])),
            exact.map_or("-".into(), |e| format!("{:.3}", e.error.kendall_tau_b)),
            exact.map_or("-".into(), |e| e.error.top5_overlap.to_string()),
            exact.map_or("-".into(), |e| format!("{:.3}", e.frame_step_pp)),
            exact.map_or("-".into(), |e| format!(
                "{:.3}–{:.3}",
                e.frame_step_range_pp[0], e.frame_step_range_pp[1]
            )),
            row.precision.share_l1_pp,
            if row.pareto { "*" } else { "" },
        );
    }
    print_pick(study, console);
}

/// The recommendation, or why there is none.
fn print_pick(study: &ufcsr_capture::study::Study, console: &Console) {
    match (&study.recommended, &study.reason) {
        (Some(pick), _) => say!(
            console,
            "recommended (fewest pixels rendered within {} pp of the {}): {} ({:.2} Mpixels, {:.2} s, share \
             L1 {:.3} pp{})",
            study.tolerance_pp,
            if pick.against == "exact" { "exact measure at 95 %" } else { "finest setting" },
            pick.setting,
            pick.pixels_rendered as f64 / 1e6,
            pick.seconds,
            pick.share_l1_pp,
            pick.ci95_pp.map_or(String::new(), |[lo, hi]| format!(", 95 % {lo:.3}–{hi:.3}"))
        ),
        (None, Some(reason)) => say!(console, "{reason}"),
        (None, None) => say!(console, "no recommendation"),
    }
}

#[cfg(test)]
mod tests {
    use crate::program::Program;

    /// `--dedupe`'s default and help under `path` (e.g. `["capture", "demo"]`).
    fn dedupe(path: &[&str]) -> (String, String) {
        let mut command = Program::Ufcsr.command_all();
        command.build();
        let mut command = &command;
        for name in path {
            command = command.find_subcommand(name).unwrap_or_else(|| panic!("no command {name}"));
        }
        let arg = command.get_arguments().find(|arg| arg.get_long() == Some("dedupe")).expect("--dedupe");
        let default = arg.get_default_values().iter().map(|v| v.to_string_lossy().into_owned()).collect();
        (default, arg.get_help().map(ToString::to_string).unwrap_or_default())
    }

    /// Issue 45 §4: `--dedupe` has one default where a result is the paper's count (`analyze`,
    /// `capture --count`: image) and another where it is compared with the exact measure
    /// (`study`: frame), and each help says both and why.
    #[test]
    fn dedupe_defaults_to_image_for_counts_and_frame_for_the_study_and_each_help_says_so() {
        for (path, default) in
            [(&["analyze"][..], "image"), (&["capture", "demo"], "image"), (&["study"], "frame")]
        {
            let (found, help) = dedupe(path);
            assert_eq!(found, default, "{path:?}");
            assert!(help.contains("`study`") || path == ["study"], "{path:?}: {help}");
            assert!(help.contains("exact measure"), "{path:?} does not say why study differs: {help}");
            assert!(help.contains("paper's count"), "{path:?}: {help}");
        }
    }
}
