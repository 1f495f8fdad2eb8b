//! The paths of a written result set ([`WrittenFiles`]): what
//! [`crate::output::write_results`] returns and what the report page links to.

use std::path::{Path, PathBuf};

use crate::output::plots::Plot;

/// The files [`crate::output::write_results`] wrote.
#[derive(Debug, Clone)]
pub struct WrittenFiles {
    pub result_json: PathBuf,
    pub parts_csv: Option<PathBuf>,
    /// The heatmap texture `heatmap.png`: the per-texel angular area over
    /// time (deg²·s) when measured ([`crate::Analysis::texel_angular_area`]),
    /// else the paper's count; `heatmap.glb` and the views show the same.
    pub heatmap_png: PathBuf,
    /// `heatmap-count.png`, the paper-compatible count, when `heatmap.png`
    /// shows the angular area (`--texel-area off` writes the count as
    /// `heatmap.png` alone).
    pub heatmap_count_png: Option<PathBuf>,
    /// `texel-area.f32`, the per-texel angular area's values beside
    /// `result.json` (written with the angular-area heatmap), for the comparison
    /// page and the capture's `views` ([`crate::read_texel_area`]).
    pub texel_area: Option<PathBuf>,
    /// `texel-area.units`: a shard's integer per-texel sums, which `merge`
    /// adds exactly ([`crate::TexelAreaUnits`]).
    pub texel_area_units: Option<PathBuf>,
    pub timings_json: PathBuf,
    /// The vehicle with the heatmap on it, when the analysis had a vehicle model.
    pub heatmap_glb: Option<PathBuf>,
    /// The page that shows it all.
    pub report_html: PathBuf,
    /// `views.png`, the contact sheet of the eight views (with a vehicle model).
    pub views_png: Option<PathBuf>,
    /// `views.pdf`, the contact sheet for a paper (183 mm wide), beside it.
    pub views_pdf: Option<PathBuf>,
    /// `frames.csv`, when frames were tallied.
    pub frames_csv: Option<PathBuf>,
    /// `map.png`, the scenario from above (with a manifest that places the vehicle).
    pub map_png: Option<PathBuf>,
    /// `frames-strip.png`, a few frames as the eye saw them (from tile PNGs).
    pub frames_strip_png: Option<PathBuf>,
    /// Whether each view was also written alone beside `views.png`
    /// (`views/front.png`, …; `--figures all`).
    pub single_views: bool,
    /// The plots written under `plots/`.
    pub plots: Vec<Plot>,
}

impl WrittenFiles {
    /// Whether `heatmap.png`, `heatmap.glb` and the views show the per-texel
    /// angular area (else the paper's count).
    pub fn area_first(&self) -> bool {
        self.heatmap_count_png.is_some()
    }

    /// Every file of the set, in the order summaries list them (the plots'
    /// paths are relative to `out_dir`, the set's folder).
    pub fn all(&self, out_dir: &Path) -> Vec<PathBuf> {
        let mut files = vec![self.result_json.clone()];
        files.extend(self.parts_csv.clone());
        files.push(self.heatmap_png.clone());
        files.extend(self.texel_area.clone());
        files.extend(self.texel_area_units.clone());
        files.extend(self.heatmap_count_png.clone());
        files.push(self.timings_json.clone());
        files.extend(self.frames_csv.clone());
        files.extend(self.heatmap_glb.clone());
        files.extend(self.views_png.clone());
        files.extend(self.views_pdf.clone());
        files.extend(self.views());
        files.extend(self.map_png.clone());
        files.extend(self.frames_strip_png.clone());
        files.push(self.report_html.clone());
        for plot in &self.plots {
            files.extend(plot.files.iter().map(|file| out_dir.join(file)));
        }
        files
    }

    /// The eight views beside `views.png` (`views/front.png`, …), when
    /// written ([`WrittenFiles::single_views`]): `--json`'s `written` lists them too.
    pub fn views(&self) -> Vec<PathBuf> {
        let Some(sheet) = self.views_png.as_ref().filter(|_| self.single_views) else { return Vec::new() };
        let dir = sheet.parent().unwrap_or(Path::new(".")).join("views");
        crate::output::heatmap_views::DIRECTIONS
            .iter()
            .map(|(name, _)| dir.join(format!("{name}.png")))
            .collect()
    }
}
