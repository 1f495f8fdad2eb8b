//! Stage 1, the archive: everything an analysis reads from a capture's
//! archive, checked and loaded once before anything is counted — the
//! options ([`AnalyzeOptions`]), the archive's manifest and shard, the
//! archive reader (which files are the images), the palette, the labels
//! (legend and PIdT), what the manifest says about the capture, the frames'
//! scenario track, the vehicle model in glTF (`vehicle.glb`, [`glb`] the
//! axis rule of every glTF file an archive or result holds) and [`resolve`]
//! that puts them together. This is the contract between the capture and
//! the analyzer; the PNG decoder that reads its images is apart (`input/`).
//!
//! Words: a *tile* is a file of an archive (the manifest lists tiles); an
//! *image* is what is counted — a tile that was decoded or trimmed.

pub(crate) mod archive_reader;
pub(crate) mod capture_facts;
pub(crate) mod glb;
pub(crate) mod identity;
pub(crate) mod labels;
pub(crate) mod manifest;
pub(crate) mod options;
pub(crate) mod palette;
pub(crate) mod resolve;
pub(crate) mod scenario_track;
pub(crate) mod shard;
pub(crate) mod vehicle_model;

pub use archive_reader::{Archive, ImageSource};
pub use capture_facts::{CaptureGeometry, frame_spacing_warning};
pub use labels::{Legend, LoadedLabels, Part, Pidt, UNLABELLED};
pub use manifest::{MANIFEST_FILE, MANIFEST_SCHEMA, Manifest, PaletteRecord, TileEntry, inside_archive};
pub use options::{
    AnalyzeOptions, Dedupe, HeatmapOptions, PaletteChoice, Progress, Scale, Timings, TrimMode,
};
pub use palette::{Fcsp, PaletteSetting, parse_size as parse_palette_size, write_canonical_png};
pub use palette::{
    MAX_RGBA32_TEXELS, parse_capture_size as parse_capture_palette_size, rgba32_id, rgba32_pixel,
};
pub use scenario_track::{ScenarioTrack, TrackFrame};
pub use shard::Shard;
pub use vehicle_model::{ModelPart, VehicleModel};
