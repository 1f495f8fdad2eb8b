//! Stage 4, output: a result for people and other programs — the result
//! set written atomically into its folder ([`write_results`]), `parts.csv`
//! and `frames.csv` ([`csv`]), the console table, the heatmap texture, the
//! vehicle model with it (`heatmap.glb`, the archive's [`crate::VehicleModel`]
//! with the heatmap as its texture), the eight views (drawn with the CPU
//! rasterizer [`raster`], which the capture's inspect pictures share), the
//! plots ([`plots`], drawn for journal columns as PNG, SVG and PDF by
//! [`figure`] and [`pdf`]), the dot-and-whisker figures of values with
//! intervals ([`interval_figure`]), the one table of readable part names
//! ([`part_names`]), the legends and captions of raster pictures
//! ([`legend`], also the capture's inspect pictures') and the HTML pages ([`html`]).

pub(crate) mod console_table;
pub(crate) mod csv;
pub(crate) mod figure;
pub(crate) mod frame_strip;
pub(crate) mod heatmap;
pub(crate) mod heatmap_views;
pub(crate) mod html;
pub(crate) mod interval_figure;
pub(crate) mod legend;
pub(crate) mod numbers;
pub(crate) mod part_names;
pub(crate) mod pdf;
pub(crate) mod plots;
pub(crate) mod raster;
pub(crate) mod result_set;
pub(crate) mod scenario_map;
pub(crate) mod scene_model;
pub(crate) mod view_sheet;
pub(crate) mod written_files;

pub use console_table::{format_counted_table, format_table};
pub use csv::{CsvStyle, csv_field, write_parts_csv};
/// The figure units and backend the capture's study plot is drawn with too.
pub use figure::{
    DPI as FIGURE_DPI, KernedBitmap, mm as figure_mm, pt as figure_pt, stroke as figure_stroke,
    svg_in_millimetres,
};
pub use figure::{FigureSize, MIN_TEXT_PT, MM_PER_PT, OKABE_ITO};
pub use frame_strip::{FRAME_STRIP_FILE, STRIP_BACKGROUND, STRIP_FRAME_HEIGHT, STRIP_UNLABELLED};
pub use heatmap::{
    AreaLevels, COUNT_HEATMAP_FILE, HEATMAP_FILE, largest_area, plasma, render as render_heatmap,
    write_area_heatmap, write_heatmap,
};
pub use heatmap_views::{
    AREA_UNIT, DEFAULT_VIEWS_SCALE, DIRECTIONS, NEVER_SEEN, VIEW_BASE, ViewCamera, ViewTexture,
    area_views_caption, measure_unit, render_view, view_cameras, views_caption,
};
pub use html::escape::escape as html_escape;
pub use html::{
    AREA_HEATMAPS, COUNT_HEATMAPS, ComparisonOptions, NEEDS_ITS_FOLDER, OWN_SCALES, QUOTED_HEADING,
    RANKED_HEADING, SHARED_SCALE, WrittenComparison, write_comparison, write_comparison_with,
};
pub use interval_figure::{IntervalFigure, IntervalRow};
pub use legend::{LEGEND_LINE, LEGEND_TEXT_PX, LegendEntry, TextLayout, text_px_for};
pub use part_names::readable_part_name;
pub use plots::{PlotText, font_available as plot_font_available};
pub use raster::ZBuffer;
pub use result_set::{
    Figures, MAP_FILE, ResultSetOptions, default_output_dir, write_results, write_results_with,
};
pub use scenario_map::{MAP_SIZE, MapContent, MapFrame, SceneShapes, time_color, write_scenario_map};
pub use scene_model::{SceneObject, write_scene_glb};
pub use view_sheet::{VIEWS_PDF_FILE, WrittenViews, bar_ticks, sheet_text_px, write_views};
pub use written_files::WrittenFiles;
