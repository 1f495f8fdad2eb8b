//! The PNG decoder, apart from the archive it reads: headers and chunks
//! ([`format`]), the one-inflate decoder for plain tiles ([`decode`]) and
//! its row unfiltering ([`unfilter`]), the end-to-end zlib check
//! ([`zlib`]), and the rows every reader takes ([`rows`]: the tile decoder,
//! or the png crate for everything else). Nothing here knows what an
//! archive, a palette or a texel is; the archive contract uses it.

pub(crate) mod decode;
pub(crate) mod format;
pub(crate) mod rows;
pub(crate) mod unfilter;
pub(crate) mod zlib;

pub use rows::{PixelLayout, RowReader, read_color_image, read_file};
pub use zlib::verify_image_data;
