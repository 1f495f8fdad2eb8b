//! Files, safely — the one file layer of both crates and the command line
//! (issue 34): clippy.toml forbids `std::fs`'s opening, reading, writing,
//! renaming and removing everywhere else, so a new command cannot bypass it.
//! Here: opening inputs only when they are regular files and
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
mod unfinished;

pub(crate) use atomic_write::parse_journal;
pub use atomic_write::{
    Staging, copy_into, interrupted_commit, refuse_replacing_non_file, remove_dead_runs, remove_on_interrupt,
    remove_stale_staging, remove_stale_temporaries, remove_temporaries, write_atomically,
    write_bytes_atomically,
};
pub use limited_read::{IMAGE_LIMIT, SMALL_INPUT_LIMIT, open_regular, read_limited, read_limited_text};
pub use model_input::{
    GltfModel, MAX_COORDINATE_M, MODEL_LIMIT, check_accessors, check_coordinates, parse_gltf, read_gltf,
    resolve_inside,
};
pub use output_guard::{
    create_output_dir, create_private_dir, crosses_link, output_sub_dir, real_dir, refuse_overwriting_inputs,
    remove_inside, resolved, same_path,
};
pub use png_encode::{PngEncoding, encode_rgb_png, write_figure_png, write_rgb_png, write_rgba_png};
pub use unfinished::{
    UNFINISHED_FILE, mark_finished, mark_unfinished, refuse_unfinished, unfinished_outputs,
};
