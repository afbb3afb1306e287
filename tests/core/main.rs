//! Integration tests of the core: families, errors, properties, CLI.

mod builder;
mod cli;
mod convergence;
mod errors;
mod explore;
mod families;
mod fuzzed;
mod layers;
mod options;
mod properties;
mod render_api;
