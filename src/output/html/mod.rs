//! The HTML pages: `report.html` for one result ([`report_page`]) and the
//! comparison of several ([`compare_page`]), each rendered one page section
//! per function.

pub(crate) mod compare_page;
pub(crate) mod provenance;
pub(crate) mod report_page;

pub use compare_page::write_comparison;
