//! Capturing one scenario as several jobs: `--shard I/N` and `assemble`.
//!
//! Shard `I/N` renders the selected frames whose position in the selection
//! is I modulo N (both eyes and all tiles of a frame stay in one shard), into
//! the same archive folder as the other shards: tile files never collide, and
//! the files every shard writes (PIdT, legend, palette, vehicle) are the same
//! bytes, written atomically. Instead of `manifest.json` a shard writes its
//! part, `shards/manifest-I-of-N.json`; once every shard has finished,
//! [`assemble`] checks the parts against each other and joins them into the
//! `manifest.json` a single-process capture would have written (the same
//! bytes: tested), so nothing downstream knows how the archive was made.
//!
//! Frames are dealt round-robin rather than in blocks so that every shard gets
//! near and far frames alike (a close vehicle fills more tiles and costs more).

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use serde_json::Value;
use ufcsr::{MANIFEST_FILE, Manifest, Shard, format::CaptureRecord, format::FrameEntry, format::ShardRecord};

use crate::error::{CaptureError, Result};

/// Folder of the shards' partial manifests, inside the archive.
pub(crate) const SHARDS_DIR: &str = "shards";

/// Where shard `shard` writes its part of the manifest.
pub fn partial_manifest_path(archive: &Path, shard: Shard) -> PathBuf {
    archive.join(SHARDS_DIR).join(format!("manifest-{}-of-{}.json", shard.index, shard.count))
}

/// The `(position in the selection, frame)` pairs a shard (or the whole
/// capture, without one) renders.
pub(crate) fn frames_of_shard(selected: &[u32], shard: Option<Shard>) -> Vec<(usize, u32)> {
    selected
        .iter()
        .copied()
        .enumerate()
        .filter(|&(position, _)| shard.is_none_or(|s| s.takes(position)))
        .collect()
}

/// A shard's `capture.shard` record: which shard it is, the frames the
/// whole capture selected and how many tiles this shard listed, so that
/// [`assemble`] can account for every frame and tile.
pub(crate) fn shard_record(shard: Shard, selected: &[u32], tiles: usize) -> ShardRecord {
    ShardRecord {
        index: shard.index,
        count: shard.count,
        selected_frames: selected.to_vec(),
        tiles: tiles as u64,
    }
}

/// What [`assemble`] did.
#[derive(Debug)]
pub struct Assembled {
    pub manifest_path: PathBuf,
    pub shards: u32,
    pub frames: usize,
    pub tiles: usize,
}

/// One shard's part of the manifest, as [`assemble`] read it.
struct ShardPart {
    path: PathBuf,
    manifest: Manifest,
    shard: Shard,
    /// The frames the whole capture selected, as the part records them.
    selected: Vec<u32>,
    /// The tiles the shard listed when it wrote its part.
    tiles: usize,
}

/// Joins the partial manifests in `archive/shards/` into `archive/manifest.json`,
/// after checking that they are all there, each once, of one split, and
/// agree on everything but their tiles, frames and tile tallies. The partial
/// manifests are removed afterwards (the archive then reads like one made by
/// a single process); on any error nothing is written or removed.
pub fn assemble(archive: &Path) -> Result<Assembled> {
    let dir = archive.join(SHARDS_DIR);
    if std::fs::symlink_metadata(&dir).is_ok_and(|m| m.file_type().is_symlink()) {
        // Assembling removes the parts: through a link, from another folder.
        return Err(CaptureError::bad_file(
            &dir,
            "is a link: the shards' manifests must be in a real folder inside the archive",
        ));
    }
    let parts = read_parts(&dir)?;
    let count = check_complete(&dir, &parts)?;
    check_agreement(&parts)?;
    for part in &parts {
        check_accounted(part, &parts[0])?;
    }
    let first = &parts[0].manifest;
    let mut manifest = first.clone();
    manifest.tiles = parts.iter().flat_map(|part| part.manifest.tiles.iter().cloned()).collect();
    // Archive order: frame, then left before right, then row, then column.
    manifest.tiles.sort_by(|a, b| {
        (a.frame, a.eye != "left", a.row, a.col).cmp(&(b.frame, b.eye != "left", b.row, b.col))
    });
    let frames = joined_frames(&dir, &parts)?;
    let frame_count = frames.len();
    manifest.frames = Some(frames);
    manifest.capture = joined_capture(&parts);
    // The joined manifest must pass the same checks as any other (no tile twice).
    let manifest_path = archive.join(MANIFEST_FILE);
    let tiles = manifest.tiles.len();
    let text =
        serde_json::to_vec(&manifest).map_err(|e| CaptureError::bad_file(&manifest_path, e.to_string()))?;
    Manifest::parse(&manifest_path, &text)?;
    manifest.write_to_dir(archive)?;
    // The shards' capture is whole now (issue 41).
    ufcsr::files::mark_finished(archive)?;
    for part in &parts {
        ufcsr::files::remove_inside(archive, &part.path)?;
    }
    // The shards folder goes once empty (a file of the user's in it stays).
    if std::fs::read_dir(&dir).is_ok_and(|mut entries| entries.next().is_none()) {
        ufcsr::files::remove_inside(archive, &dir)?;
    }
    Ok(Assembled { manifest_path, shards: count, frames: frame_count, tiles })
}

/// The partial manifests in `dir`, by shard index; an error for any other
/// file there (atomic writes' temporary files aside), for a manifest whose
/// `capture.shard` does not match its name, and for none at all.
fn read_parts(dir: &Path) -> Result<Vec<ShardPart>> {
    let mut parts = Vec::new();
    let entries = std::fs::read_dir(dir).map_err(|e| {
        CaptureError::bad_file(dir, format!("no shard manifests to assemble ({e}); run the shards first"))
    })?;
    for entry in entries {
        let entry = entry.map_err(|e| CaptureError::io(dir, e))?;
        let path = entry.path();
        let name = entry.file_name().to_string_lossy().into_owned();
        let Some(shard) = shard_of_file_name(&name) else {
            if name.starts_with('.') {
                continue; // an atomic write's temporary file
            }
            return Err(CaptureError::bad_file(
                &path,
                "is not a shard manifest (manifest-I-of-N.json): remove it or move it out of shards/",
            ));
        };
        let bytes = ufcsr::files::read_limited(&path, ufcsr::files::SMALL_INPUT_LIMIT)?;
        let manifest = Manifest::parse(&path, &bytes)?;
        let Some(recorded) = manifest.capture.as_ref().and_then(|capture| capture.shard.clone()) else {
            return Err(CaptureError::bad_file(
                &path,
                "has no capture.shard (an older ufcsr capture, or edited): capture the shards again",
            ));
        };
        if (recorded.index, recorded.count) != (shard.index, shard.count) {
            return Err(CaptureError::bad_file(
                &path,
                format!("its capture.shard does not say {shard}, as its name does"),
            ));
        }
        let (selected, tiles) = (recorded.selected_frames, recorded.tiles as usize);
        parts.push(ShardPart { path, manifest, shard, selected, tiles });
    }
    parts.sort_by_key(|part| part.shard.index);
    if parts.is_empty() {
        return Err(CaptureError::bad_file(dir, "holds no shard manifest (manifest-I-of-N.json)"));
    }
    Ok(parts)
}

/// The number of shards, once every part is of the first part's split and
/// none is missing.
fn check_complete(dir: &Path, parts: &[ShardPart]) -> Result<u32> {
    let first = &parts[0];
    let count = first.shard.count;
    let mut seen = vec![false; count as usize];
    for part in parts {
        if part.shard.count != count {
            return Err(CaptureError::bad_file(
                &part.path,
                format!("is shard {}, but {} is of {count} shards", part.shard, first.path.display()),
            ));
        }
        seen[part.shard.index as usize] = true;
    }
    if let Some(missing) = seen.iter().position(|&s| !s) {
        return Err(CaptureError::bad_file(
            dir,
            format!(
                "shard {missing}/{count} is missing (no manifest-{missing}-of-{count}.json): it has not \
                 finished, or failed; run it again (--resume keeps its finished tiles)"
            ),
        ));
    }
    Ok(count)
}

/// An error naming the first field where a part differs from the first part
/// in anything but its tiles, frames and tallies.
fn check_agreement(parts: &[ShardPart]) -> Result<()> {
    let reference = without_shard_fields(&parts[0].manifest);
    for part in &parts[1..] {
        let other = without_shard_fields(&part.manifest);
        if other != reference {
            let field = differing_field(&reference, &other);
            return Err(CaptureError::bad_file(
                &part.path,
                format!(
                    "its {field} differs from {}'s: only shards of one capture (same scene, scenario, rig, \
                     palette and options) assemble",
                    parts[0].path.display()
                ),
            ));
        }
    }
    Ok(())
}

/// An error unless `part` holds exactly the frames its shard takes of the
/// selection (the one `first` records too) and the tiles it listed, each
/// of one of its frames: an emptied or edited part manifest would drop
/// frames from the archive without a word.
fn check_accounted(part: &ShardPart, first: &ShardPart) -> Result<()> {
    let refuse = |message: String| Err(CaptureError::bad_file(&part.path, message));
    if part.selected != first.selected {
        return refuse(format!("its selected frames differ from {}'s", first.path.display()));
    }
    let expected: Vec<u64> =
        frames_of_shard(&part.selected, Some(part.shard)).into_iter().map(|(_, f)| f.into()).collect();
    let frames: Vec<u64> = part.manifest.frame_records().iter().map(|r| u64::from(r.frame)).collect();
    if frames != expected {
        let missing: Vec<String> =
            expected.iter().filter(|f| !frames.contains(f)).take(8).map(u64::to_string).collect();
        return refuse(format!(
            "has {} frame records where shard {} takes {} of the {} selected frames (missing: {}): it \
             was emptied or edited; run the shard again",
            frames.len(),
            part.shard,
            expected.len(),
            part.selected.len(),
            if missing.is_empty() { "none, but others are there".to_string() } else { missing.join(", ") }
        ));
    }
    if part.manifest.tiles.len() != part.tiles {
        return refuse(format!(
            "lists {} tiles, but the shard wrote {}: it was emptied or edited; run the shard again",
            part.manifest.tiles.len(),
            part.tiles
        ));
    }
    if let Some(tile) = part.manifest.tiles.iter().find(|t| !frames.contains(&u64::from(t.frame))) {
        return refuse(format!(
            "lists a tile of frame {} ({} eye, row {}, column {}), not one of its frames",
            tile.frame, tile.eye, tile.row, tile.col
        ));
    }
    Ok(())
}

/// The parts' frame records in frame order; an error if a frame is in two.
fn joined_frames(dir: &Path, parts: &[ShardPart]) -> Result<Vec<FrameEntry>> {
    let mut frames: Vec<FrameEntry> = Vec::new();
    for part in parts {
        match &part.manifest.frames {
            Some(records) => frames.extend(records.iter().cloned()),
            None => return Err(CaptureError::bad_file(&part.path, "has no frames list")),
        }
    }
    frames.sort_by_key(|record| record.frame);
    let numbers: BTreeSet<u32> = frames.iter().map(|r| r.frame).collect();
    if numbers.len() != frames.len() {
        return Err(CaptureError::bad_file(
            dir,
            "two shards captured the same frame: they are not of one split",
        ));
    }
    Ok(frames)
}

/// The first part's `capture` record without its shard, with the tile
/// tallies summed over the parts.
fn joined_capture(parts: &[ShardPart]) -> Option<CaptureRecord> {
    let mut joined = parts[0].manifest.capture.as_ref()?.without_tallies();
    for capture in parts.iter().filter_map(|part| part.manifest.capture.as_ref()) {
        joined.add_tallies(capture);
    }
    Some(joined)
}

/// `manifest-I-of-N.json` → shard I/N.
fn shard_of_file_name(name: &str) -> Option<Shard> {
    let rest = name.strip_prefix("manifest-")?.strip_suffix(".json")?;
    let (index, count) = rest.split_once("-of-")?;
    Shard::new(index.parse().ok()?, count.parse().ok()?).ok()
}

/// A manifest without what differs between the shards of one capture, as
/// JSON (to compare every field, those the analyzer does not know included).
fn without_shard_fields(manifest: &Manifest) -> Value {
    let mut manifest = manifest.clone();
    manifest.tiles.clear();
    manifest.frames = None;
    manifest.capture = manifest.capture.as_ref().map(CaptureRecord::without_tallies);
    serde_json::to_value(manifest).unwrap_or(Value::Null)
}

/// The first top-level manifest field where two shards disagree.
fn differing_field(a: &Value, b: &Value) -> String {
    match (a, b) {
        (Value::Object(a), Value::Object(b)) => a
            .keys()
            .chain(b.keys())
            .find(|key| a.get(*key) != b.get(*key))
            .cloned()
            .unwrap_or_else(|| "settings".into()),
        _ => "settings".into(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shards_take_every_nth_frame_of_the_selection() {
        let selected = [0, 5, 10, 15, 20];
        let shard = Shard::new(1, 2).unwrap();
        assert_eq!(frames_of_shard(&selected, Some(shard)), vec![(1, 5), (3, 15)]);
        assert_eq!(frames_of_shard(&selected, None).len(), 5);
        let all: BTreeSet<u32> = (0..3)
            .flat_map(|i| frames_of_shard(&selected, Some(Shard::new(i, 3).unwrap())))
            .map(|(_, f)| f)
            .collect();
        assert_eq!(all, selected.into_iter().collect());
    }

    #[test]
    fn shard_file_names_round_trip() {
        let shard = Shard::new(3, 8).unwrap();
        let path = partial_manifest_path(Path::new("a"), shard);
        let name = path.file_name().unwrap().to_string_lossy();
        assert_eq!(shard_of_file_name(&name), Some(shard));
        for bad in ["manifest-8-of-8.json", "manifest-1-of-.json", "manifest.json", "notes.txt"] {
            assert_eq!(shard_of_file_name(bad), None, "{bad}");
        }
    }
}
