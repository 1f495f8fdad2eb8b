//! `ufcsr design plan|run|merge DESIGN` (also `ufcsr design …`): the
//! factorial study of issue 36. `plan` checks the design and what its tasks
//! will read, then prints one independent task per line (`--indices`: its
//! number, for `xargs -P … design run … --task {}`; else its command, line I
//! of a Slurm array), `run` measures one task (`--task I`) or every task in
//! one process, skipping complete ones, with a "task k of N" line and the
//! time left, and `merge` writes the one result set, refusing another
//! design's tasks and naming missing cells. Names read from files are
//! printed through [`printable`], never as raw control characters. The library's side is `ufcsr_capture::plan_design`,
//! `run_design` and `merge_design` (`docs/design.md`).

use std::path::{Path, PathBuf};

use anyhow::Context;
use clap::Subcommand;
use ufcsr_capture::{Gpu, design::TaskOutcome};

use crate::choices::Backend;
use crate::console::{Console, printable, say};

/// What to do with a design.
#[derive(Subcommand)]
pub(crate) enum DesignAction {
    /// Check the design and the files its tasks read; print its tasks, one per line (task I on line I+1).
    ///
    /// Example: `ufcsr design plan fixtures/designs/tiny-2x2.json --out runs/tiny --indices | xargs -P 2
    /// -I{} ufcsr design run fixtures/designs/tiny-2x2.json --out runs/tiny --task {}` (two at a time;
    /// the task numbers are digits: nothing of a path reaches a shell). Without
    /// --indices each line is a command quoted for `sh`, for one line at a time (a Slurm array's line
    /// I); never pipe those through plain `xargs`, which strips the quotes.
    Plan {
        /// The design file (ufcsr-design/1).
        design: PathBuf,
        /// The folder the tasks write into (passed to each task's command).
        #[arg(long, default_value = "design-out")]
        out: PathBuf,
        /// The program the commands call (default: the ufcsr beside this program).
        #[arg(long)]
        program: Option<String>,
        /// Print only the task numbers, one per line (for `xargs -I{} ufcsr design run … --task {}`).
        #[arg(long)]
        indices: bool,
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
    pub(crate) fn name(&self) -> &'static str {
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

/// An error when a command line would hold a control character: a newline would split a task
/// over two lines of the plan, and task I must be line I+1.
fn one_line(what: &str, text: &str) -> anyhow::Result<()> {
    match text.chars().find(|c| c.is_control()) {
        Some(c) => anyhow::bail!(
            "{what} {}: a control character ({c:?}) cannot be in a plan's command line; use --indices",
            printable(text)
        ),
        None => Ok(()),
    }
}

fn run_plan(
    design: &Path,
    out: &Path,
    program: Option<String>,
    indices: bool,
    console: &Console,
) -> anyhow::Result<()> {
    let plan = ufcsr_capture::plan_design(design)?;
    ufcsr_capture::design::check_design_inputs(&plan)?;
    let program = match program {
        Some(program) => program,
        None => std::env::current_exe()?
            .with_file_name(format!("ufcsr{}", std::env::consts::EXE_SUFFIX))
            .display()
            .to_string(),
    };
    let (design_text, out_text) = (design.display().to_string(), out.display().to_string());
    let lines: Vec<String> = if indices {
        plan.tasks.iter().map(|t| t.index.to_string()).collect()
    } else {
        one_line("design", &design_text)?;
        one_line("--out", &out_text)?;
        one_line("--program", &program)?;
        plan.tasks
            .iter()
            .map(|t| {
                let args = [
                    &program,
                    "design",
                    "run",
                    &design_text,
                    "--task",
                    &t.index.to_string(),
                    "--out",
                    &out_text,
                ];
                args.iter().map(|a| shell_quote(a)).collect::<Vec<_>>().join(" ")
            })
            .collect()
    };
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
    if task.is_none() {
        // Every task in this process: what they will read is checked before the first is measured.
        ufcsr_capture::design::check_design_inputs(&plan)?;
    }
    let gpu = Gpu::create(backend.into()).context("creating the GPU device")?;
    let (mut ran, mut skipped) = (0u32, 0u32);
    let mut progress =
        crate::progress::TaskLine::new(if task.is_some() { 1 } else { plan.tasks.len() }, console);
    ufcsr_capture::run_design(&gpu.device, &gpu.queue, &plan, task, out, |outcome| {
        match outcome {
            TaskOutcome::Skipped(index) => {
                skipped += 1;
                say!(console, "task {index}: complete already, skipped");
            }
            TaskOutcome::Ran(done) => {
                ran += 1;
                // The task's folder (its units' archives, results and task.json) is this run's.
                crate::capture::captures::record_folder(
                    &ufcsr_capture::design::task_dir(out, done.task),
                    console,
                );
                say!(
                    console,
                    "task {} ({}, replicate {}): {:.1} s",
                    done.task,
                    printable(&done.cell.to_string()),
                    done.replicate,
                    done.seconds
                );
            }
        }
        progress.finished(matches!(outcome, TaskOutcome::Ran(_)));
    })?;
    say!(
        console,
        "design {:?} (hash {}): {ran} task(s) run, {skipped} skipped",
        printable(&plan.design.name),
        plan.hash
    );
    console.fact("ran", ran);
    console.fact("skipped", skipped);
    Ok(())
}

fn run_merge(design: &Path, out: &Path, console: &Console) -> anyhow::Result<()> {
    let plan = ufcsr_capture::plan_design(design)?;
    let result = ufcsr_capture::merge_design(&plan, out)?;
    for line in &result.answer {
        say!(console, "{}", printable(line));
    }
    for file in ufcsr_capture::design::write_design_result_set(&result, out, &[design.to_path_buf()])? {
        console.wrote(&file);
        say!(console, "wrote {}", file.display());
    }
    console.fact("answer", &result.answer);
    Ok(())
}

/// Runs one design action.
pub(crate) fn run_design_action(action: DesignAction, console: &Console) -> anyhow::Result<()> {
    match action {
        DesignAction::Plan { design, out, program, indices } => {
            run_plan(&design, &out, program, indices, console)
        }
        DesignAction::Run { design, task, out, backend } => run_tasks(&design, task, &out, backend, console),
        DesignAction::Merge { design, out } => run_merge(&design, &out, console),
    }
}
