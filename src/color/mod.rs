//! The colour space everything else is built on: a 24-bit colour
//! ([`Color`]) and dense sets over all 2^24 of them ([`SeenSet`],
//! [`ColorSet`], [`AtomicColorSet`]). Every stage uses this folder; it uses
//! nothing of the crate but the error type.

mod rgb;
pub(crate) mod sets;

pub use rgb::{COLOR_COUNT, Color, ParseColorError};
pub use sets::{AtomicColorSet, SeenSet, color_key};
pub(crate) use sets::{ColorSet, zeroed_writable};
