//! The Part Identification Texture: painted from the mesh's parts over the
//! unwrap ([`painted`]), or a user's own PIdT and legend for the mesh's own
//! UVs, checked against them ([`own`]).

pub(crate) mod own;
pub(crate) mod painted;

pub use own::OwnLabelFiles;
pub use painted::{PidtImage, UNLABELLED_COLOR, paint as paint_pidt};
