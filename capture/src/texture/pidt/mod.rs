//! The Part Identification Texture: painted from the mesh's parts over the
//! unwrap ([`painted`]), or a user's own PIdT and legend for the mesh's own
//! UVs, checked against them ([`own`]).

pub mod own;
pub mod painted;

pub use painted::*;
