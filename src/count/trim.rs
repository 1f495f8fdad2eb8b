//! Trimming: skipping all-background tiles without decoding them, safely.
//!
//! A renderer writes every empty tile of one size as the same bytes, so the
//! empty-tile file size shows up again and again. We find candidate sizes per
//! tile size (width × height), *verify* each candidate by decoding one file and
//! checking it is pure background, and then trim only files whose bytes are
//! identical to a verified empty file. A small file that shows a sliver of
//! the vehicle has different bytes and is decoded: nothing is ever lost.
//! Archives of 32-bit texel ids are trimmed alike, their candidates verified
//! by their ids (alpha included) rather than their 24-bit colours.

use std::collections::BTreeMap;
use std::io::Read;

use rayon::prelude::*;

use crate::archive::archive_reader::ImageSource;
use crate::archive::options::TrimMode;
use crate::color::{AtomicColorSet, SeenSet};
use crate::count::scan::{Classifier, scan_image};
use crate::png::rows::{FileBytes, HEADER_BYTES, parse_header, read_file};

pub use crate::format::result::EmptyTile;

/// The trimming decision for an archive.
pub(crate) struct TrimPlan {
    /// Candidate per image, as an index into `empty_tiles`.
    candidate_of: Vec<Option<usize>>,
    /// The candidates, in (width, height, bytes) order.
    pub empty_tiles: Vec<EmptyTile>,
    /// Bytes of verified references, parallel to `empty_tiles`.
    verified_bytes: Vec<Option<FileBytes>>,
}

impl TrimPlan {
    /// A plan that trims nothing.
    pub(crate) fn none(images: usize) -> TrimPlan {
        TrimPlan { candidate_of: vec![None; images], empty_tiles: Vec::new(), verified_bytes: Vec::new() }
    }

    /// Finds candidate sizes and verifies one file of each by decoding it
    /// with `classifier` (24-bit colours).
    pub(crate) fn build(mode: TrimMode, images: &[ImageSource], classifier: &Classifier) -> TrimPlan {
        // A verified file has no stray pixels, so the shared stray set only
        // collects colours of candidates that fail verification; it is not
        // reported (those files are decoded again, and counted, later).
        let strays = AtomicColorSet::new();
        TrimPlan::build_verified(mode, images, |image| verify_empty(image, classifier, &strays))
    }

    /// Finds candidate sizes and verifies one file of each with
    /// `verify_empty`, which gives a file's bytes when every pixel of it is
    /// background (how depends on what a pixel names: 24-bit colours, or
    /// 32-bit texel ids, [`crate::count::rgba32::verify_empty`]).
    pub(crate) fn build_verified(
        mode: TrimMode,
        images: &[ImageSource],
        verify_empty: impl Fn(&ImageSource) -> Option<FileBytes> + Sync,
    ) -> TrimPlan {
        if mode == TrimMode::Off || images.is_empty() {
            return TrimPlan::none(images.len());
        }
        // Size and header of every file (unreadable ones are never candidates;
        // decoding will report them).
        let facts: Vec<Option<(u32, u32, u64)>> = images.par_iter().map(file_facts).collect();
        let mut by_size: BTreeMap<(u32, u32, u64), Vec<usize>> = BTreeMap::new();
        for (index, fact) in facts.iter().enumerate() {
            if let Some(key) = fact {
                by_size.entry(*key).or_default().push(index);
            }
        }
        let is_candidate = |bytes: u64, files: usize| match mode {
            TrimMode::Auto => files >= 2,
            TrimMode::Bytes(limit) => bytes <= limit,
            TrimMode::Off => false,
        };
        let chosen: Vec<((u32, u32, u64), Vec<usize>)> =
            by_size.into_iter().filter(|((_, _, bytes), files)| is_candidate(*bytes, files.len())).collect();
        // Verify each candidate's first file (in path order) in parallel.
        let verified_bytes: Vec<Option<FileBytes>> =
            chosen.par_iter().map(|(_, files)| verify_empty(&images[files[0]])).collect();
        let mut candidate_of = vec![None; images.len()];
        let mut empty_tiles = Vec::with_capacity(chosen.len());
        for (slot, ((width, height, bytes), files)) in chosen.into_iter().enumerate() {
            for &index in &files {
                candidate_of[index] = Some(slot);
            }
            empty_tiles.push(EmptyTile {
                width,
                height,
                bytes,
                reference: images[files[0]].name.clone(),
                verified: verified_bytes[slot].is_some(),
                candidates: files.len() as u64,
            });
        }
        TrimPlan { candidate_of, empty_tiles, verified_bytes }
    }

    /// True when `bytes` (the content of image `index`) are identical to a
    /// verified empty file, so decoding it could only find background.
    pub(crate) fn is_trimmable(&self, index: usize, bytes: &[u8]) -> bool {
        match self.candidate_of.get(index).copied().flatten() {
            Some(slot) => self.verified_bytes[slot].as_deref().is_some_and(|empty| empty == bytes),
            None => false,
        }
    }
}

/// `(width, height, file size)` of a PNG, or None when it cannot be read.
fn file_facts(image: &ImageSource) -> Option<(u32, u32, u64)> {
    // Never File::open here: a FIFO would block (decoding reports it instead).
    let mut file = crate::files::open_regular(&image.path).ok()?;
    let size = file.metadata().ok()?.len();
    let mut head = [0u8; HEADER_BYTES];
    file.read_exact(&mut head).ok()?;
    let header = parse_header(&image.path, &head).ok()?;
    Some((header.width, header.height, size))
}

/// Decodes `image`; returns its bytes when every pixel is background.
fn verify_empty(image: &ImageSource, classifier: &Classifier, strays: &AtomicColorSet) -> Option<FileBytes> {
    let bytes = read_file(&image.path).ok()?;
    let mut seen = SeenSet::new();
    let tally = scan_image(&image.path, &bytes, classifier, &mut seen, strays).ok()?;
    tally.is_pure_background().then_some(bytes)
}
