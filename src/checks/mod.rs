//! Checks on how a capture was rendered, beside the counts: colour
//! management and texture filtering damage.
//!
//! On the full 4096² palette almost every 24-bit colour names a texel, so a
//! pixel whose colour a tone curve, a blend or a dither changed is simply
//! another texel: no stray pixel betrays it, and the counts go silently
//! wrong. Three signatures still do, and this stage measures them:
//! [`neighbours`] samples adjacent pixels while counting (texels that are
//! far apart on the palette but side by side on screen), and
//! [`colour_damage`] judges those samples, the share of counts on
//! unlabelled texels and the share of background pixels into named warnings
//! with their causes and fixes. It depends on the inputs only, so counting
//! can feed it and the result can report it.

pub(crate) mod color_damage;
pub(crate) mod neighbours;

pub use color_damage::{ColorChecks, ColorWarning};
pub use neighbours::NeighbourSample;
