//! Integration tests of the core: families, errors, properties, CLI.

mod cli;
mod errors;
mod families;
mod properties;
