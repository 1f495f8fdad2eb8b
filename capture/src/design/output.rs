//! The merged result's files written as one set (issue 41 §2): the three
//! tables and pages and the main effects' figure.
//!
//! Written one after another, a `design.html` that could not be replaced (a
//! folder, a FIFO, a link planted there) was refused after `design.json` and
//! `design.csv` were already new: half a result, and `--json` said
//! `written: []`. Here every target is checked first (nothing is replaced
//! that is not a regular file), then the three are written into a staging
//! folder and moved into place together ([`ufcsr::files::Staging`]): the folder
//! holds the old set or the new, never a mix.

use std::path::{Path, PathBuf};

use ufcsr::format::DesignResult;

use super::report::{csv, page};
use crate::error::{CaptureError, Result};

/// The result set's files, in the order they are listed.
pub(crate) const RESULT_FILES: [&str; 3] = ["design.json", "design.csv", "design.html"];
/// The main effects' figure (with a font): each level's effect with its 95 % interval.
pub(crate) const EFFECTS_FIGURE: [&str; 2] = ["design-effects.png", "design-effects.pdf"];
/// Rows of the main effects' figure at most (the first effects, in `design.json`'s order).
const EFFECT_ROWS: usize = 48;

/// Writes `design.json`, `design.csv`, `design.html` and, with a font, the main effects' figure
/// (`design-effects.png`, `.pdf`) into `dir` as one set, never over one of `inputs` nor over
/// anything but a regular file; returns their paths.
pub fn write_result_set(result: &DesignResult, dir: &Path, inputs: &[PathBuf]) -> Result<Vec<PathBuf>> {
    ufcsr::files::create_output_dir(dir)?;
    let files = RESULT_FILES.map(|f| dir.join(f));
    let figure = EFFECTS_FIGURE.map(|f| dir.join(f));
    ufcsr::files::refuse_overwriting_inputs(&[&files[..], &figure[..]].concat(), inputs)?;
    for file in files.iter().chain(&figure) {
        ufcsr::files::refuse_replacing_non_file(file)?;
    }
    let json =
        serde_json::to_vec_pretty(result).map_err(|e| CaptureError::bad_file(&files[0], e.to_string()))?;
    let staging = ufcsr::files::Staging::new(dir)?;
    let contents = [json, csv(result).into_bytes(), page(result).into_bytes()];
    for (name, bytes) in RESULT_FILES.iter().zip(&contents) {
        ufcsr::files::write_bytes_atomically(&staging.path().join(name), bytes)?;
    }
    let figure_stem = staging.path().join("design-effects");
    let drawn = effects_figure(&result.design, &result.main_effects).write(&figure_stem)?;
    let members: Vec<&str> = RESULT_FILES.iter().chain(&EFFECTS_FIGURE).copied().collect();
    staging.commit(dir, &members)?;
    let mut written = files.to_vec();
    if !drawn.is_empty() {
        written.extend(figure);
    }
    Ok(written)
}

/// The main effects as a figure (issue 44 §2): per factor level and candidate, the level's
/// effect on the mean legible time with its 95 % interval over the random units.
pub(crate) fn effects_figure(
    design: &str,
    effects: &[ufcsr::format::MainEffect],
) -> ufcsr::output::IntervalFigure {
    let rows = effects
        .iter()
        .flat_map(|effect| {
            effect.levels.iter().map(move |level| ufcsr::output::IntervalRow {
                label: format!(
                    "{}: {} = {}",
                    ufcsr::output::readable_part_name(&effect.candidate),
                    effect.factor,
                    level.level
                ),
                value: level.effect_s.mean,
                interval: level.effect_s.ci95,
            })
        })
        .take(EFFECT_ROWS)
        .collect();
    ufcsr::output::IntervalFigure {
        title: format!("Design {design}: main effects on legible time"),
        axis: "effect on mean legible time (s; whiskers: 95 % interval over the units)".into(),
        rows,
    }
}
