//! The heatmap on the vehicle from the paper's eight directions, as pictures.
//!
//! Front, front-right, right, rear-right, rear, rear-left, left and
//! front-left, seen from slightly above, orthographic, one scale for all
//! eight so that sizes compare. Each pixel shows the count of the texel its
//! surface point maps to (nearest, through the vehicle's palette UVs) on the
//! heatmap's plasma scale; texels never seen are grey, so they are told
//! apart from the darkest colour, and everything off the vehicle is white.
//! Drawn with the CPU rasterizer ([`crate::output::raster`], which
//! inspect's pictures share): the analyzer needs no GPU, so
//! views render wherever analyses run (and in CI). The cameras are public
//! ([`view_cameras`]) and [`write_views_with`] takes any renderer of them:
//! `ufcsr-capture views` draws the same views with the capture's wgpu
//! renderer, and a test holds the two to the same pictures.
//!
//! `views/NAME.png` for each direction and `views.png`, a contact sheet
//! (four by two) with a colour bar underneath: grey (never seen), then the
//! plasma scale from 0 to the heatmap's maximum (the page and result.json
//! state the maximum and the scale).

use std::path::{Path, PathBuf};

use crate::error::Result;
use crate::output::raster::ZBuffer;
use crate::output::vehicle_model::VehicleModel;
use crate::{
    input::options::HeatmapOptions,
    output::heatmap::{plasma, position},
};

/// Colour of texels on the vehicle that were never seen.
pub const NEVER_SEEN: [u8; 3] = [160, 160, 160];
const PAPER: [u8; 3] = [255, 255, 255];
/// Size of one view.
const VIEW: (u32, u32) = (400, 300);
/// Height of the colour bar and its labels under the contact sheet.
const BAR: u32 = 52;
/// Height of the colour bar itself.
const BAR_STRIP: u32 = 20;
/// Degrees above the horizon the views look down from.
const ELEVATION_DEG: f64 = 15.0;

/// The eight directions, named; azimuth in degrees from the vehicle's front
/// (+x), counter-clockwise seen from above (towards its left, +y).
pub const DIRECTIONS: [(&str, f64); 8] = [
    ("front", 0.0),
    ("front-left", 45.0),
    ("left", 90.0),
    ("rear-left", 135.0),
    ("rear", 180.0),
    ("rear-right", 225.0),
    ("right", 270.0),
    ("front-right", 315.0),
];

/// One of the eight views: an orthographic camera looking at the vehicle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ViewCamera {
    /// The direction's name (file name of its picture).
    pub name: &'static str,
    /// Unit vectors in the vehicle frame: `right` and `up` span the picture,
    /// `back` points from the vehicle to the viewer.
    pub right: [f64; 3],
    pub up: [f64; 3],
    pub back: [f64; 3],
    /// Picture pixels per metre (the same in all eight views).
    pub pixels_per_metre: f64,
    /// The point (along `right`, `up`, in metres) at the picture's centre.
    pub centre: [f64; 2],
    /// Picture size in pixels.
    pub size: [u32; 2],
    /// Nearest and farthest depth of the vehicle (metres along −`back`).
    pub depth_range: [f64; 2],
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

impl ViewCamera {
    /// The camera looking from `azimuth_deg`, before it is fitted to a model.
    fn looking_from(name: &'static str, azimuth_deg: f64) -> ViewCamera {
        let (a, e) = (azimuth_deg.to_radians(), ELEVATION_DEG.to_radians());
        let back = [a.cos() * e.cos(), a.sin() * e.cos(), e.sin()];
        // right = normalize(Z × back); up = back × right.
        let right = [-back[1], back[0], 0.0];
        let length = (right[0] * right[0] + right[1] * right[1]).sqrt();
        let right = [right[0] / length, right[1] / length, 0.0];
        let up = [
            back[1] * right[2] - back[2] * right[1],
            back[2] * right[0] - back[0] * right[2],
            back[0] * right[1] - back[1] * right[0],
        ];
        ViewCamera {
            name,
            right,
            up,
            back,
            pixels_per_metre: 1.0,
            centre: [0.0, 0.0],
            size: [VIEW.0, VIEW.1],
            depth_range: [0.0, 1.0],
        }
    }

    /// Metres along `right` and `up`, and depth (smaller is nearer).
    fn project(&self, p: [f32; 3]) -> [f64; 3] {
        let p = [f64::from(p[0]), f64::from(p[1]), f64::from(p[2])];
        [dot(p, self.right), dot(p, self.up), -dot(p, self.back)]
    }

    /// Picture position in pixels (x to the right, y down from the top-left
    /// corner; pixel centres at +0.5) and depth in metres (smaller is nearer).
    pub fn to_picture(&self, p: [f32; 3]) -> [f64; 3] {
        let [x, y, depth] = self.project(p);
        [
            f64::from(self.size[0]) / 2.0 + (x - self.centre[0]) * self.pixels_per_metre,
            f64::from(self.size[1]) / 2.0 - (y - self.centre[1]) * self.pixels_per_metre,
            depth,
        ]
    }
}

/// The eight cameras, fitted to `model`: one scale for all eight (the
/// largest extent in any of them fits), each centred on the vehicle.
pub fn view_cameras(model: &VehicleModel) -> Vec<ViewCamera> {
    let mut cameras: Vec<ViewCamera> =
        DIRECTIONS.iter().map(|&(name, azimuth)| ViewCamera::looking_from(name, azimuth)).collect();
    let mut scale = f64::INFINITY;
    for camera in &mut cameras {
        let (mut lo, mut hi) = ([f64::MAX; 3], [f64::MIN; 3]);
        for p in model.parts.iter().flat_map(|part| part.positions.iter()) {
            let q = camera.project(*p);
            for k in 0..3 {
                lo[k] = lo[k].min(q[k]);
                hi[k] = hi[k].max(q[k]);
            }
        }
        let fit = (f64::from(VIEW.0) * 0.9 / (hi[0] - lo[0]).max(1e-6))
            .min(f64::from(VIEW.1) * 0.9 / (hi[1] - lo[1]).max(1e-6));
        scale = scale.min(fit);
        camera.centre = [(lo[0] + hi[0]) / 2.0, (lo[1] + hi[1]) / 2.0];
        camera.depth_range = [lo[2], hi[2]];
    }
    for camera in &mut cameras {
        camera.pixels_per_metre = scale;
    }
    cameras
}

/// Per-texel colours for the views: plasma for seen texels, grey for the rest.
pub struct ViewTexture<'a> {
    pub counts: &'a [u32],
    pub width: u32,
    pub height: u32,
    pub options: HeatmapOptions,
    /// What the counts are, for the contact sheet (e.g. the measure and the archive).
    pub caption: String,
}

impl ViewTexture<'_> {
    /// The scale's top: `options.max`, else the largest count.
    pub fn max(&self) -> u32 {
        self.options.max.unwrap_or_else(|| self.counts.iter().copied().max().unwrap_or(0))
    }

    fn color(&self, uv: [f64; 2], max: u32) -> [u8; 3] {
        let x = ((uv[0] * f64::from(self.width)).floor().max(0.0) as u32).min(self.width - 1);
        let y = ((uv[1] * f64::from(self.height)).floor().max(0.0) as u32).min(self.height - 1);
        match self.counts.get(y as usize * self.width as usize + x as usize) {
            Some(&count) if count > 0 => plasma(position(count, max, self.options.scale)),
            _ => NEVER_SEEN,
        }
    }

    /// Every texel's colour in the views, RGBA8, row 0 at the top: the
    /// heatmap's colours (its per-count table) with never-seen texels grey,
    /// the texture a GPU renderer draws the views with.
    pub fn texel_rgba(&self) -> Vec<u8> {
        let rgb = crate::output::heatmap::render(self.counts, self.width, self.options);
        rgb.chunks_exact(3)
            .zip(self.counts)
            .flat_map(|(color, &count)| {
                let [r, g, b] = if count > 0 { [color[0], color[1], color[2]] } else { NEVER_SEEN };
                [r, g, b, 255]
            })
            .collect()
    }
}

/// The contact sheet's caption: the measure and the archive's folder name.
pub fn views_caption(measure: &str, archive: &str) -> String {
    let name = Path::new(archive)
        .file_name()
        .map_or_else(|| archive.to_string(), |n| n.to_string_lossy().into_owned());
    format!("measure: {measure} · {name}")
}

/// Renders one camera's picture, RGB, rows top to bottom: the CPU renderer
/// [`write_views`] uses.
pub fn render_view(model: &VehicleModel, texture: &ViewTexture, camera: &ViewCamera) -> Vec<u8> {
    let [width, height] = camera.size;
    let mut rgb = PAPER.repeat((width * height) as usize);
    let mut buffer = ZBuffer::new(width, height);
    let max = texture.max();
    for part in &model.parts {
        for (corners, uvs) in part.positions.chunks_exact(3).zip(part.uvs.chunks_exact(3)) {
            let projected =
                [camera.to_picture(corners[0]), camera.to_picture(corners[1]), camera.to_picture(corners[2])];
            buffer.triangle(projected, |pixel, w| {
                let uv = [
                    w[0] * f64::from(uvs[0][0]) + w[1] * f64::from(uvs[1][0]) + w[2] * f64::from(uvs[2][0]),
                    w[0] * f64::from(uvs[0][1]) + w[1] * f64::from(uvs[1][1]) + w[2] * f64::from(uvs[2][1]),
                ];
                rgb[pixel * 3..pixel * 3 + 3].copy_from_slice(&texture.color(uv, max));
            });
        }
    }
    rgb
}

/// The files [`write_views`] wrote.
#[derive(Debug, Clone)]
pub struct WrittenViews {
    pub contact_sheet: PathBuf,
    pub views: Vec<PathBuf>,
}

/// Writes `dir/views/NAME.png` for the eight directions and `dir/views.png`,
/// drawn with the CPU renderer ([`render_view`]).
pub fn write_views(model: &VehicleModel, texture: &ViewTexture, dir: &Path) -> Result<WrittenViews> {
    write_views_with(model, texture, dir, |camera| Ok(render_view(model, texture, camera)))
}

/// [`write_views`] with another renderer: `render` draws one camera's
/// picture (RGB, `camera.size`, rows top to bottom).
pub fn write_views_with(
    model: &VehicleModel,
    texture: &ViewTexture,
    dir: &Path,
    mut render: impl FnMut(&ViewCamera) -> Result<Vec<u8>>,
) -> Result<WrittenViews> {
    let cameras = view_cameras(model);
    let views_dir = dir.join("views");
    std::fs::create_dir_all(&views_dir).map_err(|e| crate::error::Error::io(&views_dir, e))?;
    let (width, height) = VIEW;
    let sheet_width = width * 4;
    let sheet_height = height * 2 + BAR;
    let mut sheet = PAPER.repeat((sheet_width * sheet_height) as usize);
    let mut views = Vec::with_capacity(cameras.len());
    for (index, camera) in cameras.iter().enumerate() {
        let rgb = render(camera)?;
        if rgb.len() != (width * height * 3) as usize {
            return Err(crate::error::Error::bad_file(
                &views_dir,
                format!("the {} view has {} bytes, not {width}×{height} RGB", camera.name, rgb.len()),
            ));
        }
        let path = views_dir.join(format!("{}.png", camera.name));
        crate::files::write_rgb_png(&path, width, height, &rgb, png::Compression::Fast)?;
        views.push(path);
        let (column, row) = (index as u32 % 4, index as u32 / 4);
        for y in 0..height {
            let from = (y * width * 3) as usize;
            let to = (((row * height + y) * sheet_width + column * width) * 3) as usize;
            sheet[to..to + (width * 3) as usize].copy_from_slice(&rgb[from..from + (width * 3) as usize]);
        }
    }
    // Colour bar: grey (never seen) on the left, then the plasma scale.
    let grey_width = sheet_width / 16;
    for y in height * 2 + 6..height * 2 + 6 + BAR_STRIP {
        for x in 8..sheet_width - 8 {
            let color = if x < 8 + grey_width {
                NEVER_SEEN
            } else if x < 16 + grey_width {
                PAPER
            } else {
                plasma(f64::from(x - 16 - grey_width) / f64::from(sheet_width - 24 - grey_width))
            };
            let i = ((y * sheet_width + x) * 3) as usize;
            sheet[i..i + 3].copy_from_slice(&color);
        }
    }
    let max = texture.max();
    let scale = match texture.options.scale {
        crate::input::options::Scale::Linear => "linear",
        crate::input::options::Scale::Log => "log",
    };
    let labels = SheetLabels {
        views: DIRECTIONS.iter().map(|(name, _)| *name).collect(),
        never_seen_width: grey_width,
        left: "never seen".into(),
        low: "0".into(),
        high: format!("{max} ({scale} scale)"),
        caption: texture.caption.clone(),
    };
    label_sheet(&mut sheet, (sheet_width, sheet_height), (width, height), &labels);
    let contact_sheet = dir.join("views.png");
    crate::files::write_rgb_png(&contact_sheet, sheet_width, sheet_height, &sheet, png::Compression::Fast)?;
    Ok(WrittenViews { contact_sheet, views })
}

/// The words on the contact sheet.
struct SheetLabels {
    views: Vec<&'static str>,
    never_seen_width: u32,
    left: String,
    low: String,
    high: String,
    caption: String,
}

/// Writes each view's direction in its corner and the colour bar's ends and
/// caption under it, when a font is found (see [`crate::output::plots`]); without
/// one the sheet stays unlabelled and the report's text says the same.
fn label_sheet(
    sheet: &mut [u8],
    (sheet_width, sheet_height): (u32, u32),
    (width, height): (u32, u32),
    labels: &SheetLabels,
) {
    use plotters::prelude::*;
    if !crate::output::plots::font_available() {
        return;
    }
    let root = BitMapBackend::with_buffer(sheet, (sheet_width, sheet_height)).into_drawing_area();
    let style = ("sans-serif", 15).into_font().color(&BLACK);
    let mut drawn: std::result::Result<(), _> = Ok(());
    for (index, name) in labels.views.iter().enumerate() {
        let (column, row) = (index as u32 % 4, index as u32 / 4);
        let at = ((column * width + 6) as i32, (row * height + 4) as i32);
        drawn = drawn.and(root.draw(&Text::new(name.to_string(), at, style.clone())));
    }
    let text_y = (height * 2 + 8 + BAR_STRIP) as i32;
    let right = style.clone().pos(plotters::style::text_anchor::Pos::new(
        plotters::style::text_anchor::HPos::Right,
        plotters::style::text_anchor::VPos::Top,
    ));
    let centre = style.clone().pos(plotters::style::text_anchor::Pos::new(
        plotters::style::text_anchor::HPos::Center,
        plotters::style::text_anchor::VPos::Top,
    ));
    let bar_start = (16 + labels.never_seen_width) as i32;
    drawn = drawn
        .and(root.draw(&Text::new(labels.left.clone(), (8, text_y), style.clone())))
        .and(root.draw(&Text::new(labels.low.clone(), (bar_start, text_y), style.clone())))
        .and(root.draw(&Text::new(labels.high.clone(), (sheet_width as i32 - 8, text_y), right)))
        .and(root.draw(&Text::new(labels.caption.clone(), (sheet_width as i32 / 2, text_y), centre)))
        .and(root.present());
    // Labels are a courtesy: a drawing error leaves the colours as they are.
    let _ = drawn;
}
