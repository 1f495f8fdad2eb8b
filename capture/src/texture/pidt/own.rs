//! The paper's own path: a vehicle with UVs of its own and a PIdT painted
//! for them (in Blender, as the paper did), used as is.
//!
//! `--keep-uvs --pidt FILE --parts FILE` skips the automatic labelling: the
//! archive's `pidt.png` and `parts.csv` are the user's (checked to match the
//! palette, read with the analyzer's own legend and PIdT loaders). What does
//! not fit is counted and reported, never silently dropped: texels in a
//! colour the legend does not list (often the antialiased edge of a brush
//! stroke), and texels the mesh's UVs cover that the PIdT leaves unlabelled
//! — pixels showing those will count as unlabelled in the analysis.

use std::io::Write;
use std::path::{Path, PathBuf};

use ufcsr::{Color, Legend};

use crate::error::{CaptureError, Result};
use crate::texture::pidt::painted::{PidtImage, UNLABELLED_COLOR};
use crate::texture::uv_islands::{Unwrapped, for_texel_centres};

/// The user's PIdT and legend files (`--pidt`, `--parts`).
#[derive(Debug, Clone, PartialEq)]
pub struct OwnLabelFiles {
    pub pidt: PathBuf,
    pub parts: PathBuf,
}

/// The user's PIdT and legend, loaded and checked against the kept UVs.
#[derive(Debug, Clone)]
pub(crate) struct LoadedOwnLabels {
    /// In the form a capture writes (`rgb` as in the file).
    pub pidt: PidtImage,
    pub legend: Legend,
    /// What does not fit, one line each.
    pub warnings: Vec<String>,
}

/// Loads and checks the user's PIdT for the kept UVs in `unwrapped`.
pub(crate) fn load(labels: &OwnLabelFiles, unwrapped: &Unwrapped) -> Result<LoadedOwnLabels> {
    if unwrapped.method != "kept" {
        return Err(CaptureError::BadOptions(
            "--pidt needs --keep-uvs: a PIdT painted for the mesh's own UVs means nothing for the islands a capture unwraps".into(),
        ));
    }
    let legend = Legend::load(&labels.parts)?;
    let [w, h] = unwrapped.palette;
    let image = ufcsr::read_color_image(&labels.pidt, |[found_w, found_h]| {
        if [found_w, found_h] == [w, h] {
            Ok(())
        } else {
            Err(ufcsr::Error::WrongSize {
                path: labels.pidt.clone(),
                what: "the PIdT must match the palette (--palette-size or --palette)".into(),
                expected_width: w,
                expected_height: h,
                found_width: found_w,
                found_height: found_h,
            })
        }
    })?;
    if legend.parts.iter().any(|p| p.color == UNLABELLED_COLOR) {
        return Err(CaptureError::bad_file(
            &labels.parts,
            format!("{UNLABELLED_COLOR} marks unlabelled texels; no part may use it"),
        ));
    }
    let resolved = ufcsr::Pidt::from_colors([w, h], &image.colors, &legend);
    let mut warnings = Vec::new();
    let unknown: Vec<(&Color, &u64)> =
        resolved.unlabelled_colors.iter().filter(|(c, _)| **c != UNLABELLED_COLOR).collect();
    if !unknown.is_empty() {
        let texels: u64 = unknown.iter().map(|(_, n)| **n).sum();
        let mut by_count = unknown.clone();
        by_count.sort_by(|a, b| b.1.cmp(a.1));
        let examples: Vec<String> = by_count.iter().take(5).map(|(c, n)| format!("{c} ×{n}")).collect();
        warnings.push(format!(
            "{}: {texels} texels in {} colours the legend {} does not list (e.g. {}); they count as unlabelled",
            labels.pidt.display(),
            unknown.len(),
            labels.parts.display(),
            examples.join(", ")
        ));
    }
    // Texels the mesh shows that carry no legend colour.
    let (mut covered, mut unlabelled) = (0u64, 0u64);
    for tri in &unwrapped.texel_uvs {
        for_texel_centres(tri, unwrapped.palette, |x, y| {
            covered += 1;
            if resolved.part_of_texel[(y as usize) * (w as usize) + x as usize] == ufcsr::UNLABELLED {
                unlabelled += 1;
            }
        });
    }
    if unlabelled > 0 {
        warnings.push(format!(
            "{}: {unlabelled} of the {covered} texels the mesh's UVs cover are not labelled; pixels showing them count as unlabelled",
            labels.pidt.display()
        ));
    }
    let rgb: Vec<u8> = image.colors.iter().flat_map(|&c| Color::from_packed(c).rgb()).collect();
    let labelled = resolved.part_texels.iter().sum();
    let pidt = PidtImage {
        size: [w, h],
        rgb,
        part_colors: legend.parts.iter().map(|p| p.color).collect(),
        labelled,
        conflicts: 0,
    };
    Ok(LoadedOwnLabels { pidt, legend, warnings })
}

/// Writes the legend into the archive as `name,color`.
pub(crate) fn write_legend(legend: &Legend, path: &Path) -> Result<()> {
    ufcsr::files::write_atomically(path, |w| {
        writeln!(w, "name,color")?;
        for part in &legend.parts {
            writeln!(w, "{},{}", ufcsr::output::csv_field(&part.name), part.color)?;
        }
        Ok(())
    })?;
    Ok(())
}
