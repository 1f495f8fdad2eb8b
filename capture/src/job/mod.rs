//! The capture job, writing an archive: what to do ([`options`]), the job's
//! stages ([`capture_job`]: prepare the unwrap, PIdT and renderer, capture the
//! frames, write the manifest), a capture counted while rendering, alone or
//! many sharing one set-up ([`counted_capture`]), the checks of a scene before capturing
//! ([`scene_checks`]), one frame's tiles ([`frame_capture`]), where tiles go
//! ([`tile_sink`]: PNGs through the [`encoder_pool`], or counted in memory by
//! [`count_sink`]), the manifest ([`manifest_builder`]), one capture as
//! several jobs ([`capture_shard`]) and a batch of captures ([`batch`]),
//! and the guard every writing command passes first, that no output
//! replaces an input ([`overwrite_guard`]; `inspect` and `study` use it too).

pub(crate) mod batch;
pub(crate) mod capture_job;
pub(crate) mod capture_shard;
pub(crate) mod count_sink;
pub(crate) mod counted_capture;
pub(crate) mod encoder_pool;
pub(crate) mod frame_capture;
pub(crate) mod manifest_builder;
pub(crate) mod options;
pub(crate) mod overwrite_guard;
pub(crate) mod scene_checks;
pub(crate) mod tile_sink;

pub use batch::{Batch, Task, load as load_batch, plan as plan_batch};
pub use capture_job::{
    CapturedTiles, MAX_SCENARIO_SECONDS, PreparedCapture, capture, capture_all, capture_frames,
    for_each_scenario, prepare, read_rgb_png, verify,
};
pub(crate) use capture_job::{capture_inputs, prepare_archive, summarize, write_manifest};
pub use capture_shard::{Assembled, assemble, partial_manifest_path};
pub use counted_capture::{CaptureSetup, CountedCapture, capture_counted};
pub(crate) use manifest_builder::TileFiles;
pub use options::{
    CaptureOptions, CaptureProgress, Compression, FrameSelection, MAX_SELECTED_FRAMES, Summary, TileFilter,
    TileTally,
};
pub(crate) use options::{longest_step_keeping_two, step_phase, stepped_frames};
pub use scene_checks::{MAX_FRAMES, MAX_TILES};

/// The archive's copy of the vehicle as unwrapped (named in the manifest).
pub(crate) const VEHICLE_FILE: &str = "vehicle.glb";
/// The occluders, in world coordinates (glTF axes), beside it.
pub(crate) const SCENE_FILE: &str = "scene.glb";
/// Every file a capture writes at the top of its archive folder.
pub(crate) const ARCHIVE_FILES: [&str; 6] =
    [ufcsr::MANIFEST_FILE, "pidt.png", "parts.csv", "palette.png", VEHICLE_FILE, SCENE_FILE];
/// The folders of an archive a capture owns: it writes and removes files in
/// them (tiles, the counted or measured results, the shards' manifests).
pub(crate) const ARCHIVE_FOLDERS: [&str; 3] = ["tiles", "results", capture_shard::SHARDS_DIR];
