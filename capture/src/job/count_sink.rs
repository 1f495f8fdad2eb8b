//! The counting sink: rendered tiles go straight into the analyzer's tables.
//!
//! `--count` skips the PNG round trip: each readback buffer is counted by
//! [`ufcsr::TileCounter`] with the analyzer's own kernels, so the results are
//! those of writing the tiles and analysing the archive, without the encode
//! and decode. Counting runs on its own thread behind a short queue, so the
//! GPU renders the next tile while the last one is counted (as the PNG
//! encoder pool overlaps encoding with rendering).

use std::sync::mpsc::{SyncSender, sync_channel};

use ufcsr::TileCounter;

use crate::error::{CaptureError, Result};
use crate::job::tile_sink::{RenderedTile, TileSink};

/// Hands tiles to the counting thread.
pub(crate) struct CountSink {
    sender: Option<SyncSender<RenderedTile>>,
}

impl TileSink for CountSink {
    fn accept(&mut self, tile: RenderedTile) -> Result<()> {
        let sender =
            self.sender.as_ref().ok_or_else(|| CaptureError::Gpu("tile counting already finished".into()))?;
        // A closed queue means the counter stopped on an error, which
        // `count_while` returns once the capture has stopped.
        sender.send(tile).map_err(|_| CaptureError::Gpu("tile counting stopped".into()))
    }

    fn finish(&mut self) -> Result<()> {
        self.sender = None;
        Ok(())
    }
}

/// Makes `counter` tally pixels, their solid angles and texels by part per
/// eye-frame (`frames.csv` and the measures, as the analyzer does for PNG
/// tiles): the parts of `lookup` (the archive's legend and PIdT), the rig's
/// eyes.
pub(crate) fn tally_parts(
    counter: &mut TileCounter,
    lookup: ufcsr::PartLookup,
    rig: &crate::scene::rig::Rig,
) {
    counter.tally_parts(lookup, ufcsr::EyeProjection::new(rig.horizontal_fov_deg, rig.eye_pixels));
}

/// What the counting thread did.
pub(crate) struct Counted<'a> {
    pub counter: TileCounter<'a>,
    /// RGBA pixels counted.
    pub pixels: u64,
}

/// Runs `render` with a [`CountSink`] whose tiles `counter` counts on a
/// second thread; returns what `render` returned and the counter. An error
/// of the counter wins over the error it caused in `render`.
pub(crate) fn count_while<'a, T>(
    counter: TileCounter<'a>,
    render: impl FnOnce(&mut CountSink) -> Result<T>,
) -> Result<(T, Counted<'a>)> {
    std::thread::scope(|scope| {
        // Two tiles in flight: enough to overlap, little memory.
        let (sender, receiver) = sync_channel::<RenderedTile>(2);
        let worker = scope.spawn(move || -> Result<Counted<'a>> {
            let mut counted = Counted { counter, pixels: 0 };
            for tile in receiver {
                let name = tile.address.file().to_string_lossy().replace('\\', "/");
                let [width, height] = tile.size;
                // Every tile of an eye has the same size, so its origin is its place × its size.
                let origin = [tile.address.col * width, tile.address.row * height];
                let counted_tile = ufcsr::CountedTile {
                    name: &name,
                    frame: tile.address.frame,
                    eye: tile.address.eye.name(),
                    size: tile.size,
                    origin,
                };
                counted.counter.count_tile(&counted_tile, &tile.rgba)?;
                counted.pixels += u64::from(width) * u64::from(height);
            }
            Ok(counted)
        });
        let mut sink = CountSink { sender: Some(sender) };
        let rendered = render(&mut sink);
        drop(sink);
        let counted =
            worker.join().map_err(|_| CaptureError::Gpu("the tile counting thread panicked".into()))?;
        let counted = counted?;
        Ok((rendered?, counted))
    })
}
