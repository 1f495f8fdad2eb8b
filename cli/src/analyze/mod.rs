//! The command line of `ufcsr-analyze` (the binary's own modules; the
//! library knows nothing of them): the grammar ([`args`]), what ARCHIVE
//! means ([`intent`]), the main command ([`analyze_cmd`]) and the others ([`run`]), the placement search ([`placement`]), describing external frames ([`manifest`]).

pub mod analyze_cmd;
pub mod args;
pub mod intent;
pub mod manifest;
pub mod placement;
pub mod run;
