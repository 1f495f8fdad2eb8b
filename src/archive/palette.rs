//! The Full Color Space Palette (FCSP): which texel each colour names.
//!
//! The canonical palette needs no file: texel `(x, y)` of a W×H palette has
//! index `y*W + x`, and its colour *is* that index (`0xRRGGBB`). Unity and
//! Blender users may bring any palette image whose colours are all distinct;
//! then we keep the texel → colour table and a 2^24-bit membership set.

use std::path::{Path, PathBuf};

use crate::color::ColorSet;
use crate::color::{COLOR_COUNT, Color};
use crate::error::{Error, Result};
use crate::png::rows::read_color_image;

/// Default canonical palette side (4096 × 4096 = 2^24 texels).
pub(crate) const DEFAULT_PALETTE_SIDE: u32 = 4096;

/// The most texels a canonical palette of 32-bit texel ids may have
/// (`"texel_ids": "rgba32"`): 2^26, 8192 × 8192, four times the paper's
/// 4096² and room for a bus or an articulated truck at the F-150's texel
/// density. Every per-texel table is sized to the palette (at the limit:
/// 256 MiB of counts, 8 MiB per thread of seen texels), so a larger one is
/// refused rather than allocated.
pub const MAX_RGBA32_TEXELS: u64 = 1 << 26;

/// A palette, loaded: the mapping between texels and the colours that name
/// them. The one palette type of both crates: the analyzer counts with it,
/// the capture renders with it (`GpuPalette::of` there), and its relatives
/// say what they are — [`crate::PaletteChoice`] the palette an analysis is
/// asked for, [`crate::PaletteRecord`] the one `manifest.json` names,
/// [`PaletteSetting`] the one `result.json`'s settings name.
pub enum Fcsp {
    /// `colour == texel index`, for a W×H texture.
    Canonical { width: u32, height: u32 },
    /// An arbitrary palette image with unique colours.
    Image { width: u32, height: u32, path: PathBuf, colors: Vec<u32>, members: ColorSet },
}

pub use crate::format::result::PaletteSetting;

impl Fcsp {
    /// The canonical W×H palette.
    pub fn canonical([width, height]: [u32; 2]) -> Result<Fcsp> {
        let texels = u64::from(width) * u64::from(height);
        if width == 0 || height == 0 || texels > COLOR_COUNT as u64 {
            return Err(Error::BadOptions(format!(
                "a canonical palette must have between 1 and 2^24 texels; {width}×{height} has {texels}"
            )));
        }
        Ok(Fcsp::Canonical { width, height })
    }

    /// The canonical W×H palette of 32-bit texel ids (`rgba32` archives):
    /// more than 2^24 texels allowed, up to [`MAX_RGBA32_TEXELS`]. The
    /// texel `(x, y)` still has id `y*W + x`; its pixel is
    /// [`rgba32_pixel`] of it.
    pub fn canonical_rgba32([width, height]: [u32; 2]) -> Result<Fcsp> {
        let texels = u64::from(width) * u64::from(height);
        if width == 0 || height == 0 || texels > MAX_RGBA32_TEXELS {
            return Err(Error::BadOptions(format!(
                "a canonical palette of 32-bit texel ids must have between 1 and 2^26 (8192×8192) texels; \
                 {width}×{height} has {texels}"
            )));
        }
        Ok(Fcsp::Canonical { width, height })
    }

    /// True when this palette has more texels than 24-bit colours can name.
    pub fn needs_rgba32(&self) -> bool {
        self.texel_count() > COLOR_COUNT
    }

    /// Loads a palette image and checks that its colours are unique.
    pub fn from_png(path: &Path) -> Result<Fcsp> {
        let image = read_color_image(path, |[width, height]| {
            let texels = u64::from(width) * u64::from(height);
            if texels > COLOR_COUNT as u64 {
                return Err(Error::bad_file(
                    path,
                    format!(
                        "a {width}×{height} palette has {texels} texels, more than the 2^24 distinct colours"
                    ),
                ));
            }
            Ok(())
        })?;
        let mut members = ColorSet::new();
        let mut repeats = 0u64;
        let mut first_repeat = None;
        for (texel, &color) in image.colors.iter().enumerate() {
            if !members.insert(color) {
                repeats += 1;
                first_repeat.get_or_insert(texel);
            }
        }
        if let Some(texel) = first_repeat {
            let color = image.colors[texel];
            // The first occurrence exists because the repeat found it in the set.
            let first = image.colors.iter().position(|&c| c == color).unwrap_or(texel);
            let width = image.width as usize;
            return Err(Error::DuplicatePaletteColor {
                path: path.to_path_buf(),
                repeats,
                color: Color::from_packed(color),
                x: (texel % width) as u32,
                y: (texel / width) as u32,
                first_x: (first % width) as u32,
                first_y: (first / width) as u32,
            });
        }
        Ok(Fcsp::Image {
            width: image.width,
            height: image.height,
            path: path.to_path_buf(),
            colors: image.colors,
            members,
        })
    }

    /// Palette width in texels.
    pub fn width(&self) -> u32 {
        match self {
            Fcsp::Canonical { width, .. } | Fcsp::Image { width, .. } => *width,
        }
    }

    /// Palette height in texels.
    pub fn height(&self) -> u32 {
        match self {
            Fcsp::Canonical { height, .. } | Fcsp::Image { height, .. } => *height,
        }
    }

    /// Number of texels.
    pub fn texel_count(&self) -> usize {
        self.width() as usize * self.height() as usize
    }

    /// True when `color` names a texel of this palette.
    #[inline(always)]
    pub fn contains(&self, color: u32) -> bool {
        match self {
            Fcsp::Canonical { width, height } => (color as usize) < *width as usize * *height as usize,
            Fcsp::Image { members, .. } => members.contains(color),
        }
    }

    /// The colour of texel `texel` (`y * width + x`).
    #[inline(always)]
    pub fn color_of(&self, texel: usize) -> u32 {
        match self {
            Fcsp::Canonical { .. } => texel as u32,
            Fcsp::Image { colors, .. } => colors[texel],
        }
    }

    /// The texel that `color` names, if any (`y * width + x`). A palette
    /// image is searched texel by texel: for one colour, not per pixel.
    pub fn texel_of(&self, color: u32) -> Option<usize> {
        match self {
            Fcsp::Canonical { .. } => self.contains(color).then_some(color as usize),
            Fcsp::Image { colors, .. } => colors.iter().position(|&c| c == color),
        }
    }

    /// Every texel's colour as RGB bytes, row 0 at the top: the palette as an
    /// image (2^24 texels at the canonical default, so rows in parallel).
    pub fn texel_rgb(&self) -> Vec<u8> {
        use rayon::prelude::*;
        let row_bytes = self.width() as usize * 3;
        let mut rgb = vec![0u8; row_bytes * self.height() as usize];
        rgb.par_chunks_mut(row_bytes).enumerate().for_each(|(y, row)| {
            for (x, pixel) in row.chunks_exact_mut(3).enumerate() {
                let texel = y * self.width() as usize + x;
                pixel.copy_from_slice(&Color::from_packed(self.color_of(texel)).rgb());
            }
        });
        rgb
    }

    /// The setting stored in results.
    pub fn describe(&self) -> PaletteSetting {
        match self {
            Fcsp::Canonical { width, height } => {
                PaletteSetting { kind: "canonical".into(), width: *width, height: *height, file: None }
            }
            Fcsp::Image { width, height, path, .. } => PaletteSetting {
                kind: "image".into(),
                width: *width,
                height: *height,
                file: Some(path.display().to_string()),
            },
        }
    }
}

/// The 32-bit texel id of an RGBA pixel (`rgba32` archives):
/// (255 − alpha) × 2^24 + 0xRRGGBB, so an opaque pixel names the texel of
/// its 24-bit colour, as in the paper's archives.
#[inline(always)]
pub fn rgba32_id([r, g, b, a]: [u8; 4]) -> u32 {
    (u32::from(255 - a) << 24) | (u32::from(r) << 16) | (u32::from(g) << 8) | u32::from(b)
}

/// The RGBA pixel of 32-bit texel id `id`, the inverse of [`rgba32_id`].
#[inline(always)]
pub fn rgba32_pixel(id: u32) -> [u8; 4] {
    let [high, r, g, b] = id.to_be_bytes();
    [r, g, b, 255 - high]
}

/// Writes the canonical W×H palette as an 8-bit RGB PNG, for putting on a
/// mesh in Unity or Blender (texel `(x, y)` has colour `y * W + x`).
pub fn write_canonical_png(path: &Path, size: [u32; 2]) -> Result<()> {
    let rgb = Fcsp::canonical(size)?.texel_rgb();
    crate::files::write_rgb_png(path, size, &rgb, png::Compression::Fast)
}

/// Parses `W`, `WxH` or `W×H` into a palette size `[W, H]` (W alone:
/// square), of 1 to 2^24 texels (one colour each). The one parser of
/// `--palette-size` in both crates.
pub fn parse_size(text: &str) -> Result<[u32; 2]> {
    parse_size_within(text, COLOR_COUNT as u64, "1 to 2^24 texels (e.g. 4096, 512x256)")
}

/// [`parse_size`] for the capture's `--palette-size`: a canonical palette of
/// more than 2^24 texels is drawn with 32-bit texel ids (an `rgba32`
/// archive), up to [`MAX_RGBA32_TEXELS`] (8192²).
pub fn parse_capture_size(text: &str) -> Result<[u32; 2]> {
    parse_size_within(text, MAX_RGBA32_TEXELS, "1 to 2^26 texels (e.g. 4096, 8192x4096)")
}

/// `W`, `WxH` or `W×H` of 1 to `limit` texels (`needs` says so in errors).
fn parse_size_within(text: &str, limit: u64, needs: &str) -> Result<[u32; 2]> {
    let bad =
        || Error::BadOptions(format!("invalid palette size {text:?}: expected W or WxH, e.g. 4096x4096"));
    let mut parts = text.split(['x', 'X', '×']);
    let width: u32 = parts.next().ok_or_else(bad)?.trim().parse().map_err(|_| bad())?;
    let height: u32 = match parts.next() {
        Some(part) => part.trim().parse().map_err(|_| bad())?,
        None => width,
    };
    if parts.next().is_some() {
        return Err(bad());
    }
    if width == 0 || height == 0 || u64::from(width) * u64::from(height) > limit {
        return Err(Error::BadOptions(format!(
            "palette size {width}x{height}: needs {needs}, from {text:?}"
        )));
    }
    Ok([width, height])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn canonical_maps_index_to_color() {
        let palette = Fcsp::canonical([16, 4]).unwrap();
        assert_eq!(palette.color_of(17), 17);
        assert!(palette.contains(63));
        assert!(!palette.contains(64));
        assert!(Fcsp::canonical([4097, 4096]).is_err());
        assert!(Fcsp::canonical([0, 4]).is_err());
    }

    #[test]
    fn written_canonical_palette_loads_as_an_image_palette() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("fcsp.png");
        write_canonical_png(&path, [64, 32]).unwrap();
        let palette = Fcsp::from_png(&path).unwrap();
        assert_eq!((palette.width(), palette.height()), (64, 32));
        assert!((0..64 * 32).all(|texel| palette.color_of(texel) == texel as u32));
    }

    #[test]
    fn rgba32_ids_round_trip_and_opaque_pixels_keep_their_24_bit_id() {
        for id in [0u32, 0x00_0FFF, 0xFF_FFFF, 0x100_0000, 0x3FF_FFFF, u32::MAX] {
            assert_eq!(rgba32_id(rgba32_pixel(id)), id);
        }
        assert_eq!(rgba32_id([0x12, 0x34, 0x56, 255]), 0x12_3456);
        assert_eq!(rgba32_pixel(0x100_0000), [0, 0, 0, 254]);
        let palette = Fcsp::canonical_rgba32([8192, 2049]).unwrap();
        assert!(palette.needs_rgba32() && palette.contains(0x100_0000) && !palette.contains(8192 * 2049));
        assert!(Fcsp::canonical_rgba32([8192, 8193]).is_err(), "more than 2^26 texels");
        assert!(!Fcsp::canonical([4096, 4096]).unwrap().needs_rgba32());
    }

    #[test]
    fn parses_sizes() {
        assert_eq!(parse_size("4096").unwrap(), [4096, 4096]);
        assert_eq!(parse_size("64x32").unwrap(), [64, 32]);
        assert_eq!(parse_size("512×128").unwrap(), [512, 128]);
        assert!(parse_size("64x").is_err());
        assert!(parse_size("8192").is_err());
        assert!(parse_size("0x4").is_err());
        assert_eq!(parse_capture_size("8192x4096").unwrap(), [8192, 4096]);
        assert!(parse_capture_size("8192x8193").unwrap_err().to_string().contains("2^26"));
    }
}
