//! Entry points for fuzzing: each takes arbitrary bytes as one kind of input
//! file and must return, with an error if the bytes are bad, never panic,
//! hang or allocate without bound. The cargo-fuzz targets in `fuzz/` call
//! them, and `tests/it/fuzz_regressions.rs` feeds them the saved corpus and every
//! input that once failed, so CI re-checks those without nightly.

use std::path::Path;

use crate::archive::labels::Legend;
use crate::archive::manifest::Manifest;
use crate::archive::palette::Fcsp;
use crate::color::Color;

/// A tile: decoded and counted against the canonical 4096² palette. The
/// palette and the seen-set are built once per thread (a fuzzer calls this
/// millions of times); the set is emptied after each input.
pub fn tile(bytes: &[u8]) {
    static PALETTE: std::sync::OnceLock<Option<Fcsp>> = std::sync::OnceLock::new();
    thread_local! {
        static SEEN: std::cell::RefCell<crate::color::SeenSet> = std::cell::RefCell::new(crate::color::SeenSet::new());
    }
    let Some(palette) = PALETTE.get_or_init(|| Fcsp::canonical([4096, 4096]).ok()) else { return };
    let Ok(classifier) = crate::count::scan::Classifier::new(palette, &[Color::DEFAULT_BACKGROUND.packed()])
    else {
        return;
    };
    // Stray colours only accumulate across inputs: nothing reads them here.
    static STRAYS: std::sync::OnceLock<crate::color::AtomicColorSet> = std::sync::OnceLock::new();
    let strays = STRAYS.get_or_init(crate::color::AtomicColorSet::new);
    SEEN.with(|seen| {
        let mut seen = seen.borrow_mut();
        let _ = crate::count::scan::scan_image(Path::new("fuzz.png"), bytes, &classifier, &mut seen, strays);
        seen.clear();
    });
}

/// A `manifest.json`.
pub fn manifest(bytes: &[u8]) {
    let _ = Manifest::parse(Path::new("manifest.json"), bytes);
}

/// A `result.json`, as `heatmap` and `merge` read it.
pub fn result_json(bytes: &[u8]) {
    let path = Path::new("result.json");
    let _ = crate::result::result_json::parse_texel_counts(path, bytes);
    let _ = serde_json::from_slice::<crate::result::model::AnalysisResult>(bytes);
}

/// A legend, as CSV and as JSON.
pub fn legend(bytes: &[u8]) {
    let _ = Legend::parse(Path::new("parts.csv"), bytes.to_vec());
    let _ = Legend::parse(Path::new("parts.json"), bytes.to_vec());
}

/// The commit journal `.ufcsr-commit.json`, as `heatmap`, `merge`, `report`
/// and the next commit read it.
pub fn commit_journal(bytes: &[u8]) {
    let _ = crate::files::parse_journal(Path::new(".ufcsr-commit.json"), bytes);
}

/// Writes `bytes` as `name` into one private temporary folder per thread
/// and calls `read` with the folder: for readers that take a file (a few
/// microseconds per input).
fn in_file(name: &str, bytes: &[u8], read: impl FnOnce(&Path)) {
    thread_local! {
        static FOLDER: std::path::PathBuf = std::env::temp_dir().join(format!(
            "ufcsr-fuzz-{}-{:?}",
            std::process::id(),
            std::thread::current().id()
        ));
    }
    FOLDER.with(|folder| {
        if crate::files::create_output_dir(folder).is_ok()
            && crate::files::write_bytes_atomically(&folder.join(name), bytes).is_ok()
        {
            read(folder);
        }
    });
}

/// A placement table (`placement-frames.csv`), as `placement` reads it.
pub fn placement_table(bytes: &[u8]) {
    let name = crate::format::placement_csv::PLACEMENT_FRAMES_FILE;
    in_file(name, bytes, |folder| {
        let _ = crate::placement::read_table(&folder.join(name));
    });
}

/// The patches' footprints (`placement-patches.csv`), as `placement` reads
/// them beside a frames table.
pub fn placement_patches(bytes: &[u8]) {
    in_file(crate::placement::PLACEMENT_PATCHES_FILE, bytes, |folder| {
        let frames = folder.join(crate::format::placement_csv::PLACEMENT_FRAMES_FILE);
        let _ = crate::placement::footprints::read_footprints(&frames);
    });
}

/// A `placement.json`, as `report` and a result's own page read it.
pub fn placement_json(bytes: &[u8]) {
    in_file("placement.json", bytes, |folder| {
        let _ = crate::output::html::placement_section::read_placement(folder);
    });
}

/// An `observers.json` and a `study.json` read back through their types.
pub fn study_outputs(bytes: &[u8]) {
    let _ = crate::format::parse_json::<crate::format::observers::ObserverStudy>(
        Path::new("observers.json"),
        bytes,
        "observer study",
    );
    let _ = crate::format::parse_json::<crate::format::study::Study>(Path::new("study.json"), bytes, "study");
}

/// A Unity Perception SOLO frame file (`stepK.frame_data.json`), read as
/// `manifest` reads a sequence folder holding it.
pub fn solo_frame(bytes: &[u8]) {
    let name = "step0.frame_data.json";
    in_file(name, bytes, |folder| {
        let _ = crate::describe::solo::read(folder, &[folder.join(name)], &[]);
    });
}

/// A fuzz target's name (its folder under `seeds/` and `regressions/`) and
/// its entry point.
pub type Target = (&'static str, fn(&[u8]));

/// Feeds every saved input of `targets` — `fuzz_dir/seeds/TARGET/*` and
/// `fuzz_dir/regressions/TARGET/*` — to its entry point, as the fuzz
/// regression tests of both crates do. Returns how many inputs ran, or the
/// first that panicked, named.
pub fn replay_saved_inputs(fuzz_dir: &Path, targets: &[Target]) -> std::result::Result<usize, String> {
    let mut inputs = 0;
    for (target, entry) in targets {
        for folder in ["seeds", "regressions"] {
            let Ok(files) = std::fs::read_dir(fuzz_dir.join(folder).join(target)) else { continue };
            for file in files.flatten() {
                let bytes = crate::files::read_limited(&file.path(), crate::files::SMALL_INPUT_LIMIT)
                    .map_err(|e| e.to_string())?;
                if std::panic::catch_unwind(|| entry(&bytes)).is_err() {
                    return Err(format!("fuzz target {target} panics on {}", file.path().display()));
                }
                inputs += 1;
            }
        }
    }
    Ok(inputs)
}
