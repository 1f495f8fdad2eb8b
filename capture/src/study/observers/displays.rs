//! Per display over the observers: the legible seconds of every candidate
//! display patch (and every part), the measure the placement answer ranks
//! by, summarised exactly as the parts' angular areas are.
//!
//! The observers' rendered captures name parts only; display patches exist
//! only in the exact measure (`docs/placement.md`). So with a display size
//! ([`DisplayOptions`], `observers --display WxH`) each observer of the study
//! (the same draws, [`sample_observers`]) is also measured exactly with
//! placement candidates, on the CPU, at the study's frame step, and every
//! candidate's legible seconds are scored under the placement answer's
//! default rule ([`ufcsr::placement::Thresholds::default`]). Without a display size the
//! study reports no displays: there is nothing to measure them with.
//!
//! What the numbers cover, as for parts ([`super::interval`]):
//! * the 95 % interval of the population mean (Student t over independently
//!   drawn observers; none on a grid) covers the sampling of observers;
//! * each observer's *resolution* error is the frame step's: with the
//!   coarser check a second exact measure at twice the frame step (the same
//!   texel sample) gives a bound of safety factor × |difference|, whose mean
//!   widens the interval on both sides (the exact measure has no ppd);
//! * with a texel sample (`--display-sample` below 1) every observer draws
//!   its own texels (seed = observer index + 1). The patch layout does not
//!   depend on the sample (it follows the mesh), so the candidates are the
//!   same for everyone, and the sample's noise is one more independent part
//!   of each observer's value: the Monte Carlo interval covers it, and the
//!   2.5–97.5 % spread includes it (it is then not people alone).
//!
//! A candidate an observer's table does not list (never seen) counts 0 s
//! for that observer; candidates no observer ever sees are not listed.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

use ufcsr::{
    format::DisplayOverObservers, format::ObserverDisplayRecord, format::ObserverDisplays,
    format::ObserverSampling, format::ResolutionCheck, placement::Thresholds,
};

use super::interval::IntervalKind;
use super::population::sample_observers;
use super::{Measure, ObserverOptions, coarser_step, interval_kind, observer_scene};
use crate::error::{CaptureError, Result};
use crate::exact::{MeasureOptions, PlacementCandidates, measure_unobstructed};
use crate::job::{CaptureOptions, FrameSelection};
use crate::scene::Scene;

/// The file [`write_display_study`] writes (one row per candidate).
pub const OBSERVER_DISPLAYS_FILE: &str = "observer-displays.csv";

/// Which displays to measure for every observer.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DisplayOptions {
    /// Width × height, metres.
    pub display_m: [f64; 2],
    /// Spacing of the patch centres, metres.
    pub spacing_m: f64,
    /// Share of the texels each observer's exact measure samples, in (0, 1].
    pub sample: f64,
}

impl DisplayOptions {
    /// Refuses a sample outside (0, 1] or a spacing under 1 cm, naming the option.
    pub fn check(&self) -> Result<()> {
        if !(self.sample > 0.0 && self.sample <= 1.0) {
            return Err(CaptureError::BadOptions(format!(
                "--display-sample must be in (0, 1], not {}",
                self.sample
            )));
        }
        PlacementCandidates { display_m: Some(self.display_m), spacing_m: self.spacing_m }.check()
    }
}

/// One observer's legible seconds per candidate, and at twice the frame step.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ObserverLegible {
    pub fine: BTreeMap<String, f64>,
    pub coarse: Option<BTreeMap<String, f64>>,
}

/// The displays of an observer study.
#[derive(Debug, Clone, PartialEq)]
pub struct DisplayStudy {
    pub options: DisplayOptions,
    /// What the intervals are, in one sentence.
    pub interval: String,
    /// Per observer (in the study's order).
    pub observers: Vec<ObserverLegible>,
    /// Largest mean legible time first.
    pub summary: Vec<DisplayOverObservers>,
    /// Candidates no answer may hold, and why (the placement's one rule, [`ufcsr::placement::exclusions`]).
    pub excluded: Vec<ufcsr::format::ExcludedRecord>,
    pub seconds: f64,
}

impl DisplayStudy {
    /// The study as `observers.json` carries it (its `displays`).
    pub fn record(&self) -> ObserverDisplays {
        ObserverDisplays {
            display_m: self.options.display_m,
            spacing_m: self.options.spacing_m,
            sample: self.options.sample,
            interval: self.interval.clone(),
            observers: self
                .observers
                .iter()
                .map(|o| ObserverDisplayRecord {
                    legible_s: o.fine.clone(),
                    coarser_legible_s: o.coarse.clone(),
                })
                .collect(),
            summary: self.summary.clone(),
            excluded: self.excluded.clone(),
            seconds: self.seconds,
        }
    }
}

/// Legible seconds and kind of every candidate in a placement table.
fn legible_seconds(table: ufcsr::placement::PlacementTable) -> BTreeMap<String, (String, f64)> {
    let table = Arc::new(table);
    let scored = ufcsr::placement::timelines(table.clone(), &Thresholds::default());
    scored
        .timelines
        .iter()
        .map(|t| (t.name.clone(), (t.kind.name().to_string(), t.legible.len() as f64 * table.frame_s)))
        .collect()
}

/// The exact measure with placement candidates of `scene` every `step`-th frame into `out`.
fn measure_candidates(
    (device, queue): (&wgpu::Device, &wgpu::Queue),
    scene: &Scene,
    (options, displays): (&ObserverOptions, &DisplayOptions),
    (out, step, seed): (&Path, u32, u64),
) -> Result<BTreeMap<String, (String, f64)>> {
    let scenario = scene.scenario(&options.scenario)?.clone();
    let capture = CaptureOptions {
        out: out.to_path_buf(),
        frames: FrameSelection::every(step),
        ..options.capture.clone()
    };
    let measure = MeasureOptions {
        sample: displays.sample,
        seed,
        placement: Some(PlacementCandidates {
            display_m: Some(displays.display_m),
            spacing_m: displays.spacing_m,
        }),
        ..MeasureOptions::default()
    };
    let measured = measure_unobstructed(device, queue, scene, &scenario, &capture, &measure)?;
    let written = measured.placement.ok_or_else(|| CaptureError::BadOptions("no placement table".into()))?;
    Ok(legible_seconds(ufcsr::placement::read_table(&written.csv)?))
}

/// Measures every observer of the study `options` describes (the same
/// draws as [`super::run_observer_study`]) for the candidate displays and
/// summarises their legible seconds. Each observer's measures go into
/// `observer-NNN/displays` (and `displays-coarser`) of the study folder.
pub fn run_observer_displays(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    scene: &Scene,
    options: &ObserverOptions,
    displays: &DisplayOptions,
) -> Result<DisplayStudy> {
    super::check(options, scene)?;
    displays.check()?;
    crate::job::overwrite_guard::refuse_overwriting_inputs(
        &options.capture.out,
        &[OBSERVER_DISPLAYS_FILE],
        &[],
        &crate::job::capture_inputs(scene, &options.capture),
    )?;
    let start = Instant::now();
    let sampled = sample_observers(&options.population, &options.sampling, scene.rig.anchor().to_array())?;
    let mut kinds = BTreeMap::new();
    let mut observers = Vec::with_capacity(sampled.len());
    for (index, observer) in sampled.iter().enumerate() {
        let dir =
            ufcsr::files::output_sub_dir(&options.capture.out, Path::new(&format!("observer-{index:03}")))?;
        let observer_scene = observer_scene(scene, options, observer, options.ppd)?;
        let seed = if displays.sample < 1.0 { index as u64 + 1 } else { 1 };
        let gpu = (device, queue);
        let step = options.frame_step;
        let fine = measure_candidates(
            gpu,
            &observer_scene,
            (options, displays),
            (&dir.join("displays"), step, seed),
        )?;
        let coarse = match options.resolution_check {
            ResolutionCheck::None => None,
            ResolutionCheck::Coarser { .. } => {
                let frames = observer_scene.rig.frame_count(scene.scenario(&options.scenario)?.duration_s);
                let coarse_out = dir.join("displays-coarser");
                let step = coarser_step(step, frames);
                Some(measure_candidates(
                    gpu,
                    &observer_scene,
                    (options, displays),
                    (&coarse_out, step, seed),
                )?)
            }
        };
        let seconds = |table: BTreeMap<String, (String, f64)>, kinds: &mut BTreeMap<String, String>| {
            table
                .into_iter()
                .map(|(name, (kind, s))| {
                    kinds.entry(name.clone()).or_insert(kind);
                    (name, s)
                })
                .collect::<BTreeMap<String, f64>>()
        };
        let fine = seconds(fine, &mut kinds);
        let coarse = coarse.map(|c| c.into_iter().map(|(name, (_, s))| (name, s)).collect());
        eprintln!("observers: displays {}/{} measured", index + 1, sampled.len());
        observers.push(ObserverLegible { fine, coarse });
    }
    let summary =
        summarize_displays(&kinds, &observers, interval_kind(&options.sampling), options.resolution_check);
    Ok(DisplayStudy {
        options: *displays,
        interval: interval_sentence(&options.sampling, options.resolution_check),
        observers,
        excluded: ufcsr::placement::default_exclusions(kinds.iter().map(|(n, k)| (n.as_str(), k.as_str()))),
        summary,
        seconds: start.elapsed().as_secs_f64(),
    })
}

/// What the display intervals are, in one sentence.
fn interval_sentence(sampling: &ObserverSampling, check: ResolutionCheck) -> String {
    let resolution = match check {
        ResolutionCheck::None => "the observers' frame-step error is NOT included".to_string(),
        ResolutionCheck::Coarser { safety_factor } => format!(
            "widened by the mean of the observers' frame-step bounds ({safety_factor} × |legible s − legible s at \
             twice the frame step|, exact measure)"
        ),
    };
    match sampling {
        ObserverSampling::Random { .. } => format!(
            "legible seconds under the placement answer's default rule; 95 % interval of the population mean: \
             mean ± t(0.975, n−1)·s/√n over independently drawn observers (and their texel samples), {resolution}"
        ),
        ObserverSampling::Grid { .. } => {
            format!(
                "legible seconds on a grid of observers: no interval is claimed for its mean ({resolution})"
            )
        }
    }
}

/// Per candidate (`kinds`: name → part/patch) over the observers, largest
/// mean legible time first: the parts' path ([`Measure`]) with a candidate
/// an observer never saw at 0 s.
pub fn summarize_displays(
    kinds: &BTreeMap<String, String>,
    observers: &[ObserverLegible],
    kind: IntervalKind,
    check: ResolutionCheck,
) -> Vec<DisplayOverObservers> {
    let row = |values: &BTreeMap<String, f64>| -> Vec<f64> {
        kinds.keys().map(|name| values.get(name).copied().unwrap_or(0.0)).collect()
    };
    let fine: Vec<Vec<f64>> = observers.iter().map(|o| row(&o.fine)).collect();
    let coarse: Vec<Option<Vec<f64>>> = observers.iter().map(|o| o.coarse.as_ref().map(row)).collect();
    let measure = Measure::from_rows(fine, &coarse, check);
    let mut summary: Vec<DisplayOverObservers> = kinds
        .iter()
        .enumerate()
        .map(|(i, (name, kind_name))| DisplayOverObservers {
            candidate: name.clone(),
            kind: kind_name.clone(),
            legible_s: measure.at(i, kind),
        })
        .collect();
    summary.sort_by(|a, b| b.legible_s.mean.total_cmp(&a.legible_s.mean).then(a.candidate.cmp(&b.candidate)));
    summary
}

/// Writes `observer-displays.csv` into `dir`: per candidate its kind and the
/// legible seconds' mean, interval (empty on a grid), Monte Carlo
/// half-width, resolution bound and spread.
pub fn write_display_study(study: &DisplayStudy, dir: &Path) -> Result<PathBuf> {
    ufcsr::files::create_output_dir(dir)?;
    let mut table = String::from(
        "candidate,kind,legible_s_mean,legible_s_ci95_low,legible_s_ci95_high,legible_s_monte_carlo_half_width,\
         legible_s_resolution_bound,legible_s_p2_5,legible_s_p97_5\n",
    );
    for s in &study.summary {
        let v = &s.legible_s;
        let row = [
            ufcsr::output::csv_field(&s.candidate),
            s.kind.clone(),
            super::cell(Some(v.mean)),
            super::cell(v.mean_ci95.map(|c| c[0])),
            super::cell(v.mean_ci95.map(|c| c[1])),
            super::cell(v.monte_carlo_half_width),
            super::cell(v.resolution_bound),
            super::cell(Some(v.p2_5)),
            super::cell(Some(v.p97_5)),
        ];
        table.push_str(&(row.join(",") + "\n"));
    }
    let path = dir.join(OBSERVER_DISPLAYS_FILE);
    ufcsr::files::write_bytes_atomically(&path, table.as_bytes())?;
    Ok(path)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn legible(fine: &[(&str, f64)], coarse: Option<&[(&str, f64)]>) -> ObserverLegible {
        let map = |v: &[(&str, f64)]| v.iter().map(|(n, s)| (n.to_string(), *s)).collect();
        ObserverLegible { fine: map(fine), coarse: coarse.map(map) }
    }

    #[test]
    fn a_display_an_observer_never_saw_counts_zero_and_its_bound_is_the_coarser_difference() {
        let kinds: BTreeMap<String, String> = [("hood", "part"), ("hood@0.40x0.15@x1.00y0.05z1.20", "patch")]
            .map(|(a, b)| (a.into(), b.into()))
            .into();
        let patch = "hood@0.40x0.15@x1.00y0.05z1.20";
        let a = legible(&[("hood", 3.0), (patch, 2.0)], Some(&[("hood", 3.0), (patch, 1.6)]));
        let b = legible(&[("hood", 1.0)], Some(&[("hood", 1.0)]));
        let check = ResolutionCheck::Coarser { safety_factor: 3.0 };
        let summary = summarize_displays(&kinds, &[a, b], IntervalKind::MonteCarlo, check);
        assert_eq!(summary[0].candidate, "hood");
        let patch = summary.iter().find(|s| s.kind == "patch").unwrap().legible_s;
        // Values 2 and 0 (never seen): mean 1; bounds 3 × 0.4 and 0: mean 0.6.
        assert!((patch.mean - 1.0).abs() < 1e-12);
        assert!((patch.resolution_bound.unwrap() - 0.6).abs() < 1e-12);
        let [low, high] = patch.mean_ci95.unwrap();
        // t(0.975, 1) · s / √2 = 12.706 × 1; the low end cut at 0.
        assert!((high - 1.0 - 12.706 - 0.6).abs() < 1e-9 && low == 0.0, "{low} {high}");
    }
}
