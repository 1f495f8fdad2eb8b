//! The HTML pages: `report.html` for one result ([`report_page`]) and the
//! comparison of several ([`compare_page`]), both with the placement section
//! ([`placement_section`]) when there is a placement result, each rendered one page section
//! per function (the report's sections are listed in order in
//! `report_page::SECTIONS`: a new section is its function and one line there),
//! the run's provenance ([`provenance`]) and the one [`escape`] they all use.

pub(crate) mod compare_page;
pub(crate) mod escape;
pub(crate) mod placement_section;
pub(crate) mod provenance;
pub(crate) mod report_page;

pub use compare_page::{
    AREA_HEATMAPS, COUNT_HEATMAPS, ComparisonOptions, OWN_SCALES, RANKED_HEADING, SHARED_SCALE,
    WrittenComparison, write_comparison, write_comparison_with,
};
pub use report_page::{NEEDS_ITS_FOLDER, QUOTED_HEADING};
