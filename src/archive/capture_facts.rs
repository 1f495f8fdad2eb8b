//! What a capture's manifest says about how it was taken: its eye-frames
//! ([`EyeFrame`], [`eye_frames`]), how long one stands for ([`FrameClock`]),
//! its resolution and texel size ([`CaptureGeometry`]) and the eyes'
//! projection ([`EyeOptics`]).

use std::collections::BTreeMap;

use crate::format::manifest::{FrameEntry, Manifest};
use crate::optics::solid_angle::{EyeProjection, TileView};

/// One eye-frame of a manifest (group ids as [`crate::Archive`] numbers them).
#[derive(Debug, Clone, PartialEq)]
pub struct EyeFrame {
    pub frame: u32,
    pub eye: String,
    pub time_s: Option<f64>,
    pub distance_m: Option<f64>,
}

/// The eye-frames of `manifest`, indexed by eye-frame group: sorted by
/// `(frame, eye)`, as [`crate::Archive::from_manifest`] numbers them.
pub(crate) fn eye_frames(manifest: &Manifest) -> Vec<EyeFrame> {
    let records: BTreeMap<u32, &FrameEntry> =
        manifest.frame_records().iter().map(|record| (record.frame, record)).collect();
    let mut groups: BTreeMap<(u32, String), EyeFrame> = BTreeMap::new();
    for tile in &manifest.tiles {
        groups.entry((tile.frame, tile.eye.clone())).or_insert_with(|| {
            let record = records.get(&tile.frame);
            EyeFrame {
                frame: tile.frame,
                eye: tile.eye.clone(),
                time_s: tile.time_s.or_else(|| record?.time_s),
                distance_m: tile.distance_m.or_else(|| record?.distance_m),
            }
        });
    }
    groups.into_values().collect()
}

/// How long one captured eye-frame stands for, and how many eyes look.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct FrameClock {
    /// Seconds between captured frames: the smallest gap between the frame
    /// numbers of the manifest over the rig's fps (a capture of every 20th
    /// frame at 60 fps: 1/3 s). `None` without the rig's fps.
    pub seconds_per_frame: Option<f64>,
    /// Distinct eyes in the manifest (2 for a stereo rig).
    pub eyes: usize,
    /// The rig's pixels per degree (at the image centre).
    pub pixels_per_degree: Option<f64>,
}

impl FrameClock {
    /// Reads the clock from a capture's manifest (`rig.settings.fps`,
    /// `rig.pixels_per_degree` and the tiles' frame numbers).
    pub fn from_manifest(manifest: &Manifest) -> FrameClock {
        let fps = manifest_fps(manifest);
        let pixels_per_degree =
            manifest.rig.as_ref().and_then(|rig| rig.pixels_per_degree).filter(|ppd| *ppd > 0.0);
        let frames = tile_frames(manifest);
        let step = frames.windows(2).map(|pair| pair[1] - pair[0]).min().unwrap_or(1).max(1);
        let mut eyes: Vec<&str> = manifest.tiles.iter().map(|tile| tile.eye.as_str()).collect();
        eyes.sort_unstable();
        eyes.dedup();
        FrameClock {
            seconds_per_frame: fps.map(|fps| f64::from(step) / fps),
            eyes: eyes.len().max(1),
            pixels_per_degree,
        }
    }
}

/// The rig's frames per second, if the manifest has a positive one.
fn manifest_fps(manifest: &Manifest) -> Option<f64> {
    manifest.rig_settings().and_then(|settings| settings.fps).filter(|fps| *fps > 0.0)
}

/// The distinct frame numbers of the manifest's tiles, ascending.
fn tile_frames(manifest: &Manifest) -> Vec<u32> {
    let mut frames: Vec<u32> = manifest.tiles.iter().map(|tile| tile.frame).collect();
    frames.sort_unstable();
    frames.dedup();
    frames
}

/// [`frame_spacing_warning`] for the frames of a manifest's tiles and its fps.
pub(crate) fn manifest_spacing_warning(manifest: &Manifest) -> Option<String> {
    frame_spacing_warning(&tile_frames(manifest), manifest_fps(manifest)?)
}

/// What the time totals of unevenly spaced frames must say, one text for the
/// analyzer and the exact measure. Both clocks give every frame the smallest
/// gap between the frame numbers (`seconds_per_frame`), right for every Nth
/// frame; frames listed unevenly (`--frames 0-180/20,95`: gaps of 5 to 20)
/// then count every frame as the smallest gap, so `exposure_s` and
/// `angular_area_deg2_s` come out smaller than the time the frames stand for
/// (there 0.917 s for frames spanning 3 s). `None` for evenly spaced frames,
/// fewer than three, or no frame rate.
pub fn frame_spacing_warning(frames: &[u32], fps: f64) -> Option<String> {
    let mut frames = frames.to_vec();
    frames.sort_unstable();
    frames.dedup();
    let gaps: Vec<u32> = frames.windows(2).map(|pair| pair[1] - pair[0]).collect();
    let (&least, &most) = (gaps.iter().min()?, gaps.iter().max()?);
    if least == most || !(fps.is_finite() && fps > 0.0) {
        return None;
    }
    let (first, last) = (frames[0], frames[frames.len() - 1]);
    Some(format!(
        "frames {first}–{last} are unevenly spaced ({least} to {most} frames apart): exposure_s and \
         angular_area_deg2_s count every frame as the smallest gap, {least} frame(s) ({:.4} s at {fps} fps), so \
         the {} frames stand for {:.3} s of the {:.3} s from the first to the last; capture evenly spaced frames \
         (`--frames all/N` or `A-B/N`) for time totals",
        f64::from(least) / fps,
        frames.len(),
        frames.len() as f64 * f64::from(least) / fps,
        f64::from(last - first) / fps,
    ))
}

/// The eyes' projection and tiling, from the manifest's `rig.settings`
/// (`horizontal_fov_deg`, `eye_pixels`, `tiles`): what the solid angle of
/// each pixel needs ([`crate::optics::solid_angle`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct EyeOptics {
    pub projection: EyeProjection,
    /// Pixels of one tile, `[width, height]`.
    pub tile_pixels: [u32; 2],
}

impl EyeOptics {
    /// `None` for a manifest without these settings (hand-written ones).
    pub(crate) fn from_manifest(manifest: &Manifest) -> Option<EyeOptics> {
        let settings = manifest.rig_settings()?;
        let fov = settings.horizontal_fov_deg?;
        let (eye, tiles) = (settings.eye_pixels?, settings.tiles?);
        if tiles[0] == 0 || tiles[1] == 0 || eye[0] % tiles[0] != 0 || eye[1] % tiles[1] != 0 {
            return None;
        }
        Some(EyeOptics {
            projection: EyeProjection::new(fov, eye)?,
            tile_pixels: [eye[0] / tiles[0], eye[1] / tiles[1]],
        })
    }

    /// Where the tile `[row, col]` lies in its eye.
    pub(crate) fn view(&self, [row, col]: [u32; 2]) -> TileView {
        TileView {
            projection: self.projection,
            origin: [col * self.tile_pixels[0], row * self.tile_pixels[1]],
        }
    }
}

/// What a capture's manifest says about resolution and texel size.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct CaptureGeometry {
    pub pixels_per_degree: Option<f64>,
    pub texel_size_mm: Option<f64>,
    /// The vehicle's distance from the pedestrian in each captured frame.
    pub frame_distances_m: Vec<f64>,
}

impl CaptureGeometry {
    /// Reads the `rig`, `unwrap` and `frames` records `ufcsr capture` writes
    /// (absent for hand-written manifests: then only pixels per count is known).
    pub fn from_manifest(manifest: &Manifest) -> CaptureGeometry {
        CaptureGeometry {
            pixels_per_degree: manifest.rig.as_ref().and_then(|rig| rig.pixels_per_degree),
            texel_size_mm: manifest.unwrap.as_ref().and_then(|unwrap| unwrap.texel_size_mm),
            frame_distances_m: manifest
                .frame_records()
                .iter()
                .filter_map(|record| record.distance_m)
                .collect(),
        }
    }

    /// The distance beyond which one texel is smaller than one pixel.
    pub fn sub_pixel_distance_m(&self) -> Option<f64> {
        let (ppd, texel_mm) = (self.pixels_per_degree?, self.texel_size_mm?);
        // A pixel spans 1/ppd degrees: d · tan(1°/ppd) metres at distance d.
        let pixel_angle = (1.0 / ppd).to_radians().tan();
        (pixel_angle > 0.0).then(|| texel_mm / 1000.0 / pixel_angle)
    }
}

#[cfg(test)]
mod tests {
    use super::frame_spacing_warning;

    #[test]
    fn unevenly_spaced_frames_warn_that_their_time_totals_count_the_smallest_gap() {
        // The guide's `--frames 0-180/20,95`: 11 frames counted as 5 frames (1/12 s) each.
        let mut frames: Vec<u32> = (0..=180).step_by(20).collect();
        frames.push(95);
        let warning = frame_spacing_warning(&frames, 60.0).unwrap();
        for part in
            ["frames 0–180", "5 to 20 frames apart", "0.0833 s at 60 fps", "11 frames stand for 0.917 s"]
        {
            assert!(warning.contains(part), "{part}: {warning}");
        }
        assert!(warning.contains("of the 3.000 s from the first to the last"), "{warning}");
        // Every Nth frame, in any order or repeated, two frames, or no frame rate: nothing to say.
        assert_eq!(frame_spacing_warning(&[15, 45, 75, 45, 105], 60.0), None);
        assert_eq!(frame_spacing_warning(&[0, 7], 60.0), None);
        assert_eq!(frame_spacing_warning(&[0, 1, 3], 0.0), None);
        assert_eq!(frame_spacing_warning(&[], 60.0), None);
    }
}
