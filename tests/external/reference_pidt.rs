//! The real F-150 PIdT and legend from `../shared/ref/f150/` (the published
//! Unity project): per-part texel counts from our PIdT reader must equal an
//! independent count made here with the png crate and a plain HashMap.
//! Ignored (with the reason) when `../shared` is not beside the checkout
//! (or `UFCSR_SHARED` names a folder without it).

use std::collections::HashMap;

use crate::need::{Outcome, missing, shared_dir};
use libtest_mimic::Completion;
use ufcsr::{Legend, Pidt};

pub fn f150_part_texel_counts_match_an_independent_count() -> Outcome {
    let dir = shared_dir().join("ref/f150");
    if !(dir.join("pidt.png").is_file() && dir.join("parts.csv").is_file()) {
        return missing(&format!("{} (reference data in shared/ref beside the checkout)", dir.display()));
    }
    let legend = Legend::load(&dir.join("parts.csv")).unwrap();
    assert_eq!(legend.parts.len(), 68);
    let pidt = Pidt::load(&dir.join("pidt.png"), &legend, [4096, 4096]).unwrap();

    // Independent count: decode to RGB(A) bytes and tally colours.
    let file = std::io::BufReader::new(std::fs::File::open(dir.join("pidt.png")).unwrap());
    let mut decoder = png::Decoder::new(file);
    decoder.set_transformations(png::Transformations::EXPAND);
    let mut reader = decoder.read_info().unwrap();
    let mut buffer = vec![0u8; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buffer).unwrap();
    let channels = info.color_type.samples();
    let mut tally: HashMap<[u8; 3], u64> = HashMap::new();
    for pixel in buffer[..info.buffer_size()].chunks_exact(channels) {
        *tally.entry([pixel[0], pixel[1], pixel[2]]).or_default() += 1;
    }
    for (part, &texels) in legend.parts.iter().zip(&pidt.part_texels) {
        assert_eq!(tally.get(&part.color.rgb()).copied().unwrap_or(0), texels, "part {}", part.name);
    }
    let labelled: u64 = pidt.part_texels.iter().sum();
    let unlabelled: u64 = pidt.unlabelled_colors.values().sum();
    assert_eq!(labelled + unlabelled, 4096 * 4096);
    // The source notes ~1.7 M texels of #0A0000 that no part names.
    let stray_label = pidt.unlabelled_colors[&"#0A0000".parse().unwrap()];
    assert!((1_500_000..2_000_000).contains(&stray_label), "{stray_label}");
    eprintln!(
        "f150: {} labelled texels in {} parts, {} unlabelled in {} colours",
        labelled,
        legend.parts.len(),
        unlabelled,
        pidt.unlabelled_colors.len()
    );
    Ok(Completion::Completed)
}
