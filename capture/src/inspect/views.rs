//! A result's eight heatmap views redrawn from its folder: `ufcsr views
//! RESULTS` (another scale, the count instead of the area, another model).
//! The pictures are the analysis' own ([`ufcsr::output::write_views`], on the CPU),
//! so `cli/tests/it/views.rs` holds a redraw to the analysis' views pixel
//! for pixel.

use std::path::{Path, PathBuf};

use ufcsr::{VehicleModel, output::ViewTexture, output::WrittenViews};

use crate::error::{CaptureError, Result};

/// Where [`views_from_results`] reads and writes.
#[derive(Debug, Clone)]
pub struct ViewsOptions {
    /// A result folder: `result.json` and (unless `model` says otherwise)
    /// `heatmap.glb`.
    pub results: PathBuf,
    /// The vehicle model with its palette UVs (default `RESULTS/heatmap.glb`).
    pub model: Option<PathBuf>,
    /// Where `views/` and `views.png` go (default: the result folder).
    pub out: Option<PathBuf>,
    /// Each view is 400×300 pixels times this (`--views-scale`).
    pub views_scale: u32,
    /// Draw the paper's count (`--count`) even where the result kept its
    /// per-texel angular area (`texel-area.f32`), which is drawn by default.
    pub count: bool,
}

/// What the views paint, read from a result folder: per-texel angular area
/// from `texel-area.f32` (the measure to quote, as the analyzer's own views)
/// unless [`ViewsOptions::count`] or the file is absent, else the paper's
/// count from `result.json`.
#[derive(Debug, Clone)]
pub struct ViewValues {
    /// Whole levels the painters take (counts, or area in units of `quantum`).
    pub levels: Vec<u32>,
    pub width: u32,
    pub height: u32,
    pub heatmap: ufcsr::HeatmapOptions,
    /// deg²·s per level when the values are angular area; `None` for counts.
    pub quantum: Option<f64>,
    /// The caption before the renderer's mark, and the colour bar's unit.
    pub caption: String,
    pub unit: String,
    /// Every file read, which the views may not overwrite.
    pub inputs: Vec<PathBuf>,
    /// The analysed archive (its manifest names the scenario).
    pub archive: String,
}

/// Reads what [`views_from_results`] paints.
pub fn view_values(options: &ViewsOptions) -> Result<ViewValues> {
    let json = options.results.join("result.json");
    let counts = ufcsr::read_texel_counts(&json)?;
    let track = ufcsr::ScenarioTrack::from_archive(Path::new(&counts.archive));
    let scenario = track.as_ref().and_then(|track| track.name.as_deref());
    // Anything at texel-area.f32 that is no regular file is refused naming
    // it, not painted as the count.
    let area = if options.count {
        None
    } else {
        ufcsr::read_texel_area_in(&options.results, counts.width, counts.height)?
    };
    if let Some(values) = area {
        let area = ufcsr::output::AreaLevels::new(&values);
        return Ok(ViewValues {
            heatmap: ufcsr::HeatmapOptions { scale: counts.scale, max: area.top(counts.area_max) },
            quantum: Some(area.quantum),
            levels: area.levels,
            width: counts.width,
            height: counts.height,
            caption: ufcsr::output::area_views_caption(scenario),
            unit: ufcsr::output::AREA_UNIT.to_string(),
            inputs: vec![json, options.results.join(ufcsr::TEXEL_AREA_FILE)],
            archive: counts.archive,
        });
    }
    Ok(ViewValues {
        heatmap: ufcsr::HeatmapOptions { scale: counts.scale, max: counts.max },
        quantum: None,
        caption: ufcsr::output::views_caption(counts.measure, &counts.archive, scenario),
        unit: ufcsr::output::measure_unit(counts.measure).to_string(),
        levels: counts.texel_counts,
        width: counts.width,
        height: counts.height,
        inputs: vec![json],
        archive: counts.archive,
    })
}

/// Reads `result.json` and the model, and draws the views as the analysis
/// does: what `ufcsr views` does. Returns the files written.
pub fn views_from_results(options: &ViewsOptions) -> Result<WrittenViews> {
    let values = view_values(options)?;
    let model_path = options.model.clone().unwrap_or_else(|| options.results.join("heatmap.glb"));
    if !model_path.is_file() {
        return Err(CaptureError::BadFile {
            path: model_path,
            message: "no vehicle model here (the result has no heatmap.glb; name the model with --model)"
                .into(),
        });
    }
    let model = VehicleModel::read(&model_path)?;
    // The scenario as the analysed archive's manifest says, when it is still there.
    let track = ufcsr::ScenarioTrack::from_archive(Path::new(&values.archive));
    let texture = ViewTexture {
        counts: &values.levels,
        width: values.width,
        height: values.height,
        options: values.heatmap,
        caption: values.caption.clone(),
        unit: values.unit.clone(),
        quantum: values.quantum,
        views_scale: options.views_scale,
        pedestrian_azimuths_deg: track.map_or_else(Vec::new, |track| {
            track.frames.iter().filter_map(ufcsr::TrackFrame::pedestrian_azimuth_deg).collect()
        }),
    };
    let out = options.out.clone().unwrap_or_else(|| options.results.clone());
    let mut outputs: Vec<String> =
        ufcsr::output::DIRECTIONS.iter().map(|(name, _)| format!("views/{name}.png")).collect();
    outputs.push("views.png".into());
    outputs.push("views.pdf".into());
    crate::job::overwrite_guard::refuse_overwriting_inputs(
        &out,
        &outputs.iter().map(String::as_str).collect::<Vec<_>>(),
        &[],
        &values.inputs.iter().cloned().chain([model_path]).collect::<Vec<_>>(),
    )?;
    Ok(ufcsr::output::write_views(&model, &texture, &out)?)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn views_paint_the_kept_angular_area_by_default_and_the_count_when_asked() {
        let dir = tempfile::tempdir().unwrap();
        let results = dir.path().join("results");
        let archive = Path::new(env!("CARGO_MANIFEST_DIR")).join("../fixtures/example");
        // The per-texel pass is off by default (its cost, docs/performance.md).
        let options = ufcsr::AnalyzeOptions { archive, frames: true, texel_area: true, ..Default::default() };
        let mut analysis = ufcsr::analyze(&options, None).unwrap();
        ufcsr::output::write_results(&mut analysis, &results).unwrap();
        let area = analysis.texel_angular_area.clone().unwrap();
        let mut options =
            ViewsOptions { results: results.clone(), model: None, out: None, views_scale: 1, count: false };
        // By default: the analysis' own area levels, the area caption and unit.
        let values = view_values(&options).unwrap();
        let expected = ufcsr::output::AreaLevels::new(&area);
        assert_eq!(values.levels, expected.levels);
        assert_eq!(values.quantum, Some(expected.quantum));
        assert_eq!(values.unit, ufcsr::output::AREA_UNIT);
        assert!(values.inputs.contains(&results.join(ufcsr::TEXEL_AREA_FILE)));
        // --count: the paper's count from result.json.
        options.count = true;
        let values = view_values(&options).unwrap();
        assert_eq!(values.levels, analysis.texel_counts);
        assert_eq!(values.quantum, None);
        // A damaged texel-area.f32 is an error naming it, not a wrong picture.
        options.count = false;
        let file = results.join(ufcsr::TEXEL_AREA_FILE);
        let bytes = std::fs::read(&file).unwrap();
        std::fs::write(&file, &bytes[..bytes.len() - 4]).unwrap();
        let error = view_values(&options).unwrap_err().to_string();
        assert!(error.contains(ufcsr::TEXEL_AREA_FILE), "{error}");
        // Without it (an older result, a merge): the count.
        std::fs::remove_file(&file).unwrap();
        assert_eq!(view_values(&options).unwrap().levels, analysis.texel_counts);
    }
}
