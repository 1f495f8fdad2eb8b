//! Stage 2, count: the hot path. Work units counted in parallel
//! ([`work`]), the row kernels that classify pixels and collect texels
//! ([`scan`], with AVX2 and AVX-512 versions held to the portable one's
//! answers), per-colour counts, trimming of empty tiles, tallies by part
//! ([`part_lookup`], pixels weighted by their solid angle) and the counter for tiles held in memory
//! ([`TileCounter`], the capture's `--count`) and the solid angle each
//! texel subtends summed over the images ([`texel_area`], the default heatmap's measure).

pub(crate) mod counts;
pub(crate) mod part_lookup;
pub(crate) mod rgba32;
pub(crate) mod scan;
pub(crate) mod slot_table;
pub(crate) mod texel_area;
pub(crate) mod tile_counter;
pub(crate) mod trim;
pub(crate) mod work;

pub use counts::Counts;
pub use part_lookup::{FrameLabel, FrameRecord, PartLookup, PartPixels};
pub use rgba32::read_rgba32_ids;
pub use scan::{
    Classifier, ImageTally, KERNEL_ENV, Kernel, PartRows, PixelClass, RowScan, scan_image, scan_image_by_part,
};
pub use tile_counter::{CountedTile, TileCounter};
pub use trim::EmptyTile;
