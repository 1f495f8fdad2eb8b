//! Text made safe for HTML, shared by every page and section.
//!
//! Its own file, below the pages: when it lived in `report_page.rs`, the
//! sections the report page includes (`placement_section`, `provenance`)
//! had to reach back up into the page for it, a cycle between the files.

/// Escapes text for HTML.
pub fn escape(text: &str) -> String {
    text.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;").replace('"', "&quot;")
}
