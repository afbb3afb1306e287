//! Automaton files: parsing (through the design builder) with positioned
//! errors, writing any design back as a commented file, and the shipped ones.

mod builtin;
mod error;
mod parse;
mod write;

pub use builtin::BUILTIN_AUTOMATA;
pub use error::FormatError;
pub(crate) use error::Source;
pub use parse::{ReadError, builtin_design, parse_design, read_design};
pub use write::write_design;
