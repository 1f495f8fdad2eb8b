//! The PNG sink: encoder threads behind a short queue.
//!
//! The GPU renders the next tile while earlier tiles are encoded; the bounded
//! queue (two jobs per thread) keeps the renderer at most a few tiles ahead,
//! so memory stays flat however long the capture.

use std::path::{Path, PathBuf};
use std::sync::mpsc::{Receiver, SyncSender, sync_channel};
use std::sync::{Arc, Mutex, PoisonError};
use std::thread::JoinHandle;

use ufcsr::files::PngEncoding;

use crate::error::{CaptureError, Result};
use crate::job::options::{Compression, TileFilter};
use crate::job::tile_sink::{RenderedTile, TileAddress, TileSink, is_tile_name};

/// What to do with tiles an earlier capture left in the archive.
#[derive(Debug, Clone)]
pub(crate) enum OldTiles {
    /// Remove them all (a fresh capture).
    All,
    /// Remove those of these frames (a shard: the others belong to other shards).
    OfFrames(std::collections::BTreeSet<u32>),
    /// Keep them; finished tiles are not rendered again (`--resume`).
    Keep,
}

struct EncodeJob {
    path: PathBuf,
    size: [u32; 2],
    rgba: Vec<u8>,
}

/// Writes tiles as RGB PNGs under `archive/tiles/` on worker threads.
pub(crate) struct EncoderPool {
    archive: PathBuf,
    tile_size: [u32; 2],
    resume: bool,
    sender: Option<SyncSender<EncodeJob>>,
    workers: Vec<JoinHandle<()>>,
    errors: Arc<Mutex<Vec<CaptureError>>>,
}

impl EncoderPool {
    /// Starts `threads` encoders (0: one per core) writing into `archive/tiles`.
    /// Tiles of an earlier capture are removed first as `old_tiles` says:
    /// tiles this capture does not write again must not linger beside its
    /// manifest (a shard removes only those of its own frames, since the other
    /// shards write into the same folder; `--resume` keeps them all).
    pub(crate) fn start(
        archive: &Path,
        tile_size: [u32; 2],
        compression: Compression,
        filter: TileFilter,
        threads: usize,
        old_tiles: OldTiles,
    ) -> Result<EncoderPool> {
        let tiles_dir = archive.join("tiles");
        ufcsr::files::real_dir(&tiles_dir)?;
        // Tiles half-written by a killed capture (SIGKILL runs no handler)
        // go, so `--resume` keeps only whole tiles and nothing of theirs.
        ufcsr::files::remove_stale_temporaries(&tiles_dir);
        ufcsr::files::remove_stale_temporaries(archive);
        let resume = matches!(old_tiles, OldTiles::Keep);
        match &old_tiles {
            OldTiles::Keep => {}
            OldTiles::All => remove_old_tiles(&tiles_dir)?,
            OldTiles::OfFrames(frames) => {
                remove_old_tiles_where(&tiles_dir, |frame| frames.contains(&frame))?
            }
        }
        let threads =
            if threads == 0 { std::thread::available_parallelism().map_or(2, |n| n.get()) } else { threads };
        let (sender, receiver) = sync_channel::<EncodeJob>(threads * 2);
        let receiver = Arc::new(Mutex::new(receiver));
        let errors = Arc::new(Mutex::new(Vec::new()));
        let workers = (0..threads)
            .map(|_| {
                let (receiver, errors) = (receiver.clone(), errors.clone());
                let format = PngEncoding { compression: compression.png(), filter: Some(filter.png()) };
                std::thread::spawn(move || encoder_worker(&receiver, format, &errors))
            })
            .collect();
        Ok(EncoderPool {
            archive: archive.to_path_buf(),
            tile_size,
            resume,
            sender: Some(sender),
            workers,
            errors,
        })
    }

    fn first_error(&self) -> Option<CaptureError> {
        self.errors.lock().unwrap_or_else(PoisonError::into_inner).drain(..).next()
    }
}

impl TileSink for EncoderPool {
    fn is_done(&self, address: &TileAddress) -> bool {
        self.resume && is_complete_tile(&self.archive.join(address.file()), self.tile_size)
    }

    fn accept(&mut self, tile: RenderedTile) -> Result<()> {
        if let Some(error) = self.first_error() {
            return Err(error);
        }
        let job =
            EncodeJob { path: self.archive.join(tile.address.file()), size: tile.size, rgba: tile.rgba };
        let sender =
            self.sender.as_ref().ok_or_else(|| CaptureError::Gpu("PNG encoders already finished".into()))?;
        sender.send(job).map_err(|_| CaptureError::Gpu("PNG encoders stopped".into()))
    }

    fn finish(&mut self) -> Result<()> {
        // Closing the queue lets the workers drain it and exit.
        self.sender = None;
        for worker in self.workers.drain(..) {
            if worker.join().is_err() {
                return Err(CaptureError::Gpu("a PNG encoder thread panicked".into()));
            }
        }
        self.first_error().map_or(Ok(()), Err)
    }
}

impl Drop for EncoderPool {
    fn drop(&mut self) {
        // On an early error the workers still finish what is queued; joining
        // here keeps no thread writing after the capture returned.
        self.sender = None;
        for worker in self.workers.drain(..) {
            let _ = worker.join();
        }
    }
}

fn encoder_worker(jobs: &Mutex<Receiver<EncodeJob>>, format: PngEncoding, errors: &Mutex<Vec<CaptureError>>) {
    let mut rgb = Vec::new();
    loop {
        let job = match jobs.lock() {
            Ok(receiver) => receiver.recv(),
            Err(_) => return,
        };
        let Ok(job) = job else { return };
        // Tiles are written as RGB where alpha is 255 everywhere (always, for
        // palettes of up to 2^24 texels), and as RGBA where a pixel names a
        // texel above 2^24 (a 32-bit texel id's high byte is 255 − alpha,
        // `ufcsr::rgba32_id`); the analyzer reads an RGB tile as opaque.
        let written = if job.rgba.chunks_exact(4).all(|pixel| pixel[3] == 255) {
            rgba_to_rgb(&job.rgba, &mut rgb);
            write_tile_png(&job.path, job.size, &rgb, format)
        } else {
            ufcsr::files::write_rgba_png(&job.path, job.size, &job.rgba, format).map_err(CaptureError::from)
        };
        if let Err(error) = written {
            errors.lock().unwrap_or_else(PoisonError::into_inner).push(error);
        }
    }
}

/// Drops the alpha byte of every pixel into `rgb` (reused between tiles).
/// A fixed-size copy per pixel, which the compiler turns into wide moves,
/// instead of an iterator chain that grows a vector byte by byte.
pub(crate) fn rgba_to_rgb(rgba: &[u8], rgb: &mut Vec<u8>) {
    rgb.clear();
    rgb.resize(rgba.len() / 4 * 3, 0);
    for (to, from) in rgb.chunks_exact_mut(3).zip(rgba.chunks_exact(4)) {
        to.copy_from_slice(&from[..3]);
    }
}

/// Writes one RGB tile atomically with the capture's deflate level and row
/// filter (`format`), through the one encoder.
fn write_tile_png(path: &Path, size: [u32; 2], rgb: &[u8], format: PngEncoding) -> Result<()> {
    ufcsr::files::write_rgb_png(path, [size[0], size[1]], rgb, format)?;
    Ok(())
}

/// Removes files named like our tiles (`fNNNN_left|right_rR_cC.png`).
pub(crate) fn remove_old_tiles(dir: &Path) -> Result<()> {
    remove_old_tiles_where(dir, |_| true)
}

/// Removes the tiles in `dir` whose frame number `remove` accepts.
fn remove_old_tiles_where(dir: &Path, remove: impl Fn(u32) -> bool) -> Result<()> {
    if !dir.is_dir() {
        return Ok(());
    }
    let entries = std::fs::read_dir(dir).map_err(|e| CaptureError::io(dir, e))?;
    for entry in entries {
        let entry = entry.map_err(|e| CaptureError::io(dir, e))?;
        let name = entry.file_name();
        let name = name.to_string_lossy();
        let frame = name.get(1..).and_then(|rest| rest.split('_').next()).and_then(|n| n.parse().ok());
        if is_tile_name(&name) && frame.is_some_and(&remove) {
            ufcsr::files::remove_inside(dir, &entry.path())?;
        }
    }
    Ok(())
}

/// True for a tile that decodes completely (zlib checksum included) at the
/// tile size: a header alone is not enough, since an interrupted write
/// leaves a valid header over missing image data.
fn is_complete_tile(path: &Path, tile_size: [u32; 2]) -> bool {
    ufcsr::read_color_image(path, |[width, height]| {
        if [width, height] == tile_size {
            Ok(())
        } else {
            Err(ufcsr::Error::bad_file(path, "not the tile size"))
        }
    })
    .is_ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rgb_keeps_every_pixel_s_color_in_order_and_drops_alpha() {
        let mut rgb = vec![7; 100];
        rgba_to_rgb(&[1, 2, 3, 255, 4, 5, 6, 0, 7, 8, 9, 128], &mut rgb);
        assert_eq!(rgb, [1, 2, 3, 4, 5, 6, 7, 8, 9]);
        rgba_to_rgb(&[], &mut rgb);
        assert!(rgb.is_empty());
    }

    #[test]
    fn an_up_filtered_tile_decodes_to_the_same_pixels_and_says_up_on_every_row() {
        let dir = tempfile::tempdir().unwrap();
        // Rows alike, as in tiles (the fast deflate stores rows it cannot shrink unfiltered).
        let rgb: Vec<u8> = (0..64 * 32 * 3).map(|i: usize| (i % 192 / 12 * 5) as u8).collect();
        for (filter, name) in [(png::Filter::Up, "up.png"), (png::Filter::Adaptive, "adaptive.png")] {
            let format = PngEncoding { compression: png::Compression::Fast, filter: Some(filter) };
            write_tile_png(&dir.path().join(name), [64, 32], &rgb, format).unwrap();
        }
        let read = |name: &str| ufcsr::read_color_image(&dir.path().join(name), |_| Ok(())).unwrap().colors;
        assert_eq!(read("up.png"), read("adaptive.png"));
        let packed: Vec<u32> =
            rgb.chunks_exact(3).map(|p| u32::from_be_bytes([0, p[0], p[1], p[2]])).collect();
        assert_eq!(read("up.png"), packed);
        // Inflated but not unfiltered, each row starts with its filter type (2 = Up).
        let rows = filtered_image_data(&std::fs::read(dir.path().join("up.png")).unwrap());
        assert_eq!(rows.len(), 32 * (1 + 64 * 3));
        let filters: Vec<u8> = rows.chunks_exact(1 + 64 * 3).map(|row| row[0]).collect();
        assert_eq!(filters, [2; 32], "every row Up");
    }

    /// The inflated, still filtered image data of a PNG (the png crate's streaming decoder).
    fn filtered_image_data(bytes: &[u8]) -> Vec<u8> {
        let mut decoder = png::StreamingDecoder::new();
        let (mut buffer, mut region, mut at) = (vec![0u8; 1 << 16], png::UnfilterRegion::default(), 0);
        while at < bytes.len() {
            let (used, _) = decoder.update(&bytes[at..], Some(&mut region.as_buf(&mut buffer))).unwrap();
            at += used;
        }
        buffer.truncate(region.filled);
        buffer
    }
}
