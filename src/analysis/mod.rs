//! Analysis of instantiated automata.

mod check;

pub use check::{CheckReport, DEFAULT_CHECK_TOLERANCE, check, contractive_spectrum};
