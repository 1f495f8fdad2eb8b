//! Labels the caller already loaded (`AnalyzeOptions::loaded_labels`, what a
//! study's settings share instead of decoding the PIdT again each time)
//! give the analysis the files give, and a PIdT of another size is refused.

use std::path::PathBuf;
use std::sync::Arc;

use ufcsr::{AnalyzeOptions, Legend, LoadedLabels, Pidt, analyze};

fn example() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("fixtures/example")
}

#[test]
fn labels_loaded_by_the_caller_give_what_the_files_give_and_another_size_is_refused() {
    let options = AnalyzeOptions { archive: example(), frames: true, ..AnalyzeOptions::default() };
    let from_files = analyze(&options, None).unwrap();
    let palette = &from_files.result.settings.palette;
    let legend = Legend::load(&example().join("parts.csv")).unwrap();
    let pidt = Pidt::load(&example().join("pidt.png"), &legend, [palette.width, palette.height]).unwrap();
    let loaded = LoadedLabels { legend: legend.clone(), pidt: Arc::new(pidt) };
    let with_loaded = AnalyzeOptions { loaded_labels: Some(loaded), ..options.clone() };
    let from_loaded = analyze(&with_loaded, None).unwrap();
    assert_eq!(
        serde_json::to_value(&from_loaded.result).unwrap(),
        serde_json::to_value(&from_files.result).unwrap()
    );
    assert_eq!(from_loaded.frames, from_files.frames);
    // A PIdT loaded at another size than the palette's is no PIdT of this archive.
    let small = Pidt::from_colors([2, 2], &[0; 4], &legend);
    let wrong = AnalyzeOptions {
        loaded_labels: Some(LoadedLabels { legend, pidt: Arc::new(small) }),
        ..options.clone()
    };
    let message = analyze(&wrong, None).err().unwrap().to_string();
    assert!(message.contains("pidt.png") && message.contains("was loaded at 2×2"), "{message}");
}
