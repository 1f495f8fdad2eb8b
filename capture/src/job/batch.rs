//! Batches: many scenes × scenarios × settings as independent tasks for a
//! job array (Slurm, Kubernetes Indexed Jobs, AWS Batch) or `xargs -P`.
//!
//! We plan, an existing engine schedules: [`plan`] turns a `batch.json` into
//! one shell command per task, in a fixed order, so task *i* of an array is
//! line *i* of `ufcsr batch plan batch.json` (see
//! `scripts/slurm/batch-array.sbatch`). Each task captures and counts one
//! setting with `--count` (no PNGs) into its own folder, so tasks never
//! share files.
//!
//! ```json
//! { "out": "runs", "scenes": ["demo", "fixtures/scenes/milk-truck.json"],
//!   "scenarios": ["A", "B"], "ppd": [60, 30], "frame_step": [1, 4],
//!   "dedupe": "image", "palette_size": "4096", "extra_args": [] }
//! ```
//! `scenarios` may be omitted (every scenario of each scene).

use std::path::{Path, PathBuf};

use serde::Deserialize;

use crate::error::{CaptureError, Result};
use crate::scene::Scene;

/// A batch file.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Batch {
    /// The batch file, for messages (set by [`load`]).
    #[serde(skip)]
    pub path: PathBuf,
    /// Root folder of all task outputs.
    pub out: PathBuf,
    /// `demo` or scene files (relative to the batch file).
    pub scenes: Vec<String>,
    /// Scenario names; absent: all of each scene's.
    #[serde(default)]
    pub scenarios: Option<Vec<String>>,
    #[serde(default = "default_ppd")]
    pub ppd: Vec<f64>,
    #[serde(default = "default_frame_step")]
    pub frame_step: Vec<u32>,
    #[serde(default)]
    pub dedupe: ufcsr::Dedupe,
    #[serde(default = "default_palette_size")]
    pub palette_size: String,
    /// More `ufcsr capture` arguments for every task.
    #[serde(default)]
    pub extra_args: Vec<String>,
}

fn default_ppd() -> Vec<f64> {
    vec![60.0]
}
fn default_frame_step() -> Vec<u32> {
    vec![1]
}
fn default_palette_size() -> String {
    "4096".into()
}

/// One task: its output folder and its command (arguments, program first).
#[derive(Debug, Clone, PartialEq)]
pub struct Task {
    pub out: PathBuf,
    pub args: Vec<String>,
}

impl Task {
    /// The command as one shell line (arguments quoted).
    pub fn shell_line(&self) -> String {
        self.args.iter().map(|a| shell_quote(a)).collect::<Vec<_>>().join(" ")
    }
}

fn shell_quote(text: &str) -> String {
    if !text.is_empty() && text.bytes().all(|b| b.is_ascii_alphanumeric() || b"-_./=,:+".contains(&b)) {
        text.to_string()
    } else {
        format!("'{}'", text.replace('\'', "'\\''"))
    }
}

/// Reads and checks a batch file.
pub fn load(path: &Path) -> Result<Batch> {
    let bytes = ufcsr::files::read_limited(path, 16 << 20)?;
    let mut batch: Batch = serde_json::from_slice(&bytes)
        .map_err(|e| CaptureError::bad_file(path, format!("invalid batch file: {e}")))?;
    batch.path = path.to_path_buf();
    check(&batch).map_err(|message| CaptureError::bad_file(path, message))?;
    Ok(batch)
}

/// What every task of a batch needs, checked once when planning instead of
/// failing in every task: values, the palette size, and text that keeps
/// the plan one task per line.
fn check(batch: &Batch) -> std::result::Result<(), String> {
    if batch.scenes.is_empty() || batch.ppd.is_empty() || batch.frame_step.is_empty() {
        return Err("scenes, ppd and frame_step must not be empty".into());
    }
    if batch.ppd.iter().any(|p| !(p.is_finite() && *p > 0.0)) || batch.frame_step.contains(&0) {
        return Err("ppd values must be positive and frame steps at least 1".into());
    }
    ufcsr::parse_capture_palette_size(&batch.palette_size).map_err(|e| format!("palette_size: {e}"))?;
    let out = batch.out.to_string_lossy();
    let texts = std::iter::once(("out", out.as_ref()))
        .chain(batch.scenes.iter().map(|s| ("scenes", s.as_str())))
        .chain(batch.scenarios.iter().flatten().map(|s| ("scenarios", s.as_str())))
        .chain(batch.extra_args.iter().map(|s| ("extra_args", s.as_str())));
    for (field, text) in texts {
        one_line(field, text)?;
    }
    if let Some(set) = batch.extra_args.iter().find(|a| PLANNED_OPTIONS.contains(&option_name(a))) {
        return Err(format!("extra_args: {set} is an option the plan sets for every task"));
    }
    Ok(())
}

/// The options every task's command line sets (as `extra_args` must not).
const PLANNED_OPTIONS: [&str; 9] =
    ["--scenario", "--ppd", "--frames", "--palette-size", "--count", "--dedupe", "--quiet", "-q", "--out"];

/// `--out=x` → `--out`.
fn option_name(arg: &str) -> &str {
    arg.split_once('=').map_or(arg, |(name, _)| name)
}

/// An error when `text` has a control character: a newline would split a
/// task over two plan lines, and task i must be line i.
fn one_line(field: &str, text: &str) -> std::result::Result<(), String> {
    match text.chars().find(|c| c.is_control()) {
        Some(c) => {
            Err(format!("{field}: {text:?} has a control character ({c:?}): the plan is one task per line"))
        }
        None => Ok(()),
    }
}

/// The tasks of a batch, in order: scene, scenario, ppd, frame step.
/// `program` is the `ufcsr` to call (each task is `PROGRAM capture …`); scene files are resolved
/// against `base` (the batch file's folder) and their scenarios read. An
/// error names the batch file and the scene; two tasks writing into one
/// folder are an error too.
pub fn plan(batch: &Batch, base: &Path, program: &str) -> Result<Vec<Task>> {
    let in_batch = |message: String| CaptureError::bad_file(&batch.path, message);
    check(batch).and_then(|()| one_line("program", program)).map_err(in_batch)?;
    let mut tasks: Vec<Task> = Vec::new();
    for (scene_index, scene_name) in batch.scenes.iter().enumerate() {
        let in_scene = |e: CaptureError| in_batch(format!("scenes[{scene_index}] {scene_name:?}: {e}"));
        let (scene, scene_args) = if scene_name == "demo" {
            (Scene::demo(), vec!["capture".to_string(), "demo".to_string()])
        } else {
            let path = base.join(scene_name);
            (
                Scene::load(&path).map_err(in_scene)?,
                vec!["capture".into(), "scene".into(), path.display().to_string()],
            )
        };
        let scenarios: Vec<String> = match &batch.scenarios {
            Some(names) => names
                .iter()
                .map(|n| scene.scenario(n).map(|s| s.name.clone()))
                .collect::<Result<_>>()
                .map_err(in_scene)?,
            None => scene.scenarios.iter().map(|s| s.name.clone()).collect(),
        };
        let scene_label = format!(
            "{scene_index}-{}",
            Path::new(scene_name).file_stem().map_or("scene".into(), |s| s.to_string_lossy().into_owned())
        );
        for scenario in &scenarios {
            for &ppd in &batch.ppd {
                let mut rig = scene.rig.clone();
                rig.set_pixels_per_degree(ppd).map_err(in_scene)?;
                scene.scenario(scenario)?;
                for &step in &batch.frame_step {
                    let out =
                        batch.out.join(&scene_label).join(scenario).join(format!("ppd{ppd}-step{step}"));
                    if let Some(earlier) = tasks.iter().position(|task| task.out == out) {
                        return Err(in_batch(format!(
                            "tasks {earlier} and {} would both write into {} (a ppd, frame step or scenario \
                             given twice)",
                            tasks.len(),
                            out.display()
                        )));
                    }
                    let setting = Setting { scenario, ppd, step };
                    let args = task_args(batch, program, &scene_args, &setting, &out);
                    tasks.push(Task { out, args });
                }
            }
        }
    }
    Ok(tasks)
}

/// One task's scenario, resolution and frames.
struct Setting<'a> {
    scenario: &'a str,
    ppd: f64,
    step: u32,
}

/// A task's command line, program first.
fn task_args(
    batch: &Batch,
    program: &str,
    scene_args: &[String],
    setting: &Setting,
    out: &Path,
) -> Vec<String> {
    let mut args = vec![program.to_string()];
    args.extend(scene_args.iter().cloned());
    args.extend([
        "--scenario".into(),
        setting.scenario.to_string(),
        "--ppd".into(),
        setting.ppd.to_string(),
        "--frames".into(),
        // Every step-th frame as `capture` keeps them for the scenario's length.
        format!("all/{}", setting.step),
        "--palette-size".into(),
        batch.palette_size.clone(),
        "--count".into(),
        "--dedupe".into(),
        batch.dedupe.name().to_string(),
        "--quiet".into(),
        "--out".into(),
        out.display().to_string(),
    ]);
    args.extend(batch.extra_args.iter().cloned());
    args
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_batch_plans_one_command_per_setting_in_a_fixed_order() {
        let batch: Batch = serde_json::from_str(
            r#"{"out": "runs", "scenes": ["demo"], "scenarios": ["A", "C"], "ppd": [60, 10], "frame_step": [1, 4]}"#,
        )
        .unwrap();
        let tasks = plan(&batch, Path::new("."), "ufcsr").unwrap();
        assert_eq!(tasks.len(), 8);
        assert_eq!(tasks[0].out, PathBuf::from("runs/0-demo/A/ppd60-step1"));
        assert_eq!(tasks[7].out, PathBuf::from("runs/0-demo/C/ppd10-step4"));
        let line = tasks[1].shell_line();
        assert!(line.starts_with("ufcsr capture demo --scenario A --ppd 60 --frames all/4"), "{line}");
        assert!(line.contains("--count") && line.ends_with("--out runs/0-demo/A/ppd60-step4"), "{line}");
        assert_eq!(shell_quote("it's"), "'it'\\''s'");
        let unknown: std::result::Result<Batch, _> =
            serde_json::from_str(r#"{"out": "x", "scenes": [], "ppm": 3}"#);
        assert!(unknown.is_err());
        let missing = Batch { scenarios: Some(vec!["Z".into()]), ..batch };
        assert!(plan(&missing, Path::new("."), "ufcsr").is_err());
    }
}
