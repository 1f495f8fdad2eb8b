//! Files, safely: opening inputs only when they are regular files and
//! reading them with a size limit ([`read_limited`]), and writing outputs
//! atomically through temporaries that an interruption removes
//! ([`write_atomically`], [`Staging`] for a whole result set), never over
//! an input nor through a link ([`refuse_overwriting_inputs`]), PNGs encoded
//! by one function ([`encode_rgb_png`]). Every stage
//! reads or writes through this folder; it uses nothing of the crate but the
//! error type.

mod atomic_write;
mod limited_read;
mod model_input;
mod output_guard;
mod png_encode;

pub use atomic_write::{
    Staging, interrupted_commit, remove_on_interrupt, remove_stale_staging, remove_temporaries,
    write_atomically, write_bytes_atomically,
};
pub use limited_read::{IMAGE_LIMIT, SMALL_INPUT_LIMIT, open_regular, read_limited};
pub use model_input::{
    GltfModel, MAX_COORDINATE_M, MODEL_LIMIT, check_accessors, check_coordinates, parse_gltf, read_gltf,
    resolve_inside,
};
pub use output_guard::{crosses_link, real_dir, refuse_overwriting_inputs, resolved, same_path};
pub use png_encode::{PngEncoding, encode_rgb_png, write_rgb_png};
