//! Judging a capture for colour-management and filtering damage: three
//! measured shares against thresholds set with a wide margin, each warning
//! named, with what it measured, its likely causes and the fix.
//!
//! The Blender measurements (4096² palette, the right PIdT): a
//! correct capture puts 0 % of its counts on unlabelled texels, wrong view
//! transforms, dithering and filtering 27–59 %; AgX and Filmic leave no
//! background pixel; antialiasing and linear interpolation leave neither
//! stray pixels nor (on their own) much else but blended neighbours, which
//! [`crate::checks::neighbours`] samples. `--strict-colors` turns any of
//! these warnings into a failure.

use crate::checks::neighbours::NeighbourSample;

/// Warn above this share of counts on unlabelled texels.
const UNLABELLED_THRESHOLD: f64 = 0.01;
/// ... when at least this many counts fell on them (a toy archive's few
/// unlabelled counts are no evidence of damage).
const UNLABELLED_MIN_COUNTS: u64 = 100;

/// Warn below this share of background pixels ...
const BACKGROUND_THRESHOLD: f64 = 0.001;
/// ... over at least this many decoded pixels, and only when no tile was
/// trimmed or listed empty (an all-background tile proves the background
/// came through: a vehicle may fill every other tile).
const BACKGROUND_MIN_PIXELS: u64 = 1 << 20;

/// Warn above this share of jumps among varying neighbour triples (a
/// correct capture measured at most 0.5 %, damaged ones 10 % and more;
/// see docs/guide.md#colour-damage) ...
const JUMP_THRESHOLD: f64 = 0.03;
/// ... when at least this many triples varied.
const JUMP_MIN_VARYING: u64 = 1000;

/// Names of the checks, as `result.json` and the warnings spell them.
pub(crate) const UNLABELLED_CHECK: &str = "unlabelled-counts";
pub(crate) const BACKGROUND_CHECK: &str = "no-background";
pub(crate) const JUMP_CHECK: &str = "texel-jumps";

/// Every warning about colour damage starts with this (stderr, report).
pub(crate) const COLOR_WARNING: &str = "colour damage";

/// The settings that render the palette unchanged (every fix ends so).
const RECIPE: &str = "Blender: view transform Standard, look None, exposure 0, gamma 1, dither 0, Image \
    Texture interpolation Closest, 1 sample and pixel filter 0 (Cycles box 0.01, EEVEE filter 0), no \
    denoising; Unity: point filtering, no mipmaps, no MSAA, no post-processing, and a colour space that \
    passes the texture through (docs/guide.md#colour-damage)";

pub use crate::format::result::ColorChecks;

pub use crate::format::result::ColorWarning;

impl ColorWarning {
    /// The one-line warning for `result.json`'s `warnings`, stderr and the report.
    pub fn line(&self) -> String {
        format!(
            "{COLOR_WARNING} ({}): {}; likely causes: {}; fix: {}",
            self.check, self.message, self.causes, self.fix
        )
    }
}

/// What the checks are judged from.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct ColorFacts {
    /// Counts on unlabelled texels, with a PIdT.
    pub unlabelled_counts: Option<u64>,
    /// Counts on legend parts (the grand total).
    pub labelled_counts: u64,
    pub decoded_pixels: u64,
    pub background_pixels: u64,
    /// Tiles trimmed or listed empty.
    pub background_tiles: u64,
    pub neighbours: Option<NeighbourSample>,
}

impl ColorChecks {
    /// Measures the shares of `facts` and warns about those past their thresholds.
    pub(crate) fn judge(facts: &ColorFacts) -> ColorChecks {
        let share = |part: u64, whole: u64| (whole > 0).then(|| part as f64 / whole as f64);
        let unlabelled_count_share =
            facts.unlabelled_counts.and_then(|u| share(u, u + facts.labelled_counts));
        let background_pixel_share = share(facts.background_pixels, facts.decoded_pixels);
        let jump_share = facts.neighbours.and_then(|n| n.jump_share());
        let mut warnings = Vec::new();
        if let Some(share) = unlabelled_count_share
            && share > UNLABELLED_THRESHOLD
            && facts.unlabelled_counts.unwrap_or(0) >= UNLABELLED_MIN_COUNTS
        {
            warnings.push(unlabelled_warning(share));
        }
        if let Some(share) = background_pixel_share
            && share < BACKGROUND_THRESHOLD
            && facts.decoded_pixels >= BACKGROUND_MIN_PIXELS
            && facts.background_tiles == 0
        {
            warnings.push(background_warning(share, facts.decoded_pixels));
        }
        if let (Some(share), Some(sample)) = (jump_share, facts.neighbours)
            && share > JUMP_THRESHOLD
            && sample.varying >= JUMP_MIN_VARYING
        {
            warnings.push(jump_warning(share, &sample));
        }
        ColorChecks {
            unlabelled_count_share,
            background_pixel_share,
            background_tiles: facts.background_tiles,
            neighbours: facts.neighbours,
            jump_share,
            warnings,
        }
    }
}

fn warning(
    check: &str,
    share: f64,
    threshold: f64,
    message: String,
    causes: &str,
    fix: &str,
) -> ColorWarning {
    ColorWarning {
        check: check.to_string(),
        percent: 100.0 * share,
        threshold_percent: 100.0 * threshold,
        message,
        causes: causes.to_string(),
        fix: format!("{fix}; {RECIPE}"),
    }
}

fn unlabelled_warning(share: f64) -> ColorWarning {
    warning(
        UNLABELLED_CHECK,
        share,
        UNLABELLED_THRESHOLD,
        format!(
            "{:.1} % of counts on unlabelled texels (threshold {} %): pixels name texels the PIdT gives no part",
            100.0 * share,
            100.0 * UNLABELLED_THRESHOLD
        ),
        "colours changed on their way to the PNG, so pixels name other texels: a view transform (Blender's \
         AgX or Filmic), an sRGB/Raw mismatch (palette image sRGB with view Raw, or Non-Color with \
         Standard), exposure or gamma, dithering, linear filtering or antialiasing; or a PIdT that is not \
         this capture's",
        "render the palette unchanged and pass the capture's own PIdT",
    )
}

fn background_warning(share: f64, decoded: u64) -> ColorWarning {
    warning(
        BACKGROUND_CHECK,
        share,
        BACKGROUND_THRESHOLD,
        format!(
            "{:.3} % background pixels in {decoded} decoded pixels (threshold {} %), and no tile was all \
             background: the background colour does not reach the PNGs",
            100.0 * share,
            100.0 * BACKGROUND_THRESHOLD
        ),
        "a tone curve moved the background (#000FFF becomes e.g. #0001FF or #0044FF): a view transform \
         (AgX, Filmic), an sRGB/Raw mismatch, exposure or gamma; or the world colour is not the \
         background",
        "give the world the sRGB-decoded background colour and render it unchanged, or name the \
         capture's background with --background",
    )
}

fn jump_warning(share: f64, sample: &NeighbourSample) -> ColorWarning {
    warning(
        JUMP_CHECK,
        share,
        JUMP_THRESHOLD,
        format!(
            "{:.1} % of {} sampled triples of adjacent pixels have a middle pixel naming a texel far from \
             both neighbours on the palette (threshold {} %): pixels are blends of texels",
            100.0 * share,
            sample.varying,
            100.0 * JUMP_THRESHOLD
        ),
        "antialiasing (several samples per pixel, a pixel filter wider than a pixel, MSAA), linear or \
         mipmapped texture filtering, dithering or denoising",
        "sample the texture with nearest (Closest/point) filtering, one sample per pixel",
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn facts() -> ColorFacts {
        ColorFacts {
            unlabelled_counts: Some(0),
            labelled_counts: 35_811,
            decoded_pixels: 10_000_000,
            background_pixels: 8_000_000,
            background_tiles: 0,
            neighbours: Some(NeighbourSample { triples: 100_000, varying: 10_000, jumps: 20 }),
        }
    }

    #[test]
    fn a_correct_capture_gets_no_warning() {
        let checks = ColorChecks::judge(&facts());
        assert_eq!(checks.warnings, []);
        assert_eq!(checks.unlabelled_count_share, Some(0.0));
        assert_eq!(checks.background_pixel_share, Some(0.8));
        assert_eq!(checks.jump_share, Some(0.002));
    }

    #[test]
    fn each_signature_is_named_with_its_number() {
        // The sRGB/Raw case: 18,238 unlabelled of 12,801 + 18,238 counts.
        let raw = ColorFacts { unlabelled_counts: Some(18_238), labelled_counts: 12_801, ..facts() };
        let warning = &ColorChecks::judge(&raw).warnings[0];
        assert_eq!(warning.check, UNLABELLED_CHECK);
        assert!(
            warning.message.starts_with("58.8 % of counts on unlabelled texels (threshold 1 %)"),
            "{warning:?}"
        );
        let filmic = ColorFacts { background_pixels: 0, ..facts() };
        assert_eq!(ColorChecks::judge(&filmic).warnings[0].check, BACKGROUND_CHECK);
        let blended = ColorFacts {
            neighbours: Some(NeighbourSample { triples: 100_000, varying: 10_000, jumps: 1_500 }),
            ..facts()
        };
        let warning = &ColorChecks::judge(&blended).warnings[0];
        assert_eq!((warning.check.as_str(), warning.percent), (JUMP_CHECK, 15.0));
        assert!(warning.line().starts_with("colour damage (texel-jumps): 15.0 % of 10000 sampled"));
    }

    #[test]
    fn small_or_legitimately_background_free_captures_are_not_judged() {
        let few = ColorFacts { unlabelled_counts: Some(50), labelled_counts: 50, ..facts() };
        let covered = ColorFacts { background_pixels: 0, background_tiles: 3, ..facts() };
        let tiny = ColorFacts { background_pixels: 0, decoded_pixels: 1000, ..facts() };
        let sparse = ColorFacts {
            neighbours: Some(NeighbourSample { triples: 900, varying: 900, jumps: 900 }),
            ..facts()
        };
        for facts in [few, covered, tiny, sparse] {
            assert_eq!(ColorChecks::judge(&facts).warnings, [], "{facts:?}");
        }
    }
}
