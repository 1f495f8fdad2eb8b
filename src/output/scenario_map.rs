//! `map.png`: the scenario seen from above, so a reader knows what the
//! numbers are of — the vehicle's trajectory coloured by time (viridis,
//! dark = start) with its footprint at a few frames, the pedestrian (a
//! walk as a path), the static occluders of `scene.glb` filled grey, the
//! moving occluders' paths and footprints, and sightlines from the eyes to
//! the vehicle at the same few frames. Everything comes from the manifest
//! ([`ScenarioTrack`]), `scene.glb` and the vehicle model; north is up and
//! one metre is as long across as up.

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use crate::archive::scenario_track::{ScenarioTrack, TrackFrame};
use crate::archive::vehicle_model::VehicleModel;
use crate::error::{Error, Result};

/// Size of the map in pixels.
pub const MAP_SIZE: (u32, u32) = (1600, 1200);
/// Frames whose footprints and sightlines are drawn.
const MARKED_FRAMES: usize = 5;
/// Metres of ground shown around everything that moves.
const MARGIN_M: f64 = 6.0;
/// Occluder triangles lower than this (the ground) are not drawn.
const GROUND_M: f32 = 0.05;
const OCCLUDER: RGBColor = RGBColor(190, 190, 190);
const MOVING: RGBColor = RGBColor(70, 110, 200);
const PEDESTRIAN: RGBColor = RGBColor(0, 150, 60);

/// The trajectory's colour at `share` of the scenario's duration (0–1).
pub fn time_color(share: f64) -> [u8; 3] {
    let color = colorous::VIRIDIS.eval_continuous(share.clamp(0.0, 1.0));
    [color.r, color.g, color.b]
}

/// What `scene.glb` holds: every occluder's triangles by name, world axes
/// (static ones placed, moving ones in their own frame).
pub struct SceneShapes {
    pub occluders: Vec<(String, Vec<[f32; 3]>)>,
}

impl SceneShapes {
    /// Reads `scene.glb` (an empty scene has no shapes).
    pub fn read(path: &Path) -> Result<SceneShapes> {
        match VehicleModel::read_shapes(path) {
            Ok(model) => Ok(SceneShapes {
                occluders: model.parts.into_iter().map(|part| (part.name, part.positions)).collect(),
            }),
            Err(Error::BadFile { message, .. }) if message == "has no mesh" => {
                Ok(SceneShapes { occluders: Vec::new() })
            }
            Err(error) => Err(error),
        }
    }
}

/// Where world metres land on the map: `pixel` of a ground point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MapFrame {
    /// World x and y at the plot's left and bottom edges.
    pub origin: [f64; 2],
    pub pixels_per_metre: f64,
    /// The plot's top-left corner and size on the map, pixels.
    pub plot: [i32; 4],
}

impl MapFrame {
    /// The map pixel of world point `(x, y)` (north up).
    pub fn pixel(&self, [x, y]: [f64; 2]) -> (i32, i32) {
        let [left, top, _, height] = self.plot;
        (
            left + ((x - self.origin[0]) * self.pixels_per_metre).round() as i32,
            top + height - ((y - self.origin[1]) * self.pixels_per_metre).round() as i32,
        )
    }

    /// Fits the ground between `low` and `high` (world x, y) into `plot`, centred.
    fn fit(low: [f64; 2], high: [f64; 2], plot: [i32; 4]) -> MapFrame {
        let span = [high[0] - low[0], high[1] - low[1]].map(|s| s.max(1.0));
        let pixels_per_metre = (f64::from(plot[2]) / span[0]).min(f64::from(plot[3]) / span[1]);
        let origin = [0, 1].map(|k| {
            let shown = f64::from(plot[2 + k]) / pixels_per_metre;
            (low[k] + high[k]) / 2.0 - shown / 2.0
        });
        MapFrame { origin, pixels_per_metre, plot }
    }
}

/// The ground every moving thing covers, with a margin.
fn extent(track: &[TrackFrame]) -> ([f64; 2], [f64; 2]) {
    let mut low = [f64::MAX; 2];
    let mut high = [f64::MIN; 2];
    let points = track.iter().flat_map(|frame| {
        let eyes = frame.eyes.iter().copied();
        let occluders = frame.occluders.iter().map(|(_, position, _)| *position);
        std::iter::once(frame.vehicle_position).chain(eyes).chain(frame.pedestrian).chain(occluders)
    });
    for point in points {
        for k in 0..2 {
            low[k] = low[k].min(point[k] - MARGIN_M);
            high[k] = high[k].max(point[k] + MARGIN_M);
        }
    }
    (low, high)
}

/// `count` frame indices spread evenly over `frames` frames, first and last included.
fn marked(frames: usize, count: usize) -> Vec<usize> {
    if frames <= count {
        return (0..frames).collect();
    }
    let mut chosen: Vec<usize> = (0..count).map(|k| k * (frames - 1) / (count - 1)).collect();
    chosen.dedup();
    chosen
}

/// A shape's footprint at a pose: the bounding rectangle of its triangles'
/// ground projection (own frame), turned and moved, as world corners.
fn footprint(shape: &[[f32; 3]], position: [f64; 3], yaw_deg: f64) -> Option<Vec<[f64; 2]>> {
    let (mut low, mut high) = ([f64::MAX; 2], [f64::MIN; 2]);
    for p in shape {
        for k in 0..2 {
            low[k] = low[k].min(f64::from(p[k]));
            high[k] = high[k].max(f64::from(p[k]));
        }
    }
    if shape.is_empty() {
        return None;
    }
    let (sin, cos) = yaw_deg.to_radians().sin_cos();
    let corners = [[low[0], low[1]], [high[0], low[1]], [high[0], high[1]], [low[0], high[1]]];
    Some(
        corners
            .iter()
            .map(|[x, y]| [position[0] + cos * x - sin * y, position[1] + sin * x + cos * y])
            .collect(),
    )
}

/// Everything the map shows.
pub struct MapContent<'a> {
    pub track: &'a ScenarioTrack,
    /// `scene.glb`'s shapes, or why they are missing (said on the map).
    pub scene: std::result::Result<SceneShapes, String>,
    pub vehicle: Option<&'a VehicleModel>,
    /// The title (the scenario).
    pub title: String,
}

type Drawn = std::result::Result<(), Box<dyn std::error::Error>>;

/// What one drawing step needs: where to draw, where world points land,
/// what to draw and the frames whose footprints and sightlines are shown.
#[derive(Clone, Copy)]
struct Layer<'a, 'b> {
    root: &'a DrawingArea<BitMapBackend<'b>, Shift>,
    frame: &'a MapFrame,
    content: &'a MapContent<'a>,
    marked_frames: &'a [usize],
}

/// Writes `map.png`; returns where world points landed.
pub fn write_scenario_map(path: &Path, content: &MapContent) -> Result<MapFrame> {
    let frames = &content.track.frames;
    if frames.is_empty() {
        return Err(Error::bad_file(path, "the manifest has no frames with a vehicle pose to map"));
    }
    let (low, high) = extent(frames);
    let frame = MapFrame::fit(low, high, [90, 70, MAP_SIZE.0 as i32 - 130, MAP_SIZE.1 as i32 - 180]);
    // Drawn into pixels, written by the file layer (plotters' file backend
    // would write through a link planted at `path`: issue 41).
    let mut rgb = vec![0u8; MAP_SIZE.0 as usize * MAP_SIZE.1 as usize * 3];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, MAP_SIZE).into_drawing_area();
        draw_map(&root, &frame, content)
            .map_err(|e| Error::bad_file(path, format!("drawing the map: {e}")))?;
        root.present().map_err(|e| Error::bad_file(path, format!("drawing the map: {e}")))?;
    }
    crate::files::write_rgb_png(path, [MAP_SIZE.0, MAP_SIZE.1], &rgb, png::Compression::Fast)?;
    Ok(frame)
}

fn draw_map(root: &DrawingArea<BitMapBackend, Shift>, map: &MapFrame, content: &MapContent) -> Drawn {
    root.fill(&WHITE)?;
    draw_grid(root, map)?;
    // Shapes go into the plot's own area, which clips them; its pixels
    // start at the plot's corner.
    let [left, top, width, height] = map.plot;
    let area = root.clone().shrink((left, top), (width as u32, height as u32));
    let frame = &MapFrame { plot: [0, 0, width, height], ..*map };
    draw_shapes(&area, frame, content)?;
    root.draw(&Rectangle::new([(left, top), (left + width, top + height)], BLACK.stroke_width(1)))?;
    let marked_frames = marked(content.track.frames.len(), MARKED_FRAMES);
    draw_words(&Layer { root, frame: map, content, marked_frames: &marked_frames })
}

fn draw_shapes(root: &DrawingArea<BitMapBackend, Shift>, frame: &MapFrame, content: &MapContent) -> Drawn {
    let frames = &content.track.frames;
    let moving_names: Vec<&str> =
        frames.iter().flat_map(|f| f.occluders.iter().map(|(name, _, _)| name.as_str())).collect();
    if let Ok(scene) = &content.scene {
        for (name, triangles) in &scene.occluders {
            if moving_names.contains(&name.as_str()) {
                continue;
            }
            for corners in triangles.chunks_exact(3) {
                if corners.iter().all(|c| c[2] < GROUND_M) {
                    continue;
                }
                let points: Vec<(i32, i32)> =
                    corners.iter().map(|c| frame.pixel([f64::from(c[0]), f64::from(c[1])])).collect();
                root.draw(&Polygon::new(points, OCCLUDER.filled()))?;
            }
        }
    }
    let marked_frames = marked(frames.len(), MARKED_FRAMES);
    let layer = Layer { root, frame, content, marked_frames: &marked_frames };
    draw_moving_occluders(&layer)?;
    draw_vehicle(&layer)?;
    draw_pedestrian(root, frame, frames)
}

/// Light lines every 10 m with their coordinates, and the axes' names.
fn draw_grid(root: &DrawingArea<BitMapBackend, Shift>, frame: &MapFrame) -> Drawn {
    let [left, top, width, height] = frame.plot;
    let shown = [f64::from(width), f64::from(height)].map(|s| s / frame.pixels_per_metre);
    let style = ("sans-serif", 20).into_font().color(&BLACK);
    let line = RGBColor(225, 225, 225);
    for (axis, (origin, shown)) in frame.origin.into_iter().zip(shown).enumerate() {
        let first = (origin / 10.0).ceil() as i64;
        let last = ((origin + shown) / 10.0).floor() as i64;
        for step in first..=last {
            let value = step as f64 * 10.0;
            if axis == 0 {
                let (x, _) = frame.pixel([value, frame.origin[1]]);
                root.draw(&PathElement::new(vec![(x, top), (x, top + height)], line))?;
                root.draw(&Text::new(format!("{value:.0}"), (x - 10, top + height + 6), style.clone()))?;
            } else {
                let (_, y) = frame.pixel([frame.origin[0], value]);
                root.draw(&PathElement::new(vec![(left, y), (left + width, y)], line))?;
                root.draw(&Text::new(format!("{value:.0}"), (left - 50, y - 10), style.clone()))?;
            }
        }
    }
    root.draw(&Text::new("north (m)", (left - 80, top - 24), style.clone()))?;
    root.draw(&Text::new("east (m)", (left + width - 70, top + height + 28), style))?;
    Ok(())
}

fn draw_moving_occluders(layer: &Layer<'_, '_>) -> Drawn {
    let Layer { root, frame, content, marked_frames } = *layer;
    let frames = &content.track.frames;
    let names: Vec<String> =
        frames.first().map_or_else(Vec::new, |f| f.occluders.iter().map(|o| o.0.clone()).collect());
    for name in &names {
        let path: Vec<(i32, i32)> = frames
            .iter()
            .filter_map(|f| f.occluders.iter().find(|o| &o.0 == name))
            .map(|(_, p, _)| frame.pixel([p[0], p[1]]))
            .collect();
        root.draw(&PathElement::new(path, MOVING.stroke_width(2)))?;
        let shape = content.scene.as_ref().ok().and_then(|s| s.occluders.iter().find(|o| &o.0 == name));
        for &index in marked_frames {
            let Some((_, position, yaw)) = frames[index].occluders.iter().find(|o| &o.0 == name) else {
                continue;
            };
            if let Some((_, triangles)) = shape {
                draw_footprint(root, frame, (triangles, *position, *yaw), MOVING)?;
            }
        }
    }
    Ok(())
}

/// The outline of a shape's [`footprint`] at a pose (nothing for no shape).
fn draw_footprint(
    root: &DrawingArea<BitMapBackend, Shift>,
    frame: &MapFrame,
    (shape, position, yaw_deg): (&[[f32; 3]], [f64; 3], f64),
    color: RGBColor,
) -> Drawn {
    if let Some(corners) = footprint(shape, position, yaw_deg) {
        let mut points: Vec<(i32, i32)> = corners.iter().map(|c| frame.pixel(*c)).collect();
        points.push(points[0]);
        root.draw(&PathElement::new(points, color.stroke_width(2)))?;
    }
    Ok(())
}

/// The trajectory coloured by time, the vehicle's footprint and the
/// sightlines at the marked frames.
fn draw_vehicle(layer: &Layer<'_, '_>) -> Drawn {
    let Layer { root, frame, content, marked_frames } = *layer;
    let frames = &content.track.frames;
    let (start, end) = (frames[0].time_s, frames[frames.len() - 1].time_s);
    let share = |time: f64| if end > start { (time - start) / (end - start) } else { 0.0 };
    let color = |time: f64| {
        let [r, g, b] = time_color(share(time));
        RGBColor(r, g, b)
    };
    let shape: Vec<[f32; 3]> = content
        .vehicle
        .map_or_else(Vec::new, |model| model.parts.iter().flat_map(|p| p.positions.clone()).collect());
    for &index in marked_frames {
        let here = &frames[index];
        let at = frame.pixel([here.vehicle_position[0], here.vehicle_position[1]]);
        if let Some(eye) = here.eye_centre() {
            let eye = frame.pixel([eye[0], eye[1]]);
            root.draw(&PathElement::new(vec![eye, at], color(here.time_s).stroke_width(1)))?;
        }
        draw_footprint(
            root,
            frame,
            (&shape, here.vehicle_position, here.vehicle_yaw_deg),
            color(here.time_s),
        )?;
    }
    for pair in frames.windows(2) {
        let ends: Vec<(i32, i32)> =
            pair.iter().map(|f| frame.pixel([f.vehicle_position[0], f.vehicle_position[1]])).collect();
        root.draw(&PathElement::new(ends, color((pair[0].time_s + pair[1].time_s) / 2.0).stroke_width(5)))?;
    }
    Ok(())
}

/// The pedestrian: a dot where the eyes were, a path when they moved.
fn draw_pedestrian(
    root: &DrawingArea<BitMapBackend, Shift>,
    frame: &MapFrame,
    frames: &[TrackFrame],
) -> Drawn {
    let points: Vec<(i32, i32)> =
        frames.iter().filter_map(TrackFrame::eye_centre).map(|p| frame.pixel([p[0], p[1]])).collect();
    if points.len() > 1 {
        root.draw(&PathElement::new(points.clone(), PEDESTRIAN.stroke_width(3)))?;
    }
    if let Some(&last) = points.last() {
        root.draw(&Circle::new(last, 8, PEDESTRIAN.filled()))?;
    }
    Ok(())
}

/// Title, the marked frames' times, the legend and the time scale.
fn draw_words(layer: &Layer<'_, '_>) -> Drawn {
    let Layer { root, frame, content, marked_frames } = *layer;
    let frames = &content.track.frames;
    let style = ("sans-serif", 21).into_font().color(&BLACK);
    root.draw(&Text::new(
        content.title.clone(),
        (frame.plot[0], 18),
        ("sans-serif", 30).into_font().color(&BLACK),
    ))?;
    for &index in marked_frames {
        let here = &frames[index];
        let (x, y) = frame.pixel([here.vehicle_position[0], here.vehicle_position[1]]);
        root.draw(&Text::new(format!("{:.1} s", here.time_s), (x + 10, y + 8), style.clone()))?;
    }
    if let Some(eye) = frames.last().and_then(TrackFrame::eye_centre) {
        let (x, y) = frame.pixel([eye[0], eye[1]]);
        root.draw(&Text::new("pedestrian", (x + 12, y - 8), style.clone().color(&PEDESTRIAN)))?;
    }
    let occluders = match &content.scene {
        Ok(scene) if scene.occluders.is_empty() => "no occluders".to_string(),
        Ok(_) => "grey: occluders (scene.glb), blue: moving occluders".to_string(),
        Err(why) => format!("occluders not shown: {why}"),
    };
    let legend = format!(
        "vehicle: trajectory coloured by time, footprints and sightlines from the eyes at {} frames · {occluders}",
        marked_frames.len()
    );
    let bottom = frame.plot[1] + frame.plot[3] + 52;
    root.draw(&Text::new(legend, (frame.plot[0], bottom), style.clone()))?;
    // The time scale: viridis from the first frame's time to the last's.
    let (left, top) = (frame.plot[0], bottom + 30);
    for k in 0..300 {
        let [r, g, b] = time_color(f64::from(k) / 299.0);
        root.draw(&PathElement::new(vec![(left + k, top), (left + k, top + 14)], RGBColor(r, g, b)))?;
    }
    let (start, end) = (frames[0].time_s, frames[frames.len() - 1].time_s);
    root.draw(&Text::new(format!("{start:.1} s"), (left - 60, top - 3), style.clone()))?;
    root.draw(&Text::new(format!("{end:.1} s"), (left + 308, top - 2), style))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn marked_frames_spread_evenly_and_include_both_ends() {
        assert_eq!(marked(10, 5), [0, 2, 4, 6, 9]);
        assert_eq!(marked(3, 5), [0, 1, 2]);
    }

    #[test]
    fn a_footprint_turns_with_the_yaw() {
        let shape = [[-1.0, -0.5, 0.0], [1.0, 0.5, 1.0], [0.0, 0.0, 0.0]];
        let corners = footprint(&shape, [10.0, 0.0, 0.0], 90.0).unwrap();
        // Heading north: the 2 m length runs along y.
        let ys: Vec<f64> = corners.iter().map(|c| c[1]).collect();
        assert!((ys.iter().cloned().fold(f64::MIN, f64::max) - 1.0).abs() < 1e-9, "{corners:?}");
    }
}
