//! The progress bar of a capture: the library reports rendered tiles through
//! [`ufcsr::Progress`] and the binary draws them on stderr.

use std::sync::Mutex;

use indicatif::{ProgressBar, ProgressStyle};

/// A bar per scenario: `start` draws a new one, `finish` clears it.
#[derive(Default)]
pub struct TileBar(Mutex<Option<ProgressBar>>);

impl ufcsr::Progress for TileBar {
    fn start(&self, total: u64) {
        let bar = ProgressBar::new(total);
        if let Ok(style) = ProgressStyle::with_template(
            "{prefix} [{elapsed_precise}] {wide_bar} {pos}/{len} tiles ({per_sec}, eta {eta})",
        ) {
            bar.set_style(style);
        }
        bar.set_prefix("capturing");
        if let Ok(mut slot) = self.0.lock() {
            *slot = Some(bar);
        }
    }

    fn advance(&self, done: u64) {
        if let Ok(slot) = self.0.lock()
            && let Some(bar) = slot.as_ref()
        {
            bar.inc(done);
        }
    }

    fn finish(&self) {
        if let Ok(mut slot) = self.0.lock()
            && let Some(bar) = slot.take()
        {
            bar.finish_and_clear();
        }
    }
}
