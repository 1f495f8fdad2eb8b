//! The chosen placements on the vehicle, as pictures: the analyzer's eight
//! views ([`crate::output::view_cameras`], drawn with the CPU rasterizer)
//! of the vehicle in grey, the chosen parts filled in colour and the chosen
//! display patches filled and outlined where they lie on the surface (their
//! footprints from `placement-patches.csv`, else a disc of
//! [`MARKER_RADIUS_M`] at the centre the name carries), for the best 1, 2
//! and 3 of each kind (by the mean over the archives).
//!
//! `placement.png`: a key line, then per chosen set its caption (wrapped to
//! the picture's width with the kerned text layout the figures use, so it
//! is never cut off), a legend (a swatch per member, its displays' names)
//! and a row of eight small views, each named by its direction
//! ([`OverviewLayout`]); `placement-views/KIND-best-K.png`
//! (`part-best-2.png`): each set at full size (four by two), views named.
//! Marks are tested per pixel on the surface point the pixel shows, so what
//! is hidden behind the body stays hidden.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use crate::archive::VehicleModel;
use crate::error::Result;
use crate::format::placement::CombinationRecord;
use crate::output::figure::{FigureSize, MIN_TEXT_PT};
use crate::output::legend::{LEGEND_TEXT_PX, LegendEntry, TextLayout, draw_texts, text_px_for};
use crate::output::part_names::readable_part_name;
use crate::output::{ViewCamera, ZBuffer, view_cameras};
use crate::placement::footprints::{PatchFootprint, centre_in_name};
use crate::placement::search::Objective;

/// The overview picture written beside placement.json.
pub const PLACEMENT_PICTURE_FILE: &str = "placement.png";
/// The folder of full-size pictures, one per chosen set.
pub const PLACEMENT_VIEWS_DIR: &str = "placement-views";
/// Radius of the disc drawn for a patch whose footprint is not recorded, m.
pub(crate) const MARKER_RADIUS_M: f64 = 0.10;
/// Chosen sets drawn per kind: the best 1, 2 and 3.
pub(crate) const PICTURED_SETS: usize = 3;

const PAPER: [u8; 3] = [255, 255, 255];
const BODY: [u8; 3] = [205, 205, 205];
const OUTLINE: [u8; 3] = [20, 20, 20];
/// One colour per member of a set (Okabe–Ito, distinguishable with colour blindness).
const MEMBER_COLORS: [[u8; 3]; 6] =
    [[230, 159, 0], [0, 114, 178], [0, 158, 115], [204, 121, 167], [213, 94, 0], [86, 180, 233]];

/// What one member of a set marks on the vehicle.
#[derive(Debug, Clone, PartialEq)]
pub enum Mark {
    /// A whole part (the model's part of that name).
    Part(String),
    /// A patch with its recorded footprint.
    Patch(PatchFootprint),
    /// A patch known only by its centre: a disc of [`MARKER_RADIUS_M`].
    Centre([f64; 3]),
}

impl Mark {
    /// The mark of candidate `name` of `kind` (`part` or `patch`).
    pub fn of(name: &str, kind: &str, footprints: &BTreeMap<String, PatchFootprint>) -> Option<Mark> {
        if kind == "part" {
            return Some(Mark::Part(name.to_string()));
        }
        match footprints.get(name) {
            Some(footprint) => Some(Mark::Patch(footprint.clone())),
            None => centre_in_name(name).map(Mark::Centre),
        }
    }

    fn covers(&self, part: &str, p: [f64; 3]) -> bool {
        match self {
            Mark::Part(name) => name == part,
            Mark::Patch(footprint) => footprint.contains(p),
            Mark::Centre(c) => {
                (p[0] - c[0]).powi(2) + (p[1] - c[1]).powi(2) + (p[2] - c[2]).powi(2)
                    <= MARKER_RADIUS_M * MARKER_RADIUS_M
            }
        }
    }
}

/// One chosen set to draw: its caption and its members' marks.
#[derive(Debug, Clone, PartialEq)]
pub struct PicturedSet {
    /// `part-best-2`: the file name of its full-size picture.
    pub name: String,
    pub caption: String,
    pub marks: Vec<Mark>,
    /// Per mark, its colour's index: one per member, so a pair shares one.
    pub colors: Vec<usize>,
    /// The legend: per member (colour index = position), its displays' names.
    pub legend: Vec<String>,
    /// Legible seconds (the mean over the archives) and its 95 % interval,
    /// drawn as a bar with whiskers under the caption.
    pub legible_s: f64,
    pub interval_s: Option<[f64; 2]>,
}

/// The sets to draw: per kind, the best sets of 1 to [`PICTURED_SETS`]
/// displays by the mean; a pair's two displays share a colour. A set with
/// no legible time (a "best" of 0 s) is left out, and a set that repeats an
/// earlier one of its kind (at most 3 displays choosing the same as at most
/// 2) is drawn once, its caption saying so. Members are named by
/// [`readable_part_name`].
pub(crate) fn pictured_sets(
    combinations: &[CombinationRecord],
    footprints: &BTreeMap<String, PatchFootprint>,
) -> Vec<PicturedSet> {
    let mut sets: Vec<(PicturedSet, Vec<String>)> = Vec::new();
    for c in combinations.iter().filter(|c| c.objective == Objective::Mean && c.k <= PICTURED_SETS) {
        if c.legible_s <= 0.0 {
            continue;
        }
        let kind = c.kind.name();
        let mut candidates = c.candidates();
        candidates.sort();
        let key = [vec![kind.to_string()], candidates.clone()].concat();
        if let Some((earlier, _)) = sets.iter_mut().find(|(_, k)| *k == key) {
            earlier.caption.push_str(&format!("; also the best with at most {}", c.k));
            continue;
        }
        sets.push((pictured_set(c, footprints), key));
    }
    sets.into_iter().map(|(set, _)| set).collect()
}

/// One chosen set as pictured.
fn pictured_set(c: &CombinationRecord, footprints: &BTreeMap<String, PatchFootprint>) -> PicturedSet {
    let kind = c.kind.name();
    // "patches", not "patchs": the caption is prose.
    let kinds = if kind.ends_with('h') { format!("{kind}es") } else { format!("{kind}s") };
    let colors = c.members.iter().enumerate().flat_map(|(i, m)| m.candidates.iter().map(move |_| i));
    let interval = c.interval_s.map_or(String::new(), |[low, high]| format!(" (95 %: {low:.2}–{high:.2} s)"));
    PicturedSet {
        name: format!("{kind}-best-{}", c.k),
        caption: format!(
            "best {kinds}, at most {} display{} ({} used): {:.2} s legible{interval}, {:.0} % of the time",
            c.k,
            if c.k == 1 { "" } else { "s" },
            c.displays,
            c.legible_s,
            100.0 * c.share_of_time
        ),
        marks: c.candidates().iter().filter_map(|name| Mark::of(name, kind, footprints)).collect(),
        colors: colors.collect(),
        legend: c
            .members
            .iter()
            .map(|m| {
                let names: Vec<String> = m.candidates.iter().map(|n| readable_part_name(n)).collect();
                let names = names.join(" & ");
                if m.adds_no_time { format!("{names} [adds 0 s]") } else { names }
            })
            .collect(),
        legible_s: c.legible_s,
        interval_s: c.interval_s,
    }
}

/// Draws one view: grey body shaded by how squarely it faces the viewer,
/// marked surface in its member's colour, each mark's rim outlined.
/// `colours[i]` picks mark i's colour (missing: its own index).
pub fn render_marked(model: &VehicleModel, camera: &ViewCamera, marks: &[Mark], colors: &[usize]) -> Vec<u8> {
    let [width, height] = camera.size;
    let mut rgb = PAPER.repeat((width * height) as usize);
    // 0: background, 1: body, 2 + i: member i.
    let mut owner = vec![0u8; (width * height) as usize];
    let mut buffer = ZBuffer::new(width, height);
    for part in &model.parts {
        for corners in part.positions.chunks_exact(3) {
            let shade = facing(corners, camera.back);
            let projected =
                [camera.to_picture(corners[0]), camera.to_picture(corners[1]), camera.to_picture(corners[2])];
            buffer.triangle(projected, |pixel, w| {
                let p: [f64; 3] = std::array::from_fn(|axis| {
                    (0..3).map(|corner| w[corner] * f64::from(corners[corner][axis])).sum()
                });
                let member = marks.iter().position(|mark| mark.covers(&part.name, p));
                let color = member.map(|m| colors.get(m).copied().unwrap_or(m) % MEMBER_COLORS.len());
                let base = color.map_or(BODY, |c| MEMBER_COLORS[c]);
                owner[pixel] = member.map_or(1, |m| 2 + m.min(250) as u8);
                let lit = base.map(|c| (f64::from(c) * (0.55 + 0.45 * shade)).round() as u8);
                rgb[pixel * 3..pixel * 3 + 3].copy_from_slice(&lit);
            });
        }
    }
    outline(&mut rgb, &owner, width as usize);
    rgb
}

/// |cos| of the angle between a triangle's normal and the view direction.
fn facing(corners: &[[f32; 3]], back: [f64; 3]) -> f64 {
    let c = |i: usize| corners[i].map(f64::from);
    let (a, b, o) = (c(1), c(2), c(0));
    let (u, v) = ([a[0] - o[0], a[1] - o[1], a[2] - o[2]], [b[0] - o[0], b[1] - o[1], b[2] - o[2]]);
    let n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]];
    let length = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    if length == 0.0 { 0.0 } else { ((n[0] * back[0] + n[1] * back[1] + n[2] * back[2]) / length).abs() }
}

/// Darkens marked pixels whose right or lower neighbour shows something else.
fn outline(rgb: &mut [u8], owner: &[u8], width: usize) {
    for pixel in 0..owner.len() {
        if owner[pixel] < 2 {
            continue;
        }
        let (x, y) = (pixel % width, pixel / width);
        let neighbours = [
            (x > 0).then(|| pixel - 1),
            (x + 1 < width).then_some(pixel + 1),
            (y > 0).then(|| pixel - width),
            (pixel + width < owner.len()).then_some(pixel + width),
        ];
        if neighbours.into_iter().flatten().any(|n| owner[n] != owner[pixel]) {
            rgb[pixel * 3..pixel * 3 + 3].copy_from_slice(&OUTLINE);
        }
    }
}

/// The pictures written.
#[derive(Debug, Clone)]
pub struct WrittenPicture {
    pub overview: PathBuf,
    pub views: Vec<PathBuf>,
    /// `placement.pdf`: the overview at two journal columns (183 mm).
    pub pdf: PathBuf,
}

/// Writes `out/placement.png` and `out/placement-views/NAME.png` for `sets`.
pub(crate) fn write_placement_picture(
    model: &VehicleModel,
    sets: &[PicturedSet],
    out: &Path,
) -> Result<WrittenPicture> {
    // At scale 1: the overview draws each view at half that size.
    let cameras = view_cameras(model, 1);
    let views_dir = out.join(PLACEMENT_VIEWS_DIR);
    // A link planted at placement-views is replaced by a real folder, never written through.
    crate::files::real_dir(&views_dir)?;
    let [view_w, view_h] = cameras[0].size;
    let small: Vec<ViewCamera> = cameras
        .iter()
        .map(|c| ViewCamera {
            size: [view_w / 2, view_h / 2],
            pixels_per_metre: c.pixels_per_metre / 2.0,
            ..*c
        })
        .collect();
    let layout = OverviewLayout::new(sets, [view_w / 2, view_h / 2]);
    let [width, height] = layout.size;
    let mut overview = PAPER.repeat((width * height) as usize);
    let mut views = Vec::with_capacity(sets.len());
    for (row, set) in sets.iter().enumerate() {
        let (sheet_w, sheet_h) = (view_w * 4, view_h * 2);
        let mut sheet = PAPER.repeat((sheet_w * sheet_h) as usize);
        let mut names = Vec::with_capacity(cameras.len());
        for (index, camera) in cameras.iter().enumerate() {
            let picture = render_marked(model, camera, &set.marks, &set.colors);
            let at = (index as u32 % 4 * view_w, index as u32 / 4 * view_h);
            paste(&mut sheet, sheet_w, &picture, (view_w, view_h), at);
            names.push(((at.0 + 6) as i32, (at.1 + 4) as i32, camera.name.to_string()));
        }
        draw_texts(&mut sheet, [sheet_w, sheet_h], &names, LEGEND_TEXT_PX);
        let path = views_dir.join(format!("{}.png", set.name));
        crate::files::write_figure_png(&path, [sheet_w, sheet_h], &sheet, crate::output::figure::DPI)?;
        views.push(path);
        for (index, camera) in small.iter().enumerate() {
            let picture = render_marked(model, camera, &set.marks, &set.colors);
            let at = (index as u32 * view_w / 2, layout.views_y[row]);
            paste(&mut overview, width, &picture, (view_w / 2, view_h / 2), at);
        }
    }
    layout.text.draw(&mut overview, layout.size);
    for bar in &layout.bars {
        bar.draw(&mut overview, width);
    }
    draw_texts(&mut overview, layout.size, &layout.view_names, layout.text.size);
    let path = out.join(PLACEMENT_PICTURE_FILE);
    // The overview says the resolution that prints it as placement.pdf does (183 mm).
    let dpi = f64::from(layout.size[0]) / (crate::output::figure::FigureSize::TwoColumns.width_mm() / 25.4);
    crate::files::write_figure_png(&path, layout.size, &overview, dpi)?;
    let pdf = out.join(PLACEMENT_PDF_FILE);
    let title = "The chosen eHMI placements on the vehicle";
    crate::output::pdf::write_image_pdf(
        &pdf,
        &overview,
        layout.size,
        FigureSize::TwoColumns.width_mm(),
        title,
    )?;
    Ok(WrittenPicture { overview: path, views, pdf })
}

/// The overview as a PDF, printed two journal columns (183 mm) wide.
pub(crate) const PLACEMENT_PDF_FILE: &str = "placement.pdf";
/// Left and right margin of the overview's text.
const MARGIN: u32 = 6;

/// What the overview says where: the key line at the top, per set its
/// caption (wrapped to the width) and legend (a swatch per member, its
/// displays' names), and each small view's direction name.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct OverviewLayout {
    pub size: [u32; 2],
    /// Key, captions and legends ([`crate::output::legend`]).
    pub text: TextLayout,
    /// Direction names of the small views: `(x, y, name)`.
    pub view_names: Vec<(i32, i32, String)>,
    /// Top of each set's row of views.
    pub views_y: Vec<u32>,
    /// Each set's legible time as a bar with its interval's whiskers.
    pub bars: Vec<TimeBar>,
}

/// A set's legible time drawn as a bar from `x0` to `value_x` with a
/// whisker from `low_x` to `high_x` (its 95 % interval), on one scale for
/// every set of the picture (`px_per_s`); `y`, `height`: the bar's band.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct TimeBar {
    pub x0: u32,
    pub y: u32,
    pub height: u32,
    pub px_per_s: f64,
    pub value_x: u32,
    pub interval_x: Option<[u32; 2]>,
}

impl TimeBar {
    /// Draws the bar (Okabe–Ito blue) and the whisker with end caps (ink).
    fn draw(&self, rgb: &mut [u8], width: u32) {
        let mut fill = |x0: u32, x1: u32, y0: u32, y1: u32, color: [u8; 3]| {
            for y in y0..y1 {
                for x in x0..x1.min(width) {
                    let i = ((y * width + x) * 3) as usize;
                    if i + 3 <= rgb.len() {
                        rgb[i..i + 3].copy_from_slice(&color);
                    }
                }
            }
        };
        let (top, bottom) = (self.y, self.y + self.height);
        fill(self.x0, self.value_x.max(self.x0 + 1), top + self.height / 4, bottom - self.height / 4, BAR);
        if let Some([low, high]) = self.interval_x {
            let middle = self.y + self.height / 2;
            fill(low, high + 1, middle - 1, middle + 1, OUTLINE);
            fill(low, low + 2, top, bottom, OUTLINE);
            fill(high.saturating_sub(1), high + 1, top, bottom, OUTLINE);
        }
    }
}

/// The legible-time bars' colour (Okabe–Ito blue).
const BAR: [u8; 3] = [0, 114, 178];

/// The key at the top of the overview.
pub(crate) const OVERVIEW_KEY: &str = "Each row: the vehicle from front, front-left, left, rear-left, rear, rear-right, \
     right and front-right (15° from above); coloured = the chosen displays (one colour per member of the \
     set, a left/right pair shares one), outlined at their rims; grey = the rest of the vehicle. Under each caption, the blue bar is the seconds \
     legible and the black whisker its 95 % interval, on one scale for every set.";

impl OverviewLayout {
    /// The layout of `sets` over rows of eight `view`-sized pictures.
    pub(crate) fn new(sets: &[PicturedSet], view: [u32; 2]) -> OverviewLayout {
        let width = view[0] * 8;
        let room = f64::from(width - 2 * MARGIN);
        // Text at least 7 pt where the picture is printed two columns wide
        // (placement.pdf), never under the screen size.
        let size =
            text_px_for(MIN_TEXT_PT, width, FigureSize::TwoColumns.width_mm()).max(LEGEND_TEXT_PX).ceil();
        let mut text = TextLayout::new(size);
        let mut view_names = Vec::new();
        let mut views_y = Vec::new();
        let mut bars = Vec::new();
        // One scale for every set: the longest time or interval end takes 60 % of the width.
        let longest = sets
            .iter()
            .map(|s| s.interval_s.map_or(s.legible_s, |i| i[1].max(s.legible_s)))
            .fold(0.0, f64::max);
        let px_per_s = if longest > 0.0 { 0.6 * room / longest } else { 0.0 };
        let mut y = text.paragraph(OVERVIEW_KEY, MARGIN, 4, room);
        for set in sets {
            y = text.paragraph(&set.caption, MARGIN, y + text.line() / 2, room);
            let at = |seconds: f64| MARGIN + (seconds.max(0.0) * px_per_s).round() as u32;
            bars.push(TimeBar {
                x0: MARGIN,
                y,
                height: text.line(),
                px_per_s,
                value_x: at(set.legible_s),
                interval_x: set.interval_s.map(|[low, high]| [at(low), at(high)]),
            });
            y += text.line() + 2;
            let entries: Vec<LegendEntry> = set
                .legend
                .iter()
                .enumerate()
                .map(|(i, label)| LegendEntry {
                    color: MEMBER_COLORS[i % MEMBER_COLORS.len()],
                    label: label.clone(),
                })
                .collect();
            y = text.entries(&entries, MARGIN, y, room);
            views_y.push(y);
            for (index, (name, _)) in crate::output::DIRECTIONS.iter().enumerate() {
                let x = (index as u32 * view[0] + 4) as i32;
                view_names.push((x, (y + 2) as i32, (*name).to_string()));
            }
            y += view[1];
        }
        OverviewLayout { size: [width, y.max(1)], text, view_names, views_y, bars }
    }
}

/// Copies a `size` picture into `sheet` (`sheet_w` wide) at `at`.
fn paste(sheet: &mut [u8], sheet_w: u32, picture: &[u8], size: (u32, u32), at: (u32, u32)) {
    let row_bytes = (size.0 * 3) as usize;
    for y in 0..size.1 {
        let from = (y * size.0 * 3) as usize;
        let to = (((at.1 + y) * sheet_w + at.0) * 3) as usize;
        sheet[to..to + row_bytes].copy_from_slice(&picture[from..from + row_bytes]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::archive::ModelPart;

    /// A 2 m cube of two parts: `front` (the +x face) and `body` (the rest).
    fn cube() -> VehicleModel {
        let quad = |corners: [[f32; 3]; 4]| {
            vec![corners[0], corners[1], corners[2], corners[0], corners[2], corners[3]]
        };
        let front = quad([[1.0, -1.0, 0.0], [1.0, 1.0, 0.0], [1.0, 1.0, 2.0], [1.0, -1.0, 2.0]]);
        let mut body = quad([[-1.0, -1.0, 0.0], [-1.0, 1.0, 0.0], [-1.0, 1.0, 2.0], [-1.0, -1.0, 2.0]]);
        body.extend(quad([[-1.0, 1.0, 0.0], [1.0, 1.0, 0.0], [1.0, 1.0, 2.0], [-1.0, 1.0, 2.0]]));
        body.extend(quad([[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [1.0, -1.0, 2.0], [-1.0, -1.0, 2.0]]));
        body.extend(quad([[-1.0, -1.0, 2.0], [1.0, -1.0, 2.0], [1.0, 1.0, 2.0], [-1.0, 1.0, 2.0]]));
        let part = |name: &str, positions: Vec<[f32; 3]>| ModelPart {
            name: name.into(),
            uvs: vec![[0.0, 0.0]; positions.len()],
            positions,
        };
        VehicleModel { parts: vec![part("front", front), part("body", body)] }
    }

    fn count(rgb: &[u8], color: [u8; 3], shade: f64) -> usize {
        let lit = color.map(|c| (f64::from(c) * (0.55 + 0.45 * shade)).round() as u8);
        rgb.chunks_exact(3).filter(|p| *p == lit).count()
    }

    #[test]
    fn a_chosen_part_is_colored_only_where_it_faces_the_view() {
        let model = cube();
        let cameras = view_cameras(&model, 1);
        let marks = [Mark::Part("front".into())];
        let front = render_marked(&model, &cameras[0], &marks, &[]);
        let rear = render_marked(&model, &cameras[4], &marks, &[]);
        // Seen from the front (15° above), the front face is 2 m × 2 m·cos 15°.
        let camera = &cameras[0];
        let expected = 2.0 * 2.0 * 15f64.to_radians().cos() * camera.pixels_per_metre.powi(2);
        let shade = 15f64.to_radians().cos();
        let colored = count(&front, MEMBER_COLORS[0], shade) as f64;
        // Interior pixels only: the rim is outlined.
        assert!(colored < expected && colored > 0.9 * expected, "{colored} of {expected}");
        assert_eq!(count(&rear, MEMBER_COLORS[0], shade), 0, "hidden behind the body from the rear");
    }

    #[test]
    fn a_patch_is_drawn_its_size_and_a_patch_without_footprint_as_a_disc() {
        let model = cube();
        let camera = &view_cameras(&model, 1)[0];
        let patch = PatchFootprint {
            centre: [1.0, 0.0, 1.0],
            normal: [1.0, 0.0, 0.0],
            up: [0.0, 0.0, 1.0],
            size_m: [0.8, 0.4],
            covers: Vec::new(),
        };
        let shade = 15f64.to_radians().cos();
        let drawn =
            count(&render_marked(&model, camera, &[Mark::Patch(patch)], &[]), MEMBER_COLORS[0], shade) as f64;
        let expected = 0.8 * 0.4 * shade * camera.pixels_per_metre.powi(2);
        assert!(drawn < expected && drawn > 0.8 * expected, "{drawn} of {expected}");
        let disc = count(
            &render_marked(&model, camera, &[Mark::Centre([1.0, 0.0, 1.0])], &[]),
            MEMBER_COLORS[0],
            shade,
        ) as f64;
        let expected =
            std::f64::consts::PI * MARKER_RADIUS_M.powi(2) * shade * camera.pixels_per_metre.powi(2);
        assert!(disc < expected && disc > 0.5 * expected, "{disc} of {expected}");
    }

    fn long_set() -> PicturedSet {
        PicturedSet {
            name: "patch-best-3".into(),
            caption: format!(
                "best patches, at most 3 displays (6 used): {}",
                "front_bumper@x2.95y-0.76z0.46 ".repeat(8)
            ),
            marks: vec![Mark::Part("front".into()), Mark::Part("body".into())],
            colors: vec![0, 1],
            legend: vec![
                "front".into(),
                "windshield@x1.02y0.76z1.82 & windshield@x1.03y-0.76z1.82".into(),
                "front_fender_right@x2.45y-1.00z0.65 ".repeat(9),
            ],
            legible_s: 2.0,
            interval_s: Some([1.5, 2.5]),
        }
    }

    #[test]
    fn the_overview_caption_fits_and_every_view_is_named_and_every_member_in_the_legend() {
        if !crate::output::plot_font_available() {
            eprintln!("skipped: no font (set UFCSR_FONT)");
            return;
        }
        let sets = [long_set(), long_set()];
        let layout = OverviewLayout::new(&sets, [200, 150]);
        let width = layout.size[0];
        assert_eq!(width, 1600);
        for (x, _, text) in &layout.text.texts {
            let right = f64::from(*x) + layout.text.width(text);
            assert!(right <= f64::from(width - MARGIN), "{right} > {width}: {text}");
        }
        // The long caption was wrapped, not cut: every word is on some line.
        let lines: Vec<&str> = layout.text.texts.iter().map(|(_, _, t)| t.as_str()).collect();
        assert!(lines.iter().filter(|l| l.contains("front_bumper@")).count() >= 2, "{lines:?}");
        assert!(lines.contains(&"front") && lines.iter().any(|l| l.starts_with("windshield@x1.02")));
        // The over-long legend entry is cut with an ellipsis.
        assert!(lines.iter().any(|l| l.starts_with("front_fender_right@") && l.ends_with('…')));
        assert_eq!(layout.text.swatches.len(), 6, "a swatch per member per set");
        assert_eq!(layout.text.swatches[1].2, MEMBER_COLORS[1]);
        let names: Vec<&str> = layout.view_names.iter().map(|(_, _, n)| n.as_str()).collect();
        assert_eq!(names.len(), 16);
        assert_eq!(
            &names[..8],
            ["front", "front-left", "left", "rear-left", "rear", "rear-right", "right", "front-right"]
        );
        // Views start below their set's legend, rows do not overlap.
        assert!(layout.views_y[1] >= layout.views_y[0] + 150);
        assert_eq!(layout.size[1], layout.views_y[1] + 150);
    }

    #[test]
    fn the_overview_draws_the_legend_swatches_and_the_direction_names() {
        if !crate::output::plot_font_available() {
            eprintln!("skipped: no font (set UFCSR_FONT)");
            return;
        }
        let dir = tempfile::tempdir().unwrap();
        let sets = [long_set()];
        let written = write_placement_picture(&cube(), &sets, dir.path()).unwrap();
        let image = crate::png::rows::read_color_image(&written.overview, |_| Ok(())).unwrap();
        let layout = OverviewLayout::new(&sets, [200, 150]);
        assert_eq!([image.width, image.height], layout.size);
        let at = |x: i32, y: i32| image.colors[y as usize * image.width as usize + x as usize];
        let packed = |[r, g, b]: [u8; 3]| u32::from(r) << 16 | u32::from(g) << 8 | u32::from(b);
        for (index, &(x, y, color)) in layout.text.swatches.iter().enumerate() {
            let (cx, cy) = layout.text.swatch_centre(index);
            assert_eq!(at(cx, cy), packed(color), "swatch at {x},{y}");
        }
        // placement.pdf: the picture at 183 mm, its text at least 7 pt there.
        let pdf = std::fs::read(&written.pdf).unwrap();
        assert!(pdf.starts_with(b"%PDF-") && pdf.trim_ascii_end().ends_with(b"%%EOF"));
        let text = String::from_utf8_lossy(&pdf);
        assert!(text.contains(&format!("/Width {}", image.width)), "placement.pdf's image width");
        assert!(text.contains(&format!("/Height {}", image.height)), "placement.pdf's image height");
        let em_mm = layout.text.size / 1.24 / f64::from(image.width) * 183.0;
        assert!(em_mm / crate::output::figure::MM_PER_PT >= 7.0, "{em_mm} mm");
        // Dark text pixels where each view's name is (the views are paper and grey there).
        for (x, y, name) in &layout.view_names {
            let dark = (0..60)
                .flat_map(|dx| (0..20).map(move |dy| (x + dx, y + dy)))
                .filter(|&(px, py)| at(px, py) & 0xFF < 100)
                .count();
            assert!(dark > 10, "no label {name} at {x},{y}");
        }
    }

    fn combination(k: usize, members: &[&[&str]], legible_s: f64) -> CombinationRecord {
        use crate::format::placement::{CandidateKind, MemberRecord, Method};
        let member = |names: &&[&str]| MemberRecord {
            candidates: names.iter().map(|n| n.to_string()).collect(),
            displays: names.len(),
            adds_s: 0.5,
            adds_no_time: false,
        };
        CombinationRecord {
            k,
            displays: members.iter().map(|m| m.len()).sum(),
            kind: CandidateKind::Part,
            objective: Objective::Mean,
            method: Method::Exhaustive,
            members: members.iter().map(member).collect(),
            legible_s,
            interval_s: None,
            p_best: None,
            p_within_epsilon: None,
            share_of_time: 0.5,
            worst_case_s: 1.0,
            per_archive_s: vec![1.0],
            upper_bound_s: 1.0,
            gap_s: 0.0,
            runners_up: Vec::new(),
            tied_with: Vec::new(),
            p_best_note: None,
        }
    }

    #[test]
    fn a_left_right_pair_shares_one_color() {
        let set = combination(3, &[&["b_pillar_left", "b_pillar_right"], &["grill"]], 1.0);
        let pictured = pictured_sets(&[set], &BTreeMap::new());
        assert_eq!(pictured[0].colors, vec![0, 0, 1]);
        assert_eq!(pictured[0].legend, ["B-pillar, left & B-pillar, right", "grill"]);
        assert!(pictured[0].caption.contains("at most 3 displays (3 used)"), "{}", pictured[0].caption);
    }

    #[test]
    fn a_repeated_set_is_drawn_once_and_a_set_of_no_legible_time_not_at_all() {
        let sets = [
            combination(1, &[&["hood"]], 1.5),
            combination(2, &[&["hood"], &["grill"]], 2.0),
            // At most 3 chooses what at most 2 chose (the same displays, listed in another order).
            combination(3, &[&["grill"], &["hood"]], 2.0),
        ];
        let pictured = pictured_sets(&sets, &BTreeMap::new());
        assert_eq!(pictured.len(), 2, "{pictured:?}");
        assert!(pictured[1].caption.ends_with("also the best with at most 3"), "{}", pictured[1].caption);
        let nothing = [combination(1, &[&["front_bumper@x2.95y-0.76z0.46"]], 0.0)];
        assert!(pictured_sets(&nothing, &BTreeMap::new()).is_empty(), "a 0 s best display is drawn");
    }

    #[test]
    fn the_legible_time_bar_spans_its_interval_on_one_scale() {
        let mut wide = long_set();
        wide.caption = "a".into();
        let mut plain = wide.clone();
        (plain.legible_s, plain.interval_s) = (1.0, None);
        let layout = OverviewLayout::new(&[wide.clone(), plain], [200, 150]);
        let [bar, other] = [layout.bars[0], layout.bars[1]];
        let seconds = |x: u32| f64::from(x - bar.x0) / bar.px_per_s;
        let [low, high] = bar.interval_x.unwrap();
        assert!((seconds(low) - 1.5).abs() < 0.01 && (seconds(high) - 2.5).abs() < 0.01, "{bar:?}");
        assert!((seconds(bar.value_x) - 2.0).abs() < 0.01);
        assert!((seconds(other.value_x) - 1.0).abs() < 0.01 && other.interval_x.is_none());
        assert!(bar.y + bar.height <= layout.views_y[0], "the bar runs into the views");
        // Drawn: the whisker's end caps are ink at 1.5 s and 2.5 s, the bar blue at 1 s.
        let mut rgb = PAPER.repeat((layout.size[0] * layout.size[1]) as usize);
        bar.draw(&mut rgb, layout.size[0]);
        let at = |x: u32, y: u32| {
            let i = ((y * layout.size[0] + x) * 3) as usize;
            [rgb[i], rgb[i + 1], rgb[i + 2]]
        };
        assert_eq!(at(low, bar.y + 1), OUTLINE);
        assert_eq!(at(high, bar.y + 1), OUTLINE);
        assert_eq!(at(bar.x0 + bar.px_per_s as u32, bar.y + bar.height / 2 - 3), BAR);
    }
}
