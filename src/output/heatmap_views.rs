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
//! views render wherever analyses run (and in CI); `ufcsr views` redraws
//! a result's views the same way.
//!
//! `views/NAME.png` for each direction (400×300 pixels times
//! `--views-scale`, default 2) and `views.png`, a contact sheet (four by
//! two) with a colour bar underneath; the shading, outlines, compass and
//! the sheet's words are [`crate::output::view_sheet`]'s.

use crate::archive::vehicle_model::VehicleModel;
use crate::format::result::CountMeasure;
use crate::optics::vector::dot;
use crate::output::raster::ZBuffer;
use crate::{
    archive::options::HeatmapOptions,
    output::heatmap::{plasma, position},
};

pub use crate::output::heatmap::NEVER_SEEN;
const PAPER: [u8; 3] = [255, 255, 255];
/// Size of one view at `--views-scale 1`.
pub const VIEW_BASE: (u32, u32) = (400, 300);
/// The default `--views-scale`.
pub const DEFAULT_VIEWS_SCALE: u32 = 2;
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
    /// The direction's azimuth, degrees counter-clockwise from the front.
    pub azimuth_deg: f64,
    /// Picture pixels per metre (the same in all eight views).
    pub pixels_per_metre: f64,
    /// The point (along `right`, `up`, in metres) at the picture's centre.
    pub centre: [f64; 2],
    /// Picture size in pixels.
    pub size: [u32; 2],
    /// Nearest and farthest depth of the vehicle (metres along −`back`).
    pub depth_range: [f64; 2],
}

impl ViewCamera {
    /// The camera looking from `azimuth_deg`, before it is fitted to a model.
    fn looking_from(name: &'static str, azimuth_deg: f64, size: [u32; 2]) -> ViewCamera {
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
            azimuth_deg,
            right,
            up,
            back,
            pixels_per_metre: 1.0,
            centre: [0.0, 0.0],
            size,
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
/// `scale` multiplies the 400×300 pixels of a view (0 counts as 1).
pub fn view_cameras(model: &VehicleModel, scale: u32) -> Vec<ViewCamera> {
    let size = [VIEW_BASE.0 * scale.max(1), VIEW_BASE.1 * scale.max(1)];
    let mut cameras: Vec<ViewCamera> =
        DIRECTIONS.iter().map(|&(name, azimuth)| ViewCamera::looking_from(name, azimuth, size)).collect();
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
        let fit = (f64::from(size[0]) * 0.9 / (hi[0] - lo[0]).max(1e-6))
            .min(f64::from(size[1]) * 0.9 / (hi[1] - lo[1]).max(1e-6));
        scale = scale.min(fit);
        camera.centre = [(lo[0] + hi[0]) / 2.0, (lo[1] + hi[1]) / 2.0];
        camera.depth_range = [lo[2], hi[2]];
    }
    for camera in &mut cameras {
        camera.pixels_per_metre = scale;
    }
    cameras
}

/// What the views show: per-texel colours (plasma for seen texels, grey
/// for the rest), the words on the sheet, the size and the pedestrian's
/// directions.
pub struct ViewTexture<'a> {
    pub counts: &'a [u32],
    pub width: u32,
    pub height: u32,
    pub options: HeatmapOptions,
    /// What the counts are, for the contact sheet ([`views_caption`]).
    pub caption: String,
    /// What one count is, for the colour bar ([`measure_unit`]).
    pub unit: String,
    /// The value of one count when the counts are levels of a measured
    /// quantity ([`crate::output::heatmap::AreaLevels`]): the colour bar's
    /// numbers are counts × this. `None`: counts.
    pub quantum: Option<f64>,
    /// Pixels per view are 400×300 times this (`--views-scale`, default 2).
    pub views_scale: u32,
    /// Where the pedestrian was seen from the vehicle, one azimuth per frame
    /// (degrees counter-clockwise from its front; [`crate::TrackFrame`]):
    /// marked in each view's compass. Empty without a manifest.
    pub pedestrian_azimuths_deg: Vec<f64>,
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
}

/// What one count is, in words, for the colour bar: `images` for the
/// paper's measure, `eye-frames` for the unobstructed one.
pub fn measure_unit(measure: CountMeasure) -> &'static str {
    match measure {
        CountMeasure::Pixels => "images",
        CountMeasure::Unobstructed => "eye-frames",
    }
}

/// The colour bar's unit for per-texel angular area.
pub const AREA_UNIT: &str = "deg²·s per texel";

/// The contact sheet's caption when the views show per-texel angular area.
pub fn area_views_caption(scenario: Option<&str>) -> String {
    let what =
        "Visible angular area over time of each point of the vehicle (deg²·s per texel, the quoted measure)";
    match scenario {
        Some(name) => format!("{what} · scenario {name}"),
        None => what.to_string(),
    }
}

/// The contact sheet's caption: the measure in words and the scenario's
/// name from the manifest. The archive's folder name is not a figure's to
/// carry (issue 35: the page's captions say the scenario); `_archive` is
/// kept for callers.
pub fn views_caption(measure: CountMeasure, _archive: &str, scenario: Option<&str>) -> String {
    let what = match measure {
        CountMeasure::Pixels => "Images in which each point of the vehicle was seen",
        CountMeasure::Unobstructed => {
            "Eye-frames in which each point of the vehicle was in unobstructed view"
        }
    };
    match scenario {
        Some(name) => format!("{what} (paper-compatible count) · scenario {name}"),
        None => format!("{what} (paper-compatible count)"),
    }
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
