//! Batches: many scenes × scenarios × settings as independent tasks for a
//! job array (Slurm, Kubernetes Indexed Jobs, AWS Batch) or `xargs -P`.
//!
//! We plan, an existing engine schedules: [`plan`] turns a `batch.json` into
//! one shell command per task, in a fixed order, so task *i* of an array is
//! line *i* of `ufcsr-capture batch plan batch.json` (see
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
    #[serde(default = "default_dedupe")]
    pub dedupe: String,
    #[serde(default = "default_palette_size")]
    pub palette_size: String,
    /// More `ufcsr-capture` arguments for every task.
    #[serde(default)]
    pub extra_args: Vec<String>,
}

fn default_ppd() -> Vec<f64> {
    vec![60.0]
}
fn default_frame_step() -> Vec<u32> {
    vec![1]
}
fn default_dedupe() -> String {
    "image".into()
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
    let bytes = ufcsr::read_limited(path, 16 << 20)?;
    let batch: Batch = serde_json::from_slice(&bytes)
        .map_err(|e| CaptureError::bad_input(path, format!("invalid batch file: {e}")))?;
    if batch.scenes.is_empty() || batch.ppd.is_empty() || batch.frame_step.is_empty() {
        return Err(CaptureError::bad_input(path, "scenes, ppd and frame_step must not be empty"));
    }
    if batch.ppd.iter().any(|p| !(p.is_finite() && *p > 0.0)) || batch.frame_step.contains(&0) {
        return Err(CaptureError::bad_input(path, "ppd values must be positive and frame steps at least 1"));
    }
    Ok(batch)
}

/// The tasks of a batch, in order: scene, scenario, ppd, frame step.
/// `program` is the `ufcsr-capture` to call; scene files are resolved
/// against `base` (the batch file's folder) and their scenarios read.
pub fn plan(batch: &Batch, base: &Path, program: &str) -> Result<Vec<Task>> {
    let mut tasks = Vec::new();
    for (scene_index, scene_name) in batch.scenes.iter().enumerate() {
        let (scene, scene_args) = if scene_name == "demo" {
            (Scene::demo(), vec!["demo".to_string()])
        } else {
            let path = base.join(scene_name);
            (Scene::load(&path)?, vec!["scene".to_string(), path.display().to_string()])
        };
        let scenarios: Vec<String> = match &batch.scenarios {
            Some(names) => {
                names.iter().map(|n| scene.scenario(n).map(|s| s.name.clone())).collect::<Result<_>>()?
            }
            None => scene.scenarios.iter().map(|s| s.name.clone()).collect(),
        };
        let scene_label = format!(
            "{scene_index}-{}",
            Path::new(scene_name).file_stem().map_or("scene".into(), |s| s.to_string_lossy().into_owned())
        );
        for scenario in &scenarios {
            for &ppd in &batch.ppd {
                let mut rig = scene.rig.clone();
                rig.set_pixels_per_degree(ppd)?;
                let last = rig.frame_count(scene.scenario(scenario)?.duration_s).saturating_sub(1);
                for &step in &batch.frame_step {
                    let out =
                        batch.out.join(&scene_label).join(scenario).join(format!("ppd{ppd}-step{step}"));
                    let mut args = vec![program.to_string()];
                    args.extend(scene_args.iter().cloned());
                    args.extend([
                        "--scenario".into(),
                        scenario.clone(),
                        "--ppd".into(),
                        ppd.to_string(),
                        "--frames".into(),
                        format!("0-{last}/{step}"),
                        "--palette-size".into(),
                        batch.palette_size.clone(),
                        "--count".into(),
                        "--dedupe".into(),
                        batch.dedupe.clone(),
                        "--quiet".into(),
                        "--out".into(),
                        out.display().to_string(),
                    ]);
                    args.extend(batch.extra_args.iter().cloned());
                    tasks.push(Task { out, args });
                }
            }
        }
    }
    Ok(tasks)
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
        let tasks = plan(&batch, Path::new("."), "ufcsr-capture").unwrap();
        assert_eq!(tasks.len(), 8);
        assert_eq!(tasks[0].out, PathBuf::from("runs/0-demo/A/ppd60-step1"));
        assert_eq!(tasks[7].out, PathBuf::from("runs/0-demo/C/ppd10-step4"));
        let line = tasks[1].shell_line();
        assert!(line.starts_with("ufcsr-capture demo --scenario A --ppd 60 --frames 0-180/4"), "{line}");
        assert!(line.contains("--count") && line.ends_with("--out runs/0-demo/A/ppd60-step4"), "{line}");
        assert_eq!(shell_quote("it's"), "'it'\\''s'");
        let unknown: std::result::Result<Batch, _> =
            serde_json::from_str(r#"{"out": "x", "scenes": [], "ppm": 3}"#);
        assert!(unknown.is_err());
        let missing = Batch { scenarios: Some(vec!["Z".into()]), ..batch };
        assert!(plan(&missing, Path::new("."), "ufcsr-capture").is_err());
    }
}
