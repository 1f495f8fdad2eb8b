//! The paths of a written result set ([`WrittenFiles`]): what
//! [`crate::write_results`] returns and what the report page links to.

use std::path::PathBuf;

use crate::output::plots::Plot;

/// The files [`crate::write_results`] wrote.
#[derive(Debug, Clone)]
pub struct WrittenFiles {
    pub result_json: PathBuf,
    pub parts_csv: Option<PathBuf>,
    pub heatmap_png: PathBuf,
    pub timings_json: PathBuf,
    /// The vehicle with the heatmap on it, when the analysis had a vehicle model.
    pub heatmap_glb: Option<PathBuf>,
    /// The page that shows it all.
    pub report_html: PathBuf,
    /// `views.png`, the contact sheet of the eight views (with a vehicle model).
    pub views_png: Option<PathBuf>,
    /// `frames.csv`, when frames were tallied.
    pub frames_csv: Option<PathBuf>,
    /// `map.png`, the scenario from above (with a manifest that places the vehicle).
    pub map_png: Option<PathBuf>,
    /// `frames-strip.png`, a few frames as the eye saw them (from tile PNGs).
    pub frames_strip_png: Option<PathBuf>,
    /// The plots written under `plots/`.
    pub plots: Vec<Plot>,
}
