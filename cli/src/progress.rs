//! The progress bar: the libraries report progress through
//! [`ufcsr::Progress`] (images counted, tiles rendered) and the command line
//! draws it on stderr (only on a terminal, and not with `--quiet` or
//! `--json`). One bar type for both: a new bar per `start` (a capture starts
//! one per scenario), cleared at `finish`.

use std::sync::Mutex;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

use crate::console::Console;

/// A bar drawn from what a library reports.
pub struct Bar {
    template: &'static str,
    hidden: bool,
    bar: Mutex<Option<ProgressBar>>,
}

impl Bar {
    /// The analysis's bar: images counted.
    pub fn counting(console: &Console) -> Bar {
        Bar::new("{spinner} counting {pos}/{len} images [{bar:40}] {per_sec} eta {eta}", console)
    }

    /// A capture's bar: tiles rendered.
    #[cfg(feature = "capture")]
    pub fn capturing(console: &Console) -> Bar {
        Bar::new("capturing [{elapsed_precise}] {wide_bar} {pos}/{len} tiles ({per_sec}, eta {eta})", console)
    }

    fn new(template: &'static str, console: &Console) -> Bar {
        Bar { template, hidden: console.quiet(), bar: Mutex::new(None) }
    }
}

impl ufcsr::Progress for Bar {
    fn start(&self, total: u64) {
        let target = if self.hidden { ProgressDrawTarget::hidden() } else { ProgressDrawTarget::stderr() };
        let bar = ProgressBar::with_draw_target(Some(total), target);
        let style =
            ProgressStyle::with_template(self.template).unwrap_or_else(|_| ProgressStyle::default_bar());
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
