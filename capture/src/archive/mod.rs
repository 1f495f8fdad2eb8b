//! The capture job, writing an archive: what to do ([`options`]), the job's
//! stages ([`capture_job`]: prepare the unwrap, PIdT and renderer, capture the
//! frames, write the manifest), the checks of a scene before capturing
//! ([`scene_checks`]), one frame's tiles ([`frame_capture`]), where tiles go
//! ([`tile_sink`]: PNGs through the [`encoder_pool`], or counted in memory by
//! [`count_sink`]), the manifest ([`manifest_builder`]), one capture as
//! several jobs ([`capture_shard`]) and a batch of captures ([`batch`]).

pub mod batch;
pub mod capture_job;
pub mod capture_shard;
pub mod count_sink;
pub mod encoder_pool;
pub mod frame_capture;
pub mod manifest_builder;
pub mod options;
pub mod scene_checks;
pub mod tile_sink;

pub use capture_job::*;
