//! A capture counted while rendering (`--count`), alone or as one of many
//! captures of one scene that share their set-up.
//!
//! [`capture_counted`] prepares the archive (unwrap, PIdT, the archive's
//! files, the renderer), renders the selected frames into the counting sink,
//! and writes the manifest and the analyzer's results. A study or an
//! observer grid captures one scene many times and changes only the rig (its
//! resolution, the pedestrian) and the frames; [`CaptureSetup`] is what does
//! not depend on them, built once, and [`CaptureSetup::capture_counted`] is
//! one of those captures: the same files, byte for byte, as
//! [`capture_counted`] of that setting alone, without unwrapping, painting,
//! encoding, uploading and reading back the same things again.

use std::path::PathBuf;
use std::time::Instant;

use ufcsr::{Dedupe, Fcsp, Legend, PaletteRecord, Pidt};

use crate::error::{CaptureError, Result};
use crate::job::capture_job::{
    PreparedCapture, capture_frames, prepare_archive, prepare_folder, summarize, write_manifest,
};
use crate::job::count_sink::{Counted, count_while};
use crate::job::options::{CaptureOptions, Summary};
use crate::job::{SCENE_FILE, TileFiles, VEHICLE_FILE};
use crate::scene::Scene;
use crate::scene::scenario::Scenario;

/// A capture counted while rendering (`--count`): its summary, the analysis
/// and where the analyzer's files went.
pub struct CountedCapture {
    pub summary: Summary,
    pub analysis: ufcsr::Analysis,
    pub written: ufcsr::output::WrittenFiles,
    /// RGBA pixels counted (what PNGs would have held).
    pub pixels_counted: u64,
}

/// What counted captures of one scene share, whatever the rig's resolution,
/// pedestrian or frames: the unwrap and PIdT, the renderer with its pipeline,
/// palette texture and vehicle uploaded, the palette and labels counting
/// joins with, and the archive's files (`parts.csv`, `pidt.png`,
/// `vehicle.glb`, `scene.glb`, and `palette.png` for a palette image).
pub struct CaptureSetup {
    prepared: PreparedCapture,
    /// The palette as the archive records it, for counting.
    palette: Fcsp,
    /// The legend and PIdT as the archive holds them, for the per-part
    /// tallies and the analysis (which would otherwise decode `pidt.png`
    /// again for every setting).
    labels: ufcsr::LoadedLabels,
    /// What it was built for: only the rig and the frames may change.
    built_for: BuiltFor,
    /// The archive folder the set-up was built in (its files are there).
    built_in: PathBuf,
    /// Those files' names and bytes, read once another folder needs them.
    files: Vec<(String, Vec<u8>)>,
    /// Wall seconds it took to build.
    pub seconds: f64,
}

impl CaptureSetup {
    /// Prepares `scene` with `options` as a capture into `options.out` does
    /// (see [`prepare_archive`]: the archive's files are written there), and
    /// reads back the palette, legend and PIdT that counting joins with.
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        scene: &Scene,
        options: &CaptureOptions,
    ) -> Result<CaptureSetup> {
        let start = Instant::now();
        let prepared = prepare_archive(device, queue, scene, options)?;
        let out = &options.out;
        // A canonical palette above 2^24 texels is one of 32-bit texel ids,
        // which the counter counts as the analyzer counts an `rgba32` archive.
        let palette = match &prepared.palette {
            PaletteRecord::Canonical { canonical: [width, height] } => {
                Fcsp::canonical_rgba32([*width, *height])?
            }
            PaletteRecord::File(file) => Fcsp::from_png(&out.join(file))?,
        };
        let legend = Legend::load(&out.join("parts.csv"))?;
        let pidt = Pidt::load(&out.join("pidt.png"), &legend, [palette.width(), palette.height()])?;
        Ok(CaptureSetup {
            prepared,
            palette,
            labels: ufcsr::LoadedLabels { legend, pidt: pidt.into() },
            built_for: BuiltFor::of(scene, options),
            built_in: out.clone(),
            files: Vec::new(),
            seconds: start.elapsed().as_secs_f64(),
        })
    }

    /// The files [`prepare_archive`] wrote for this set-up.
    fn file_names(&self) -> Vec<String> {
        let mut names: Vec<String> =
            ["parts.csv", "pidt.png", VEHICLE_FILE, SCENE_FILE].map(String::from).to_vec();
        if let PaletteRecord::File(file) = &self.prepared.palette {
            names.push(file.to_string_lossy().into_owned());
        }
        names
    }

    /// Makes `options.out` an archive folder with the set-up's files (checked
    /// and created as [`prepare_archive`] does), and the renderer one for
    /// `scene`'s rig.
    fn place(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        scene: &Scene,
        options: &CaptureOptions,
    ) -> Result<()> {
        if let Some(what) = self.built_for.differs(scene, options) {
            return Err(CaptureError::BadOptions(format!(
                "{}: a capture set-up is shared only by captures of the same {what}",
                options.out.display()
            )));
        }
        let out = &options.out;
        if !ufcsr::files::same_path(out, &self.built_in) {
            prepare_folder(scene, options)?;
            if self.files.is_empty() {
                for name in self.file_names() {
                    let path = self.built_in.join(&name);
                    let bytes = ufcsr::files::read_limited(&path, ufcsr::files::MODEL_LIMIT)?;
                    self.files.push((name, bytes));
                }
            }
            for (name, bytes) in &self.files {
                ufcsr::files::write_bytes_atomically(&out.join(name), bytes)?;
            }
        }
        let rig = &scene.rig;
        self.prepared.renderer.retarget(device, queue, rig.tile_pixels(), rig.head(), &scene.occluders)
    }

    /// [`capture_counted`] of `scene` (the scene the set-up was built for,
    /// its rig changed at will) without building the set-up again; the
    /// summary's `seconds` and `setup_seconds` leave the set-up's own out.
    pub fn capture_counted(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        scene: &Scene,
        scenario: &Scenario,
        options: &CaptureOptions,
        dedupe: Dedupe,
    ) -> Result<CountedCapture> {
        let start = Instant::now();
        check_countable(scene, options)?;
        self.place(device, queue, scene, options)?;
        // Tiles of an earlier capture would contradict a manifest that says none were written.
        crate::job::encoder_pool::remove_old_tiles(&options.out.join("tiles"))?;
        let setup_seconds = start.elapsed().as_secs_f64();
        let prepared = &self.prepared;
        let mut counter = ufcsr::TileCounter::new(&self.palette, &[prepared.background], dedupe)?;
        let lookup = ufcsr::PartLookup::new(
            &self.palette,
            Some((&self.labels.legend, &*self.labels.pidt)),
            &[prepared.background.packed()],
        );
        crate::job::count_sink::tally_parts(&mut counter, lookup, &scene.rig);
        let (captured, counted) = count_while(counter, |sink| {
            capture_frames(device, queue, scene, scenario, options, prepared, sink)
        })?;
        let summary = summarize(scene, scenario, options, prepared, &captured, setup_seconds);
        write_manifest(scene, scenario, options, prepared, captured, TileFiles::NotWritten)?;
        let analyze_options = ufcsr::AnalyzeOptions {
            archive: options.out.clone(),
            dedupe,
            // Nothing to trim: the renderer knew which tiles were empty.
            trim: ufcsr::TrimMode::Off,
            // The archive's parts.csv and pidt.png, which the set-up read.
            loaded_labels: Some(self.labels.clone()),
            ..ufcsr::AnalyzeOptions::default()
        };
        let Counted { counter, pixels } = counted;
        let mut analysis = ufcsr::analyze_counted(&analyze_options, counter)?;
        let results =
            ufcsr::output::ResultSetOptions { views_scale: options.views_scale, ..Default::default() };
        let written = ufcsr::output::write_results_with(
            &mut analysis,
            &ufcsr::output::default_output_dir(&options.out),
            &results,
        )?;
        let summary = Summary { seconds: start.elapsed().as_secs_f64(), ..summary };
        Ok(CountedCapture { summary, analysis, written, pixels_counted: pixels })
    }
}

/// What a set-up depends on: the vehicle, the occluders as `scene.glb`
/// holds them, and the palette and labels of the options.
struct BuiltFor {
    vehicle: crate::scene::Mesh,
    occluders: Vec<ufcsr::output::SceneObject>,
    moving_occluders: usize,
    palette: ([u32; 2], Option<PathBuf>),
    keep_uvs: bool,
    own_labels: Option<crate::texture::OwnLabelFiles>,
}

impl BuiltFor {
    fn of(scene: &Scene, options: &CaptureOptions) -> BuiltFor {
        BuiltFor {
            vehicle: scene.vehicle.clone(),
            occluders: scene.occluders.scene_objects(),
            moving_occluders: scene.occluders.moving.len(),
            palette: (options.palette, options.palette_file.clone()),
            keep_uvs: options.keep_uvs,
            own_labels: options.own_labels.clone(),
        }
    }

    /// What `scene` and `options` change that the set-up depends on, if anything.
    fn differs(&self, scene: &Scene, options: &CaptureOptions) -> Option<&'static str> {
        if scene.vehicle != self.vehicle {
            Some("vehicle")
        } else if scene.occluders.moving.len() != self.moving_occluders
            || scene.occluders.scene_objects() != self.occluders
        {
            Some("occluders")
        } else if (options.palette, &options.palette_file) != (self.palette.0, &self.palette.1) {
            Some("palette")
        } else if options.keep_uvs != self.keep_uvs || options.own_labels != self.own_labels {
            Some("UVs and labels")
        } else {
            None
        }
    }
}

/// What a counted capture needs of the rig and the options.
fn check_countable(scene: &Scene, options: &CaptureOptions) -> Result<()> {
    scene.rig.check()?;
    if options.shard.is_some() {
        return Err(CaptureError::BadOptions(
            "--count with --shard is not supported: capture the shards as PNG tiles, `ufcsr assemble` \
             them, then analyse (`ufcsr analyze --shard` and `merge` split the counting)"
                .into(),
        ));
    }
    if !(1..=MAX_VIEWS_SCALE).contains(&options.views_scale) {
        return Err(CaptureError::BadOptions(format!(
            "--views-scale must be 1 to {MAX_VIEWS_SCALE}, not {}",
            options.views_scale
        )));
    }
    Ok(())
}

/// The largest views scale (8: 3200×2400 pixels a view), as the analyzer's `--views-scale`.
pub(crate) const MAX_VIEWS_SCALE: u32 = 8;

/// Captures one scenario and counts every tile straight from the readback
/// buffer: writes the archive's `manifest.json`, `pidt.png` and `parts.csv`
/// (no tiles) and the analyzer's results into `options.out/results`, the same
/// `result.json` as writing the tiles and running `ufcsr analyze --trim off`
/// on them.
pub fn capture_counted(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    scene: &Scene,
    scenario: &Scenario,
    options: &CaptureOptions,
    dedupe: ufcsr::Dedupe,
) -> Result<CountedCapture> {
    let start = Instant::now();
    check_countable(scene, options)?;
    let mut setup = CaptureSetup::new(device, queue, scene, options)?;
    let counted = setup.capture_counted(device, queue, scene, scenario, options, dedupe)?;
    // This capture's set-up was its own.
    let setup_seconds = setup.seconds + counted.summary.setup_seconds;
    let summary = Summary { seconds: start.elapsed().as_secs_f64(), setup_seconds, ..counted.summary };
    Ok(CountedCapture { summary, ..counted })
}
