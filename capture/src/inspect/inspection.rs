//! `ufcsr inspect`: look at a vehicle before spending a capture on it.
//!
//! Builds the vehicle exactly as a capture would (see [`crate::scene::vehicle`]) and
//! reports its size and bounds in metres after `axes`, where its origin is,
//! its triangle count, degenerate and sliver triangles, whether it has UVs
//! of its own, the parts it will have with their surface areas and what the
//! region rules did; then writes pictures from the side, the top and the
//! front with the parts in their PIdT colours, and the legend of those
//! colours (`inspect-parts.csv`).

use std::fmt;
use std::io::Write;
use std::path::{Path, PathBuf};

use glam::DVec3;
use ufcsr::Color;

use crate::error::{CaptureError, Result};
use crate::inspect::pictures;
use crate::inspect::pictures::with_legend;
use crate::scene::mesh::{Axes, Mesh, triangle_area};
use crate::scene::regions::RegionReport;
use crate::scene::vehicle::{self, LENGTH_TOLERANCE};
use crate::scene::{SceneFile, VehicleSpec};
use crate::texture::pidt::painted::part_colors;

/// Below this area (m²) a triangle has no area at all (f32 rounding).
pub(crate) const DEGENERATE_AREA_M2: f64 = 1e-12;
/// A sliver has less than 1 mm² ...
pub(crate) const SLIVER_AREA_M2: f64 = 1e-6;
/// ... or is thinner than 0.1 mm (its smallest altitude).
pub(crate) const SLIVER_ALTITUDE_M: f64 = 1e-4;
/// Longest side of an inspect picture, pixels.
pub(crate) const MAX_PICTURE_PIXELS: f64 = 16384.0;
/// How many slivers the report lists by number.
const EXAMPLES: usize = 5;

/// What to inspect.
#[derive(Debug, Clone)]
pub struct InspectOptions {
    /// A scene file (`.json`) or a mesh (`.glb`, `.gltf`, `.obj`, default axes).
    pub input: PathBuf,
    /// Folder for the pictures and the legend.
    pub out: PathBuf,
    /// Picture scale; `None` keeps the longest picture near 1200 pixels.
    pub pixels_per_metre: Option<f64>,
}

/// One part of the vehicle.
#[derive(Debug, Clone, PartialEq)]
pub struct PartInfo {
    pub name: String,
    /// Its colour in the capture's PIdT (and in the pictures).
    pub color: Color,
    pub triangles: usize,
    pub area_m2: f64,
}

/// A sliver, for the report.
#[derive(Debug, Clone, PartialEq)]
pub struct Sliver {
    pub triangle: usize,
    pub part: String,
    pub area_m2: f64,
    /// The triangle's smallest altitude, m.
    pub altitude_m: f64,
}

/// Degenerate and thin triangles.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct TriangleQuality {
    /// Zero-area triangles: never seen, but they still cost an island.
    pub degenerate: usize,
    /// Slivers (see [`SLIVER_AREA_M2`], [`SLIVER_ALTITUDE_M`]): seen in at
    /// most a pixel's width, each still costs a 5×5-texel island gutter.
    pub slivers: usize,
    pub sliver_area_m2: f64,
    /// The thinnest few slivers.
    pub examples: Vec<Sliver>,
}

/// Whether the mesh has UVs of its own (for `--keep-uvs`).
#[derive(Debug, Clone, PartialEq)]
pub enum UvState {
    /// Every primitive has UVs, no two triangles sharing a texel.
    Complete,
    /// Every primitive has UVs, but some overlap (where: by pair of parts).
    Overlapping(crate::texture::UvOverlaps),
    /// No UVs at all (or the built-in demo truck).
    None,
    /// Some primitives lack UVs; they are named.
    Partial(Vec<String>),
}

/// What `inspect` found.
#[derive(Debug, Clone)]
pub struct Inspection {
    pub input: PathBuf,
    /// The mesh as the scene names it.
    pub mesh: String,
    pub axes: Axes,
    pub expect_length_m: Option<f64>,
    pub triangles: usize,
    /// Bounds in the vehicle frame (x forward, y left, z up), m.
    pub bounds: (DVec3, DVec3),
    /// The ground under the bounding box's centre, in the vehicle frame: the
    /// origin ought to be there.
    pub ground_centre: DVec3,
    pub quality: TriangleQuality,
    pub uvs: UvState,
    pub parts: Vec<PartInfo>,
    pub regions: RegionReport,
    /// What labelling through a part map found (`parts_from.part_map`).
    pub part_map: Option<crate::scene::PartMapReport>,
    pub warnings: Vec<String>,
    /// Pictures and legend written.
    pub files: Vec<PathBuf>,
}

/// Measures triangle quality.
pub fn triangle_quality(mesh: &Mesh) -> TriangleQuality {
    let mut quality = TriangleQuality::default();
    let mut slivers = Vec::new();
    for t in 0..mesh.triangles.len() {
        let corners = mesh.corners(t);
        let area = triangle_area(corners);
        let p = corners.map(|c| c.as_dvec3());
        let longest = [(p[1] - p[0]).length(), (p[2] - p[1]).length(), (p[0] - p[2]).length()]
            .into_iter()
            .fold(0.0, f64::max);
        let altitude = if longest > 0.0 { 2.0 * area / longest } else { 0.0 };
        if area < DEGENERATE_AREA_M2 {
            quality.degenerate += 1;
        } else if area < SLIVER_AREA_M2 || altitude < SLIVER_ALTITUDE_M {
            quality.slivers += 1;
            quality.sliver_area_m2 += area;
            let part = mesh.parts.get(mesh.triangle_part[t] as usize).cloned().unwrap_or_default();
            slivers.push(Sliver { triangle: t, part, area_m2: area, altitude_m: altitude });
        }
    }
    slivers.sort_by(|a, b| a.altitude_m.total_cmp(&b.altitude_m));
    slivers.truncate(EXAMPLES);
    quality.examples = slivers;
    quality
}

/// The vehicle entry of a scene file, or a bare mesh with default settings;
/// with the folder its paths are relative to.
/// The scene file at `input` and the folder its paths are relative to.
fn scene_file(input: &Path) -> Result<(SceneFile, PathBuf)> {
    let base = input.parent().map_or_else(|| PathBuf::from("."), Path::to_path_buf);
    let bytes = ufcsr::files::read_limited(input, ufcsr::files::SMALL_INPUT_LIMIT)?;
    let file: SceneFile = serde_json::from_slice(&bytes)
        .map_err(|e| CaptureError::bad_file(input, format!("invalid scene file: {e}")))?;
    Ok((file, base))
}

fn vehicle_spec(input: &Path) -> Result<(VehicleSpec, PathBuf)> {
    let base = input.parent().map_or_else(|| PathBuf::from("."), Path::to_path_buf);
    let is_scene = input.extension().is_some_and(|e| e.eq_ignore_ascii_case("json"));
    if is_scene {
        let (file, base) = scene_file(input)?;
        return Ok((file.vehicle, base));
    }
    let Some(name) = input.file_name() else {
        return Err(CaptureError::bad_file(input, "not a scene file or mesh"));
    };
    let spec = VehicleSpec {
        mesh: name.to_string_lossy().into_owned(),
        body: None,
        dims: None,
        parts_from: Default::default(),
        rename: Default::default(),
        axes: Axes::default(),
        parts: Vec::new(),
        expect_length_m: None,
        measure: None,
    };
    Ok((spec, base))
}

/// The pictures span the vehicle and its origin: bounded, or a 10 km mesh
/// at 2000 px/m never finishes (it aborted on its allocation).
fn check_picture_size(mesh: &Mesh, pixels_per_metre: f64) -> Result<()> {
    let (min, max) = mesh.bounds();
    let extent = (max - min).max_element().max(min.abs().max_element()).max(max.abs().max_element());
    if extent * pixels_per_metre > MAX_PICTURE_PIXELS {
        return Err(CaptureError::BadOptions(format!(
            "pictures of {extent:.1} m at {pixels_per_metre} pixels per metre would be {:.0} pixels wide, more than \
             {MAX_PICTURE_PIXELS}: lower --pixels-per-metre (at most {:.3} here)",
            extent * pixels_per_metre,
            MAX_PICTURE_PIXELS / extent
        )));
    }
    Ok(())
}

/// The palette on which inspect looks for overlapping own UVs (a capture's
/// default is 4096²; a finer palette finds at least these overlaps).
pub(crate) const OVERLAP_CHECK_PALETTE: [u32; 2] = [1024, 1024];

/// The files [`inspect`] writes into its folder.
const INSPECT_FILES: [&str; 5] =
    ["inspect-side.png", "inspect-top.png", "inspect-front.png", "inspect-parts.csv", OVERLAP_PICTURE];

/// Where the own UVs overlap, as a picture of the check's palette (only
/// written when they do).
pub(crate) const OVERLAP_PICTURE: &str = "inspect-uv-overlaps.png";

/// Whether the mesh has own UVs, and where they overlap.
fn uv_state(mesh: &Mesh) -> UvState {
    match (&mesh.uvs, mesh.missing_uvs.is_empty()) {
        (Some(_), _) => match crate::texture::uv_overlaps(mesh, OVERLAP_CHECK_PALETTE) {
            Some(overlaps) if overlaps.texels > 0 => UvState::Overlapping(overlaps),
            _ => UvState::Complete,
        },
        (None, true) => UvState::None,
        (None, false) => UvState::Partial(mesh.missing_uvs.clone()),
    }
}

/// What the overlap picture shows, the first line of its legend.
const OVERLAP_TITLE: &str = "The model's own UVs on a 1024² palette (u to the right, v = 0 at the top, as glTF; \
     the legend is below the palette's 1024 rows). Each texel centre one triangle covers is in its part's colour:";

/// The overlap picture's legend: what red and white mean, then the parts.
fn overlap_entries(parts: &[String], colors: &[Color]) -> Vec<ufcsr::output::LegendEntry> {
    let mut entries = vec![
        ufcsr::output::LegendEntry {
            color: OVERLAP_RED,
            label: "two or more triangles: the UVs overlap".into(),
        },
        ufcsr::output::LegendEntry { color: [255, 255, 255], label: "no triangle".into() },
    ];
    entries.extend(crate::inspect::pictures::part_entries(parts, colors));
    entries
}

/// Texels two or more triangles cover, in the overlap picture.
const OVERLAP_RED: [u8; 3] = [230, 0, 0];

/// [`OVERLAP_PICTURE`]: the own UVs on the check's palette, each texel
/// centre a triangle covers in its part's colour, red where two or more
/// cover it, white where none does (row 0 = v 0, the top, as glTF), and
/// the legend saying so below the palette's rows.
fn write_overlap_picture(mesh: &Mesh, colors: &[Color], out: &Path) -> Result<Option<PathBuf>> {
    let Some(uvs) = &mesh.uvs else { return Ok(None) };
    let [w, h] = OVERLAP_CHECK_PALETTE;
    let size = glam::DVec2::new(f64::from(w), f64::from(h));
    let mut rgb = vec![255u8; (w * h * 3) as usize];
    let mut count = vec![0u8; (w * h) as usize];
    for (t, triangle) in mesh.triangles.iter().enumerate() {
        let uv = triangle.map(|i| uvs.get(i as usize).map_or(glam::DVec2::ZERO, |uv| uv.as_dvec2() * size));
        let color = colors[mesh.triangle_part[t] as usize].rgb();
        crate::texture::uv_islands::for_texel_centres(&uv, OVERLAP_CHECK_PALETTE, |x, y| {
            let i = (y * w + x) as usize;
            count[i] = count[i].saturating_add(1);
            let shown = if count[i] > 1 { OVERLAP_RED } else { color };
            rgb[i * 3..i * 3 + 3].copy_from_slice(&shown);
        });
    }
    let (rgb, size, _) = with_legend(&rgb, [w, h], OVERLAP_TITLE, &overlap_entries(&mesh.parts, colors));
    let path = out.join(OVERLAP_PICTURE);
    ufcsr::files::write_rgb_png(&path, size, &rgb, png::Compression::Fast)?;
    Ok(Some(path))
}

/// Inspects the vehicle of a scene file or mesh and writes its pictures.
pub fn inspect(options: &InspectOptions) -> Result<Inspection> {
    let (spec, base) = vehicle_spec(&options.input)?;
    inspect_spec(options, &spec, &base, &options.out)
}

/// Inspects every measured vehicle of a scene file that measures several
/// ([`crate::scene::fleet`]: its own `vehicle` and the `vehicle` occluders
/// with `measure`, a copy of the scene's vehicle or their own `model`), each
/// into `out/NAME`, in the scene's order, its names checked as the capture
/// checks them. Empty for any other input, which [`inspect`] inspects.
pub fn inspect_fleet(options: &InspectOptions) -> Result<Vec<(String, Inspection)>> {
    let is_scene = options.input.extension().is_some_and(|e| e.eq_ignore_ascii_case("json"));
    if !is_scene {
        return Ok(Vec::new());
    }
    let (file, base) = scene_file(&options.input)?;
    let vehicles = fleet_specs(&options.input, &file)?;
    if !vehicles.is_empty() {
        ufcsr::files::create_output_dir(&options.out)?;
    }
    vehicles
        .into_iter()
        .map(|(name, spec)| {
            let out = ufcsr::files::output_sub_dir(&options.out, Path::new(&name))?;
            Ok((name, inspect_spec(options, &spec, &base, &out)?))
        })
        .collect()
}

/// The measured vehicles of `file` (at `path`) and their specs, the scene's
/// own first; empty when it measures one.
fn fleet_specs(path: &Path, file: &SceneFile) -> Result<Vec<(String, VehicleSpec)>> {
    use crate::scene::fleet::FleetVehicle;
    use crate::scene::scene_file::OccluderShape;
    let mut specs = Vec::new();
    let mut measured = Vec::new();
    for (number, occluder) in file.occluders.iter().enumerate() {
        if let OccluderShape::Vehicle { measure: Some(name), model } = &occluder.shape {
            specs.push((name.clone(), model.as_deref().cloned().unwrap_or_else(|| file.vehicle.clone())));
            let source = format!("occluders[{number}]");
            measured.push(FleetVehicle { name: name.clone(), source, moving: None, described: None });
        }
    }
    let fleet = crate::scene::fleet::fleet(path, &file.vehicle, "", measured)?;
    let Some(own) = fleet.first() else {
        return Ok(Vec::new());
    };
    Ok(std::iter::once((own.name.clone(), file.vehicle.clone())).chain(specs).collect())
}

/// Inspects the vehicle `spec` (paths relative to `base`; `options.input`
/// the file it came from) into `out`.
fn inspect_spec(options: &InspectOptions, spec: &VehicleSpec, base: &Path, out: &Path) -> Result<Inspection> {
    let built = vehicle::build(spec, base, &options.input)?;
    let mesh = &built.mesh;
    let colors = part_colors(mesh.parts.len());
    let areas = crate::texture::uv_islands::part_areas(mesh);
    let mut counts = vec![0usize; mesh.parts.len()];
    for &part in &mesh.triangle_part {
        counts[part as usize] += 1;
    }
    let parts: Vec<PartInfo> = mesh
        .parts
        .iter()
        .enumerate()
        .map(|(i, name)| PartInfo {
            name: name.clone(),
            color: colors[i],
            triangles: counts[i],
            area_m2: areas[i],
        })
        .collect();
    let uvs = uv_state(mesh);

    let mut inputs = vec![options.input.clone()];
    inputs.extend(built.files.iter().cloned());
    crate::job::overwrite_guard::refuse_overwriting_inputs(out, &INSPECT_FILES, &[], &inputs)?;
    ufcsr::files::create_output_dir(out)?;
    let pixels_per_metre = match options.pixels_per_metre {
        Some(ppm) if ppm.is_finite() && ppm > 0.0 && ppm <= 2000.0 => ppm,
        Some(ppm) => {
            return Err(CaptureError::BadOptions(format!(
                "pixels per metre must be in (0, 2000], not {ppm}"
            )));
        }
        None => pictures::default_pixels_per_metre(mesh),
    };
    check_picture_size(mesh, pixels_per_metre)?;
    let mut files = pictures::write_views(mesh, &colors, out, pixels_per_metre)?;
    if matches!(uvs, UvState::Overlapping(_)) {
        files.extend(write_overlap_picture(mesh, &colors, out)?);
    }
    let legend = out.join("inspect-parts.csv");
    ufcsr::files::write_atomically(&legend, |w| {
        writeln!(w, "name,color,triangles,area_m2")?;
        for part in &parts {
            writeln!(
                w,
                "{},{},{},{:.6}",
                ufcsr::output::csv_field(&part.name),
                part.color,
                part.triangles,
                part.area_m2
            )?;
        }
        Ok(())
    })?;
    files.push(legend);

    Ok(Inspection {
        input: options.input.clone(),
        mesh: spec.body.as_ref().map_or_else(|| spec.mesh.clone(), |body| format!("body: {body}")),
        axes: spec.axes.clone(),
        expect_length_m: spec.expect_length_m,
        triangles: mesh.triangles.len(),
        bounds: mesh.bounds(),
        ground_centre: vehicle::ground_centre(mesh),
        quality: triangle_quality(mesh),
        uvs,
        parts,
        regions: built.regions,
        part_map: built.part_map,
        warnings: built.warnings,
        files,
    })
}

impl fmt::Display for Inspection {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        self.fmt_geometry(f)?;
        self.fmt_triangles(f)?;
        self.fmt_parts(f)?;
        for file in &self.files {
            writeln!(f, "wrote {}", file.display())?;
        }
        for warning in &self.warnings {
            writeln!(f, "warning: {warning}")?;
        }
        Ok(())
    }
}

impl Inspection {
    /// Axes, size against `expect_length_m`, bounds and origin.
    fn fmt_geometry(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (min, max) = self.bounds;
        let size = max - min;
        let a = &self.axes;
        writeln!(f, "vehicle: {} (from {})", self.mesh, self.input.display())?;
        writeln!(
            f,
            "axes: forward {}, up {}, scale {}, origin [{}, {}, {}] (file units, subtracted before scaling)",
            a.forward, a.up, a.scale, a.origin[0], a.origin[1], a.origin[2]
        )?;
        write!(f, "size: {:.3} m long (x) × {:.3} m wide (y) × {:.3} m high (z)", size.x, size.y, size.z)?;
        match self.expect_length_m {
            Some(expected) => {
                let off = size.x / expected - 1.0;
                let verdict = if off.abs() > LENGTH_TOLERANCE { "OFF" } else { "ok" };
                writeln!(f, "; expect_length_m {expected}: {verdict} ({:+.1}%)", off * 100.0)?;
            }
            None => writeln!(f, "; no expect_length_m to check against")?,
        }
        writeln!(
            f,
            "bounds (vehicle frame: x forward, y left, z up; m): x {:.3}..{:.3}, y {:.3}..{:.3}, z {:.3}..{:.3}",
            min.x, max.x, min.y, max.y, min.z, max.z
        )?;
        let g = self.ground_centre;
        writeln!(
            f,
            "origin: the ground under the vehicle's centre is at x {:+.3}, y {:+.3}, z {:+.3} m from it (poses place and turn the vehicle about its origin)",
            g.x, g.y, g.z
        )
    }

    /// Triangle quality, the worst slivers, and the state of the mesh's UVs.
    fn fmt_triangles(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let q = &self.quality;
        writeln!(
            f,
            "triangles: {}; degenerate (area < {DEGENERATE_AREA_M2:e} m²): {}; slivers (area < 1 mm² or thinner than 0.1 mm): {} ({:.3e} m² in all)",
            self.triangles, q.degenerate, q.slivers, q.sliver_area_m2
        )?;
        for s in &q.examples {
            writeln!(
                f,
                "  sliver: triangle {} ({}): {:.4} mm², {:.4} mm thin",
                s.triangle,
                s.part,
                s.area_m2 * 1e6,
                s.altitude_m * 1e3
            )?;
        }
        match &self.uvs {
            UvState::Complete => writeln!(
                f,
                "UVs: every primitive has its own, without overlaps at {}×{} (--keep-uvs can use them)",
                OVERLAP_CHECK_PALETTE[0], OVERLAP_CHECK_PALETTE[1]
            )?,
            UvState::Overlapping(overlaps) => {
                writeln!(
                    f,
                    "UVs: every primitive has its own, but {} texels of a {}×{} palette are covered by more than one \
                     triangle: --keep-uvs would refuse them (a part map painted over them still labels parts: \
                     parts_from.part_map). Where (red in {OVERLAP_PICTURE}):",
                    overlaps.texels, overlaps.palette[0], overlaps.palette[1]
                )?;
                for line in overlaps.lines() {
                    writeln!(f, "  {line}")?;
                }
            }
            UvState::None => writeln!(f, "UVs: none (captures unwrap the mesh themselves)")?,
            UvState::Partial(missing) => {
                writeln!(f, "UVs: partial, --keep-uvs would fail; without UVs:")?;
                for primitive in missing {
                    writeln!(f, "  {primitive}")?;
                }
            }
        }
        Ok(())
    }

    /// The part rules' matches, and the parts with their colours and areas.
    fn fmt_parts(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some(map) = &self.part_map {
            writeln!(
                f,
                "parts from the part map {} (legend {}) through the model's own UVs: {} texels sampled, {} \
                 triangles split between parts, {} unmapped, {} samples in unlisted colours",
                map.part_map.display(),
                map.legend.display(),
                map.samples,
                map.split_triangles,
                map.unmapped_triangles,
                map.unknown_colors.values().sum::<u64>()
            )?;
        }
        if !self.regions.rules.is_empty() {
            writeln!(f, "part rules (first match wins):")?;
            for rule in &self.regions.rules {
                writeln!(
                    f,
                    "  {:<32} {:>7} triangles {:>10.4} m²",
                    rule.label, rule.triangles, rule.area_m2
                )?;
            }
            writeln!(f, "  unmatched: {} triangles kept their part", self.regions.unmatched_triangles)?;
            writeln!(
                f,
                "  cut: {} triangles cut along the rules' boundaries (each into two or three) before matching",
                self.regions.cut_triangles
            )?;
        }
        writeln!(f, "parts ({}; colours as in the capture's pidt.png and parts.csv):", self.parts.len())?;
        for part in &self.parts {
            writeln!(
                f,
                "  {:<32} {} {:>7} triangles {:>10.4} m²",
                part.name, part.color, part.triangles, part.area_m2
            )?;
        }
        let total: f64 = self.parts.iter().map(|p| p.area_m2).sum();
        writeln!(f, "  surface: {total:.4} m²")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::vec3;

    #[test]
    fn slivers_and_degenerate_triangles_are_counted() {
        let mut mesh = Mesh::default();
        mesh.add_triangle("ok", vec3(0.0, 0.0, 0.0), vec3(1.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0));
        // 1 m long, 0.05 mm high: 25 mm² but a sliver by its altitude.
        mesh.add_triangle("thin", vec3(0.0, 0.0, 0.0), vec3(1.0, 0.0, 0.0), vec3(0.5, 0.00005, 0.0));
        // 0.5 mm × 0.5 mm: 0.125 mm², a sliver by its area.
        mesh.add_triangle("tiny", vec3(0.0, 0.0, 0.0), vec3(0.0005, 0.0, 0.0), vec3(0.0, 0.0005, 0.0));
        // Three points on a line.
        mesh.add_triangle("flat", vec3(0.0, 0.0, 0.0), vec3(1.0, 0.0, 0.0), vec3(2.0, 0.0, 0.0));
        let quality = triangle_quality(&mesh);
        assert_eq!((quality.degenerate, quality.slivers), (1, 2));
        assert_eq!(quality.examples[0].part, "thin");
        assert!((quality.examples[0].altitude_m - 0.00005).abs() < 1e-8);
    }

    #[test]
    fn the_summary_says_how_many_triangles_the_part_rules_cut() {
        let rule = crate::scene::regions::RuleReport { label: "roof".into(), triangles: 12, area_m2: 6.8 };
        let inspection = Inspection {
            input: "scene.json".into(),
            mesh: "box.glb".into(),
            axes: Axes::default(),
            expect_length_m: None,
            triangles: 40,
            bounds: (DVec3::ZERO, DVec3::ONE),
            ground_centre: DVec3::ZERO,
            quality: TriangleQuality::default(),
            uvs: UvState::None,
            parts: Vec::new(),
            regions: RegionReport {
                rules: vec![rule],
                unmatched_triangles: 28,
                cut_triangles: 7,
                left_whole: Vec::new(),
            },
            part_map: None,
            warnings: Vec::new(),
            files: Vec::new(),
        };
        let text = inspection.to_string();
        assert!(text.contains("  unmatched: 28 triangles kept their part"), "{text}");
        assert!(text.contains("  cut: 7 triangles cut along the rules' boundaries"), "{text}");
    }

    #[test]
    fn the_degenerate_vehicle_has_every_kind_of_bad_triangle() {
        let mesh = crate::scene::degenerate_mesh::degenerate_vehicle();
        let quality = triangle_quality(&mesh);
        assert!(quality.degenerate >= 200, "{} zero-area triangles", quality.degenerate);
        assert!(quality.slivers >= 500, "{} slivers", quality.slivers);
        assert_eq!(mesh, crate::scene::degenerate_mesh::degenerate_vehicle());
    }
}
