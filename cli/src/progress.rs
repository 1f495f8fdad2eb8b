//! The progress bar: the libraries report progress through
//! [`ufcsr::Progress`] (images counted, tiles rendered) and the command line
//! draws it on stderr (only on a terminal, and not with `--quiet` or
//! `--json`). One bar type and ONE style for both (issue 35 item 6): a verb,
//! the bar, done/total and the unit, the rate rounded to what it means
//! (whole items per second from 10 up, one decimal below), the time left in
//! whole seconds or minutes — at most 80 columns for any count up to
//! 9,999,999. A new bar per `start` (a capture starts one per scenario),
//! cleared at `finish`.

use std::sync::Mutex;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressState, ProgressStyle};

use crate::console::Console;

/// A bar drawn from what a library reports.
pub struct Bar {
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
    pub fn counting(console: &Console) -> Bar {
        Bar::new(template("counting", "images"), console)
    }

    /// A capture's bar: tiles rendered.
    #[cfg(feature = "capture")]
    pub fn capturing(console: &Console) -> Bar {
        Bar::new(template("capturing", "tiles"), console)
    }

    fn new(template: String, console: &Console) -> Bar {
        Bar { template, hidden: console.quiet(), bar: Mutex::new(None) }
    }
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
