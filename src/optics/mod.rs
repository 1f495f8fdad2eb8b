//! Optics: the solid angle each pixel of a pinhole eye subtends
//! ([`solid_angle`]), the weight the rendered angular-area measure gives a
//! pixel; and the three-vector arithmetic the geometry shares ([`vector`]).
//!
//! Its own folder rather than beside the measures in `count/`: two stages
//! use it — the archive, whose capture facts turn the manifest's field of
//! view and tile layout into an [`EyeProjection`] and [`TileView`]s, and the
//! count, which sums the weights per run — and the archive comes before the
//! count. Kept apart, it depends on nothing and both point down to it; inside
//! `count/` the archive would need the count and the count the archive.

pub(crate) mod solid_angle;
pub(crate) mod vector;

pub use solid_angle::{EyeProjection, TileView};
