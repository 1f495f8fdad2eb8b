//! The counting sink: rendered tiles go straight into the analyzer's tables.
//!
//! `--count` skips the PNG round trip: each readback buffer is counted by
//! [`ufcsr::TileCounter`] with the analyzer's own kernels, so the results are
//! those of writing the tiles and analysing the archive, without the encode
//! and decode that dominate that path.

use ufcsr::TileCounter;

use crate::error::Result;
use crate::tile_sink::{RenderedTile, TileSink};

/// Counts every tile it is given.
pub struct CountSink<'a> {
    pub counter: TileCounter<'a>,
    /// RGBA pixels counted.
    pub pixels: u64,
}

impl<'a> CountSink<'a> {
    pub fn new(counter: TileCounter<'a>) -> CountSink<'a> {
        CountSink { counter, pixels: 0 }
    }
}

impl TileSink for CountSink<'_> {
    fn accept(&mut self, tile: RenderedTile) -> Result<()> {
        let name = tile.address.file().to_string_lossy().replace('\\', "/");
        let [width, height] = tile.size;
        self.counter.count_rgba(
            &name,
            tile.address.frame,
            tile.address.eye.name(),
            width,
            height,
            &tile.rgba,
        )?;
        self.pixels += u64::from(width) * u64::from(height);
        Ok(())
    }

    fn finish(&mut self) -> Result<()> {
        Ok(())
    }
}
