//! Synthetic archives: realistic stand-ins for a capture, for tests and
//! benchmarks (behind the `synthetic` feature, which the tests and benches
//! turn on; the bundled example is a real capture).
//!
//! An archive has frames × eyes × rows × cols tiles. Most tiles are empty
//! (byte-identical background PNGs, as a renderer writes them); the tiles the
//! "vehicle" covers show a few overlapping convex surfaces, each mapping
//! pixels to palette texels through a rotated, scaled grid (0.2–2 texels per
//! pixel, nearest sampling), so object tiles have smooth unique-colour
//! gradients with occlusion edges. Deterministic for a given seed.
//!
//! Beside them, the SVG readers the figures' tests in both crates share
//! ([`svg_polylines`], [`svg_attribute`]).

pub use crate::png::format::png_from_chunks;
use std::path::Path;

use crate::archive::manifest::{MANIFEST_SCHEMA, Manifest, PaletteRecord, TileEntry};
use crate::color::Color;
use crate::error::{Error, Result};
use crate::files::{write_bytes_atomically, write_rgb_png};

/// The synthetic archives' generator: [`crate::SplitMix64`] with draws in a range.
#[derive(Debug, Clone)]
pub struct Rng(crate::stats::SplitMix64);

impl Rng {
    pub fn new(seed: u64) -> Rng {
        Rng(crate::stats::SplitMix64(seed))
    }

    pub fn next_u64(&mut self) -> u64 {
        self.0.next_u64()
    }

    /// Uniform in `[low, high)`.
    pub fn uniform(&mut self, low: f64, high: f64) -> f64 {
        low + (high - low) * self.0.unit()
    }

    /// Uniform integer in `[0, n)`.
    pub fn below(&mut self, n: u64) -> u64 {
        self.0.below(n)
    }
}

/// Paints one object tile (RGB bytes): background plus 1–3 surfaces.
pub fn object_tile(
    [width, height]: [u32; 2],
    palette: [u32; 2],
    background: Color,
    texels_per_pixel: (f64, f64),
    rng: &mut Rng,
) -> Vec<u8> {
    let mut rgb = Vec::with_capacity(width as usize * height as usize * 3);
    for _ in 0..width as usize * height as usize {
        rgb.extend_from_slice(&background.rgb());
    }
    let (w, h) = (f64::from(width), f64::from(height));
    let surfaces = 1 + rng.below(3);
    for _ in 0..surfaces {
        // A convex quad around a random centre.
        let (cx, cy) = (rng.uniform(0.1 * w, 0.9 * w), rng.uniform(0.1 * h, 0.9 * h));
        let radius = rng.uniform(0.25, 0.7) * w.min(h);
        let start = rng.uniform(0.0, std::f64::consts::TAU);
        let corners: Vec<(f64, f64)> = (0..4)
            .map(|k| {
                let angle = start + f64::from(k) * std::f64::consts::FRAC_PI_2 + rng.uniform(-0.4, 0.4);
                let r = radius * rng.uniform(0.6, 1.0);
                (cx + r * angle.cos(), cy + r * angle.sin())
            })
            .collect();
        // Pixel → texel: rotation and scale (sqrt of texels per pixel per axis).
        let scale = rng.uniform(texels_per_pixel.0, texels_per_pixel.1).sqrt();
        let theta = rng.uniform(0.0, std::f64::consts::TAU);
        let (sin, cos) = theta.sin_cos();
        let origin = (rng.uniform(0.0, f64::from(palette[0])), rng.uniform(0.0, f64::from(palette[1])));
        for y in 0..height {
            for x in 0..width {
                let (px, py) = (f64::from(x) + 0.5, f64::from(y) + 0.5);
                if !inside(&corners, px, py) {
                    continue;
                }
                let u = origin.0 + scale * (cos * px - sin * py);
                let v = origin.1 + scale * (sin * px + cos * py);
                let tx = u.floor().rem_euclid(f64::from(palette[0])) as u32;
                let ty = v.floor().rem_euclid(f64::from(palette[1])) as u32;
                let mut index = ty * palette[0] + tx;
                if index == background.packed() {
                    index = (index + 1) % (palette[0] * palette[1]);
                }
                let at = (y as usize * width as usize + x as usize) * 3;
                rgb[at..at + 3].copy_from_slice(&Color::from_packed(index).rgb());
            }
        }
    }
    rgb
}

fn inside(corners: &[(f64, f64)], x: f64, y: f64) -> bool {
    let mut sign = 0.0f64;
    for k in 0..corners.len() {
        let (ax, ay) = corners[k];
        let (bx, by) = corners[(k + 1) % corners.len()];
        let cross = (bx - ax) * (y - ay) - (by - ay) * (x - ax);
        if cross != 0.0 {
            if sign != 0.0 && cross.signum() != sign {
                return false;
            }
            sign = cross.signum();
        }
    }
    true
}

/// What to generate.
#[derive(Debug, Clone)]
pub struct ArchiveSpec {
    pub frames: u32,
    pub eyes: u32,
    pub rows: u32,
    pub cols: u32,
    pub tile_width: u32,
    pub tile_height: u32,
    pub palette: [u32; 2],
    /// Side of the square block of tiles the vehicle covers in each eye-frame.
    pub object_block: u32,
    pub texels_per_pixel: (f64, f64),
    /// Number of parts in the generated PIdT (horizontal bands of the palette).
    pub parts: u32,
    pub compression: png::Compression,
    pub seed: u64,
}

impl Default for ArchiveSpec {
    fn default() -> ArchiveSpec {
        ArchiveSpec {
            frames: 4,
            eyes: 2,
            rows: 5,
            cols: 5,
            tile_width: 1284,
            tile_height: 1620,
            palette: [4096, 4096],
            object_block: 2,
            texels_per_pixel: (0.2, 2.0),
            parts: 8,
            compression: png::Compression::Fast,
            seed: 1,
        }
    }
}

/// Names of the generated parts, cycled when more are asked for.
const PART_NAMES: [&str; 8] =
    ["Bumper", "Grill", "Hood", "Windshield", "Roof", "Door_Front_Left", "Tailgate", "Tyre_Front_Left"];

/// What [`write_archive`] wrote.
#[derive(Debug, Clone, Default)]
pub struct ArchiveSummary {
    pub tiles: u64,
    pub object_tiles: u64,
    pub bytes: u64,
}

/// Writes an archive with `manifest.json`, `pidt.png` and `parts.csv` into `dir`.
pub fn write_archive(dir: &Path, spec: &ArchiveSpec) -> Result<ArchiveSummary> {
    let tiles_dir = dir.join("tiles");
    crate::files::create_output_dir(&tiles_dir)?;
    let background = Color::DEFAULT_BACKGROUND;
    let empty_path = dir.join(".empty.png");
    let empty_rgb = object_free_tile([spec.tile_width, spec.tile_height], background);
    write_rgb_png(&empty_path, [spec.tile_width, spec.tile_height], &empty_rgb, spec.compression)?;
    let empty_bytes = crate::files::read_limited(&empty_path, crate::files::IMAGE_LIMIT)?;
    crate::files::remove_inside(dir, &empty_path)?;

    let mut rng = Rng::new(spec.seed);
    let mut summary = ArchiveSummary::default();
    let mut tiles = Vec::new();
    for frame in 0..spec.frames {
        for eye in 0..spec.eyes {
            let eye_name = if eye == 0 { "left" } else { "right" }.to_string();
            let block = spec.object_block.min(spec.rows).min(spec.cols);
            let top = rng.below(u64::from(spec.rows - block + 1)) as u32;
            let left = rng.below(u64::from(spec.cols - block + 1)) as u32;
            for row in 0..spec.rows {
                for col in 0..spec.cols {
                    let name = format!("tiles/f{frame:04}_{eye_name}_r{row}_c{col}.png");
                    let path = dir.join(&name);
                    let covered = (top..top + block).contains(&row) && (left..left + block).contains(&col);
                    if covered {
                        let rgb = object_tile(
                            [spec.tile_width, spec.tile_height],
                            spec.palette,
                            background,
                            spec.texels_per_pixel,
                            &mut rng,
                        );
                        write_rgb_png(&path, [spec.tile_width, spec.tile_height], &rgb, spec.compression)?;
                        summary.object_tiles += 1;
                    } else {
                        write_bytes_atomically(&path, &empty_bytes)?;
                    }
                    summary.bytes += std::fs::metadata(&path).map_err(|e| Error::io(&path, e))?.len();
                    summary.tiles += 1;
                    tiles.push(TileEntry {
                        file: Some(name.into()),
                        frame,
                        eye: eye_name.clone(),
                        row,
                        col,
                        empty: false,
                        distance_m: None,
                        time_s: None,
                    });
                }
            }
        }
    }
    write_parts(dir, spec)?;
    let manifest = Manifest {
        schema: Some(MANIFEST_SCHEMA.to_string()),
        palette: Some(PaletteRecord::Canonical { canonical: spec.palette }),
        pidt: Some("pidt.png".into()),
        parts: Some("parts.csv".into()),
        background: Some(vec![background]),
        tiles,
        generator: Some(format!("ufcsr::synthetic, seed {}", spec.seed)),
        ..Manifest::default()
    };
    manifest.write_to_dir(dir)?;
    Ok(summary)
}

fn object_free_tile([width, height]: [u32; 2], background: Color) -> Vec<u8> {
    background.rgb().iter().copied().cycle().take(width as usize * height as usize * 3).collect()
}

/// The colour of generated part `k`.
pub fn part_color(k: u32) -> Color {
    Color::from_rgb(40 + (k * 50 % 200) as u8, (k * 37 % 256) as u8, 200u8.wrapping_sub((k * 23) as u8))
}

/// Writes `pidt.png` (horizontal bands, one per part) and `parts.csv`.
fn write_parts(dir: &Path, spec: &ArchiveSpec) -> Result<()> {
    let [width, height] = spec.palette;
    let parts = spec.parts.max(1);
    let mut rgb = Vec::with_capacity(width as usize * height as usize * 3);
    for y in 0..height {
        let part = (u64::from(y) * u64::from(parts) / u64::from(height)) as u32;
        let color = part_color(part).rgb();
        for _ in 0..width {
            rgb.extend_from_slice(&color);
        }
    }
    write_rgb_png(&dir.join("pidt.png"), [width, height], &rgb, png::Compression::Balanced)?;
    let mut csv = String::from("name,color\n");
    for k in 0..parts {
        let base = PART_NAMES[k as usize % PART_NAMES.len()];
        let name = if k as usize >= PART_NAMES.len() { format!("{base}_{k}") } else { base.to_string() };
        csv.push_str(&format!("{name},{}\n", part_color(k)));
    }
    write_bytes_atomically(&dir.join("parts.csv"), csv.as_bytes())
}

/// Attribute `name` of one SVG tag (the text after `<tag`), as written: the
/// figures' tests read what was drawn back from the SVG with it.
pub fn svg_attribute(tag: &str, name: &str) -> Option<String> {
    let start = tag.find(&format!(" {name}=\""))? + name.len() + 3;
    tag[start..].split('"').next().map(str::to_string)
}

/// The points of every `<polyline>` of `svg` stroked in `stroke` (e.g.
/// `"#0072B2"`), in drawing order: how the figures' tests find the interval
/// bars and whiskers they drew.
pub fn svg_polylines(svg: &str, stroke: &str) -> Vec<Vec<(f64, f64)>> {
    svg.split("<polyline")
        .skip(1)
        .filter(|tag| svg_attribute(tag, "stroke").as_deref() == Some(stroke))
        .filter_map(|tag| {
            svg_attribute(tag, "points")?
                .split_whitespace()
                .map(|p| p.split_once(',').and_then(|(x, y)| Some((x.parse().ok()?, y.parse().ok()?))))
                .collect()
        })
        .collect()
}
