//! Does this count depend on resolution? Two diagnostics every result carries.
//!
//! The paper counts a texel once per image that shows it, however many pixels
//! show it. When the vehicle is close, one texel covers many pixels and the
//! count *saturates*: more pixels per degree add pixels, not counts. When it
//! is far, a texel is smaller than a pixel and is sampled only in some
//! frames: more pixels per degree add counts. Either way the number changes
//! with `ppd`. [`ResolutionReport`] measures both — pixels per count from the
//! analysis itself, and the share of frames in which a texel is smaller than a
//! pixel from the capture's geometry — and [`ResolutionReport::warnings`]
//! says when the counts should not be compared across resolutions (run
//! `ufcsr study`, or use a resolution-independent measure).

use crate::archive::capture_facts::CaptureGeometry;

/// Pixels per count above which counts are called saturated.
pub(crate) const SATURATION_WARNING: f64 = 1.5;
/// Share of frames with sub-pixel texels above which sampling is called sparse.
pub(crate) const SUB_PIXEL_WARNING: f64 = 0.1;

pub use crate::format::result::ResolutionReport;

impl ResolutionReport {
    /// `texel_pixels` pixels showed texels; `per_image_total` counts (each
    /// texel once per image) came of them.
    pub fn new(texel_pixels: u64, per_image_total: u64, geometry: &CaptureGeometry) -> ResolutionReport {
        let sub_pixel_distance_m = geometry.sub_pixel_distance_m();
        let sub_pixel_frame_share = sub_pixel_distance_m.and_then(|limit| {
            let frames = &geometry.frame_distances_m;
            (!frames.is_empty())
                .then(|| frames.iter().filter(|&&d| d > limit).count() as f64 / frames.len() as f64)
        });
        ResolutionReport {
            pixels_per_count: if per_image_total == 0 {
                0.0
            } else {
                texel_pixels as f64 / per_image_total as f64
            },
            per_image_counts: per_image_total,
            texel_pixels,
            pixels_per_degree: geometry.pixels_per_degree,
            texel_size_mm: geometry.texel_size_mm,
            sub_pixel_distance_m,
            sub_pixel_frame_share,
        }
    }

    /// The report of several shards together (same capture geometry).
    pub fn merged(reports: &[&ResolutionReport]) -> Option<ResolutionReport> {
        let first = *reports.first()?;
        let texel_pixels = reports.iter().map(|r| r.texel_pixels).sum::<u64>();
        let per_image_counts = reports.iter().map(|r| r.per_image_counts).sum::<u64>();
        Some(ResolutionReport {
            pixels_per_count: if per_image_counts == 0 {
                0.0
            } else {
                texel_pixels as f64 / per_image_counts as f64
            },
            per_image_counts,
            texel_pixels,
            ..first.clone()
        })
    }

    /// Warnings for `result.json` when the counts depend on resolution.
    pub fn warnings(&self) -> Vec<String> {
        let mut warnings = Vec::new();
        if self.pixels_per_count > SATURATION_WARNING {
            warnings.push(format!(
                "counts saturate: {:.1} pixels showed each counted texel on average, and a texel counts once per \
                 image however many pixels show it, so totals and shares depend on pixels per degree \
                 (compare settings with `ufcsr study`)",
                self.pixels_per_count
            ));
        }
        if let (Some(share), Some(distance)) = (self.sub_pixel_frame_share, self.sub_pixel_distance_m)
            && share > SUB_PIXEL_WARNING
        {
            warnings.push(format!(
                "texels are smaller than a pixel beyond {distance:.1} m, in {:.0}% of the frames: such texels are \
                 sampled only sometimes, so counts depend on pixels per degree (compare settings with \
                 `ufcsr study`)",
                100.0 * share
            ));
        }
        warnings
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sub_pixel_distance_and_warnings_follow_the_geometry() {
        // 2.7 mm texels at 60 px/°: a pixel is 2.7 mm at about 9.3 m.
        let geometry = CaptureGeometry {
            pixels_per_degree: Some(60.0),
            texel_size_mm: Some(2.7),
            frame_distances_m: vec![5.0, 8.0, 12.0, 40.0],
        };
        let distance = geometry.sub_pixel_distance_m().unwrap();
        assert!(
            (distance - 0.0027 / (1.0f64 / 60.0).to_radians().tan()).abs() < 1e-9
                && (9.2..9.4).contains(&distance)
        );
        let report = ResolutionReport::new(3000, 1000, &geometry);
        assert_eq!(report.pixels_per_count, 3.0);
        assert_eq!(report.sub_pixel_frame_share, Some(0.5));
        assert_eq!(report.warnings().len(), 2);
        let quiet = ResolutionReport::new(1000, 1000, &CaptureGeometry::default());
        assert!(quiet.warnings().is_empty() && quiet.sub_pixel_frame_share.is_none());
    }
}
