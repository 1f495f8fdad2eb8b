//! Resolution-independent measures per part, beside the paper's counts
//! (`result.json` → `measures`, and two columns of `parts.csv`).
//!
//! The paper's count (once per image or eye-frame per texel) changes meaning
//! with resolution and distance (issue 8). Two measures that do not:
//!
//! * **visible angular area over time**, deg²·s: per eye, the solid angle the
//!   part covers, integrated over the capture — the sum over eye-frames of
//!   the solid angle of its pixels (each pixel weighted by the solid angle
//!   it subtends in the eye's rectilinear projection, `frames.csv`'s
//!   `solid_angle_sr`, in deg²) × the seconds one captured frame stands for,
//!   averaged over the eyes (divided by their number). It converges to the
//!   ray-traced solid angle of the exact measure as pixels per degree grow
//!   (`docs/science.md`). Without the projection in the manifest, `pixels /
//!   ppd²` stands in (exact only at the image centre, with a note);
//! * **exposure**, s: how long the part is seen — eye-frames in which at
//!   least one pixel shows it × seconds per frame, averaged over the eyes
//!   (`eye-frames / eyes × frame step / fps`).
//!
//! Both are kept as sums (pixels, eye-frames, steradians) and derived at the
//! end, so shard results add up ([`Measures::merged`]; the integer sums
//! exactly, the steradians to rounding).

use crate::{archive::capture_facts::FrameClock, result::frames::FrameTable};

/// How the measures are defined, recorded in every result.
pub(crate) const DEFINITION: &str = "angular_area_deg2_s = sum over eye-frames of solid_angle_sr (the sum over the \
     part's pixels of the solid angle each subtends in the eye's rectilinear projection) * (180/pi)^2 * \
     seconds_per_frame / eyes; exposure_s = eye_frames_seen * seconds_per_frame / eyes; seconds_per_frame = \
     smallest step between captured frame numbers / fps";

/// The definition when the manifest gives no projection (older captures).
pub(crate) const DEFINITION_CENTRE_PPD: &str = "angular_area_deg2_s = sum over eye-frames of pixels / \
     pixels_per_degree^2 * seconds_per_frame / eyes (no projection in the manifest: pixels_per_degree holds \
     at the image centre, off-axis pixels are overweighted); exposure_s = eye_frames_seen * seconds_per_frame \
     / eyes; seconds_per_frame = smallest step between captured frame numbers / fps";

/// Square degrees per steradian.
const DEG2_PER_SR: f64 = (180.0 / std::f64::consts::PI) * (180.0 / std::f64::consts::PI);

pub(crate) use crate::format::result::PartMeasure;

pub use crate::format::result::Measures;

impl Measures {
    /// Sums the per-eye-frame tallies of `frames` and derives the measures.
    pub fn from_frames(frames: &FrameTable, clock: &FrameClock) -> Measures {
        let parts = frames
            .parts
            .iter()
            .enumerate()
            .map(|(part, name)| PartMeasure {
                name: name.clone(),
                pixels: frames.records.iter().map(|r| r.pixels[part]).sum(),
                eye_frames_seen: frames.records.iter().filter(|r| r.pixels[part] > 0).count() as u64,
                solid_angle_sr: frames
                    .records
                    .iter()
                    .map(|r| r.solid_angle_sr.as_ref().map(|sr| sr[part]))
                    .sum::<Option<f64>>(),
                angular_area_deg2_s: None,
                exposure_s: None,
            })
            .collect();
        let weighted =
            !frames.records.is_empty() && frames.records.iter().all(|r| r.solid_angle_sr.is_some());
        let mut measures = Measures {
            definition: if weighted { DEFINITION } else { DEFINITION_CENTRE_PPD }.to_string(),
            pixels_per_degree: clock.pixels_per_degree,
            seconds_per_frame: clock.seconds_per_frame,
            eyes: clock.eyes,
            eye_frames: frames.records.len() as u64,
            parts,
            notes: Vec::new(),
        };
        measures.derive();
        measures
    }

    /// Fills the derived fields (and notes) from the integer sums.
    fn derive(&mut self) {
        self.notes.clear();
        let eyes = self.eyes.max(1) as f64;
        let seconds = self.seconds_per_frame;
        if seconds.is_none() {
            self.notes.push(
                "no fps in the manifest (rig.settings.fps): angular_area_deg2_s and exposure_s are omitted"
                    .into(),
            );
        }
        if self.pixels_per_degree.is_none() && self.parts.iter().any(|p| p.solid_angle_sr.is_none()) {
            self.notes.push(
                "no pixels per degree in the manifest (rig.pixels_per_degree): angular_area_deg2_s is omitted"
                    .into(),
            );
        }
        for part in &mut self.parts {
            part.exposure_s = seconds.map(|s| part.eye_frames_seen as f64 * s / eyes);
            part.angular_area_deg2_s = match (seconds, part.solid_angle_sr, self.pixels_per_degree) {
                (Some(s), Some(sr), _) => Some(sr * DEG2_PER_SR * s / eyes),
                (Some(s), None, Some(ppd)) => Some(part.pixels as f64 / (ppd * ppd) * s / eyes),
                _ => None,
            };
        }
    }

    /// The measures of shards that together hold every eye-frame once: sums
    /// added, measures derived again (so equal to the whole's).
    pub fn merged(shards: &[&Measures]) -> Option<Measures> {
        let (first, rest) = shards.split_first()?;
        let mut merged = (*first).clone();
        for shard in rest {
            merged.eye_frames += shard.eye_frames;
            for (sum, part) in merged.parts.iter_mut().zip(&shard.parts) {
                sum.pixels += part.pixels;
                sum.eye_frames_seen += part.eye_frames_seen;
                sum.solid_angle_sr = sum.solid_angle_sr.zip(part.solid_angle_sr).map(|(a, b)| a + b);
            }
        }
        merged.derive();
        Some(merged)
    }

    /// The factor that turns per-texel solid angles summed over the
    /// eye-frames into per-texel angular area over time (the part measure's
    /// definition, [`DEFINITION`], texel by texel,
    /// [`crate::result::texel_area_file::TexelAreaUnits::areas`]): deg²·s per sr of a texel's summed solid angle: deg² per sr × seconds
    /// per frame / eyes. `None` without fps.
    pub fn texel_area_factor(clock: &FrameClock) -> Option<f64> {
        Some(DEG2_PER_SR * clock.seconds_per_frame? / clock.eyes.max(1) as f64)
    }

    /// The measure of the part called `name`.
    pub fn part(&self, name: &str) -> Option<&PartMeasure> {
        self.parts.iter().find(|part| part.name == name)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::count::part_lookup::{FrameLabel, FrameRecord};

    #[test]
    fn measures_follow_their_definition_and_merge_exactly() {
        let record = |position, pixels: [u64; 2]| FrameRecord {
            label: FrameLabel::Image(position),
            pixels: pixels.to_vec(),
            texels: vec![0, 0],
            solid_angle_sr: None,
        };
        let table = |records| FrameTable { parts: vec!["a".into(), "b".into()], records };
        let clock = FrameClock { seconds_per_frame: Some(0.5), eyes: 2, pixels_per_degree: Some(10.0) };
        assert_eq!(
            Measures::from_frames(&table(vec![record(0, [1, 1])]), &clock).definition,
            DEFINITION_CENTRE_PPD
        );
        let whole = Measures::from_frames(&table(vec![record(0, [100, 0]), record(1, [300, 4])]), &clock);
        let a = whole.part("a").unwrap();
        assert_eq!((a.pixels, a.eye_frames_seen), (400, 2));
        // 400 px / 100 px per deg² × 0.5 s / 2 eyes.
        assert_eq!(a.angular_area_deg2_s, Some(1.0));
        assert_eq!(a.exposure_s, Some(0.5));
        assert_eq!(whole.part("b").unwrap().exposure_s, Some(0.25));
        let first = Measures::from_frames(&table(vec![record(0, [100, 0])]), &clock);
        let second = Measures::from_frames(&table(vec![record(1, [300, 4])]), &clock);
        assert_eq!(Measures::merged(&[&first, &second]), Some(whole));
        let no_clock = Measures::from_frames(&table(vec![record(0, [1, 1])]), &FrameClock::default());
        assert_eq!(no_clock.parts[0].angular_area_deg2_s, None);
        assert_eq!(no_clock.notes.len(), 2);
    }

    #[test]
    fn angular_area_is_the_solid_angle_of_the_pixels_when_the_projection_is_known() {
        let record = |position, sr: [f64; 2]| FrameRecord {
            label: FrameLabel::Image(position),
            pixels: vec![10, 10],
            texels: vec![1, 1],
            solid_angle_sr: Some(sr.to_vec()),
        };
        let table = FrameTable {
            parts: vec!["a".into(), "b".into()],
            records: vec![record(0, [1e-3, 0.0]), record(1, [3e-3, 2e-3])],
        };
        // No pixels per degree needed: the solid angles are what counts.
        let clock = FrameClock { seconds_per_frame: Some(0.5), eyes: 2, pixels_per_degree: None };
        let measures = Measures::from_frames(&table, &clock);
        assert_eq!(measures.definition, DEFINITION);
        assert!(measures.notes.is_empty(), "{:?}", measures.notes);
        let a = measures.part("a").unwrap();
        assert_eq!(a.solid_angle_sr, Some(4e-3));
        // 4e-3 sr · (180/π)² deg²/sr · 0.5 s / 2 eyes.
        assert!((a.angular_area_deg2_s.unwrap() - 4e-3 * DEG2_PER_SR * 0.25).abs() < 1e-12);
    }
}
