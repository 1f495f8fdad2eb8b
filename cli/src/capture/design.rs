//! `ufcsr design plan|run|merge DESIGN` (also `ufcsr design …`): the
//! factorial study of issue 36. `plan` prints one independent task per
//! line (for `xargs -P`, or line I of a Slurm array), `run` measures one
//! task (`--task I`) or every task in one process, skipping complete ones,
//! and `merge` writes the one result set, refusing another design's tasks
//! and naming missing cells. The library's side is `ufcsr_capture::plan_design`,
//! `run_design` and `merge_design` (`docs/design.md`).

use std::path::{Path, PathBuf};

use anyhow::Context;
use clap::Subcommand;
use ufcsr_capture::{Gpu, TaskOutcome};

use crate::choices::Backend;
use crate::console::{Console, say};

/// What to do with a design.
#[derive(Subcommand)]
pub enum DesignAction {
    /// Check the design and print its tasks, one command per line (task I on line I+1).
    ///
    /// Example: `ufcsr design plan fixtures/designs/tiny-2x2.json --out runs/tiny | xargs -P 2 -I{} sh
    /// -c '{}'`
    Plan {
        /// The design file (ufcsr-design/1).
        design: PathBuf,
        /// The folder the tasks write into (passed to each task's command).
        #[arg(long, default_value = "design-out")]
        out: PathBuf,
        /// The program the commands call (default: the ufcsr beside this program).
        #[arg(long)]
        program: Option<String>,
    },
    /// Run one task (--task I) or all, skipping tasks already complete in --out.
    ///
    /// Example: `ufcsr design run fixtures/designs/tiny-2x2.json --out runs/tiny --task 3`
    Run {
        /// The design file.
        design: PathBuf,
        /// Only this task (0-based, as `plan` numbers them; a Slurm array index).
        #[arg(long)]
        task: Option<u32>,
        /// The folder the tasks write into (tasks/task-NNNN/).
        #[arg(long, default_value = "design-out")]
        out: PathBuf,
        /// GPU backend (the exact measure runs on the CPU; the archive's set-up uses the GPU).
        #[arg(long, value_enum, default_value_t = Backend::Auto)]
        backend: Backend,
    },
    /// Merge every task of the design in --out into design.json, design.csv and design.html.
    ///
    /// Example: `ufcsr design merge fixtures/designs/tiny-2x2.json --out runs/tiny`
    Merge {
        /// The design file.
        design: PathBuf,
        /// The folder the tasks wrote into; the result is written here too.
        #[arg(long, default_value = "design-out")]
        out: PathBuf,
    },
}

impl DesignAction {
    /// The command's name, as `--json` reports it.
    pub fn name(&self) -> &'static str {
        match self {
            DesignAction::Plan { .. } => "design plan",
            DesignAction::Run { .. } => "design run",
            DesignAction::Merge { .. } => "design merge",
        }
    }
}

fn shell_quote(text: &str) -> String {
    if !text.is_empty() && text.bytes().all(|b| b.is_ascii_alphanumeric() || b"-_./=,:+".contains(&b)) {
        text.to_string()
    } else {
        format!("'{}'", text.replace('\'', "'\\''"))
    }
}

fn run_plan(design: &Path, out: &Path, program: Option<String>, console: &Console) -> anyhow::Result<()> {
    let plan = ufcsr_capture::plan_design(design)?;
    let program = match program {
        Some(program) => program,
        None => std::env::current_exe()?
            .with_file_name(format!("ufcsr{}", std::env::consts::EXE_SUFFIX))
            .display()
            .to_string(),
    };
    let (design_text, out_text) = (design.display().to_string(), out.display().to_string());
    let lines: Vec<String> = plan
        .tasks
        .iter()
        .map(|t| {
            let args =
                [&program, "design", "run", &design_text, "--task", &t.index.to_string(), "--out", &out_text];
            args.iter().map(|a| shell_quote(a)).collect::<Vec<_>>().join(" ")
        })
        .collect();
    console.fact("design_hash", &plan.hash);
    console.fact("cells", plan.cells.len());
    console.fact("tasks", &lines);
    let mut text = lines.join("\n");
    if !text.is_empty() {
        text.push('\n');
    }
    console.product(text.as_bytes());
    Ok(())
}

fn run_tasks(
    design: &Path,
    task: Option<u32>,
    out: &Path,
    backend: Backend,
    console: &Console,
) -> anyhow::Result<()> {
    let plan = ufcsr_capture::plan_design(design)?;
    let gpu = Gpu::create(backend.into()).context("creating the GPU device")?;
    let (mut ran, mut skipped) = (0u32, 0u32);
    ufcsr_capture::run_design(&gpu.device, &gpu.queue, &plan, task, out, |outcome| match outcome {
        TaskOutcome::Skipped(index) => {
            skipped += 1;
            say!(console, "task {index}: complete already, skipped");
        }
        TaskOutcome::Ran(done) => {
            ran += 1;
            // The task's folder (its units' archives, results and task.json) is this run's.
            crate::capture::captures::record_folder(&ufcsr_capture::task_dir(out, done.task), console);
            say!(
                console,
                "task {} ({}, replicate {}): {:.1} s",
                done.task,
                done.cell,
                done.replicate,
                done.seconds
            );
        }
    })?;
    say!(console, "design {:?} (hash {}): {ran} task(s) run, {skipped} skipped", plan.design.name, plan.hash);
    console.fact("ran", ran);
    console.fact("skipped", skipped);
    Ok(())
}

fn run_merge(design: &Path, out: &Path, console: &Console) -> anyhow::Result<()> {
    let plan = ufcsr_capture::plan_design(design)?;
    let result = ufcsr_capture::merge_design(&plan, out)?;
    for line in &result.answer {
        say!(console, "{line}");
    }
    for file in ufcsr_capture::write_design_result(&result, out, &[design.to_path_buf()])? {
        console.wrote(&file);
        say!(console, "wrote {}", file.display());
    }
    console.fact("answer", &result.answer);
    Ok(())
}

/// Runs one design action.
pub fn run_design_action(action: DesignAction, console: &Console) -> anyhow::Result<()> {
    match action {
        DesignAction::Plan { design, out, program } => run_plan(&design, &out, program, console),
        DesignAction::Run { design, task, out, backend } => run_tasks(&design, task, &out, backend, console),
        DesignAction::Merge { design, out } => run_merge(&design, &out, console),
    }
}
