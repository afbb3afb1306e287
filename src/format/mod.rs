//! Automaton files: parsing with positioned errors, and writing.

mod error;
mod parse;
mod write;

pub use error::FormatError;
pub use parse::{ReadError, parse_design, read_design};
pub use write::TomlWriter;
