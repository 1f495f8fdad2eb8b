//! Where rendered tiles go: the seam between rendering and output.
//!
//! The frame loop ([`crate::job::frame_capture`]) renders tiles and hands each one
//! that shows anything but background to a [`TileSink`]. Writing PNGs
//! ([`crate::job::encoder_pool::EncoderPool`]) is one sink; counting the readback
//! buffer straight into the analyzer's tables is another. Keeping the loop
//! ignorant of files is what lets both produce the same archive bookkeeping.

use std::path::PathBuf;

use crate::error::Result;
use crate::scene::rig::Eye;

/// Where a tile sits in a capture.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct TileAddress {
    pub frame: u32,
    pub eye: Eye,
    pub row: u32,
    pub col: u32,
}

impl TileAddress {
    /// The tile's file name relative to the archive (`tiles/fNNNN_EYE_rR_cC.png`).
    pub fn file(&self) -> PathBuf {
        tile_file(self.frame, self.eye, self.row, self.col)
    }
}

/// The file name of a tile, relative to the archive.
pub(crate) fn tile_file(frame: u32, eye: Eye, row: u32, col: u32) -> PathBuf {
    PathBuf::from(format!("tiles/f{frame:04}_{}_r{row}_c{col}.png", eye.name()))
}

/// True for `f0000_left_r0_c0.png` and the like.
pub(crate) fn is_tile_name(name: &str) -> bool {
    let Some(rest) = name.strip_prefix('f').and_then(|n| n.strip_suffix(".png")) else {
        return false;
    };
    let parts: Vec<&str> = rest.split('_').collect();
    let number = |text: &str, prefix: char| {
        text.strip_prefix(prefix).is_some_and(|n| !n.is_empty() && n.bytes().all(|b| b.is_ascii_digit()))
    };
    matches!(parts.as_slice(), [frame, eye, row, col]
        if !frame.is_empty() && frame.bytes().all(|b| b.is_ascii_digit())
            && (*eye == "left" || *eye == "right")
            && number(row, 'r')
            && number(col, 'c'))
}

/// One rendered tile: tightly packed RGBA8 rows (readback padding already
/// stripped), row 0 at the top.
#[derive(Debug, Clone)]
pub struct RenderedTile {
    pub address: TileAddress,
    /// Position of the tile in the manifest's tile list (archive order), so a
    /// sink that works out of order can still report in order.
    pub index: usize,
    pub size: [u32; 2],
    pub rgba: Vec<u8>,
}

/// Receives the tiles of a capture that show more than background.
pub trait TileSink {
    /// True when the tile is already done and need not be rendered again
    /// (`--resume`); the default is never.
    fn is_done(&self, _address: &TileAddress) -> bool {
        false
    }

    /// Takes one tile. An error stops the capture.
    fn accept(&mut self, tile: RenderedTile) -> Result<()>;

    /// Called once after the last tile; reports errors of work still in flight.
    fn finish(&mut self) -> Result<()>;
}
