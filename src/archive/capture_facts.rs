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
        let fps = manifest.rig_settings().and_then(|settings| settings.fps).filter(|fps| *fps > 0.0);
        let pixels_per_degree =
            manifest.rig.as_ref().and_then(|rig| rig.pixels_per_degree).filter(|ppd| *ppd > 0.0);
        let mut frames: Vec<u32> = manifest.tiles.iter().map(|tile| tile.frame).collect();
        frames.sort_unstable();
        frames.dedup();
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
