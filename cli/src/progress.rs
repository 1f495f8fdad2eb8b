//! The progress bar: the libraries report progress through
//! [`ufcsr::Progress`] (images counted, tiles rendered) and the command line
//! draws it on stderr (only on a terminal, and not with `--quiet` or
//! `--json`). One bar type and ONE style for both (issue 35 item 6): a verb,
//! the bar, done/total and the unit, the rate rounded to what it means
//! (whole items per second from 10 up, one decimal below), the time left in
//! whole seconds or minutes — at most 80 columns for any count up to
//! 9,999,999. A new bar per `start` (a capture starts one per scenario),
//! cleared at `finish`. A design run, whose tasks take minutes each, prints
//! one line per finished task instead ([`TaskLine`]: "task k of N", the bar,
//! the time left), so a log shows it too.

use std::sync::Mutex;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressState, ProgressStyle};

use crate::console::Console;

/// A bar drawn from what a library reports.
pub(crate) struct Bar {
    template: String,
    hidden: bool,
    bar: Mutex<Option<ProgressBar>>,
}

/// The one style's template for `verb` and `unit` (`counting` / `images`).
fn template(verb: &str, unit: &str) -> String {
    format!("{verb} [{{bar:{BAR_WIDTH}}}] {{pos}}/{{len}} {unit} {{rate}} {{left}}")
}

/// Columns of the bar itself.
const BAR_WIDTH: usize = 20;

/// A rate per second, rounded to what it means.
fn rate_text(per_second: f64) -> String {
    if !per_second.is_finite() || per_second <= 0.0 {
        "–/s".to_string()
    } else if per_second >= 10.0 {
        format!("{per_second:.0}/s")
    } else {
        format!("{per_second:.1}/s")
    }
}

/// The time left, in whole seconds under two minutes, else whole minutes.
fn left_text(seconds: f64) -> String {
    if !seconds.is_finite() || seconds <= 0.0 {
        String::new()
    } else if seconds < 120.0 {
        format!("{:.0} s left", seconds.ceil())
    } else if seconds < 6000.0 * 60.0 {
        format!("{:.0} min left", (seconds / 60.0).ceil())
    } else {
        "> 99 h left".to_string()
    }
}

impl Bar {
    /// The analysis's bar: images counted.
    pub(crate) fn counting(console: &Console) -> Bar {
        Bar::new(template("counting", "images"), console)
    }

    /// A capture's bar: tiles rendered.
    #[cfg(feature = "capture")]
    pub(crate) fn capturing(console: &Console) -> Bar {
        Bar::new(template("capturing", "tiles"), console)
    }

    fn new(template: String, console: &Console) -> Bar {
        Bar { template, hidden: console.quiet(), bar: Mutex::new(None) }
    }
}

/// A design run's progress (issue 42 §8): after each task, on stderr (not with `--quiet` or
/// `--json`), "task k of N", the bar and the time left, estimated from the tasks measured so
/// far (a skipped, already complete task costs nothing and is not counted in the rate).
#[cfg(feature = "capture")]
pub(crate) struct TaskLine {
    total: usize,
    done: usize,
    measured: usize,
    started: std::time::Instant,
    hidden: bool,
}

#[cfg(feature = "capture")]
impl TaskLine {
    pub(crate) fn new(total: usize, console: &Console) -> TaskLine {
        TaskLine { total, done: 0, measured: 0, started: std::time::Instant::now(), hidden: console.quiet() }
    }

    /// One more task finished (`measured`: run now, not skipped): prints its line.
    pub(crate) fn finished(&mut self, measured: bool) {
        self.done += 1;
        self.measured += usize::from(measured);
        let per_task = self.started.elapsed().as_secs_f64() / self.measured.max(1) as f64;
        let left =
            if self.measured == 0 { 0.0 } else { per_task * self.total.saturating_sub(self.done) as f64 };
        if !self.hidden {
            eprintln!("{}", task_line(self.done, self.total, left));
        }
    }
}

/// `task 3 of 8 [=======             ] 40 s left`: the bars' width and time-left words.
#[cfg(feature = "capture")]
fn task_line(done: usize, total: usize, left_s: f64) -> String {
    let filled = (BAR_WIDTH * done / total.max(1)).min(BAR_WIDTH);
    let line = format!(
        "task {done} of {total} [{}{}] {}",
        "=".repeat(filled),
        " ".repeat(BAR_WIDTH - filled),
        left_text(left_s)
    );
    line.trim_end().to_string()
}

impl ufcsr::Progress for Bar {
    fn start(&self, total: u64) {
        let target = if self.hidden { ProgressDrawTarget::hidden() } else { ProgressDrawTarget::stderr() };
        let bar = ProgressBar::with_draw_target(Some(total), target);
        let style = ProgressStyle::with_template(&self.template)
            .unwrap_or_else(|_| ProgressStyle::default_bar())
            .with_key("rate", |state: &ProgressState, w: &mut dyn std::fmt::Write| {
                let _ = w.write_str(&rate_text(state.per_sec()));
            })
            .with_key("left", |state: &ProgressState, w: &mut dyn std::fmt::Write| {
                let _ = w.write_str(&left_text(state.eta().as_secs_f64()));
            });
        bar.set_style(style.progress_chars("=> "));
        if let Ok(mut slot) = self.bar.lock() {
            *slot = Some(bar);
        }
    }

    fn advance(&self, done: u64) {
        if let Ok(slot) = self.bar.lock()
            && let Some(bar) = slot.as_ref()
        {
            bar.inc(done);
        }
    }

    fn finish(&self) {
        if let Ok(mut slot) = self.bar.lock()
            && let Some(bar) = slot.take()
        {
            bar.finish_and_clear();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The widest line the template can draw: every key at its widest.
    fn widest_line(verb: &str, unit: &str) -> usize {
        let mut line = template(verb, unit);
        let longest_rate = ["9999999/s", &rate_text(9.94), &rate_text(0.0)].iter().map(|s| s.len()).max();
        let longest_left = [left_text(119.0), left_text(5999.0 * 60.0), left_text(1e9)]
            .iter()
            .map(|s| s.chars().count())
            .max();
        line = line.replace(&format!("{{bar:{BAR_WIDTH}}}"), &"=".repeat(BAR_WIDTH));
        line = line.replace("{pos}", "9999999").replace("{len}", "9999999");
        line = line.replace("{rate}", &"r".repeat(longest_rate.unwrap_or(0)));
        line = line.replace("{left}", &"l".repeat(longest_left.unwrap_or(0)));
        line.chars().count()
    }

    #[test]
    fn both_bars_fit_an_80_column_terminal() {
        assert!(widest_line("counting", "images") <= 80, "{}", widest_line("counting", "images"));
        assert!(widest_line("capturing", "tiles") <= 80, "{}", widest_line("capturing", "tiles"));
    }

    #[cfg(feature = "capture")]
    #[test]
    fn a_design_run_says_task_k_of_n_with_the_time_left() {
        assert_eq!(task_line(3, 8, 100.0), "task 3 of 8 [=======             ] 100 s left");
        assert_eq!(task_line(8, 8, 0.0), "task 8 of 8 [====================]");
        assert_eq!(task_line(1, 1000, 7200.0), "task 1 of 1000 [                    ] 120 min left");
        assert!(task_line(9_999_999, 9_999_999, 5999.0 * 60.0).chars().count() <= 80);
    }

    #[test]
    fn rates_and_times_are_rounded_to_what_they_mean() {
        assert_eq!(rate_text(1234.5678), "1235/s");
        assert_eq!(rate_text(3.0625), "3.1/s");
        assert_eq!(rate_text(f64::NAN), "–/s");
        assert_eq!(left_text(4.2), "5 s left");
        assert_eq!(left_text(600.0), "10 min left");
        assert_eq!(left_text(0.0), "");
    }
}
