//! Atomic output files: write to a temporary file beside the target, then rename.
//!
//! An interrupted run therefore leaves either the previous file or the complete
//! new one, never half a result that a later script would read as truth. A
//! result set of several files is written into a [`Staging`] folder first and
//! moved into place only when every file was written (with the old files
//! restored if a move fails). Temporary files and staging folders are
//! registered while they exist, so that a signal handler in the binaries can
//! remove them ([`remove_temporaries`]) before exiting.

use std::fs::{self, File};
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Mutex, PoisonError};

use crate::error::{Error, Result};

/// Temporary files and folders that exist right now.
static TEMPORARIES: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// Set by [`remove_temporaries`]: from then on no temporary file is created,
/// so a worker thread cannot make one after the handler has swept them.
static CLOSED: AtomicBool = AtomicBool::new(false);

/// Creates the temporary file `path` and registers it in one step, under the
/// registry's lock: either the sweep of [`remove_temporaries`] sees the file,
/// or the file is never made (the write fails as interrupted).
fn create_registered(path: &Path) -> std::io::Result<File> {
    let mut registered = TEMPORARIES.lock().unwrap_or_else(PoisonError::into_inner);
    if CLOSED.load(Ordering::SeqCst) {
        return Err(std::io::Error::new(std::io::ErrorKind::Interrupted, "the run is being interrupted"));
    }
    let file = create_new(path)?;
    registered.push(path.to_path_buf());
    Ok(file)
}

/// Registers a file or folder the process made for its own use (e.g. the
/// capture's private runtime folder) to be removed with the temporaries when
/// the run is interrupted ([`remove_temporaries`]).
pub fn remove_on_interrupt(path: &Path) {
    register(path);
}

fn register(path: &Path) {
    TEMPORARIES.lock().unwrap_or_else(PoisonError::into_inner).push(path.to_path_buf());
}

fn unregister(path: &Path) {
    let mut registered = TEMPORARIES.lock().unwrap_or_else(PoisonError::into_inner);
    if let Some(at) = registered.iter().rposition(|p| p == path) {
        registered.swap_remove(at);
    }
}

/// Held while a result set is moved into place ([`Staging::commit`]): an
/// interrupt waits for it, so `--out` never holds half an old and half a new set.
static COMMITTING: Mutex<()> = Mutex::new(());

/// Removes every temporary file and staging folder this process has open
/// (for a SIGINT/SIGTERM handler, which then exits): an interrupted run
/// leaves the previous outputs and nothing else. A commit in progress is
/// finished first (a few renames), never cut in half; after it no new temporary file is created (a write
/// then fails as interrupted). Returns how many were
/// removed.
pub fn remove_temporaries() -> usize {
    CLOSED.store(true, Ordering::SeqCst);
    remove_registered(&TEMPORARIES)
}

/// [`remove_temporaries`] of a registry (tests use their own).
fn remove_registered(registry: &Mutex<Vec<PathBuf>>) -> usize {
    let _commit = COMMITTING.lock().unwrap_or_else(PoisonError::into_inner);
    let registered = std::mem::take(&mut *registry.lock().unwrap_or_else(PoisonError::into_inner));
    let mut removed = 0;
    for path in registered {
        removed += usize::from(remove_path(&path));
    }
    removed
}

/// Removes a file or a folder tree; folders are retried, because worker
/// threads may still be writing into them when an interrupt arrives.
#[allow(clippy::disallowed_methods)] // the layer: removes only registered temporaries of this process (links not followed)
fn remove_path(path: &Path) -> bool {
    let is_dir = fs::symlink_metadata(path).is_ok_and(|m| m.is_dir());
    if !is_dir {
        return fs::remove_file(path).is_ok();
    }
    for _ in 0..20 {
        if fs::remove_dir_all(path).is_ok() || !path.exists() {
            return true;
        }
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    false
}

/// Staging folders are named `.ufcsr-staging-<pid>-<n>`.
const STAGING_PREFIX: &str = ".ufcsr-staging-";

/// A staging folder older than this is stale even if a process of its id
/// runs (ids are reused): no result set takes a day to write.
const STALE_AFTER: std::time::Duration = std::time::Duration::from_secs(24 * 3600);

/// A folder inside the output folder that a result set is written into, then
/// moved into place by [`Staging::commit`]; removed if dropped uncommitted.
pub struct Staging {
    dir: PathBuf,
}

impl Staging {
    /// A fresh staging folder inside `out_dir` (same file system: moves are
    /// renames). It is registered before it exists, so an interrupt at any
    /// moment removes it.
    #[allow(clippy::disallowed_methods)] // the layer: a fresh folder of a new name, never an existing one
    pub fn new(out_dir: &Path) -> Result<Staging> {
        static NEXT: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
        loop {
            let n = NEXT.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
            let dir = out_dir.join(format!("{STAGING_PREFIX}{}-{n}", std::process::id()));
            register(&dir);
            match fs::create_dir(&dir) {
                Ok(()) => return Ok(Staging { dir }),
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => unregister(&dir),
                Err(e) => {
                    unregister(&dir);
                    return Err(Error::io(out_dir, e));
                }
            }
        }
    }

    pub fn path(&self) -> &Path {
        &self.dir
    }

    /// Moves every file of the staging folder into `out_dir`, replacing
    /// same-named files (folders such as `views/` are merged file by file, so
    /// nothing else in them is lost; a link where a folder goes is replaced
    /// by a real folder, never written through). When `out_dir` held an
    /// earlier result set (its `result.json`), the files of `set` (every
    /// path, relative to `out_dir`, a set can have, `plots/parts.svg`
    /// included) that the new set lacks are taken away, so no stale
    /// `frames.csv` or plot sits beside results it does not belong to. If a
    /// move fails, everything is put back: `out_dir` holds the old set or
    /// the new. An interrupt waits for the commit to end. Afterwards stale
    /// staging folders of killed runs are removed ([`remove_stale_staging`]).
    #[allow(clippy::disallowed_methods)] // the layer: makes its own backup folder, removes its own journal
    pub fn commit(self, out_dir: &Path, set: &[&str]) -> Result<()> {
        let guard = COMMITTING.lock().unwrap_or_else(PoisonError::into_inner);
        finish_interrupted_commit(out_dir, set)?;
        let backups = self.dir.join(".replaced");
        let earlier_set = fs::symlink_metadata(out_dir.join("result.json")).is_ok_and(|m| m.is_file());
        let mut moves = Moves { backups: backups.clone(), counter: 0, done: Vec::new() };
        let journal = Journal::of(&self.dir, if earlier_set { set } else { &[] })?;
        let outcome = (|| -> Result<()> {
            fs::create_dir_all(&backups).map_err(|e| Error::io(&backups, e))?;
            journal.write(out_dir)?;
            move_tree(&self.dir, out_dir, &mut moves)?;
            if earlier_set {
                remove_stale_members(out_dir, set, &mut moves)?;
            }
            Ok(())
        })();
        if outcome.is_err() {
            moves.undo();
        }
        // Whole, old or new: the journal has nothing left to finish.
        let _ = fs::remove_file(out_dir.join(COMMIT_JOURNAL));
        drop(self);
        drop(guard);
        if outcome.is_ok() {
            remove_stale_staging(out_dir);
        }
        outcome
    }
}

/// The moves of one commit, to undo on failure.
struct Moves {
    backups: PathBuf,
    counter: usize,
    done: Vec<Move>,
}

enum Move {
    /// A file moved to `target`, the file it replaced (if any) in the backup.
    File { target: PathBuf, backup: Option<PathBuf> },
    /// A link replaced by a new folder: the link saved in `backup`.
    Link { target: PathBuf, backup: PathBuf },
}

impl Moves {
    /// Moves whatever is at `target` (a file or a link, never followed) into
    /// the backups; returns where it went.
    #[allow(clippy::disallowed_methods)] // the layer: moves a file or a link itself (never followed) into the run's own backups
    fn back_up(&mut self, target: &Path) -> Result<Option<PathBuf>> {
        if fs::symlink_metadata(target).is_err() {
            return Ok(None);
        }
        self.counter += 1;
        let backup = self.backups.join(self.counter.to_string());
        fs::rename(target, &backup).map_err(|e| Error::io(target, e))?;
        Ok(Some(backup))
    }

    #[allow(clippy::disallowed_methods)] // the layer: puts back what this commit moved, inside the output folder
    fn undo(&self) {
        for change in self.done.iter().rev() {
            match change {
                Move::File { target, backup } => {
                    let _ = fs::remove_file(target);
                    if let Some(backup) = backup {
                        let _ = fs::rename(backup, target);
                    }
                }
                Move::Link { target, backup } => {
                    let _ = fs::remove_dir_all(target);
                    let _ = fs::rename(backup, target);
                }
            }
        }
    }
}

/// Takes away the members of `set` that this commit did not write (only
/// files, and never through a link: a linked folder is not ours to empty).
fn remove_stale_members(out_dir: &Path, set: &[&str], moves: &mut Moves) -> Result<()> {
    for name in set {
        let target = out_dir.join(name);
        let written = moves.done.iter().any(|m| matches!(m, Move::File { target: t, .. } if *t == target));
        let is_file = fs::symlink_metadata(&target).is_ok_and(|m| m.is_file() || m.file_type().is_symlink());
        if written || !is_file || crate::files::crosses_link(out_dir, Path::new(name)) {
            continue;
        }
        // Undo puts the backup back (nothing was moved in).
        let backup = moves.back_up(&target)?;
        moves.done.push(Move::File { target, backup });
    }
    Ok(())
}

/// The commit journal: written into the output folder before a commit's
/// first move and removed after its last. Only a run killed with SIGKILL in
/// between (an interrupt waits for the commit) leaves it, beside a result set
/// that is part old, part new; then readers of the set refuse it
/// ([`interrupted_commit`]), and the next commit into the folder first
/// finishes the killed one ([`finish_interrupted_commit`]): the staging
/// folder still holds every file not yet moved.
const COMMIT_JOURNAL: &str = ".ufcsr-commit.json";

/// The most bytes a journal may have: it lists one result set's files (a
/// few hundred names), so a larger one is not ours (a link to `/dev/zero`).
const JOURNAL_LIMIT: u64 = 4 << 20;

#[derive(serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct Journal {
    /// The staging folder's name (inside the output folder).
    staging: String,
    /// Every file of the new set, relative to the output folder.
    files: Vec<String>,
    /// The set's members that the commit takes away when the new set lacks them.
    stale: Vec<String>,
}

/// A relative path of plain names only (no `..`, no root, not empty).
fn plain(name: &str) -> bool {
    !name.is_empty() && Path::new(name).components().all(|c| matches!(c, std::path::Component::Normal(_)))
}

/// Reads and checks the journal at `path` through the layer's reader (a
/// regular file, at most [`JOURNAL_LIMIT`] bytes): a truncated, foreign or
/// malformed journal is an error naming it, never ignored.
fn read_journal(path: &Path) -> Result<Journal> {
    parse_journal(path, &crate::files::read_limited(path, JOURNAL_LIMIT)?)
}

/// Parses and checks a journal's bytes (`path` for messages; the fuzz
/// target `journal` calls this).
pub(crate) fn parse_journal(path: &Path, bytes: &[u8]) -> Result<Journal> {
    let bad = |why: String| {
        Error::bad_file(
            path,
            format!("an unfinished commit's journal {why}; remove it if no run is writing here"),
        )
    };
    let journal: Journal = serde_json::from_slice(bytes).map_err(|e| bad(format!("cannot be read ({e})")))?;
    if !journal.staging.starts_with(STAGING_PREFIX) || !plain(&journal.staging) {
        return Err(bad(format!("names {:?}, no staging folder of ours", journal.staging)));
    }
    if let Some(name) = journal.files.iter().chain(&journal.stale).find(|name| !plain(name)) {
        return Err(bad(format!("names {name:?}, which is not a plain path inside the output folder")));
    }
    Ok(journal)
}

impl Journal {
    /// The journal of committing `staging`, which replaces an earlier set's `set` members.
    fn of(staging: &Path, set: &[&str]) -> Result<Journal> {
        let mut files = Vec::new();
        let mut pending = vec![PathBuf::new()];
        while let Some(relative) = pending.pop() {
            let folder = staging.join(&relative);
            for entry in fs::read_dir(&folder).map_err(|e| Error::io(&folder, e))?.flatten() {
                let name = relative.join(entry.file_name());
                if name == Path::new(".replaced") {
                    continue;
                }
                if entry.file_type().is_ok_and(|t| t.is_dir()) {
                    pending.push(name);
                } else {
                    files.push(name.to_string_lossy().replace('\\', "/"));
                }
            }
        }
        files.sort();
        let stale = set.iter().filter(|m| !files.iter().any(|f| f == *m)).map(|m| (*m).to_string()).collect();
        let staging = staging.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
        Ok(Journal { staging, files, stale })
    }

    fn write(&self, out_dir: &Path) -> Result<()> {
        let text = serde_json::to_vec(self)
            .map_err(|e| Error::bad_file(&out_dir.join(COMMIT_JOURNAL), e.to_string()))?;
        write_bytes_atomically(&out_dir.join(COMMIT_JOURNAL), &text)
    }
}

/// The journal of a commit into `dir` that a killed run left unfinished
/// (`None` when there is none, or its run is still committing); an error
/// naming the journal when it is there but unreadable (truncated, foreign,
/// a FIFO, too large).
pub fn interrupted_commit(dir: &Path) -> Result<Option<PathBuf>> {
    let path = dir.join(COMMIT_JOURNAL);
    if fs::symlink_metadata(&path).is_err() {
        return Ok(None);
    }
    let journal = read_journal(&path)?;
    let pid = journal.staging.strip_prefix(STAGING_PREFIX).and_then(|rest| rest.split('-').next());
    let Some(pid) = pid.and_then(|id| id.parse::<u32>().ok()) else { return Ok(Some(path)) };
    Ok((pid == std::process::id() || !process_alive(pid)).then_some(path))
}

/// Finishes the commit a killed run left in `out_dir` (see [`COMMIT_JOURNAL`]):
/// the files still in its staging folder are moved into place, the members
/// the new set lacks are taken away, and the staging folder and journal are
/// removed, so the folder holds the new set whole. Only members of `set`
/// (the files a result set owns) are ever taken away: a journal naming any
/// other file is refused. Returns whether there was one.
#[allow(clippy::disallowed_methods)] // the layer: moves only a validated journal's staging folder's files, removes only the set's members
pub(crate) fn finish_interrupted_commit(out_dir: &Path, set: &[&str]) -> Result<bool> {
    let Some(path) = interrupted_commit(out_dir)? else { return Ok(false) };
    let journal = read_journal(&path)?;
    if let Some(member) = journal.stale.iter().find(|m| !set.contains(&m.as_str())) {
        return Err(Error::bad_file(
            &path,
            format!(
                "an unfinished commit's journal would remove {member:?}, which is no file of a result set; \
                 remove the journal if no run is writing here"
            ),
        ));
    }
    let staging = out_dir.join(&journal.staging);
    if fs::symlink_metadata(&staging).is_ok_and(|m| m.is_dir()) {
        let backups = staging.join(".replaced");
        fs::create_dir_all(&backups).map_err(|e| Error::io(&backups, e))?;
        // Numbered past what the killed run backed up (its backups go with the folder).
        let counter = fs::read_dir(&backups).map_or(0, |entries| entries.count()) + 1_000_000;
        let mut moves = Moves { backups, counter, done: Vec::new() };
        move_tree(&staging, out_dir, &mut moves)?;
        fs::remove_dir_all(&staging).map_err(|e| Error::io(&staging, e))?;
    }
    for member in &journal.stale {
        let target = out_dir.join(member);
        let is_file = fs::symlink_metadata(&target).is_ok_and(|m| m.is_file());
        if is_file && !crate::files::crosses_link(out_dir, Path::new(member)) {
            fs::remove_file(&target).map_err(|e| Error::io(&target, e))?;
        }
    }
    fs::remove_file(&path).map_err(|e| Error::io(&path, e))?;
    Ok(true)
}

/// Moves the files under `from` into `to` (folders created or merged; a link
/// where a folder goes replaced by a real folder), backing up each replaced
/// file and recording every move. The staging folder's own backup folder is
/// skipped (only the top level can hold it: a path deeper down is never it).
#[allow(clippy::disallowed_methods)] // the layer: renames inside one output folder, a link where a folder goes set aside, never followed
fn move_tree(from: &Path, to: &Path, moves: &mut Moves) -> Result<()> {
    let mut entries: Vec<PathBuf> = fs::read_dir(from)
        .map_err(|e| Error::io(from, e))?
        .map(|entry| entry.map(|e| e.path()).map_err(|e| Error::io(from, e)))
        .collect::<Result<_>>()?;
    entries.sort();
    for entry in entries {
        let Some(name) = entry.file_name() else { continue };
        if entry == moves.backups {
            continue;
        }
        let target = to.join(name);
        if fs::symlink_metadata(&entry).is_ok_and(|m| m.is_dir()) {
            match fs::symlink_metadata(&target) {
                // A real folder (links are not followed here): merge into it.
                Ok(metadata) if metadata.is_dir() => {}
                // A link (or a file) where a folder goes: never write through
                // it; set the link itself aside and make a real folder.
                Ok(_) => {
                    if let Some(backup) = moves.back_up(&target)? {
                        moves.done.push(Move::Link { target: target.clone(), backup });
                    }
                    fs::create_dir(&target).map_err(|e| Error::io(&target, e))?;
                }
                Err(_) => fs::create_dir_all(&target).map_err(|e| Error::io(&target, e))?,
            }
            move_tree(&entry, &target, moves)?;
            continue;
        }
        let backup = moves.back_up(&target)?;
        let renamed = fs::rename(&entry, &target).map_err(|e| Error::io(&target, e));
        moves.done.push(Move::File { target, backup });
        renamed?;
    }
    Ok(())
}

/// Removes staging folders in `out_dir` that no running process owns: the
/// leftovers of a run killed with SIGKILL (which no handler sees). A folder
/// is stale when the process whose id its name carries is gone (on Linux,
/// no `/proc/<pid>`), when its name carries no id (an older version's
/// name), or when it is older than a day. Returns how many were removed.
#[allow(clippy::disallowed_methods)] // the layer: removes only staging folders (by name) of dead processes
pub fn remove_stale_staging(out_dir: &Path) -> usize {
    let Ok(entries) = fs::read_dir(out_dir) else { return 0 };
    let mut own: Vec<PathBuf> = TEMPORARIES.lock().unwrap_or_else(PoisonError::into_inner).clone();
    // A killed commit's staging folder holds the files its journal still needs.
    if let Ok(journal) = read_journal(&out_dir.join(COMMIT_JOURNAL)) {
        own.push(out_dir.join(journal.staging));
    }
    let mut removed = 0;
    for entry in entries.flatten() {
        let name = entry.file_name().to_string_lossy().into_owned();
        let Some(rest) = name.strip_prefix(STAGING_PREFIX) else { continue };
        let path = entry.path();
        let is_dir = fs::symlink_metadata(&path).is_ok_and(|m| m.is_dir());
        if !is_dir || own.contains(&path) {
            continue;
        }
        let pid = rest.split('-').next().and_then(|id| id.parse::<u32>().ok());
        let alive = pid.is_some_and(|pid| pid != std::process::id() && process_alive(pid));
        let old = entry
            .metadata()
            .and_then(|m| m.modified())
            .ok()
            .and_then(|t| t.elapsed().ok())
            .is_some_and(|age| age > STALE_AFTER);
        if (!alive || old) && fs::remove_dir_all(&path).is_ok() {
            removed += 1;
        }
    }
    removed
}

/// Whether process `pid` runs (Linux: `/proc/<pid>` exists; elsewhere
/// assumed running, so only the age rule applies).
/// Removes the temporary files ([`write_atomically`]'s `.NAME.tmp-PID`)
/// that killed processes left in `dir`: SIGKILL runs no handler, so a
/// capture killed while it wrote tiles left `.f0001_….png.tmp-PID` files
/// that `--resume` kept. Only plain files and links of that name whose
/// process is gone are removed (never one of a process still running, nor
/// what a link points to). Returns how many were removed.
#[allow(clippy::disallowed_methods)] // the layer: only dead processes' temporaries, by name, links not followed
pub fn remove_stale_temporaries(dir: &Path) -> usize {
    let Ok(entries) = fs::read_dir(dir) else { return 0 };
    let mut removed = 0;
    for entry in entries.flatten() {
        let name = entry.file_name();
        let name = name.to_string_lossy();
        let pid = name
            .strip_prefix('.')
            .and_then(|rest| rest.rsplit_once(".tmp-"))
            .and_then(|(_, pid)| pid.parse::<u32>().ok());
        let Some(pid) = pid else { continue };
        let is_dir = fs::symlink_metadata(entry.path()).is_ok_and(|m| m.is_dir());
        if is_dir || pid == std::process::id() || process_alive(pid) {
            continue;
        }
        if fs::remove_file(entry.path()).is_ok() {
            removed += 1;
        }
    }
    removed
}

/// Removes the entries of `dir` named `PREFIX<pid>` (a killed run's own
/// folder, e.g. the capture's `ufcsr-runtime-<pid>` in the temporary
/// folder) whose process is gone, through [`crate::files::remove_inside`]
/// (a link is removed itself, never followed). Returns how many were removed.
pub fn remove_dead_runs(dir: &Path, prefix: &str) -> usize {
    let Ok(entries) = fs::read_dir(dir) else { return 0 };
    let mut removed = 0;
    for entry in entries.flatten() {
        let name = entry.file_name();
        let pid = name.to_str().and_then(|n| n.strip_prefix(prefix)).and_then(|pid| pid.parse::<u32>().ok());
        let Some(pid) = pid else { continue };
        if pid != std::process::id()
            && !process_alive(pid)
            && crate::files::remove_inside(dir, &entry.path()).unwrap_or(false)
        {
            removed += 1;
        }
    }
    removed
}

fn process_alive(pid: u32) -> bool {
    if cfg!(target_os = "linux") { Path::new(&format!("/proc/{pid}")).exists() } else { true }
}

impl Drop for Staging {
    #[allow(clippy::disallowed_methods)] // the layer: removes the run's own staging folder
    fn drop(&mut self) {
        let _ = fs::remove_dir_all(&self.dir);
        unregister(&self.dir);
    }
}

/// Writes `path` atomically: `fill` writes into a buffered temporary file in the
/// same directory, which is flushed, synced and renamed over `path` only if
/// `fill` succeeds. On failure the temporary file is removed.
#[allow(clippy::disallowed_methods)] // the layer: renames a registered temporary over a regular file or nothing
pub fn write_atomically<F>(path: &Path, fill: F) -> Result<()>
where
    F: FnOnce(&mut BufWriter<BoundedWrites>) -> std::io::Result<()>,
{
    refuse_replacing_non_file(path)?;
    let temporary = temporary_path(path);
    let outcome = (|| {
        let file = create_registered(&temporary)?;
        let mut writer = BufWriter::with_capacity(WRITE_LIMIT, BoundedWrites(file));
        fill(&mut writer)?;
        writer.flush()?;
        let BoundedWrites(file) = writer.into_inner().map_err(|e| e.into_error())?;
        file.sync_all()?;
        drop(file);
        fs::rename(&temporary, path)
    })();
    unregister(&temporary);
    outcome.map_err(|source| {
        let _ = fs::remove_file(&temporary);
        Error::io(path, source)
    })
}

/// Errors, naming `path`, when something is there that an output never
/// replaces: a device (`--out /dev/null` would replace the machine's
/// `/dev/null`), a FIFO, a socket, a folder, or a link (`--out /dev/stdout`
/// would replace the link and write nothing). Only a regular file, or
/// nothing, is replaced.
pub fn refuse_replacing_non_file(path: &Path) -> Result<()> {
    match fs::symlink_metadata(path) {
        Ok(metadata) if metadata.file_type().is_symlink() => Err(Error::bad_file(
            path,
            "is a link: an output never replaces a link (nor writes through one); remove it or choose another path",
        )),
        Ok(metadata) if !metadata.is_file() => Err(Error::bad_file(
            path,
            format!(
                "is {}: an output only replaces a regular file; choose another path",
                crate::files::limited_read::kind(&metadata)
            ),
        )),
        _ => Ok(()),
    }
}

/// The most bytes [`BoundedWrites`] hands the system at once.
const WRITE_LIMIT: usize = 1 << 20;

/// A file written at most [`WRITE_LIMIT`] bytes per system call.
///
/// `BufWriter` passes a write larger than its buffer straight through, and
/// the png encoder writes a whole image's compressed data at once: one
/// write of 49 MB into a new file (the generated archive's `heatmap.png`)
/// took 0.48–0.72 s on the development machine (Linux 6.18, `strace -T`),
/// against 0.19 s for the whole heatmap stage in 1 MiB pieces, while the
/// 82 MB of `result.json` in 1 MiB writes took 0.03 s.
pub struct BoundedWrites<W = File>(W);

impl<W: Write> Write for BoundedWrites<W> {
    fn write(&mut self, bytes: &[u8]) -> std::io::Result<usize> {
        self.0.write(&bytes[..bytes.len().min(WRITE_LIMIT)])
    }

    fn flush(&mut self) -> std::io::Result<()> {
        self.0.flush()
    }
}

/// Creates `path` new (`O_EXCL`): whatever sits there already, a link
/// planted there included, is removed (the link itself, never what it points
/// to) and the file made afresh, so a write never follows a link.
#[allow(clippy::disallowed_methods, clippy::disallowed_types)] // the layer: O_EXCL: a link planted under the temporary's name is removed, never followed
fn create_new(path: &Path) -> std::io::Result<File> {
    let mut options = fs::OpenOptions::new();
    options.write(true).create_new(true);
    match options.open(path) {
        Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {
            fs::remove_file(path)?;
            options.open(path)
        }
        other => other,
    }
}

/// Copies the regular file `from` (at most `limit` bytes) to `to`,
/// atomically, never through a link at `to` nor over a device.
pub fn copy_into(from: &Path, to: &Path, limit: u64) -> Result<()> {
    write_bytes_atomically(to, &crate::files::read_limited(from, limit)?)
}

/// Writes bytes to `path` atomically.
pub fn write_bytes_atomically(path: &Path, bytes: &[u8]) -> Result<()> {
    write_atomically(path, |writer| writer.write_all(bytes))
}

/// `dir/.name.tmp-<pid>`: same directory, so the rename never crosses devices.
fn temporary_path(path: &Path) -> PathBuf {
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    path.with_file_name(format!(".{name}.tmp-{}", std::process::id()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bounded_writes_hand_on_at_most_a_mebibyte_per_call_and_lose_nothing() {
        /// Records the size of every write it is handed.
        struct Sizes(Vec<usize>, Vec<u8>);
        impl Write for Sizes {
            fn write(&mut self, bytes: &[u8]) -> std::io::Result<usize> {
                self.0.push(bytes.len());
                self.1.extend_from_slice(bytes);
                Ok(bytes.len())
            }
            fn flush(&mut self) -> std::io::Result<()> {
                Ok(())
            }
        }
        let data: Vec<u8> = (0..(5 * WRITE_LIMIT / 2)).map(|i| (i % 251) as u8).collect();
        let mut writer = BufWriter::with_capacity(WRITE_LIMIT, BoundedWrites(Sizes(Vec::new(), Vec::new())));
        writer.write_all(b"header").unwrap();
        writer.write_all(&data).unwrap();
        writer.flush().unwrap();
        let BoundedWrites(Sizes(sizes, written)) = writer.into_inner().ok().unwrap();
        assert!(sizes.iter().all(|&size| size <= WRITE_LIMIT), "{sizes:?}");
        assert_eq!(written.len(), 6 + data.len());
        assert_eq!(&written[..6], b"header");
        assert_eq!(&written[6..], &data[..]);
    }

    #[test]
    fn failed_write_leaves_old_file_and_no_temporary() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("result.json");
        write_bytes_atomically(&path, b"old").unwrap();
        let failed = write_atomically(&path, |w| {
            w.write_all(b"half")?;
            Err(std::io::Error::other("interrupted"))
        });
        assert!(failed.is_err());
        assert_eq!(fs::read(&path).unwrap(), b"old");
        assert_eq!(fs::read_dir(dir.path()).unwrap().count(), 1);
    }

    #[cfg(unix)]
    #[test]
    fn a_link_planted_as_the_temporary_file_is_not_written_through() {
        let dir = tempfile::tempdir().unwrap();
        let precious = dir.path().join("precious.txt");
        fs::write(&precious, b"mine").unwrap();
        let path = dir.path().join("result.json");
        std::os::unix::fs::symlink(&precious, temporary_path(&path)).unwrap();
        write_bytes_atomically(&path, b"new").unwrap();
        assert_eq!(fs::read(&precious).unwrap(), b"mine");
        assert_eq!(fs::read(&path).unwrap(), b"new");
    }

    #[test]
    fn an_interrupt_waits_for_a_commit_in_progress() {
        let commit = COMMITTING.lock().unwrap_or_else(PoisonError::into_inner);
        let (sender, receiver) = std::sync::mpsc::channel();
        std::thread::spawn(move || {
            static NONE: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());
            remove_registered(&NONE);
            let _ = sender.send(());
        });
        let waited = receiver.recv_timeout(std::time::Duration::from_millis(200));
        assert!(waited.is_err(), "the interrupt did not wait for the commit");
        drop(commit);
        receiver.recv_timeout(std::time::Duration::from_secs(5)).expect("the interrupt never ran");
    }

    #[test]
    fn a_commit_killed_halfway_is_refused_by_readers_and_finished_by_the_next_commit() {
        let out = tempfile::tempdir().unwrap();
        let out = out.path();
        for name in ["result.json", "parts.csv", "frames.csv"] {
            fs::write(out.join(name), "old").unwrap();
        }
        // A run (its process long gone) staged a new set without frames.csv,
        // wrote its journal and had moved parts.csv when it was killed.
        let staging = out.join(format!("{STAGING_PREFIX}999999999-0"));
        fs::create_dir_all(staging.join("plots")).unwrap();
        for name in ["result.json", "parts.csv", "plots/a.svg"] {
            fs::write(staging.join(name), "new").unwrap();
        }
        let set = ["result.json", "parts.csv", "frames.csv", "plots/a.svg"];
        let journal = Journal::of(&staging, &set).unwrap();
        assert_eq!(journal.files, ["parts.csv", "plots/a.svg", "result.json"]);
        assert_eq!(journal.stale, ["frames.csv"]);
        journal.write(out).unwrap();
        fs::rename(staging.join("parts.csv"), out.join("parts.csv")).unwrap();
        // Half old, half new: named as such, and its staging folder is kept for the finish.
        assert!(interrupted_commit(out).unwrap().is_some());
        assert_eq!(remove_stale_staging(out), 0);
        assert!(staging.is_dir());
        // The next commit into the folder finishes the killed one first, then commits its own.
        let next = Staging::new(out).unwrap();
        fs::write(next.path().join("result.json"), "newer").unwrap();
        fs::write(next.path().join("parts.csv"), "newer").unwrap();
        fs::create_dir(next.path().join("plots")).unwrap();
        fs::write(next.path().join("plots/a.svg"), "newer").unwrap();
        next.commit(out, &set).unwrap();
        for name in ["result.json", "parts.csv", "plots/a.svg"] {
            assert_eq!(fs::read_to_string(out.join(name)).unwrap(), "newer", "{name}");
        }
        assert!(!out.join("frames.csv").exists(), "the killed set lacked frames.csv");
        assert!(
            !staging.exists()
                && !out.join(COMMIT_JOURNAL).exists()
                && interrupted_commit(out).unwrap().is_none()
        );

        // Finishing alone (what the next commit does first) gives the killed run's set whole.
        fs::write(out.join("frames.csv"), "old").unwrap();
        fs::create_dir(&staging).unwrap();
        fs::write(staging.join("result.json"), "new").unwrap();
        Journal {
            staging: staging.file_name().unwrap().to_string_lossy().into(),
            files: vec!["result.json".into()],
            stale: vec!["frames.csv".into()],
        }
        .write(out)
        .unwrap();
        assert!(finish_interrupted_commit(out, &set).unwrap());
        assert_eq!(fs::read_to_string(out.join("result.json")).unwrap(), "new");
        assert!(!out.join("frames.csv").exists() && !staging.exists());
        assert!(!finish_interrupted_commit(out, &set).unwrap(), "nothing left to finish");
    }

    #[test]
    fn temporaries_of_killed_processes_are_removed_and_others_kept() {
        let dir = tempfile::tempdir().unwrap();
        let dir = dir.path();
        let own = format!(".b.png.tmp-{}", std::process::id());
        for name in [".a.png.tmp-999999999", own.as_str(), "c.png", ".d.png.tmp-x"] {
            fs::write(dir.join(name), "x").unwrap();
        }
        assert_eq!(remove_stale_temporaries(dir), 1);
        assert!(!dir.join(".a.png.tmp-999999999").exists());
        for kept in [own.as_str(), "c.png", ".d.png.tmp-x"] {
            assert!(dir.join(kept).exists(), "{kept}");
        }
    }

    #[test]
    fn folders_of_dead_runs_are_removed_and_live_ones_kept() {
        let dir = tempfile::tempdir().unwrap();
        let dir = dir.path();
        let own = format!("run-{}", std::process::id());
        for name in ["run-999999999", own.as_str(), "run-x", "other-999999999"] {
            fs::create_dir_all(dir.join(name).join("inside")).unwrap();
        }
        assert_eq!(remove_dead_runs(dir, "run-"), 1);
        assert!(!dir.join("run-999999999").exists());
        for kept in [own.as_str(), "run-x", "other-999999999"] {
            assert!(dir.join(kept).is_dir(), "{kept}");
        }
    }

    #[test]
    fn a_truncated_or_foreign_journal_is_an_error_naming_it_and_removes_nothing() {
        let out = tempfile::tempdir().unwrap();
        let out = out.path();
        fs::write(out.join("result.json"), "old").unwrap();
        fs::write(out.join("precious.txt"), "mine").unwrap();
        let set = ["result.json", "frames.csv"];
        let journal = out.join(COMMIT_JOURNAL);
        let staging = format!("{STAGING_PREFIX}999999999-0");
        let cases = [
            format!("{{\"staging\": \"{staging}\", \"files\": [\"result.json\"], \"sta"),
            format!("{{\"staging\": \"{staging}\", \"files\": [], \"stale\": [\"precious.txt\"]}}"),
            format!("{{\"staging\": \"{staging}\", \"files\": [], \"stale\": [\"../x\"]}}"),
            "{\"staging\": \"../elsewhere\", \"files\": [], \"stale\": []}".to_string(),
        ];
        for text in cases {
            fs::write(&journal, &text).unwrap();
            let error = finish_interrupted_commit(out, &set).unwrap_err().to_string();
            assert!(error.contains(COMMIT_JOURNAL), "{text}: {error}");
            assert_eq!(fs::read_to_string(out.join("precious.txt")).unwrap(), "mine");
            assert_eq!(fs::read_to_string(out.join("result.json")).unwrap(), "old");
        }
        // A journal that is a FIFO or a link to a device is refused, never read.
        fs::remove_file(&journal).unwrap();
        #[cfg(unix)]
        {
            std::os::unix::fs::symlink("/dev/zero", &journal).unwrap();
            let error = interrupted_commit(out).unwrap_err().to_string();
            assert!(error.contains("a device"), "{error}");
        }
    }
}
