//! `ufcsr._native`: the analyzer library behind the Python package `ufcsr`.
//!
//! It exists so that Python runs the very code `ufcsr-analyze` runs — the
//! analysis in-process, result.json's delta-encoded counts decoded in Rust,
//! the heatmap painted by the library — instead of a second implementation in
//! Python. Only the `ufcsr` crate's public API is used. The Python layer
//! (`ufcsr/__init__.py`) checks option names and shapes values; this module
//! maps them onto [`ufcsr::AnalyzeOptions`] as the command line does, and
//! turns every [`ufcsr::Error`] into `ufcsr.UfcsrError` with its message.

use std::path::{Path, PathBuf};

use pyo3::create_exception;
use pyo3::exceptions::{PyException, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyByteArray, PyDict};
use ufcsr::{AnalyzeOptions, Color, Dedupe, HeatmapOptions, PaletteChoice, Scale, Shard, TrimMode};

create_exception!(
    _native,
    UfcsrError,
    PyException,
    "An analysis or result file failed; the message names the file and the problem."
);

/// More worker threads than this is a typo, not a machine (as in `ufcsr-analyze`).
const MAX_THREADS: usize = 1024;

/// The analyzer's error as a Python exception.
fn to_python(error: ufcsr::Error) -> PyErr {
    UfcsrError::new_err(error.to_string())
}

/// `ufcsr.analyze`'s options, by the command line's names in snake_case:
/// every key present (`ufcsr/__init__.py` fills in the command line's
/// defaults), `None` where the analyzer decides.
#[derive(FromPyObject)]
#[pyo3(from_item_all)]
struct OptionValues {
    pidt: Option<PathBuf>,
    parts: Option<PathBuf>,
    fcsp: Option<PathBuf>,
    palette_size: Option<String>,
    background: Vec<String>,
    dedupe: Option<String>,
    trim: Option<String>,
    scale: Option<String>,
    max: Option<u32>,
    shard: Option<String>,
    mesh: Option<PathBuf>,
    frames_csv: bool,
    threads: Option<usize>,
    strict: bool,
    no_manifest: bool,
}

/// The palette the options choose (`fcsp` wins over `palette_size`, which the
/// Python layer refuses together).
fn palette_choice(values: &OptionValues) -> ufcsr::Result<Option<PaletteChoice>> {
    Ok(match (&values.fcsp, &values.palette_size) {
        (Some(path), _) => Some(PaletteChoice::Image(path.clone())),
        (None, Some(size)) => {
            let [width, height] = ufcsr::parse_palette_size(size)?;
            Some(PaletteChoice::Canonical { width, height })
        }
        (None, None) => None,
    })
}

/// The background colours, `None` for the default (#000FFF or the manifest's).
fn backgrounds(values: &OptionValues) -> ufcsr::Result<Option<Vec<Color>>> {
    if values.background.is_empty() {
        return Ok(None);
    }
    let colors = values.background.iter().map(|text| {
        text.parse::<Color>()
            .map_err(|error| ufcsr::Error::BadOptions(format!("invalid background {text:?}: {}", error.0)))
    });
    colors.collect::<ufcsr::Result<Vec<_>>>().map(Some)
}

/// Heatmap settings from a scale name and top count (`None`: linear, largest count).
fn heatmap_options(scale: Option<&str>, max: Option<u32>) -> ufcsr::Result<HeatmapOptions> {
    if max == Some(0) {
        return Err(ufcsr::Error::BadOptions("max must be at least 1".to_string()));
    }
    let scale = scale.map(str::parse::<Scale>).transpose()?.unwrap_or_default();
    Ok(HeatmapOptions { scale, max })
}

/// The options as `ufcsr-analyze ARCHIVE [--out OUT] …` builds them.
fn analyze_options(archive: PathBuf, out_dir: &Path, values: &OptionValues) -> ufcsr::Result<AnalyzeOptions> {
    let shard = match &values.shard {
        Some(text) => Some(text.parse::<Shard>()?),
        None => Shard::from_job_array(|name| std::env::var(name).ok())?,
    };
    Ok(AnalyzeOptions {
        archive,
        palette: palette_choice(values)?,
        pidt: values.pidt.clone(),
        legend: values.parts.clone(),
        background: backgrounds(values)?,
        dedupe: values.dedupe.as_deref().map(str::parse::<Dedupe>).transpose()?.unwrap_or_default(),
        trim: values.trim.as_deref().map(str::parse::<TrimMode>).transpose()?.unwrap_or_default(),
        heatmap: heatmap_options(values.scale.as_deref(), values.max)?,
        strict: values.strict,
        exclude: vec![out_dir.to_path_buf()],
        ignore_manifest: values.no_manifest,
        shard,
        mesh: values.mesh.clone(),
        frames: values.frames_csv,
        loaded_labels: None,
    })
}

/// Analyses and writes the result set into `out_dir`.
fn analyze_and_write(options: &AnalyzeOptions, out_dir: &Path) -> ufcsr::Result<()> {
    let mut analysis = ufcsr::analyze(options, None)?;
    ufcsr::write_results(&mut analysis, out_dir)?;
    Ok(())
}

/// Runs the analysis of `archive` and writes its result set to `out` (default:
/// the analyzer's default output folder); returns that folder. `options` is a
/// dict of the command line's options in snake_case. The GIL is released
/// while counting.
#[pyfunction]
#[pyo3(signature = (archive, out, options))]
fn analyze(
    py: Python<'_>,
    archive: PathBuf,
    out: Option<PathBuf>,
    options: &Bound<'_, PyDict>,
) -> PyResult<PathBuf> {
    let values: OptionValues = options.extract()?;
    let out_dir = out.unwrap_or_else(|| ufcsr::default_output_dir(&archive));
    let options = analyze_options(archive, &out_dir, &values).map_err(to_python)?;
    let threads = match values.threads {
        Some(threads) if threads > MAX_THREADS => {
            return Err(PyValueError::new_err(format!("threads={threads}: at most {MAX_THREADS}")));
        }
        Some(threads) => {
            Some(rayon::ThreadPoolBuilder::new().num_threads(threads.max(1)).build().map_err(|error| {
                UfcsrError::new_err(format!("could not start the worker threads: {error}"))
            })?)
        }
        None => None,
    };
    py.detach(|| match &threads {
        Some(pool) => pool.install(|| analyze_and_write(&options, &out_dir)),
        None => analyze_and_write(&options, &out_dir),
    })
    .map_err(to_python)?;
    Ok(out_dir)
}

/// The summary of a `result.json` (everything but the per-texel counts), as
/// JSON text for `json.loads`.
#[pyfunction]
fn read_summary_json(py: Python<'_>, path: PathBuf) -> PyResult<String> {
    let summary = py.detach(|| ufcsr::read_result_summary(&path)).map_err(to_python)?;
    serde_json::to_string(&summary)
        .map_err(|error| UfcsrError::new_err(format!("{}: {error}", path.display())))
}

/// The per-texel counts of a `result.json`, decoded from its delta encoding:
/// `(counts, width, height)` where `counts` is a bytearray of `width * height`
/// little-endian u32 (for `numpy.frombuffer(counts, "<u4")`, no copy).
#[pyfunction]
fn read_texel_counts<'py>(py: Python<'py>, path: PathBuf) -> PyResult<(Bound<'py, PyByteArray>, u32, u32)> {
    let stored = py.detach(|| ufcsr::read_texel_counts(&path)).map_err(to_python)?;
    let counts = PyByteArray::new_with(py, stored.texel_counts.len() * 4, |bytes| {
        for (slot, count) in bytes.chunks_exact_mut(4).zip(&stored.texel_counts) {
            slot.copy_from_slice(&count.to_le_bytes());
        }
        Ok(())
    })?;
    Ok((counts, stored.width, stored.height))
}

/// Writes the heatmap PNG of `counts` (little-endian u32 bytes, row-major,
/// `width * height` of them) with the library's colour scale.
#[pyfunction]
#[pyo3(signature = (out, counts, width, height, scale=None, max=None))]
fn write_heatmap(
    py: Python<'_>,
    out: PathBuf,
    counts: &[u8],
    width: u32,
    height: u32,
    scale: Option<&str>,
    max: Option<u32>,
) -> PyResult<()> {
    let texels = width as usize * height as usize;
    if counts.len() != texels * 4 {
        return Err(PyValueError::new_err(format!(
            "{} texel counts for a {width}×{height} palette (expected {texels})",
            counts.len() / 4
        )));
    }
    let options = heatmap_options(scale, max).map_err(to_python)?;
    let texel_counts: Vec<u32> = counts
        .chunks_exact(4)
        .map(|bytes| u32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]))
        .collect();
    py.detach(|| ufcsr::write_heatmap(&out, &texel_counts, width, height, options)).map_err(to_python)
}

/// The native module: the functions above and `UfcsrError`.
#[pymodule]
fn _native(module: &Bound<'_, PyModule>) -> PyResult<()> {
    module.add("UfcsrError", module.py().get_type::<UfcsrError>())?;
    module.add_function(wrap_pyfunction!(analyze, module)?)?;
    module.add_function(wrap_pyfunction!(read_summary_json, module)?)?;
    module.add_function(wrap_pyfunction!(read_texel_counts, module)?)?;
    module.add_function(wrap_pyfunction!(write_heatmap, module)?)?;
    Ok(())
}
