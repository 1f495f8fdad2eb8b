//! The PNG decoder the archive's images are read with: the format's chunks
//! ([`png_format`]), the zlib stream ([`png_zlib`]), the decode
//! ([`png_decode`]) with its row filters ([`unfilter`], SIMD kernels beside a
//! scalar reference) and the row reader the counters use ([`png_rows`]).
//!
//! What remains of the former `input/` stage once the archive contract moved
//! to `archive/` and the optics to `optics/`: only the decoder, which moves
//! to its own folder (`png/`) with the SIMD in one module.

pub(crate) mod png_decode;
pub(crate) mod png_format;
pub(crate) mod png_rows;
pub(crate) mod png_zlib;
pub(crate) mod unfilter;

pub use png_rows::{PixelLayout, RowReader, read_color_image, read_file};
pub use png_zlib::verify_image_data;
