//! The planes along which a mesh's triangles are cut, so that region rules
//! ([`crate::scene::regions`]) follow their boundaries instead of the mesh's
//! (the cutting itself: [`crate::scene::region_pieces`]).
//!
//! A rule decides by a triangle's centroid; a model of few large triangles
//! (the milk truck's side walls are a handful of triangles each) would give a
//! whole wedge of wall to a "roof" box whose boundary crosses it. Cut along
//! the rule's planes first, every piece lies on one side of each of them, and
//! the centroid test is exact: a part's area is the area inside its region.
//!
//! Every triangle the plane crosses near the region ([`CutPlane::within`])
//! is cut, whatever its part, and the point on a crossed edge is computed
//! from the edge's two positions in a fixed order: two triangles sharing an
//! edge (even of different parts, whose vertices a glTF file keeps apart)
//! get the same new corner, so cutting leaves no T-junction along the plane
//! (only a neighbour lying wholly outside `within` stays whole, at the
//! region's far edge). New corners interpolate the UVs
//! (kept and own) linearly, as the rasteriser would; the pieces keep the
//! triangle's part and winding.

use glam::DVec3;

/// Distance (metres) within which a corner counts as lying on the plane:
/// no cut passes closer than this to a corner. (A cut near the sharp end of
/// a long triangle can still leave a piece thinner than this, which
/// `inspect` counts as a sliver: the milk truck's rules leave 11, 0.6 cm²
/// in all.)
pub(crate) const ON_PLANE_M: f64 = 1e-4;

/// A plane `normal · p = offset` (normal of unit length) and the box
/// (`min`, `max`, already widened by [`ON_PLANE_M`]) outside which no
/// triangle needs cutting: the part of the plane that bounds a region.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct CutPlane {
    pub normal: DVec3,
    pub offset: f64,
    pub within: (DVec3, DVec3),
}
